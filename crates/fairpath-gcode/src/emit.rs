//! From smoothed curves to the written program: each run rendered as the
//! output format can say it (shaped by the plan of the exact curves, so
//! that the controller keeps their speed), written in the controller's
//! dialect, read back, verified against the original and timed. Runs whose
//! written text fails are rendered again with half the chord share, a few
//! times, then kept as the program wrote them; so are runs that read back
//! slower than the program's own.

pub use crate::pipeline::written::{
    forms, render_options, resolution, write_options, FANUC_MAX_DEGREE, MIN_ARC_RADIUS_MM,
    MIN_ARC_UNITS, MIN_BLOCK_PERIODS, PLANAR_MM,
};
use crate::pipeline::{
    compare_runs, group_by_source, pair_runs, RunCountMismatch, WrittenCheck, WrittenReading,
};
pub use crate::pipeline::{EmitOptions, CURVE_BLEND_SHARE, G1_BLEND_SHARE};
use crate::{ArcWords, Format, GcodeError, JsonError, Program, RunOutput, WriteError};
use fairpath::budget::{BudgetError, ToleranceBudget};
use fairpath::feed::plan::{plan_time_shaped, Corners, PlanOptions, RunPlan};
use fairpath::feed::shaping::Shaping;
use fairpath::feed::FeedError;
use fairpath::path::{Piece, Run};
use fairpath::pipeline::par_map;
use fairpath::render::{
    absorb_lines, linuxcnc_g5_2_motion, render_range, render_run, CurveForm, PlannedSpeed,
    RenderError, RenderStats, Rendered,
};

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
}

type Result<T, E = EmitError> = core::result::Result<T, E>;

/// Runs of at least this many pieces are planned at both feeds side by
/// side (shorter ones run side by side with other runs).
const PARALLEL_FEEDS_PIECES: usize = 10_000;

/// A run of at least this many curves is long: its only candidate
/// rendering is not planned before it is written (the written text is), and
/// the all-G1 candidate is not tried where the arcs fell back to lines on
/// fewer than [`LINES_CANDIDATE_SHARE`] of their blocks. Each plan of such a
/// run costs seconds (`docs/scale.md`).
const LONG_RUN_PIECES: usize = PARALLEL_FEEDS_PIECES;

/// Share of a long run's arc rendering that fell back to G1 below which
/// the all-G1 rendering is not tried: where arcs follow nearly all of a
/// long run, G1 throughout plans slower (on the reference programs it won
/// on 24 of 300 runs under 1,000 curves and on none of the 6 longer ones,
/// `docs/tuning.md`).
const LINES_CANDIDATE_SHARE: f64 = 0.1;

/// Pieces per part when a long run is rendered in parts side by side.
const RENDER_PART_PIECES: usize = 4096;

/// Parts rendered side by side before they are joined: enough to keep
/// the cores busy, few enough that the parts waiting to be joined hold
/// little beside the joined rendering.
const RENDER_GROUP_PARTS: usize = 8;

/// Times a failing run is rendered again with half the chord.
pub const RETRIES: usize = 3;

/// A run is rewritten only if its rendering plans at least this much
/// faster than the run as the program wrote it (rounding of the written
/// coordinates can cost a few parts in ten thousand).
pub const KEEP_MARGIN: f64 = 1e-3;

/// The written program.
#[derive(Clone, Debug)]
pub struct Emitted {
    pub text: String,
    /// The budget the text was written with ([`EmitOptions::budget_for`]:
    /// a blending share where the program's own G64 needs one).
    pub budget: ToleranceBudget,
    pub stats: RenderStats,
    /// The verdict on the text read back.
    pub check: WrittenCheck,
    /// Runs rendered again with a finer chord.
    pub retried_runs: usize,
    /// Runs kept as the program wrote them: their rendering planned no
    /// faster (or did not verify).
    pub kept_runs: usize,
    /// The written G-code as read back for the check (`None` for JSON),
    /// for planning it without reading it again
    /// ([`crate::pipeline::plan_written`]).
    pub reading: Option<WrittenReading>,
}

/// What is written for one run.
#[derive(Clone, Debug)]
struct Choice {
    /// The form rendered, or `None`: the original lines.
    form: Option<CurveForm>,
    chord: f64,
    /// The rendered pieces; emptied once written (the text holds them),
    /// rendered again from `form` and `chord` if the text is written again.
    pieces: Vec<Piece>,
    stats: RenderStats,
}

impl Choice {
    /// The run as the program wrote it.
    fn original(chord: f64) -> Choice {
        Choice {
            form: None,
            chord,
            pieces: Vec::new(),
            stats: RenderStats::default(),
        }
    }
}

/// Renders, writes and verifies. `smoothed` and `plans` are per run of
/// `program` (the plan of exactly those pieces on `opts.machine` at its
/// maximum feed). Each run is written in the form that plans fastest among
/// those the format allows (arcs or, for curves arcs cannot follow, G1),
/// or as the program wrote it when none is faster, both at the machine's
/// maximum feed and at the programmed feeds. `original` is
/// `program.runs()` (lent by the caller, which holds it already).
pub fn emit(
    program: &Program,
    original: &[Run],
    smoothed: &[Vec<Piece>],
    plans: &[RunPlan],
    opts: &EmitOptions,
) -> Result<Emitted> {
    let opts = &EmitOptions {
        budget: opts.budget_for(program).map_err(EmitError::Blend)?,
        ..*opts
    };
    let tolerance = opts.budget.written();
    if opts.format == Format::Json {
        let text = crate::write_json(program, smoothed).map_err(EmitError::WriteJson)?;
        let pieces = crate::read_json(&text).map_err(EmitError::ReadJson)?;
        let check = compare_runs(original, &group_by_source(original, &pieces), tolerance)?;
        return Ok(Emitted {
            budget: opts.budget,
            text,
            stats: RenderStats::default(),
            check,
            retried_runs: 0,
            kept_runs: 0,
            reading: None,
        });
    }
    let forms = forms(opts.format, opts.controller);
    let mut wo = write_options(opts);
    wo.arcs = wo.arcs.map(|_| arc_words_of(program));
    let render = |k: usize, form: CurveForm, chord: f64| -> Result<Choice> {
        let units = program.run_spans()[k].units;
        let ro = render_options(opts, form, chord, units, &wo);
        let speed = PlannedSpeed::new(smoothed[k].len(), &plans[k], opts.machine.period);
        let pieces = &smoothed[k];
        let error = |source| EmitError::Render { run: k, source };
        if pieces.len() < PARALLEL_FEEDS_PIECES {
            let r = render_run(pieces, &speed, &ro).map_err(error)?;
            return Ok(Choice {
                form: Some(form),
                chord,
                pieces: r.pieces,
                stats: r.stats,
            });
        }
        // A long run in parts side by side (each piece is rendered on its
        // own: the same pieces as one call), a group of parts at a time,
        // so that the rendered parts waiting to be joined stay few.
        let parts = pieces.len().div_ceil(RENDER_PART_PIECES);
        let mut choice = Choice::original(chord);
        choice.form = Some(form);
        for group in (0..parts).step_by(RENDER_GROUP_PARTS) {
            let in_group = RENDER_GROUP_PARTS.min(parts - group);
            let rendered = par_map(in_group, |i| {
                let j = group + i;
                let end = ((j + 1) * RENDER_PART_PIECES).min(pieces.len());
                render_range(pieces, j * RENDER_PART_PIECES..end, &speed, &ro)
            });
            for r in rendered {
                let r = r.map_err(error)?;
                choice.pieces.extend(r.pieces);
                choice.stats.add(&r.stats);
            }
        }
        // The parts joined: their short lines merged as render_run merges
        // a whole run's.
        let mut joined = Rendered {
            pieces: core::mem::take(&mut choice.pieces),
            stats: choice.stats,
        };
        absorb_lines(&mut joined, &ro);
        choice.pieces = joined.pieces;
        choice.stats = joined.stats;
        Ok(choice)
    };
    let feeds: Vec<bool> = if opts.override_feed {
        vec![true]
    } else {
        vec![true, false]
    };
    // The planned time of a run's pieces at the maximum feed (`true`) or
    // the programmed ones.
    let time = |pieces: &[Piece], override_feed: bool| -> Result<f64> {
        let po = PlanOptions {
            limits: opts.machine,
            override_feed,
            window: None,
            ends: Default::default(),
        };
        plan_time_shaped(pieces, &po, &Shaping::none(), opts.judged_by).map_err(EmitError::Plan)
    };
    // A rendering's time: its G5.2 blocks as LinuxCNC runs them (as the
    // written text reads back).
    let rendered_time = |c: &Choice, override_feed: bool| -> Result<f64> {
        if opts.format == Format::G5_2 && matches!(c.form, Some(CurveForm::Nurbs(_))) {
            time(&linuxcnc_g5_2_motion(&c.pieces, PLANAR_MM), override_feed)
        } else {
            time(&c.pieces, override_feed)
        }
    };
    // A run smoothed into itself (method `none`) is written as the program
    // wrote it: no rendering could say it more exactly, and its own times
    // are not needed.
    let itself: Vec<bool> = par_map(smoothed.len(), |k| smoothed[k] == original[k].pieces);
    let nf = feeds.len();
    // The planned time of each of the program's own runs, at each feed:
    // side by side by run, each run's feeds one after the other (two plans
    // of one long run at once hold twice the memory for little time).
    let own: Vec<Vec<f64>> = par_map(smoothed.len(), |k| {
        if itself[k] {
            return Ok(vec![f64::INFINITY; nf]);
        }
        feeds
            .iter()
            .map(|&f| time(&original[k].pieces, f))
            .collect::<Result<Vec<f64>>>()
    })
    .into_iter()
    .collect::<Result<_>>()?;
    // A run's times at each feed (`t(feed)`), side by side for a long run.
    let at_feeds = |len: usize, t: &(dyn Fn(bool) -> Result<f64> + Sync)| -> Result<Vec<f64>> {
        if len >= PARALLEL_FEEDS_PIECES && nf > 1 {
            par_map(nf, |i| t(feeds[i])).into_iter().collect()
        } else {
            feeds.iter().map(|&f| t(f)).collect()
        }
    };
    let chosen: Vec<Result<Choice>> = par_map(smoothed.len(), |k| {
        let own = &own[k];
        if itself[k] {
            return Ok(Choice::original(opts.budget.output));
        }
        let mut best: Option<(f64, Choice)> = None;
        // A long run whose arcs fell back to G1 on few blocks.
        let long_with_few_lines = |c: &Choice| {
            smoothed[k].len() >= LONG_RUN_PIECES
                && (c.stats.fallback_lines as f64) < LINES_CANDIDATE_SHARE * c.pieces.len() as f64
        };
        for (i, &form) in forms.iter().enumerate() {
            // G1 is the other candidate for curves that arcs could not
            // follow: where they all became arcs, it is not tried; nor on
            // a long run where few did.
            if i > 0
                && form == CurveForm::Lines
                && best
                    .as_ref()
                    .is_some_and(|(_, b)| b.stats.fallback_lines == 0 || long_with_few_lines(b))
            {
                continue;
            }
            let c = render(k, form, opts.budget.output)?;
            // A long run's only candidate is timed once, as written (the
            // check below plans what reads back at every feed and keeps the
            // run as the program wrote it where that is slower).
            let sole = i + 1 == forms.len() || (form == CurveForm::Arcs && long_with_few_lines(&c));
            if best.is_none() && sole && smoothed[k].len() >= LONG_RUN_PIECES {
                return Ok(c);
            }
            // Where a rendering is already chosen, a candidate that does
            // not beat it at the first feed loses whatever its other
            // times: they are planned only when it does.
            if let Some((b, _)) = &best {
                let t0 = rendered_time(&c, feeds[0])?;
                if t0 >= *b || t0 * (1.0 + KEEP_MARGIN) > own[0] {
                    continue;
                }
            }
            let ts = at_feeds(c.pieces.len(), &|f| rendered_time(&c, f))?;
            // Faster than the program's own run at every feed.
            if ts
                .iter()
                .zip(own)
                .any(|(t, o)| *t * (1.0 + KEEP_MARGIN) > *o)
            {
                continue;
            }
            if best.as_ref().is_none_or(|(b, _)| ts[0] < *b) {
                best = Some((ts[0], c));
            }
        }
        Ok(best.map_or(Choice::original(opts.budget.output), |b| b.1))
    });
    let mut choices: Vec<Choice> = chosen.into_iter().collect::<Result<_>>()?;
    let mut retried = vec![false; choices.len()];
    // Write, read back, verify and time per run until every rewritten run
    // verifies and is faster than the program's own. A run that fails is
    // rendered again with half the chord, up to RETRIES times, then kept
    // as written; one that reads back slower is kept as written at once.
    // Runs kept as written always verify and are never slower, so the text
    // returned is the one written last.
    let mut attempt = 0;
    loop {
        let outputs: Vec<RunOutput> = choices
            .iter()
            .map(|c| match c.form {
                Some(_) => RunOutput::Pieces(&c.pieces),
                None => RunOutput::Original,
            })
            .collect();
        let text =
            crate::write_gcode_with(program, &outputs, &wo).map_err(EmitError::WriteGcode)?;
        // The rendered pieces are in the text now, and on a long run they
        // are among the largest things held: dropped before the text is
        // read back (rendering is deterministic: a retry renders them again).
        drop(outputs);
        for c in &mut choices {
            c.pieces = Vec::new();
        }
        // Read back for what checking and planning it need (its motions
        // and runs' pieces; no lines held: on long outputs the reading is
        // the largest thing held).
        let (reread_outline, reread) =
            crate::read_motion(text.as_bytes()).map_err(EmitError::Reread)?;
        let check = compare_runs(original, &reread, tolerance)?;
        #[allow(unused_mut)]
        let mut failed: Vec<usize> = check.failed_runs.iter().flatten().copied().collect();
        #[cfg(test)]
        if attempt == 0 {
            failed.extend(tests::FAIL_FIRST_CHECK.with(|f| f.take()));
        }
        let mut is_failed = vec![false; choices.len()];
        for &k in &failed {
            is_failed[k] = true;
        }
        let pairs = pair_runs(original, &reread)?;
        // The feed `fairpath simulate` plans the written program at, and
        // whether `time` plans as it does there (then its time is kept for
        // the written program's plan).
        let user_feed = feeds.iter().position(|&f| f == opts.override_feed);
        let as_simulate = opts.judged_by == Corners::Blended;
        // (the run is slower than the program's own, its time at the
        // user's feed).
        type Judged = (Option<usize>, Option<f64>);
        let judged: Vec<Judged> = par_map(pairs.len(), |i| -> Result<Judged> {
            let (o, c) = pairs[i];
            if choices[o].form.is_none() || is_failed[o] {
                return Ok((None, None));
            }
            let pieces = &reread[c].pieces;
            let kept = |ts: &[f64]| {
                user_feed
                    .filter(|_| as_simulate)
                    .and_then(|u| ts.get(u).copied())
            };
            if pieces.len() >= PARALLEL_FEEDS_PIECES {
                let ts = at_feeds(pieces.len(), &|f| time(pieces, f))?;
                let slower = ts.iter().zip(&own[o]).any(|(t, w)| t > w);
                return Ok((slower.then_some(o), kept(&ts)));
            }
            let mut ts = Vec::with_capacity(nf);
            for (fi, &f) in feeds.iter().enumerate() {
                ts.push(time(pieces, f)?);
                if ts[fi] > own[o][fi] {
                    return Ok((Some(o), None));
                }
            }
            Ok((None, kept(&ts)))
        })
        .into_iter()
        .collect::<Result<Vec<_>>>()?;
        let slower: Vec<usize> = judged.iter().filter_map(|j| j.0).collect();
        // Nothing left to change, or nothing this loop can change (a run
        // the program wrote itself fails: the caller refuses).
        let stuck = failed.iter().any(|&k| choices[k].form.is_none());
        if (failed.is_empty() && slower.is_empty()) || stuck {
            let mut stats = RenderStats::default();
            for c in &choices {
                stats.add(&c.stats);
            }
            let kept_runs = choices.iter().filter(|c| c.form.is_none()).count();
            let mut run_times = vec![None; reread.len()];
            for (&(_, c), j) in pairs.iter().zip(&judged) {
                run_times[c] = j.1;
            }
            return Ok(Emitted {
                budget: opts.budget,
                text,
                stats,
                check,
                retried_runs: retried.iter().filter(|&&r| r).count(),
                kept_runs,
                reading: Some(WrittenReading {
                    outline: reread_outline,
                    runs: reread,
                    run_times,
                }),
            });
        }
        attempt += 1;
        for o in slower {
            choices[o] = Choice::original(choices[o].chord);
        }
        for k in failed {
            retried[k] = true;
            let (form, chord) = (choices[k].form, choices[k].chord);
            choices[k] = match form {
                Some(form) if attempt < RETRIES => render(k, form, 0.5 * chord)?,
                _ => Choice::original(chord),
            };
        }
        // Every other rewritten run is rendered again for the next text.
        for (k, c) in choices.iter_mut().enumerate() {
            if let (Some(form), true) = (c.form, c.pieces.is_empty()) {
                *c = render(k, form, c.chord)?;
            }
        }
    }
}

/// The arc form of `program`: R when any of its arcs is written with R,
/// IJK otherwise (what the machinist reads, and the safe form near half
/// circles).
pub fn arc_words_of(program: &Program) -> ArcWords {
    let lines = program.lines();
    let uses_r = program.moves().iter().any(|m| {
        m.kind == crate::MoveKind::Arc && lines[m.line - 1].words.iter().any(|w| w.letter == 'R')
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
    use std::cell::Cell;

    thread_local! {
        /// A run that the first check counts as failed (whatever it
        /// measured): the retry path, which real renderings never take.
        pub(super) static FAIL_FIRST_CHECK: Cell<Option<usize>> = const { Cell::new(None) };
    }

    #[test]
    fn a_retry_renders_the_failed_run_finer_and_every_other_run_again() {
        // Two runs (a rapid between them), each a zigzag of sharp corners.
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
                    write_options(&EmitOptions { budget: b, ..o }).g64_blend_mm,
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
