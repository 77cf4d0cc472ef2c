//! From smoothed curves to the written program: each run rendered as the
//! output format can say it (shaped by the plan of the exact curves, so
//! that the controller keeps their speed), written in the controller's
//! dialect, read back, verified against the original and timed. Runs whose
//! written text fails are rendered again with half the chord share, a few
//! times, then kept as the program wrote them; so are runs that read back
//! slower than the program's own.

mod choose;
mod emitter;
mod streamed;
mod write;

use crate::facts::ProgramFacts;
use crate::interp::{MotionReader, ReadBackError};
pub use crate::pipeline::written::{
    forms, render_options, resolution, write_options, FANUC_MAX_DEGREE, MIN_ARC_RADIUS_MM,
    MIN_ARC_UNITS, MIN_BLOCK_PERIODS, PLANAR_MM,
};
use crate::pipeline::{
    compare_runs, group_by_source, RunCountMismatch, WrittenCheck, WrittenReading,
};
pub use crate::pipeline::{EmitOptions, RenderMemo, CURVE_BLEND_SHARE, G1_BLEND_SHARE};
use crate::text_out::TextOut;
use crate::write_gcode::WriterCarry;
use crate::{ArcWords, Format, GcodeError, JsonError, Program, WriteError};
pub use choose::Chosen;
use fairpath::budget::{BudgetError, ToleranceBudget};
use fairpath::feed::plan::RunPlan;
use fairpath::feed::FeedError;
use fairpath::path::{Piece, Run};
use fairpath::render::{PlannedSpeed, RenderError, RenderStats};
use std::sync::Arc;

/// Why the curves could not be written.
#[derive(Debug, thiserror::Error)]
pub enum EmitError {
    /// The blending share a program's own `G64` asks for does not fit
    /// ([`EmitOptions::budget_for`]).
    #[error("the blending share for the program's own G64")]
    Blend(#[source] BudgetError),
    #[error("writing JSON")]
    WriteJson(#[source] WriteError),
    #[error("the written JSON does not read back")]
    ReadJson(#[source] JsonError),
    #[error("rendering run {run}")]
    Render {
        /// Index of the run in the program's runs.
        run: usize,
        #[source]
        source: RenderError,
    },
    #[error("planning")]
    Plan(#[source] FeedError),
    #[error("writing G-code")]
    WriteGcode(#[source] WriteError),
    #[error("the written G-code does not read back")]
    Reread(#[source] GcodeError),
    /// The text read back has other runs than the program.
    #[error(transparent)]
    Runs(#[from] RunCountMismatch),
    /// The output ([`TextOut`]) refused the text or could not give it back.
    #[error("the output")]
    Output(#[source] std::io::Error),
}

impl From<ReadBackError> for EmitError {
    fn from(e: ReadBackError) -> EmitError {
        match e {
            ReadBackError::Gcode(e) => EmitError::Reread(e),
            ReadBackError::Io(e) => EmitError::Output(e),
        }
    }
}

type Result<T, E = EmitError> = core::result::Result<T, E>;

/// Runs of at least this many pieces are planned at both feeds side by
/// side (shorter ones run side by side with other runs).
const PARALLEL_FEEDS_PIECES: usize = 10_000;

/// A run of at least this many curves is long: its only candidate
/// rendering is not planned before it is written (the written text is), and
/// the all-G1 candidate is not tried where the arcs fell back to lines on
/// fewer than [`LINES_CANDIDATE_SHARE`] of its curves. Each plan of such a
/// run costs seconds (`docs/scale.md`).
pub(crate) const LONG_RUN_PIECES: usize = PARALLEL_FEEDS_PIECES;

/// Share of a long run's curves whose arcs fell back to G1 below which
/// the all-G1 rendering is not tried: where arcs follow nearly all of a
/// long run, G1 throughout plans slower (on the reference programs it won
/// on a few short runs and on none of the long ones; measurements:
/// docs/tuning.md, `LONG_RUN_PIECES` and `LINES_CANDIDATE_SHARE`).
const LINES_CANDIDATE_SHARE: f64 = 0.1;

/// Pieces per part when a long run is rendered in parts side by side (a
/// multiple of the renderer's chains, [`fairpath::render::CHAIN_PIECES`]).
const RENDER_PART_PIECES: usize = 4096;
const _: () = assert!(RENDER_PART_PIECES % fairpath::render::CHAIN_PIECES == 0);

/// Pieces a part of a rendering timed as it is rendered renders to, about
/// ([`emitter::Emitter::streamed_times`]): a part's arcs or lines stay
/// small (measurements: docs/tuning.md, `STREAMED_PART_RENDERED`).
const STREAMED_PART_RENDERED: usize = 30_000;

/// Parts rendered side by side before they are joined: enough to keep
/// the cores busy, few enough that the parts waiting to be joined hold
/// little beside the joined rendering.
const RENDER_GROUP_PARTS: usize = 8;

/// Parts rendered side by side at a time where a long run is rendered as
/// it is written ([`emitter::PartsRenderer`]): one per core, so that what
/// waits to be written stays small (a part of 4,096 corner transitions
/// renders to about 30,000 arcs; measurements: docs/tuning.md,
/// `STREAMED_PART_RENDERED`).
fn streamed_group_parts() -> usize {
    std::thread::available_parallelism().map_or(2, |n| n.get())
}

/// The finer curvature step share arcs are also rendered at, as a share
/// of [`crate::pipeline::EmitOptions::step_share`] (`--step-share`, default
/// [`fairpath::render::arcs::STEP_SHARE`]): each run written as arcs or
/// G1 gets the faster of the two (and where the half won, a quarter is
/// tried after it: [`FINER_STEPS`]). At half the share a joint of arcs passes at
/// `sqrt(2)` times the speed the curves were planned for, which leaves
/// the planner room where chains of short arcs and block lengths bind; it
/// costs more blocks, and where the share is already small the extra
/// arcs can be slower (`130207L.ngc`, `helix.ngc` with `auto` at 0.25),
/// hence a choice per run rather than a smaller default (measurements:
/// docs/tuning.md, `FINER_STEP`).
pub const FINER_STEP: f64 = 0.5;

/// How many times a run written as arcs or G1 is rendered again at
/// [`FINER_STEP`] times the share before, each kept only where it plans
/// faster at every feed than the one before (the first that does not
/// ends the tries): two, so down to a quarter of the step share. The
/// second halving gains where fits' curvature changes fast and the first
/// already gained (dense 3D finishing, engravings, chirps), and costs a
/// rendering and its plan only on the runs the first halving won; at a
/// quarter share the joints' designed curvature steps are small enough
/// that kinks of the written coordinates' rounding can cost what the
/// rendering gained (measurements: docs/tuning.md, `FINER_STEPS`).
pub const FINER_STEPS: usize = 2;

/// Times a failing run is rendered again with half the chord.
pub const RETRIES: usize = 3;

/// A run is rewritten only if its rendering plans at least this share
/// faster than the run as the program wrote it (the library's rule, which
/// `auto` also reads). A run of splines needs only to plan no slower (the
/// written text is then checked to be no slower): see `choose`.
pub use fairpath::choose::{FINER_KEEP_MARGIN, KEEP_MARGIN};

/// The written program (its text went to the [`TextOut`] it was written
/// to).
#[derive(Clone, Debug)]
pub struct Emitted {
    /// Lines of the text, as `str::lines` counts them.
    pub lines: usize,
    /// The budget the text was written with ([`EmitOptions::budget_for`]:
    /// a blending share where the program's own G64 needs one).
    pub budget: ToleranceBudget,
    pub stats: RenderStats,
    /// The verdict on the text read back.
    pub check: WrittenCheck,
    /// Runs rendered again with a finer chord.
    pub retried_runs: usize,
    /// Runs kept as written because they are in G91 and the format has
    /// only spline blocks (a block in a G91 run is written between G90 and
    /// G91 lines, which would end the run there).
    pub g91_spline_runs: usize,
    /// Runs kept as the program wrote them: their rendering planned no
    /// faster (or did not verify).
    pub kept_runs: usize,
    /// Per run, in the program's order: true where the run is written as
    /// the program had it (what the evidence then describes).
    pub kept: Vec<bool>,
    /// The written G-code as read back for the check (`None` for JSON),
    /// for planning it without reading it again
    /// ([`crate::pipeline::plan_written`]).
    pub reading: Option<WrittenReading>,
}

/// Where a part of a program ([`crate::interp::PartReader`]) is written
/// from: what the whole program is ([`ProgramFacts`]), the state the
/// written text before the part leaves the writer in, and the reading of
/// that text, from which the part's text is read back. [`emit_part`]
/// leaves it as the next part needs it.
#[derive(Clone)]
pub struct PartContext {
    pub facts: ProgramFacts,
    pub carry: WriterCarry,
    pub reading: MotionReader,
    /// The written plan of a run that goes on into the next part (a long
    /// run cut into windows).
    pub written: Option<crate::pipeline::CarriedPlan>,
}

impl PartContext {
    /// At the start of a program whose whole has `facts`.
    pub fn new(facts: ProgramFacts) -> PartContext {
        PartContext {
            facts,
            carry: WriterCarry::new(),
            reading: MotionReader::new(),
            written: None,
        }
    }

    /// For `program` written whole.
    pub fn whole(program: &Program) -> PartContext {
        PartContext::new(ProgramFacts::of(program))
    }
}

/// Renders, writes and verifies. `smoothed` and `plans` are per run of
/// `program` (the plan of exactly those pieces on `opts.machine` at its
/// maximum feed). Each run is written in the form that plans fastest among
/// those the format allows (arcs or, for curves arcs cannot follow, G1),
/// or as the program wrote it when none is faster, both at the machine's
/// maximum feed and at the programmed feeds. `original` is
/// `program.runs()` (lent by the caller, which holds it already). Returns
/// the text with what was written.
pub fn emit(
    program: &Program,
    original: &[Run],
    smoothed: &[Vec<Piece>],
    plans: &[RunPlan],
    opts: &EmitOptions,
) -> Result<(Emitted, String)> {
    let mut ctx = PartContext::whole(program);
    let mut out: Vec<u8> = Vec::new();
    let emitted = emit_part(
        program,
        &mut ctx,
        original,
        smoothed,
        (plans, Vec::new()),
        opts,
        None,
        &mut out,
    )?;
    Ok((emitted, text_of(out)?))
}

/// The text a `Vec<u8>` output holds (whole lines of `str`s: UTF-8).
pub(crate) fn text_of(out: Vec<u8>) -> Result<String> {
    String::from_utf8(out).map_err(|e| EmitError::Output(std::io::Error::other(e)))
}

/// [`emit`] of `program`, a part of a program or a whole one, from where
/// `ctx` stands, its text written to the end of `out`; on success `ctx`
/// stands after it. The parts emitted one after the other write, check and
/// time the text [`emit`] makes of the whole program.
///
/// `memo`: the renderings `auto`'s objective made of these curves, if any
/// ([`RenderMemo`]). `(plans, speeds)`: the plans of the curves, and per
/// run the speed a dropped plan was sampled to ([`take_long_run_speeds`];
/// empty for none).
#[allow(clippy::too_many_arguments)]
pub fn emit_part(
    program: &Program,
    ctx: &mut PartContext,
    original: &[Run],
    smoothed: &[Vec<Piece>],
    (plans, speeds): (&[RunPlan], Vec<Option<Arc<PlannedSpeed>>>),
    opts: &EmitOptions,
    memo: Option<&RenderMemo>,
    out: &mut dyn TextOut,
) -> Result<Emitted> {
    if opts.format == Format::Json {
        return emit_json(program, &ctx.facts, original, smoothed, opts, out);
    }
    let mut em =
        emitter::Emitter::new(program, &ctx.facts, smoothed, plans, opts)?.with_speeds(speeds);
    em.memo = memo;
    let chosen = choose::choose(&em, original)?;
    write::write_chosen(&em, ctx, original, chosen, out)
}

/// The first half of [`emit_part`]: the rendering of each run of
/// `program`, a part of a program whose whole has `facts`, chosen (it
/// needs nothing of the parts before, so it can run while they are
/// written); `None` for JSON, which writes the curves as they are.
pub fn choose_part(
    program: &Program,
    facts: &ProgramFacts,
    original: &[Run],
    smoothed: &[Vec<Piece>],
    plans: &[RunPlan],
    opts: &EmitOptions,
    memo: Option<&RenderMemo>,
) -> Result<Option<Chosen>> {
    if opts.format == Format::Json {
        return Ok(None);
    }
    let mut em = emitter::Emitter::new(program, facts, smoothed, plans, opts)?;
    em.memo = memo;
    choose::choose(&em, original).map(Some)
}

/// The second half of [`emit_part`]: `chosen` ([`choose_part`] of the
/// same part, curves and plans) written from where `ctx` stands to the end
/// of `out`; `(plans, speeds)` as [`emit_part`] takes them.
#[allow(clippy::too_many_arguments)]
pub fn write_chosen_part(
    program: &Program,
    ctx: &mut PartContext,
    original: &[Run],
    smoothed: &[Vec<Piece>],
    (plans, speeds): (&[RunPlan], Vec<Option<Arc<PlannedSpeed>>>),
    opts: &EmitOptions,
    chosen: Option<Chosen>,
    out: &mut dyn TextOut,
) -> Result<Emitted> {
    match chosen {
        None => emit_json(program, &ctx.facts, original, smoothed, opts, out),
        Some(chosen) => {
            let em = emitter::Emitter::new(program, &ctx.facts, smoothed, plans, opts)?
                .with_speeds(speeds);
            write::write_chosen(&em, ctx, original, chosen, out)
        }
    }
}

/// The speed each long run's renderer is shaped by, sampled from its plan
/// in `plans` (on a machine with interpolation period `period` s), the
/// plan's segments then dropped (its time kept): the sampled speed is all
/// the writer needs of them, and a long run's segments would otherwise be
/// held through the whole write (measurements: docs/tuning.md,
/// `take_long_run_speeds`). `None` for the other runs (and
/// for a long run whose plan `auto`'s objective left empty).
pub fn take_long_run_speeds(
    smoothed: &[Vec<Piece>],
    plans: &mut [RunPlan],
    period: f64,
) -> Vec<Option<Arc<PlannedSpeed>>> {
    #[cfg(test)]
    if tests::KEEP_PLANS.with(|k| k.get()) {
        return vec![None; smoothed.len()];
    }
    smoothed
        .iter()
        .zip(plans)
        .map(|(pieces, plan)| {
            (pieces.len() >= LONG_RUN_PIECES && !plan.segments.is_empty()).then(|| {
                #[cfg(test)]
                tests::TAKEN_SPEEDS.with(|n| n.set(n.get() + 1));
                let segments = core::mem::take(&mut plan.segments);
                Arc::new(PlannedSpeed::from_segments(pieces.len(), segments, period))
            })
        })
        .collect()
}

/// [`emit`] in JSON: the curves as they are, read back and verified.
fn emit_json(
    program: &Program,
    facts: &ProgramFacts,
    original: &[Run],
    smoothed: &[Vec<Piece>],
    opts: &EmitOptions,
    out: &mut dyn TextOut,
) -> Result<Emitted> {
    let budget = opts
        .budget_for_blending(&facts.blending)
        .map_err(EmitError::Blend)?;
    let text = crate::write_json(program, smoothed).map_err(EmitError::WriteJson)?;
    let pieces = crate::read_json(&text).map_err(EmitError::ReadJson)?;
    let check = compare_runs(
        original,
        &group_by_source(original, &pieces),
        budget.written(),
    )?;
    out.append(text.as_bytes()).map_err(EmitError::Output)?;
    Ok(Emitted {
        budget,
        lines: text.lines().count(),
        stats: RenderStats::default(),
        check,
        retried_runs: 0,
        g91_spline_runs: 0,
        kept_runs: 0,
        kept: vec![false; original.len()],
        reading: None,
    })
}

/// The arc form of `program`: R when any of its arcs is written with R,
/// IJK otherwise (what the machinist reads, and the safe form near half
/// circles).
pub fn arc_words_of(program: &Program) -> ArcWords {
    let uses_r = program.moves().iter().any(|m| {
        m.kind == crate::MoveKind::Arc && program.line(m.line).words.iter().any(|w| w.letter == 'R')
    });
    if uses_r {
        ArcWords::R
    } else {
        ArcWords::Ijk
    }
}

/// The pieces of `runs` (for the summary's counts).
pub fn pieces_of(runs: &[Run]) -> usize {
    runs.iter().map(|r| r.pieces.len()).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Controller;
    use fairpath::feed::limits::MachineLimits;
    use fairpath::geom::Curve;
    use std::cell::Cell;

    thread_local! {
        /// A run that the first check counts as failed (whatever it
        /// measured): the retry path, which real renderings never take.
        pub(super) static FAIL_FIRST_CHECK: Cell<Option<usize>> = const { Cell::new(None) };
        /// Every run rendered whole and read back whole (the path before
        /// long runs were rendered as they are written).
        pub(super) static NO_STREAMING: Cell<bool> = const { Cell::new(false) };
        /// How many finer steps are tried ([`super::FINER_STEPS`]; 0: none).
        pub(super) static FINER_STEPS_TRIED: Cell<usize> = const { Cell::new(super::FINER_STEPS) };
        /// Runs checked as they were read back, on this thread.
        pub(super) static STREAMED_RUNS: Cell<usize> = const { Cell::new(0) };
        /// Texts read again whole after a reading in parts.
        pub(super) static READ_AGAIN: Cell<usize> = const { Cell::new(0) };
        /// Every run checked as it is read is taken for one whose windows
        /// did not stitch (a run planned as one segment end to end).
        pub(super) static UNSTITCHED: Cell<bool> = const { Cell::new(false) };
        /// Long runs' plans kept whole for the writer (the path before
        /// `take_long_run_speeds`).
        pub(super) static KEEP_PLANS: Cell<bool> = const { Cell::new(false) };
        /// Long runs whose plan `take_long_run_speeds` took, on this thread.
        pub(super) static TAKEN_SPEEDS: Cell<usize> = const { Cell::new(0) };
    }

    /// The passes of [`raster`].
    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Passes {
        /// Over a bumpy surface.
        Bumps,
        /// Wiggling in the XY plane at one height, a period of eight moves:
        /// what `arc-fit` fits with an arc every four.
        Wiggles,
        /// Bumps that also wiggle in Y: corners out of every plane, which
        /// arcs cannot follow.
        Twisted,
    }

    /// A raster of `rows` passes of `per_row` moves (one run, a step-over
    /// between passes), in mm.
    fn raster(rows: usize, per_row: usize, passes: Passes) -> String {
        let mut t = String::from("G21 G90 G17\nG0 X0 Y0 Z5\nG1 Z0 F3000\n");
        let step = if passes == Passes::Wiggles { 0.2 } else { 0.35 };
        for r in 0..rows {
            let y = r as f64 * 3.0;
            for k in 0..=per_row {
                let s = k as f64 * step;
                let x = if r % 2 == 0 {
                    s
                } else {
                    per_row as f64 * step - s
                };
                let bump = (x * 0.3).sin() + 0.01 * ((k * 7 + r) % 5) as f64;
                let (y, z) = match passes {
                    Passes::Bumps => (y, bump + (y * 0.2).cos()),
                    Passes::Wiggles => {
                        let wave = 0.3 * (k as f64 * core::f64::consts::FRAC_PI_4).sin();
                        (y + wave, 0.0)
                    }
                    Passes::Twisted => (y + 0.5 * (x * 0.4).sin(), bump),
                };
                t.push_str(&format!("G1 X{x:.4} Y{y:.4} Z{z:.4}\n"));
            }
        }
        t.push_str("G0 Z5\nM30\n");
        t
    }

    /// A long run is rendered as it is written and checked as it is read
    /// back (never held whole), shaped by the speed sampled from its plan
    /// before the writer starts (the plan then dropped): the same text and
    /// evidence as rendering and reading it whole from the plan kept, for
    /// arcs (G1 their alternative, which plans the run again and, where the
    /// arcs were chosen again against it, is timed and written as it is
    /// rendered) and G1 alone,
    /// blended and block-capped corners, and through a retry (which plans
    /// it again too).
    #[test]
    fn a_long_run_written_as_it_is_rendered_is_the_run_rendered_whole() {
        // 7,200 moves, about 14,000 pieces once smoothed: a long run.
        #[derive(Clone, Copy)]
        struct Case {
            method: &'static str,
            format: Option<Format>,
            controller: Controller,
            /// A run the first check fails.
            fail: Option<usize>,
            override_feed: bool,
            passes: Passes,
        }
        let bumps = |method| Case {
            method,
            format: None,
            controller: Controller::Generic,
            fail: None,
            override_feed: false,
            passes: Passes::Bumps,
        };
        let cases = [
            bumps("bspline-corner"),
            Case {
                format: Some(Format::G1),
                ..bumps("bspline-corner")
            },
            Case {
                controller: Controller::Linuxcnc,
                override_feed: true,
                ..bumps("ctm")
            },
            Case {
                fail: Some(0),
                ..bumps("bspline-corner")
            },
            // Judged by a block-capped planner: also timed as `simulate`
            // plans it, for the written program's time (`arc-fit` merges
            // moves into arcs: 40,000 wiggling moves make 15,000 pieces).
            Case {
                passes: Passes::Wiggles,
                ..bumps("arc-fit")
            },
            // Arcs that fall back to G1 on every block: chosen again
            // against G1, rendered whole.
            Case {
                passes: Passes::Twisted,
                ..bumps("bspline-corner")
            },
            // Windows that do not stitch (made to, below): read again
            // whole.
            bumps("bspline-corner"),
        ];
        for (i, case) in cases.iter().enumerate() {
            let Case {
                method,
                format,
                controller,
                fail,
                override_feed,
                passes,
            } = *case;
            let unstitched = i + 1 == cases.len();
            let mut opts =
                crate::SmoothOptions::new(0.05, None, method, format, controller).unwrap();
            opts.set_machine(MachineLimits::thesis(), override_feed)
                .unwrap();
            let text = match passes {
                Passes::Wiggles => raster(16, 2500, passes),
                _ => raster(24, 300, passes),
            };
            let run = |streaming: bool| {
                NO_STREAMING.with(|n| n.set(!streaming));
                KEEP_PLANS.with(|n| n.set(!streaming));
                TAKEN_SPEEDS.with(|n| n.set(0));
                STREAMED_RUNS.with(|n| n.set(0));
                READ_AGAIN.with(|n| n.set(0));
                UNSTITCHED.with(|n| n.set(unstitched));
                FAIL_FIRST_CHECK.with(|f| f.set(fail));
                let out = crate::smooth_program(&text, &opts).unwrap();
                NO_STREAMING.with(|n| n.set(false));
                KEEP_PLANS.with(|n| n.set(false));
                let again = READ_AGAIN.with(|n| n.get());
                UNSTITCHED.with(|n| n.set(false));
                let speeds = TAKEN_SPEEDS.with(|n| n.get());
                (out, STREAMED_RUNS.with(|n| n.get()), again, speeds)
            };
            let ((whole, whole_report), none, _, kept_plans) = run(false);
            let ((streamed, report), taken, again, speeds) = run(true);
            let what = format!("{method} {format:?} {controller:?} {fail:?} {passes:?}");
            assert_eq!(none, 0, "{what}");
            assert_eq!((kept_plans, speeds), (0, 1), "{what}: plans taken");
            // (Twisted: the arcs chosen again against G1, which is timed
            // as it is rendered and then written so.)
            let whole_read = unstitched;
            assert_eq!(
                taken == 0,
                whole_read,
                "{what}: {taken} runs checked as read"
            );
            assert_eq!(again > 0, unstitched, "{what}: read again {again}");
            let rechosen = passes == Passes::Twisted;
            if rechosen {
                assert_eq!(report.stats.arcs, 0, "{what}");
            }
            assert!(whole.text == streamed.text, "{what}: the texts differ");
            assert_eq!(report.times, whole_report.times, "{what}");
            assert_eq!(report.written, whole_report.written, "{what}");
            assert_eq!(report.stats, whole_report.stats, "{what}");
            assert_eq!(report.kept, whole_report.kept, "{what}");
            assert_eq!(report.retried_runs, whole_report.retried_runs, "{what}");
            assert_eq!(report.retried_runs, usize::from(fail.is_some()), "{what}");
        }
    }

    /// A part written again replaces its text where it was written: in
    /// parts to a file, a first part whose first check fails (its run
    /// rendered again finer) and a second part, the file holds the text
    /// the whole job writes with the same retry, not the first try's too
    /// (which would come before it).
    #[test]
    fn a_part_written_again_to_a_file_replaces_its_text_there() {
        use crate::text_out::TextOut;
        use std::io::Read;
        let (text, opts) = two_zigzags();
        FAIL_FIRST_CHECK.with(|f| f.set(Some(0)));
        let (whole, report) = crate::smooth_program(text, &opts).unwrap();
        assert_eq!(report.retried_runs, 1);
        let mut file = tempfile::tempfile().unwrap();
        let prepared = crate::Prepared::read(text.as_bytes(), opts.format()).unwrap();
        FAIL_FIRST_CHECK.with(|f| f.set(Some(0)));
        let (evidence, _) = crate::smooth_in_parts(
            text.as_bytes(),
            prepared,
            &opts,
            crate::PartSizes::of(1),
            &mut file,
            crate::pipeline::Phases::new(),
        )
        .unwrap();
        assert_eq!(FAIL_FIRST_CHECK.with(|f| f.get()), None, "the check failed");
        let mut written = String::new();
        file.read_from(0)
            .unwrap()
            .read_to_string(&mut written)
            .unwrap();
        assert_eq!(written, whole.text);
        assert_eq!(evidence.lines_out, whole.text.lines().count());
    }

    /// Two runs (a rapid between them), each a zigzag of sharp corners,
    /// and `bspline-corner` at 0.05 mm.
    fn two_zigzags() -> (&'static str, crate::SmoothOptions) {
        let text = "G21 G90\nG0 X0 Y0\nG1 X10 F3000\nG1 X10 Y10\nG1 X20 Y10\nG1 X20 Y0\n\
                    G0 X0 Y20\nG1 X10 Y20\nG1 X10 Y30\nG1 X20 Y30\nG1 X20 Y20\nM30\n";
        let opts = crate::SmoothOptions::new(
            0.05,
            None,
            "bspline-corner",
            None,
            crate::Controller::Generic,
        )
        .unwrap();
        (text, opts)
    }

    /// A chirp (a sine of amplitude `amp` mm whose frequency grows as
    /// `growth t` along the run), sampled every 0.5 mm at `feed` mm/min:
    /// its fit's curvature changes faster and faster, and its arcs at the
    /// default step share slow the machine at their joints where the
    /// finer share's do not.
    fn chirp(amp: f64, growth: f64, feed: f64) -> String {
        let mut text = String::from("G21 G90\nG0 X0 Y0\n");
        for i in 1..=120 {
            let t = 3.0 * i as f64 / 120.0;
            let (x, y) = (20.0 * t, amp * (growth * t * t).sin());
            let feed = if i == 1 {
                format!(" F{feed}")
            } else {
                String::new()
            };
            text.push_str(&format!("G1 X{x:.4} Y{y:.4}{feed}\n"));
        }
        text.push_str("M30\n");
        text
    }

    /// `text` smoothed by `opts` with the finer step tried or not.
    fn with_finer(
        text: &str,
        opts: &crate::SmoothOptions,
        finer: bool,
    ) -> (crate::Output, crate::Report) {
        with_finer_steps(text, opts, if finer { super::FINER_STEPS } else { 0 })
    }

    /// `text` smoothed by `opts` with `steps` finer steps tried.
    fn with_finer_steps(
        text: &str,
        opts: &crate::SmoothOptions,
        steps: usize,
    ) -> (crate::Output, crate::Report) {
        FINER_STEPS_TRIED.with(|n| n.set(steps));
        let out = crate::smooth_program(text, opts);
        FINER_STEPS_TRIED.with(|n| n.set(super::FINER_STEPS));
        out.unwrap()
    }

    /// Arcs are also rendered at the finer step share and kept where that
    /// plans faster: faster on the chirp, more blocks, within the
    /// tolerance as read back; where it is no faster (a zigzag's corner
    /// transitions) the program is written as before.
    #[test]
    fn arcs_at_the_finer_step_are_kept_where_they_plan_faster() {
        let text = chirp(8.0, 2.0, 6000.0);
        let opts = crate::SmoothOptions::new(0.05, None, "bspline-fit", None, Controller::Generic)
            .unwrap();
        let (plain, plain_report) = with_finer(&text, &opts, false);
        let (finer, report) = with_finer(&text, &opts, true);
        assert!(report.written.within && plain_report.written.within);
        let (t_plain, t_finer) = (plain_report.times.written.total, report.times.written.total);
        assert!(t_finer < 0.99 * t_plain, "{t_finer} s against {t_plain} s");
        assert!(finer.text.lines().count() > plain.text.lines().count());
        let (text, opts) = two_zigzags();
        assert_eq!(
            with_finer(text, &opts, true).0.text,
            with_finer(text, &opts, false).0.text
        );
    }

    /// A second finer step is kept where it gains again: `auto` on a
    /// chirp of amplitude 8, growth 2 at F12000 writes faster with two
    /// halvings of the step share than with one (by 2% when measured,
    /// docs/tuning.md, `FINER_STEPS`), in more blocks, within the
    /// tolerance as read back.
    #[test]
    fn a_second_finer_step_is_kept_where_it_gains_again() {
        let text = chirp(8.0, 2.0, 12000.0);
        let opts =
            crate::SmoothOptions::new(0.05, None, "auto", None, Controller::Generic).unwrap();
        let (one, one_report) = with_finer_steps(&text, &opts, 1);
        let (two, report) = with_finer_steps(&text, &opts, 2);
        assert!(report.written.within && one_report.written.within);
        let (t_one, t_two) = (one_report.times.written.total, report.times.written.total);
        assert!(t_two < 0.99 * t_one, "{t_two} s against {t_one} s");
        assert!(two.text.lines().count() > one.text.lines().count());
    }

    /// The finer step never makes a program slower: on chirps of two
    /// amplitudes, two growths and two feeds, by three methods, written as
    /// arcs and as G1, the written time with it is at most the time
    /// without, up to the rounding of the written coordinates, which the
    /// choice, made on the renderings, does not see (it asks them for
    /// [`KEEP_MARGIN`] for it).
    #[test]
    fn the_finer_step_is_never_slower() {
        let methods = ["bspline-fit", "bspline-corner", "fair"];
        for (method, format) in methods
            .into_iter()
            .flat_map(|m| [None, Some(crate::Format::G1)].map(|f| (m, f)))
        {
            let opts =
                crate::SmoothOptions::new(0.05, None, method, format, Controller::Generic).unwrap();
            for (amp, growth, feed) in [2.0, 8.0]
                .into_iter()
                .flat_map(|a| [1.0, 2.0].map(|g| (a, g)))
                .flat_map(|(a, g)| [3000.0, 12000.0].map(|f| (a, g, f)))
            {
                let text = chirp(amp, growth, feed);
                let t = |finer| with_finer(&text, &opts, finer).1.times.written.total;
                let (t_plain, t_finer) = (t(false), t(true));
                assert!(
                    t_finer <= t_plain * (1.0 + KEEP_MARGIN),
                    "{method} {format:?} amp {amp} growth {growth} F{feed}: {t_finer} s against {t_plain} s"
                );
            }
        }
    }

    // The lines of a micrometre or two that `bspline-corner` leaves
    // between transitions on a chirp hold no sample of the plan; taken as
    // passed at rest, they were written with the run's 7 decimals, whose
    // rounding turned their direction by some 40 urad, and the joints next
    // to them were planned as corners (read back 0.8% slower than the
    // rendering as judged). Passed at their neighbours' speed, they get the
    // decimals of a piece shorter than a few periods of travel.
    #[test]
    fn regression_chirp_micrometre_lines_are_written_finely() {
        let text = chirp(8.0, 1.0, 3000.0);
        let opts =
            crate::SmoothOptions::new(0.05, None, "bspline-corner", None, Controller::Generic)
                .unwrap();
        let (out, report) = crate::smooth_program(&text, &opts).unwrap();
        assert!(report.written.within);
        let written = crate::parse(out.text.as_bytes()).unwrap();
        let lines: Vec<&str> = out.text.lines().collect();
        let mut tiny = 0;
        for run in written.runs() {
            for p in &run.pieces {
                let (Curve::Line(l), (a, b)) = (&p.curve, p.source_lines) else {
                    continue;
                };
                if a != b || l.length() >= 3e-3 {
                    continue;
                }
                tiny += 1;
                let text = lines[a - 1];
                for word in text
                    .split_whitespace()
                    .filter(|w| w.starts_with(['X', 'Y']))
                {
                    let decimals = word.split('.').nth(1).map_or(0, str::len);
                    assert!(decimals >= 10, "line {a}: {text}");
                }
            }
        }
        assert!(tiny > 0, "no line shorter than 3 um to look at");
    }

    #[test]
    fn a_retry_renders_the_failed_run_finer_and_every_other_run_again() {
        let (text, opts) = two_zigzags();
        let (plain, plain_report) = crate::smooth_program(text, &opts).unwrap();
        assert_eq!(plain_report.retried_runs, 0);
        FAIL_FIRST_CHECK.with(|f| f.set(Some(0)));
        let (retried, report) = crate::smooth_program(text, &opts).unwrap();
        assert_eq!(report.retried_runs, 1);
        assert!(report.written.within);
        // The second run's text (from the second rapid on) is written again
        // from its rendering again, the same; the first is finer.
        let second = |t: &str| t[t.find("G0 X0 Y20").unwrap()..].to_string();
        assert_eq!(second(&retried.text), second(&plain.text));
        let first = |t: &str| t[..t.find("G0 X0 Y20").unwrap()].lines().count();
        assert!(first(&retried.text) >= first(&plain.text));
    }

    fn options(controller: Controller, format: Format) -> EmitOptions {
        let total = 0.05;
        let output = fairpath::budget::OUTPUT_SHARE * total;
        let blend = EmitOptions::blend_share(controller, format, output);
        EmitOptions {
            format,
            controller,
            budget: ToleranceBudget::new(total, Some(output - blend), blend).unwrap(),
            machine: MachineLimits::thesis(),
            step_share: fairpath::render::arcs::STEP_SHARE,
            override_feed: false,
            judged_by: fairpath::feed::plan::Corners::Blended,
            keeps_every_run: false,
        }
    }

    fn program(head: &str) -> Program {
        let text = format!("G20 G90 {head}\nG0 X0 Y0\nG1 X1 F10\nG1 X2 Y1\nM30\n");
        crate::parse(text.as_bytes()).unwrap()
    }

    #[test]
    fn a_program_whose_g64_blends_beyond_the_share_gets_one_for_every_controller() {
        // tolerance_parabolic_check.ngc's G64 P0.02 Q0.0 (inch).
        let p = program("G64 P0.02 Q0.0");
        for controller in [Controller::Generic, Controller::Fanuc] {
            for format in [Format::Arcs, Format::G1, Format::G6_2] {
                let o = options(controller, format);
                let b = o.budget_for(&p).unwrap();
                let want = EmitOptions::blend_share(Controller::Linuxcnc, format, o.budget.output);
                assert_eq!(b.blend, want);
                assert!(b.blend > 0.0);
                assert_eq!(b.smoothing(), o.budget.smoothing());
                assert!((b.output + b.blend - o.budget.output).abs() < 1e-15);
                assert_eq!(
                    write_options(&EmitOptions { budget: b, ..o }, 0).g64_blend_mm,
                    Some(b.blend)
                );
            }
        }
        // JSON has no blending; LinuxCNC has its share already.
        for (c, f) in [
            (Controller::Generic, Format::Json),
            (Controller::Linuxcnc, Format::Arcs),
        ] {
            let o = options(c, f);
            assert_eq!(o.budget_for(&p).unwrap(), o.budget);
        }
    }

    #[test]
    fn a_program_without_a_looser_g64_keeps_the_budget() {
        let o = options(Controller::Generic, Format::Arcs);
        for head in ["", "G61", "G64 P0.00001"] {
            assert_eq!(o.budget_for(&program(head)).unwrap(), o.budget, "{head}");
        }
        for head in ["G64", "G64 P0"] {
            assert!(o.budget_for(&program(head)).unwrap().blend > 0.0, "{head}");
        }
    }
}
