//! The entry point: a program's text in, the written program and the
//! evidence out, or an error ([`smooth_program`], [`smooth_parsed`]); and
//! its two halves, smoothing and planning ([`smooth_and_plan`]) and
//! writing ([`write_curves`]), on the steps of [`crate::pipeline`] and
//! [`crate::emit`].

mod error;
mod evidence;
mod parts;
mod report;

pub use error::SmoothProgramError;
pub use evidence::Evidence;
pub use parts::{smooth_in_parts, PartSizes, PartsError, Prepared, PART_LINES, WINDOWS_UNSTITCHED};
pub use report::Report;

use crate::emit::{
    choose_part, emit_part, take_long_run_speeds, write_chosen_part, Chosen, EmitError, PartContext,
};
use crate::pipeline::{
    plan_input_and_curves_from, plan_text, plan_written_carried, smooth_curves_memo, JobTimes,
    Phases, RenderMemo, SmoothOptions, SmoothResult, TimeSums, Times,
};
use crate::text_out::TextOut;
use crate::{Format, Program};
use fairpath::feed::plan::RunPlan;
use fairpath::path::{Piece, Run};
use std::io::Read;

type Result<T, E = SmoothProgramError> = core::result::Result<T, E>;

/// Lengths in the [`Evidence`] are measured to this share of the
/// tolerance (the verifier's accuracy).
pub const LENGTH_ACCURACY_SHARE: f64 = 1e-4;

/// The smoothed runs of a program and the plans [`write_curves`] needs.
#[derive(Clone, Debug)]
pub struct Curves {
    /// Every run: the original, its curves, the verifier's report.
    pub result: SmoothResult,
    /// The planned time of the input program.
    pub input: Times,
    /// The planned time of the program with the curves in its runs.
    pub exact: Times,
    /// Each smoothed run's plan at the machine's maximum feed, which the
    /// renderer shapes the written pieces by
    /// ([`crate::pipeline::plan_curves`]).
    pub plans: Vec<RunPlan>,
    /// The renderings `auto`'s objective made, for the writer to take the
    /// chosen candidates' ([`RenderMemo`]); `None` where there are none.
    pub memo: Option<std::sync::Arc<RenderMemo>>,
}

/// Smooths and verifies every run ([`crate::pipeline::smooth_curves`]) and plans the input
/// and the curves side by side ([`crate::pipeline::plan_input_and_curves`]).
pub fn smooth_and_plan(
    program: &Program,
    opts: &SmoothOptions,
    phases: &mut Phases,
) -> Result<Curves> {
    let memo = opts
        .smooths_for_format()
        .then(|| std::sync::Arc::new(RenderMemo::default()));
    let facts = crate::ProgramFacts::of(program);
    let result = smooth_curves_memo(program, &facts, opts, phases, memo.clone())?;
    let none = TimeSums::default();
    let (input, exact, plans) =
        plan_input_and_curves_from(program, &result, opts, none, none, memo.as_deref())?;
    let (input, exact) = (input.times(), exact.times());
    phases.mark("plan input and curves");
    Ok(Curves {
        result,
        input,
        exact,
        plans,
        memo,
    })
}

/// The written program.
#[derive(Clone, Debug, PartialEq)]
pub struct Output {
    /// The program's text in `format` (for [`smooth_program`] on a program
    /// without moves: the text as given).
    pub text: String,
    pub format: Format,
}

/// Writes the program with `curves` in its runs in `opts`' format for its
/// controller ([`crate::emit::emit`]: each run in the form that plans fastest, or as
/// the program wrote it), reads the text back, verifies it against the
/// original within [`ToleranceBudget::written`] and plans it. A text that
/// does not verify is [`SmoothProgramError::OutputNotVerified`]. `phases`
/// (the job's clock) gets `render, write, check` and `plan written` and
/// goes into the report.
///
/// [`ToleranceBudget::written`]: fairpath::budget::ToleranceBudget::written
pub fn write_curves(
    program: &Program,
    curves: Curves,
    opts: &SmoothOptions,
    phases: Phases,
) -> Result<(Output, Report)> {
    let mut ctx = PartContext::whole(program);
    let start = TimeSums::default();
    let mut out: Vec<u8> = Vec::new();
    let (report, _) = write_curves_part(
        program, curves, None, opts, phases, &mut ctx, start, &mut out,
    )?;
    let output = Output {
        text: crate::emit::text_of(out)?,
        format: opts.format(),
    };
    Ok((output, report))
}

/// The original and smoothed pieces of every run of `result`, taken out
/// of it to be lent as slices (no copy); [`put_back`] returns them.
fn lend(result: &mut SmoothResult) -> (Vec<Run>, Vec<Vec<Piece>>) {
    result
        .runs
        .iter_mut()
        .map(|r| {
            (
                core::mem::take(&mut r.original),
                core::mem::take(&mut r.smoothed.pieces),
            )
        })
        .unzip()
}

/// Puts what [`lend`] took back into `result`.
fn put_back(result: &mut SmoothResult, original: Vec<Run>, smoothed: Vec<Vec<Piece>>) {
    for ((r, run), pieces) in result.runs.iter_mut().zip(original).zip(smoothed) {
        r.original = run;
        r.smoothed.pieces = pieces;
    }
}

/// The renderings of `program`'s runs (a part of a program whose whole has
/// `facts`) chosen from `curves` ([`crate::emit::choose_part`]): the half
/// of writing that needs nothing of the parts before.
pub(crate) fn choose_renderings(
    program: &Program,
    facts: &crate::ProgramFacts,
    curves: &mut Curves,
    opts: &SmoothOptions,
) -> Result<Option<Chosen>> {
    let (original, smoothed) = lend(&mut curves.result);
    let chosen = choose_part(
        program,
        facts,
        &original,
        &smoothed,
        &curves.plans,
        &opts.emit_options(),
        curves.memo.as_deref(),
    );
    put_back(&mut curves.result, original, smoothed);
    Ok(chosen?)
}

/// [`write_curves`] of `program`, a part of a program (or a whole one),
/// from where `ctx` stands (left standing after it), its text written to
/// the end of `out`, with the written program's times so far,
/// `written_from`; also returns them with the part's added. The report's
/// written times are those sums. A text that does not verify is
/// [`SmoothProgramError::OutputNotVerified`] (what `out` got is then no
/// output).
///
/// `chosen`: the renderings [`choose_renderings`] chose for these curves,
/// or `None` to choose them here.
#[allow(clippy::too_many_arguments)]
pub(crate) fn write_curves_part(
    program: &Program,
    curves: Curves,
    chosen: Option<Option<Chosen>>,
    opts: &SmoothOptions,
    mut phases: Phases,
    ctx: &mut PartContext,
    written_from: TimeSums,
    out: &mut dyn TextOut,
) -> Result<(Report, TimeSums)> {
    // The original and smoothed pieces lent to the writer and put back for the report
    // (no copy), the plans dropped once written.
    let Curves {
        mut result,
        input,
        exact,
        mut plans,
        memo,
    } = curves;
    let (original, smoothed) = lend(&mut result);
    let eo = opts.emit_options();
    let speeds = take_long_run_speeds(&smoothed, &mut plans, eo.machine.period);
    let step = if chosen.is_some() {
        "write, check"
    } else {
        "render, write, check"
    };
    let start = out.written().map_err(EmitError::Output)?;
    let cut_line_held = ctx.carry.cut_line().is_some();
    let emitted = match chosen {
        None => emit_part(
            program,
            ctx,
            &original,
            &smoothed,
            (&plans, speeds),
            &eo,
            memo.as_deref(),
            out,
        ),
        Some(c) => write_chosen_part(
            program,
            ctx,
            &original,
            &smoothed,
            (&plans, speeds),
            &eo,
            c,
            out,
        ),
    };
    drop(plans);
    put_back(&mut result, original, smoothed);
    let mut emitted = emitted?;
    phases.mark(step);
    // From the reading the check made, or the text (JSON).
    // (JSON is written whole: its sums go nowhere.)
    let (written_times, written_sums) = match emitted.reading.take() {
        Some(reading) => {
            // (The cut line held back before is dropped where the run
            // going on is kept here too.)
            let dropped = cut_line_held && emitted.kept.first() == Some(&true);
            let cut = (program.window_cut(), dropped);
            let sums = plan_written_carried(&reading, opts, written_from, &mut ctx.written, cut)?;
            (sums.times(), sums)
        }
        None => (
            plan_text(&json_text(out, start)?, opts)?,
            TimeSums::default(),
        ),
    };
    phases.mark("plan written");
    let report = Report {
        result,
        times: JobTimes {
            input,
            exact,
            written: written_times,
        },
        budget: emitted.budget,
        written: emitted.check,
        stats: emitted.stats,
        retried_runs: emitted.retried_runs,
        g91_spline_runs: emitted.g91_spline_runs,
        kept_runs: emitted.kept_runs,
        kept: emitted.kept,
        method: opts.method_name().to_string(),
        block_capped: opts.method().writes_for_block_capped_planner(),
        lines_in: program.source_lines(),
        lines_out: emitted.lines,
        rapids: program.moves().iter().filter(|m| m.piece.rapid).count(),
        no_moves: program.is_empty(),
        window_ends: (program.window_continued(), program.window_cut()),
        phases,
    };
    if !report.written.within {
        return Err(SmoothProgramError::OutputNotVerified {
            deviation: report.written.max_deviation,
            tolerance: report.budget.written(),
            report: Box::new(report),
        });
    }
    Ok((report, written_sums))
}

/// The JSON text written to `out` from byte `start` on (JSON is written
/// and planned whole).
fn json_text(out: &mut dyn TextOut, start: u64) -> Result<String> {
    let mut text = String::new();
    out.read_from(start)
        .and_then(|mut r| r.read_to_string(&mut text))
        .map_err(EmitError::Output)?;
    Ok(text)
}

/// [`smooth_program`] of a program already read.
pub fn smooth_parsed(program: &Program, opts: &SmoothOptions) -> Result<(Output, Report)> {
    smooth_parsed_with(program, opts, Phases::new())
}

/// [`smooth_parsed`] on the clock `phases` (e.g. [`Phases::observed`], for
/// a progress display): it gets each step as it ends (`smooth`, `verify
/// curves`, `plan input and curves`, `render, write, check`, `plan
/// written`) and goes into the report.
pub fn smooth_parsed_with(
    program: &Program,
    opts: &SmoothOptions,
    mut phases: Phases,
) -> Result<(Output, Report)> {
    let curves = smooth_and_plan(program, opts, &mut phases)?;
    write_curves(program, curves, opts, phases)
}

/// The whole job on a program's text: read it, smooth every run within
/// the smoothing share and verify the curves, plan the input and the
/// curves, write the program in `opts`' format for its controller, read
/// the text back and verify it against the original within
/// [`ToleranceBudget::written`], and plan it. Returns the written text and
/// the evidence; a text that does not verify is an error
/// ([`SmoothProgramError::OutputNotVerified`]), never an output. A program
/// without moves comes back as given.
///
/// [`ToleranceBudget::written`]: fairpath::budget::ToleranceBudget::written
///
/// ```
/// use fairpath_gcode::{smooth_program, Controller, SmoothOptions};
///
/// let program = "G21 G90\nG0 X0 Y0\nG1 X10 F1200\nG1 X10 Y10\nG1 X0 Y10\nM30\n";
/// let opts = SmoothOptions::new(0.05, None, "auto", None, Controller::Generic)?;
/// let (output, report) = smooth_program(program, &opts)?;
/// let t = report.times;
/// println!("planned {:.3} s -> {:.3} s", t.input.total, t.written.total);
/// assert!(report.written.within && report.max_deviation_written() <= 0.05);
/// assert!(output.text.contains("G2") || output.text.contains("G3"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn smooth_program(text: &str, opts: &SmoothOptions) -> Result<(Output, Report)> {
    if text.bytes().all(|b| b.is_ascii_whitespace()) {
        return Err(SmoothProgramError::EmptyProgram);
    }
    let program = crate::parse(text.as_bytes())?;
    let (mut output, mut report) = smooth_parsed(&program, opts)?;
    if report.no_moves {
        output.text = text.to_string();
        report.lines_out = report.lines_in;
    }
    Ok((output, report))
}
