//! The job on a program a part at a time, writing as it goes: memory
//! grows with the largest part (at least [`PART_LINES`] lines, cut where
//! nothing but the interpreter's state carries across, before a rapid:
//! [`PartReader`]), not with the file. Each part is smoothed, planned,
//! written, read back and checked as [`super::smooth_parsed`] does the
//! whole program, from the state the parts before it leave (the written
//! text's reading, the writer's state, the running sums of the times), and
//! with what the writer needs of the whole program read first
//! ([`crate::interp::read_facts`]): the text written is the one
//! [`super::smooth_parsed`] writes, and the times and figures are the
//! same to the bit.

use super::{write_curves_part, Curves, Evidence, SmoothProgramError};
use crate::emit::PartContext;
use crate::interp::{PartReader, RunWindows};
use crate::pipeline::{
    plan_input_and_curves_carried, smooth_curves_memo, Phases, PlanError, RenderMemo, RunCarry,
    TimeSums,
};
use crate::text_out::TextOut;
use crate::{Format, GcodeError, ParseOptions, Program, ProgramFacts, SmoothOptions, Units};
use std::sync::Arc;

/// Lines a part holds at least. Each part's runs are smoothed, verified
/// and planned on all cores, so a part must hold enough runs to keep them
/// busy between its steps; what a part holds while it is written and
/// checked (its curves, renderings and written text) is many times its
/// input, so it must stay a small share of a long program. 256: smaller
/// parts hold less at once (most where G1 renderings hold many short
/// moves, as `auto`'s on `LHchips4.ngc`), for a little more time
/// (measurements: docs/tuning.md, `PART_LINES`).
pub const PART_LINES: usize = 256;

/// How a program is cut into parts for [`smooth_in_parts`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PartSizes {
    /// Lines a part holds at least ([`PART_LINES`]).
    pub lines: usize,
    /// Long runs cut into windows too ([`PartReader::windowed`]), or not.
    pub windows: Option<RunWindows>,
}

impl PartSizes {
    /// Parts of at least `lines` lines, runs not cut.
    pub fn of(lines: usize) -> PartSizes {
        PartSizes {
            lines,
            windows: None,
        }
    }
}

/// How a program is read for the job: a program without o-words in parts
/// (with the facts of the whole, read first as a stream), or whole (a
/// program with o-words is expanded as it is read; JSON output is written
/// as one document).
pub enum Prepared {
    Parts(ProgramFacts),
    Whole(Box<Program>),
}

impl Prepared {
    /// Reads `text` as the job on it in `format` needs: see [`Prepared`].
    pub fn read(text: &[u8], format: Format) -> Result<Prepared, GcodeError> {
        let opts = ParseOptions::default();
        if format != Format::Json {
            if let Some(facts) = crate::interp::read_facts(text, &opts)? {
                return Ok(Prepared::Parts(facts));
            }
        }
        Ok(Prepared::Whole(Box::new(crate::parse_with(text, &opts)?)))
    }

    /// The program's units ([`Program::units`]).
    pub fn units(&self) -> Units {
        match self {
            Prepared::Parts(f) => f.units,
            Prepared::Whole(p) => p.units(),
        }
    }

    /// Whether some feed move is a NURBS ([`ProgramFacts::nurbs`]).
    pub fn holds_nurbs(&self) -> bool {
        match self {
            Prepared::Parts(f) => f.nurbs,
            Prepared::Whole(p) => p.moves().iter().any(crate::facts::is_nurbs_feed),
        }
    }

    /// Lines passed through verbatim ([`Program::passthrough`]).
    pub fn passthrough(&self) -> &[crate::Passthrough] {
        match self {
            Prepared::Parts(f) => &f.passthrough,
            Prepared::Whole(p) => p.passthrough(),
        }
    }
}

/// Why the job on a program in parts wrote no output.
#[derive(Debug, thiserror::Error)]
pub enum PartsError {
    /// Reading, smoothing, planning or writing a part (a written part
    /// that does not verify is [`PartsError::NotVerified`]).
    #[error(transparent)]
    Job(#[from] SmoothProgramError),
    /// The written text of a part, read back, leaves the tolerance or
    /// moves a run end point. The evidence is that of the parts so far,
    /// this one included.
    #[error(
        "the output leaves the tolerance ({deviation:.6} mm > {tolerance} mm) or moves a run \
         endpoint"
    )]
    NotVerified {
        deviation: f64,
        tolerance: f64,
        evidence: Box<Evidence>,
    },
    /// `out` refused the text.
    #[error("writing the output")]
    Write(#[source] std::io::Error),
}

/// The step [`smooth_in_parts`] marks on its clock ([`Phases`]) where a run
/// cut into windows could not be planned a window at a time and the job
/// was done again without windows: its time is the attempt's, lost
/// (printed with `FAIRPATH_TIMING=1`).
pub const WINDOWS_UNSTITCHED: &str = "windows did not stitch: done again";

/// The whole job ([`super::smooth_parsed_with`]) on `text`, read as
/// `prepared` says (whole, or in parts as `sizes` says),
/// its written text given to `out` as it is written (a part's text is read
/// back from there for its check, and cut back there where the part is
/// written again: [`TextOut`]). A program without moves is given to `out`
/// as it is. On an error, what `out` got is not an output (the caller
/// drops it). Returns the evidence and the clock,
/// which marks each step of each part (step names repeat).
///
/// Where a run cut into windows cannot be planned a window at a time
/// ([`crate::pipeline::PlanError::Unstitched`]), the job is done again
/// without windows, from where `out` stood.
pub fn smooth_in_parts(
    text: &[u8],
    prepared: Prepared,
    opts: &SmoothOptions,
    sizes: PartSizes,
    out: &mut dyn TextOut,
    phases: Phases,
) -> Result<(Evidence, Phases), PartsError> {
    let again = match (&prepared, sizes.windows) {
        (Prepared::Parts(facts), Some(_)) => Some((facts.clone(), phases.sibling())),
        _ => None,
    };
    let start = out.written().map_err(PartsError::Write)?;
    let done = in_parts(text, prepared, opts, sizes, out, phases);
    match (done, again) {
        (Err(PartsError::Job(SmoothProgramError::Plan(PlanError::Unstitched { .. }))), Some(a)) => {
            out.cut(start).map_err(PartsError::Write)?;
            let (facts, mut phases) = a;
            // The time of the attempt in windows, lost.
            phases.mark(WINDOWS_UNSTITCHED);
            let whole_runs = PartSizes {
                windows: None,
                ..sizes
            };
            in_parts(text, Prepared::Parts(facts), opts, whole_runs, out, phases)
        }
        (done, _) => done,
    }
}

/// [`smooth_in_parts`], once.
fn in_parts(
    text: &[u8],
    prepared: Prepared,
    opts: &SmoothOptions,
    sizes: PartSizes,
    out: &mut dyn TextOut,
    mut phases: Phases,
) -> Result<(Evidence, Phases), PartsError> {
    let accuracy = opts.tolerance() * super::LENGTH_ACCURACY_SHARE;
    let facts = match prepared {
        Prepared::Whole(program) => {
            if program.is_empty() {
                return unchanged(text, program.lines().len(), opts, out, phases);
            }
            let (output, mut report) = super::smooth_parsed_with(&program, opts, phases)?;
            out.append(output.text.as_bytes())
                .map_err(PartsError::Write)?;
            let phases = core::mem::take(&mut report.phases);
            return Ok((Evidence::of(&report, accuracy), phases));
        }
        Prepared::Parts(facts) => facts,
    };
    if facts.moves == 0 {
        return unchanged(text, facts.lines, opts, out, phases);
    }
    let emit = opts.emit_options();
    let budget = emit
        .budget_for_blending(&facts.blending)
        .map_err(|e| SmoothProgramError::Emit(crate::emit::EmitError::Blend(e)))?;
    let block_capped = opts.method().writes_for_block_capped_planner();
    let mut evidence = Evidence::new(opts.method_name(), budget, block_capped);
    let block_delete = facts.block_delete;
    let total_lines = facts.lines;
    let mut reader = PartReader::new(text, &ParseOptions::default(), sizes.lines, block_delete);
    // (Where the writer writes a blending command around the runs it
    // rewrites, LinuxCNC or a program whose G64 blends beyond the share,
    // it is in force from a cut run's first window, kept or not, to its
    // last: `write_gcode::kept_window_blending`.)
    if let Some(w) = sizes.windows {
        reader = reader.windowed(w);
    }
    let mut ctx = PartContext::new(facts);
    let front_phases = phases.sibling();
    // The front (reading, smoothing, verifying and planning each part, in
    // order, and choosing its renderings) runs ahead of the back (writing,
    // checking and timing it, which goes on from the part before): they
    // keep the cores busy where one part's steps would leave one idle.
    // The front is two steps in two threads, each a part ahead of the
    // next: smoothing, verifying and planning a part (`fronts`), and
    // choosing its renderings (`choosers`), whose plans need the part's
    // and nothing of the next one's. At most five parts are held (one in
    // each thread, one waiting before each of the two later ones).
    let (tx_planned, rx_planned) =
        std::sync::mpsc::sync_channel::<Result<PlannedPart, SmoothProgramError>>(1);
    let (tx, rx) = std::sync::mpsc::sync_channel::<Result<Front, SmoothProgramError>>(1);
    let facts = ctx.facts.clone();
    let chooser_phases = phases.sibling();
    std::thread::scope(|s| {
        let facts = &facts;
        let front = s.spawn(move || fronts(reader, facts, opts, front_phases, tx_planned));
        let chooser = s.spawn(move || choosers(facts, opts, chooser_phases, rx_planned, tx));
        let mut written = TimeSums::default();
        let mut back = Ok(());
        for front in rx {
            let Front {
                part,
                curves,
                chosen,
            } = match front {
                Ok(f) => f,
                Err(e) => {
                    back = Err(e.into());
                    break;
                }
            };
            let mut clock = core::mem::take(&mut phases);
            clock.restart();
            let chosen = Some(chosen);
            let last_line = part.first_number() + part.source_lines() - 1;
            let part_written =
                write_curves_part(&part, curves, chosen, opts, clock, &mut ctx, written, out);
            match part_written {
                Ok((mut report, w)) => {
                    phases = core::mem::take(&mut report.phases);
                    written = w;
                    evidence.add(&report, accuracy);
                    phases.lines_done(last_line, total_lines);
                }
                Err(SmoothProgramError::OutputNotVerified {
                    deviation,
                    tolerance,
                    mut report,
                    ..
                }) => {
                    phases = core::mem::take(&mut report.phases);
                    evidence.add(&report, accuracy);
                    back = Err(PartsError::NotVerified {
                        deviation,
                        tolerance,
                        evidence: Box::new(evidence.clone()),
                    });
                    break;
                }
                Err(e) => {
                    back = Err(e.into());
                    break;
                }
            }
        }
        // On an error the channel is dropped: the front stops at its next
        // part.
        let chooser_phases = chooser
            .join()
            .expect("the choice of renderings does not panic");
        let front_phases = front.join().expect("the front does not panic");
        back?;
        let mut all = front_phases;
        all.merge(chooser_phases);
        all.merge(phases);
        Ok((evidence, all))
    })
}

/// A part smoothed, verified and planned: what its renderings are chosen
/// for.
struct PlannedPart {
    part: Program,
    curves: Curves,
}

/// A part smoothed, verified and planned, and its renderings chosen: what
/// the back writes.
struct Front {
    part: Program,
    curves: Curves,
    chosen: Option<crate::emit::Chosen>,
}

/// The first step of the front of [`smooth_in_parts`]: each part of
/// `reader` smoothed, verified and planned (the input's and the curves'
/// times going on from the parts before), sent in order until the reader
/// ends, a step fails (the error is sent) or the next step stops
/// listening. Returns its clock.
fn fronts(
    mut reader: PartReader<'_>,
    facts: &ProgramFacts,
    opts: &SmoothOptions,
    mut phases: Phases,
    tx: std::sync::mpsc::SyncSender<Result<PlannedPart, SmoothProgramError>>,
) -> Phases {
    let (mut input, mut exact) = <(TimeSums, TimeSums)>::default();
    let mut carry = RunCarry::default();
    loop {
        phases.restart();
        let front = (|| -> Result<Option<PlannedPart>, SmoothProgramError> {
            let Some(part) = reader.next_part()? else {
                return Ok(None);
            };
            phases.mark("read part");
            let memo = opts
                .smooths_for_format()
                .then(|| Arc::new(RenderMemo::default()));
            let result = smooth_curves_memo(&part, facts, opts, &mut phases, memo.clone())?;
            let sums = (input, exact);
            let (i, e, plans) = plan_input_and_curves_carried(
                &part,
                &result,
                opts,
                sums,
                memo.as_deref(),
                &mut carry,
            )?;
            phases.mark("plan input and curves");
            (input, exact) = (i, e);
            let curves = Curves {
                result,
                input: i.times(),
                exact: e.times(),
                plans,
                memo,
            };
            Ok(Some(PlannedPart { part, curves }))
        })();
        let stop = !matches!(front, Ok(Some(_)));
        let sent = match front {
            Ok(None) => true,
            Ok(Some(f)) => tx.send(Ok(f)).is_ok(),
            Err(e) => tx.send(Err(e)).is_ok(),
        };
        if stop || !sent {
            return phases;
        }
    }
}

/// The second step of the front of [`smooth_in_parts`]: the renderings of
/// each part `rx` gives chosen, sent in order until `rx` ends, a step
/// fails (the error is sent) or the back stops listening. Returns its
/// clock.
fn choosers(
    facts: &ProgramFacts,
    opts: &SmoothOptions,
    mut phases: Phases,
    rx: std::sync::mpsc::Receiver<Result<PlannedPart, SmoothProgramError>>,
    tx: std::sync::mpsc::SyncSender<Result<Front, SmoothProgramError>>,
) -> Phases {
    for planned in rx {
        phases.restart();
        let front = planned.and_then(|PlannedPart { part, mut curves }| {
            let chosen = super::choose_renderings(&part, facts, &mut curves, opts)?;
            // The renderings not chosen are not needed any more.
            curves.memo = None;
            phases.mark("render");
            Ok(Front {
                part,
                curves,
                chosen,
            })
        });
        let stop = front.is_err();
        if tx.send(front).is_err() || stop {
            break;
        }
    }
    phases
}

/// A program without moves: given to `out` as it is (nothing to smooth).
fn unchanged(
    text: &[u8],
    lines: usize,
    opts: &SmoothOptions,
    out: &mut dyn TextOut,
    phases: Phases,
) -> Result<(Evidence, Phases), PartsError> {
    out.append(text).map_err(PartsError::Write)?;
    let block_capped = opts.method().writes_for_block_capped_planner();
    let mut e = Evidence::new(opts.method_name(), opts.budget(), block_capped);
    e.lines_in = lines;
    e.lines_out = lines;
    Ok((e, phases))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::plans::UNSTITCH_WRITTEN;
    use crate::{Controller, Format};

    /// Where a run cut into windows cannot be planned a window at a time,
    /// the job is done again without windows: the text and the evidence
    /// are those of the job without windows.
    #[test]
    fn a_job_whose_windows_do_not_stitch_is_done_without_them() {
        let mut text = String::from("G21 G90\nG0 X0 Y0\nG1 Z0 F3000\n");
        for i in 1..=300 {
            let y = if i % 2 == 0 { 0.0 } else { 0.4 };
            text += &format!("X{}.5 Y{y:.1}\n", 2 * i);
        }
        text += "G0 Z5\nM2\n";
        let opts = SmoothOptions::new(0.05, None, "bspline-corner", Some(Format::Arcs), {
            Controller::Generic
        })
        .unwrap();
        let job = |windows: Option<RunWindows>, unstitch: bool| {
            UNSTITCH_WRITTEN.with(|u| u.set(unstitch));
            let prepared = Prepared::read(text.as_bytes(), opts.format()).unwrap();
            let sizes = PartSizes { lines: 1, windows };
            let mut out = b"(before)\n".to_vec();
            let (e, _) = smooth_in_parts(
                text.as_bytes(),
                prepared,
                &opts,
                sizes,
                &mut out,
                Phases::new(),
            )
            .unwrap();
            UNSTITCH_WRITTEN.with(|u| u.set(false));
            (out, e)
        };
        let w = RunWindows {
            lines: 50,
            min_cut_mm: 1.0,
        };
        let (plain, plain_e) = job(None, false);
        let (windowed, _) = job(Some(w), false);
        assert_ne!(windowed, plain, "the windows cut the run");
        let (again, again_e) = job(Some(w), true);
        assert_eq!(again, plain);
        assert_eq!(again_e, plain_e);
    }
}
