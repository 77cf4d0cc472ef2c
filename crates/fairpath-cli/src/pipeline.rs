//! The main job, step by step: read, smooth each run, verify the curves,
//! render, and verify what was rendered by reading it back.

use crate::parallel::verify_runs;
use crate::Format;
use anyhow::{anyhow, bail, Context, Result};
use fairpath::path::{Piece, Run};
use fairpath::smooth::verify::{RunReport, VerifyOptions};
use fairpath::smooth::{self, SmoothedRun, Smoother};
use fairpath_gcode::Program;
use std::path::Path;

/// What the user asked for.
pub struct SmoothOptions {
    /// Total tolerance (mm): the written output stays within it.
    pub tolerance: f64,
    /// Chord tolerance (mm) of the G1 output, part of the tolerance budget.
    pub chord: f64,
    pub method_name: String,
    pub method: Box<dyn Smoother>,
    pub format: Format,
}

impl SmoothOptions {
    pub fn new(tolerance: f64, chord: Option<f64>, method: &str, format: Format) -> Result<Self> {
        smooth::check_tolerance(tolerance)
            .map_err(|e| anyhow!("--tolerance: {e} (allowed: 1e-6 to 1000 mm)"))?;
        let chord = chord.unwrap_or(tolerance / 10.0);
        if !(chord.is_finite() && chord > 0.0 && chord <= 0.5 * tolerance) {
            bail!("--chord must be a positive number of mm, at most half the tolerance ({} mm); got {chord}", 0.5 * tolerance);
        }
        // The smoother gets what the chord tolerance leaves, and `auto`
        // gives a share of that to the chords of sampled arcs.
        let budget = (tolerance - chord) * (1.0 - smooth::ARC_SHARE);
        smooth::check_tolerance(budget).map_err(|_| {
            anyhow!(
                "--tolerance {tolerance} mm leaves {budget:e} mm for smoothing after the chord \
                 tolerance ({chord} mm) and arc sampling; at least 1e-6 mm is needed: raise \
                 --tolerance or lower --chord"
            )
        })?;
        let m = smooth::by_name(method).ok_or_else(|| {
            anyhow!(
                "unknown method {method:?}; known: {}",
                smooth::METHODS.join(", ")
            )
        })?;
        Ok(SmoothOptions {
            tolerance,
            chord,
            method_name: method.to_string(),
            method: m,
            format,
        })
    }
    /// The tolerance the smoother gets: what the chord error leaves.
    pub fn budget(&self) -> f64 {
        self.tolerance - self.chord
    }
}

/// Reads and parses a program; errors read `file:line:column: message`.
pub fn read_program(path: &Path) -> Result<Program> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    parse_program(path, &bytes)
}

pub fn parse_program(path: &Path, bytes: &[u8]) -> Result<Program> {
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        bail!("{}: empty program", path.display());
    }
    let program = fairpath_gcode::parse(bytes).map_err(|e| anyhow!("{}:{e}", path.display()))?;
    if program.pieces().is_empty() {
        bail!("{}: the program has no moves", path.display());
    }
    Ok(program)
}

/// Wall-clock time of each step (printed with `FAIRPATH_TIMING=1`).
pub struct Phases {
    last: std::time::Instant,
    done: Vec<(&'static str, std::time::Duration)>,
}

impl Default for Phases {
    fn default() -> Self {
        Phases::new()
    }
}

impl Phases {
    pub fn new() -> Phases {
        Phases {
            last: std::time::Instant::now(),
            done: Vec::new(),
        }
    }
    pub fn mark(&mut self, name: &'static str) {
        let now = std::time::Instant::now();
        self.done.push((name, now - self.last));
        self.last = now;
    }
    pub fn report(&self) -> String {
        self.done
            .iter()
            .map(|(n, d)| format!("  {n:<22} {:>9.3} s\n", d.as_secs_f64()))
            .collect()
    }
}

/// One run before and after.
pub struct RunResult {
    pub original: Run,
    pub smoothed: SmoothedRun,
    pub report: RunReport,
}

pub struct SmoothResult {
    pub runs: Vec<RunResult>,
}

/// Smooths every run with the budget left by the chord tolerance and
/// verifies the curves against that budget.
pub fn smooth_program(
    program: &Program,
    opts: &SmoothOptions,
    phases: &mut Phases,
) -> Result<SmoothResult> {
    let budget = opts.budget();
    let mut smoothed_runs = Vec::new();
    let runs = program.runs();
    for run in &runs {
        let line = run.pieces.first().map(|p| p.source_lines.0).unwrap_or(0);
        let smoothed = opts
            .method
            .smooth_run(run, budget)
            .with_context(|| format!("smoothing the run starting at line {line}"))?;
        smoothed_runs.push(smoothed);
    }
    phases.mark("smooth");
    let pairs: Vec<(&[Piece], &[Piece])> = runs
        .iter()
        .zip(&smoothed_runs)
        .map(|(r, s)| (r.pieces.as_slice(), s.pieces.as_slice()))
        .collect();
    let reports = verify_runs(&pairs, &VerifyOptions::new(budget));
    let out = runs
        .into_iter()
        .zip(smoothed_runs)
        .zip(reports)
        .map(|((original, smoothed), report)| RunResult {
            original,
            smoothed,
            report,
        })
        .collect();
    phases.mark("verify curves");
    Ok(SmoothResult { runs: out })
}

/// The output text in the chosen format.
pub fn render(program: &Program, result: &SmoothResult, opts: &SmoothOptions) -> Result<String> {
    let smoothed: Vec<Vec<Piece>> = result
        .runs
        .iter()
        .map(|r| r.smoothed.pieces.clone())
        .collect();
    match opts.format {
        Format::Gcode => {
            let wo = fairpath_gcode::GcodeWriteOptions {
                chord_mm: opts.chord,
                ..Default::default()
            };
            fairpath_gcode::write_gcode(program, &smoothed, &wo)
                .map_err(|e| anyhow!("writing G-code: {e}"))
        }
        Format::Json => {
            fairpath_gcode::write_json(program, &smoothed).map_err(|e| anyhow!("writing JSON: {e}"))
        }
    }
}

/// The verdict on the rendered output.
pub struct WrittenCheck {
    pub within: bool,
    pub max_deviation: f64,
    pub endpoint_failures: usize,
    pub runs_checked: usize,
}

/// Reads the rendered text back and verifies each of its runs against the
/// original run, at the full tolerance.
pub fn check_written(program: &Program, text: &str, opts: &SmoothOptions) -> Result<WrittenCheck> {
    let original = program.runs();
    let candidate = match opts.format {
        Format::Gcode => fairpath_gcode::parse(text.as_bytes())
            .map_err(|e| anyhow!("the written G-code does not read back: {e}"))?
            .runs(),
        Format::Json => {
            let pieces = fairpath_gcode::read_json(text)
                .map_err(|e| anyhow!("the written JSON does not read back: {e}"))?;
            group_by_source(&original, &pieces)
        }
    };
    compare_runs(&original, &candidate, opts.tolerance)
}

/// Groups feed pieces (from JSON) into the original runs by the input lines
/// they name.
pub fn group_by_source(original: &[Run], pieces: &[Piece]) -> Vec<Run> {
    original
        .iter()
        .map(|run| {
            let lo = run.pieces.first().map(|p| p.source_lines.0).unwrap_or(0);
            let hi = run.pieces.last().map(|p| p.source_lines.1).unwrap_or(0);
            Run::new(
                pieces
                    .iter()
                    .filter(|p| !p.rapid && p.source_lines.0 >= lo && p.source_lines.1 <= hi)
                    .cloned()
                    .collect(),
            )
        })
        .collect()
}

fn is_zero_length(run: &Run) -> bool {
    run.pieces
        .iter()
        .all(|p| matches!(&p.curve, fairpath::Curve::Line(l) if l.p0 == l.p1))
}

/// Pairs runs in order (runs of zero length on either side are skipped)
/// and verifies each pair.
pub fn compare_runs(original: &[Run], candidate: &[Run], tolerance: f64) -> Result<WrittenCheck> {
    let o: Vec<&Run> = original.iter().filter(|r| !is_zero_length(r)).collect();
    let c: Vec<&Run> = candidate
        .iter()
        .filter(|r| !r.pieces.is_empty() && !is_zero_length(r))
        .collect();
    if o.len() != c.len() {
        bail!(
            "the smoothed program has {} runs of feed moves where the original has {}",
            c.len(),
            o.len()
        );
    }
    let mut out = WrittenCheck {
        within: true,
        max_deviation: 0.0,
        endpoint_failures: 0,
        runs_checked: 0,
    };
    let pairs: Vec<(&[Piece], &[Piece])> = o
        .iter()
        .zip(&c)
        .map(|(a, b)| (a.pieces.as_slice(), b.pieces.as_slice()))
        .collect();
    for rep in verify_runs(&pairs, &VerifyOptions::new(tolerance)) {
        out.max_deviation = out.max_deviation.max(rep.deviation_bound);
        if rep.start_gap != 0.0 || rep.end_gap != 0.0 {
            out.endpoint_failures += 1;
        }
        out.within &= rep.within(tolerance);
        out.runs_checked += 1;
    }
    Ok(out)
}

/// The whole `fairpath smooth` job: read `input`, smooth, verify, render,
/// verify the rendered text, and write `output` only if it passes (through
/// a temporary file renamed over `output`). Returns the summary; on a
/// verification failure prints it to stderr and returns an error, leaving
/// no output file.
pub fn smooth_file(
    input: &Path,
    output: &Path,
    opts: &SmoothOptions,
) -> Result<crate::summary::Summary> {
    let started = std::time::Instant::now();
    let mut phases = Phases::new();
    let program = read_program(input)?;
    phases.mark("read");
    let result = smooth_program(&program, opts, &mut phases)?;
    let text = render(&program, &result, opts)?;
    phases.mark("render");
    let written = check_written(&program, &text, opts)?;
    phases.mark("check written output");
    let mut summary = crate::summary::Summary::new(
        input,
        output,
        opts,
        &program,
        &result,
        &written,
        started.elapsed(),
    );
    summary.feed_time = Some((
        crate::simulate::feed_time(result.runs.iter().map(|r| r.original.pieces.as_slice()))?,
        crate::simulate::feed_time(result.runs.iter().map(|r| r.smoothed.pieces.as_slice()))?,
    ));
    phases.mark("plan feed (before/after)");
    summary.elapsed = started.elapsed();
    if std::env::var_os("FAIRPATH_TIMING").is_some() {
        eprint!("{}", phases.report());
    }
    if !written.within {
        eprint!("{}", summary.text());
        bail!(
            "refusing to write {}: the output leaves the tolerance ({:.6} mm > {} mm) or moves a run endpoint",
            output.display(),
            written.max_deviation,
            opts.tolerance
        );
    }
    crate::output::write_atomically(output, text.as_bytes())?;
    Ok(summary)
}
