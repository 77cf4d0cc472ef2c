//! `fairpath smooth`: the files around the library's job
//! ([`fairpath_gcode::smooth_parsed`]): read the input, warn about lines
//! passed through, write the output atomically only when it verified, and
//! the summary. Option errors name the command line's flags.

use crate::read::read_bytes;
use crate::summary::Summary;
use crate::usage::usage;
use crate::{Controller, Format};
use anyhow::{anyhow, bail, Result};
use fairpath::pipeline::PipelineError;
use fairpath_gcode::{
    Evidence, OptionsError, PartSizes, PartsError, Prepared, SmoothOptions, SmoothProgramError,
    PART_LINES,
};
use std::path::Path;

/// [`SmoothOptions::new`] with errors naming the flags (`--tolerance`,
/// `--chord`).
pub fn options(
    tolerance: f64,
    chord: Option<f64>,
    method: &str,
    format: Option<Format>,
    controller: Controller,
) -> Result<SmoothOptions> {
    SmoothOptions::new(tolerance, chord, method, format, controller).map_err(option_error)
}

/// An option error in the command line's words: a usage error (exit
/// status 2).
pub fn option_error(e: OptionsError) -> anyhow::Error {
    usage(match e {
        OptionsError::Tolerance(t) => format!(
            "--tolerance: {} (allowed: 1e-6 to 1000 mm)",
            fairpath::smooth::SmoothError::BadTolerance(t)
        ),
        OptionsError::OutputShare { value, half } => format!(
            "--chord must be a positive number of mm, at most half the tolerance ({half} mm); got {value}"
        ),
        OptionsError::Budget { source, .. } => {
            format!("--tolerance: {source}: raise --tolerance or lower --chord")
        }
        OptionsError::NothingLeft {
            tolerance,
            output,
            left,
        } => format!(
            "--tolerance {tolerance} mm leaves {left:e} mm for smoothing after the output \
             ({output} mm) and arc sampling; at least 1e-6 mm is needed: raise \
             --tolerance or lower --chord"
        ),
        OptionsError::StepShare(s) => {
            format!("--step-share must be a positive number or inf; got {s}")
        }
        OptionsError::RunWindows(lines, _) => {
            format!("--window-lines must be a positive number of lines; got {lines}")
        }
        e @ (OptionsError::UnknownMethod(_) | OptionsError::Machine(_)) => e.to_string(),
    })
}

/// The whole `fairpath smooth` job: read `input`, smooth, verify, plan,
/// render, write, verify the written text, plan it (the library's
/// [`fairpath_gcode::smooth_in_parts`]), and write `output` only if it
/// passes (through a temporary file renamed over `output`). Returns the
/// summary; on a verification failure prints it to stderr and returns an
/// error, leaving no output file.
pub fn smooth_file(input: &Path, output: &Path, opts: &SmoothOptions) -> Result<Summary> {
    let started = std::time::Instant::now();
    let bytes = read_bytes(input)?;
    let prepared = prepare(input, &bytes, opts.format())?;
    smooth_prepared(input, &bytes, prepared, started, output, opts, None)
}

/// What the job needs read before it starts ([`Prepared::read`]: the
/// facts of a program processed in parts, or the whole program), with
/// reader errors as `file:line:column` with the line and a caret.
pub fn prepare(input: &Path, bytes: &[u8], format: Format) -> Result<Prepared> {
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        bail!("{}: empty program", crate::read::name(input));
    }
    Prepared::read(bytes, format).map_err(|e| {
        anyhow!(crate::source_error::SourceError::new(
            &crate::read::name(input),
            bytes,
            &e
        ))
    })
}

/// [`smooth_file`] of a program prepared already: `bytes` is the text of
/// `input` (`-`: standard input), `prepared` what was read of it, begun at
/// `started`; `output` `-` writes to standard output. The written text
/// goes to a temporary file part after part and becomes `output` only when
/// every part verified. `progress`, if any, follows the steps and is
/// erased before anything is printed.
pub fn smooth_prepared(
    input: &Path,
    bytes: &[u8],
    prepared: Prepared,
    started: std::time::Instant,
    output: &Path,
    opts: &SmoothOptions,
    mut progress: Option<&mut crate::progress::Progress>,
) -> Result<Summary> {
    use fairpath_gcode::pipeline::Phases;
    let clock = || match &progress {
        Some(p) => Phases::observed_with_lines(p.observer(""), p.lines_observer()),
        None => Phases::new(),
    };
    let mut phases = clock();
    phases.mark("read");
    let job = clock();
    let units = prepared.units();
    warn_passthrough(input, prepared.passthrough());
    let timing = std::env::var_os("FAIRPATH_TIMING").is_some();
    let mut sink = crate::output::OutputSink::create(output)?;
    let sizes = PartSizes {
        lines: PART_LINES,
        windows: opts.run_windows(),
    };
    let done = fairpath_gcode::smooth_in_parts(bytes, prepared, opts, sizes, &mut sink, job);
    if let Some(p) = progress.as_mut() {
        p.finish();
    }
    let summary = |e: &Evidence| {
        let mut summary = Summary::new(input, output, opts, e);
        summary.units = units;
        summary.elapsed = started.elapsed();
        summary
    };
    let (evidence, job) = match done {
        Ok(done) => done,
        Err(e) => {
            drop(sink);
            let refuse = |e: &dyn std::fmt::Display| {
                anyhow!(
                    "refusing to write {}: {e}",
                    crate::summary::output_name(output)
                )
            };
            return Err(match e {
                PartsError::NotVerified { ref evidence, .. } => {
                    if timing {
                        eprint!("{}", phases.report());
                    }
                    eprint!("{}", summary(evidence).text());
                    refuse(&e)
                }
                PartsError::Job(
                    e @ SmoothProgramError::Curves(PipelineError::NotVerified { .. }),
                ) => refuse(&e),
                PartsError::Job(SmoothProgramError::OutputNotVerified { report, .. }) => {
                    // (a program read whole)
                    let accuracy = opts.tolerance() * fairpath_gcode::entry::LENGTH_ACCURACY_SHARE;
                    let evidence = Evidence::of(&report, accuracy);
                    eprint!("{}", summary(&evidence).text());
                    refuse(&format!(
                        "the output leaves the tolerance ({:.6} mm > {} mm) or moves a run \
                         endpoint",
                        report.written.max_deviation,
                        report.budget.written()
                    ))
                }
                e => e.into(),
            });
        }
    };
    sink.commit()?;
    let mut summary = summary(&evidence);
    if timing {
        eprint!("{}{}", phases.report(), job.report());
    }
    if evidence.no_moves {
        // Nothing to smooth (tool changes, coolant ...): the program as it
        // is, byte for byte.
        eprintln!(
            "note: {}: the program has no moves: copied unchanged",
            crate::read::name(input)
        );
        summary.e.lines_out = summary.e.lines_in;
    }
    summary.elapsed = started.elapsed();
    Ok(summary)
}

/// Most ranges of passed-through lines [`warn_passthrough`] lists.
const PASSTHROUGH_LISTED: usize = 8;

/// Warns on stderr about the lines passed through verbatim (canned cycles,
/// other dialects' words): they are run as written, not smoothed.
fn warn_passthrough(input: &Path, notes: &[fairpath_gcode::Passthrough]) {
    if notes.is_empty() {
        return;
    }
    let listed: Vec<String> = notes
        .iter()
        .take(PASSTHROUGH_LISTED)
        .map(|n| {
            let (a, b) = (*n.lines.start(), *n.lines.end());
            let lines = if a == b {
                format!("line {a}")
            } else {
                format!("lines {a}-{b}")
            };
            format!("{lines} ({})", n.what)
        })
        .collect();
    let more = notes.len().saturating_sub(PASSTHROUGH_LISTED);
    eprintln!(
        "warning: {}: passed through verbatim, not smoothed: {}{}",
        crate::read::name(input),
        listed.join(", "),
        if more > 0 {
            format!(" and {more} more")
        } else {
            String::new()
        }
    );
}
