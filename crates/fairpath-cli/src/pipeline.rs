//! The main job, step by step: read, smooth each run, verify the curves,
//! plan the input and the curves, render and write what the controller
//! will run ([`fairpath_gcode::emit`]), verify what was written by reading it back,
//! and plan it as `fairpath simulate` would.

use crate::simulate_command::motions_of;
use crate::{Controller, Format};
use anyhow::{anyhow, bail, Context, Result};
use fairpath::budget::ToleranceBudget;
use fairpath::choose::{self, PlannedTime};
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::program::{simulate, Motion, Simulation};
use fairpath::path::{Piece, Run};
use fairpath::pipeline::{PipelineError, Stage};
use fairpath::render::arcs::STEP_SHARE;
use fairpath::smooth::{self, Smoother};
use fairpath_gcode::emit::{emit, EmitOptions};
use fairpath_gcode::{ParseOptions, Program};
use std::path::Path;

/// What the user asked for.
pub struct SmoothOptions {
    /// How the tolerance is shared: smoothing, writing, the controller's
    /// blending.
    pub budget: ToleranceBudget,
    pub method_name: String,
    pub method: Box<dyn Smoother>,
    pub format: Format,
    pub controller: Controller,
    /// The machine the times are planned for, and the render shaped for.
    pub machine: MachineLimits,
    /// Plan every feed move at the machine's maximum feed.
    pub override_feed: bool,
    /// See [`fairpath::render::RenderOptions::step_share`].
    pub step_share: f64,
}

impl SmoothOptions {
    /// Options for `tolerance` mm with output share `output` (default a
    /// tenth of the tolerance), `method`, `format` (default: the
    /// controller's), on the default machine with programmed feeds.
    pub fn new(
        tolerance: f64,
        output: Option<f64>,
        method: &str,
        format: Option<Format>,
        controller: Controller,
    ) -> Result<Self> {
        smooth::check_tolerance(tolerance)
            .map_err(|e| anyhow!("--tolerance: {e} (allowed: 1e-6 to 1000 mm)"))?;
        let format = format.unwrap_or(controller.default_format());
        let output = output.unwrap_or(fairpath::budget::OUTPUT_SHARE * tolerance);
        if !(output.is_finite() && output > 0.0 && output <= 0.5 * tolerance) {
            bail!("--chord must be a positive number of mm, at most half the tolerance ({} mm); got {output}", 0.5 * tolerance);
        }
        let blend = EmitOptions::blend_share(controller, format, output);
        let budget = ToleranceBudget::new(tolerance, Some(output - blend), blend)
            .map_err(|e| anyhow!("--tolerance: {e}: raise --tolerance or lower --chord"))?;
        // `auto` gives a share of the smoothing budget to the chords of
        // sampled arcs.
        let inner = budget.smoothing() * (1.0 - choose::ARC_SHARE);
        smooth::check_tolerance(inner).map_err(|_| {
            anyhow!(
                "--tolerance {tolerance} mm leaves {inner:e} mm for smoothing after the output \
                 ({output} mm) and arc sampling; at least 1e-6 mm is needed: raise \
                 --tolerance or lower --chord"
            )
        })?;
        let m = choose::by_name(method).ok_or_else(|| {
            anyhow!(
                "unknown method {method:?}; known: {}",
                choose::METHODS.join(", ")
            )
        })?;
        Ok(SmoothOptions {
            budget,
            method_name: method.to_string(),
            method: m,
            format,
            controller,
            machine: MachineLimits::thesis(),
            override_feed: false,
            step_share: STEP_SHARE,
        })
    }

    /// Plans on `machine` (at the programmed feeds unless `override_feed`),
    /// and has `auto` rank its candidates by the time planned on it (at
    /// the machine's maximum feed, so that the choice depends on the
    /// geometry, not on a feed the program may set low).
    pub fn set_machine(&mut self, machine: MachineLimits, override_feed: bool) {
        self.machine = machine;
        self.override_feed = override_feed;
        let objective = std::sync::Arc::new(PlannedTime::new(machine, true));
        if let Some(m) = choose::method(&self.method_name, objective) {
            self.method = m;
        }
    }

    /// The user's tolerance (mm).
    pub fn tolerance(&self) -> f64 {
        self.budget.total
    }

    /// The tolerance the smoother gets.
    pub fn budget(&self) -> f64 {
        self.budget.smoothing()
    }

    /// What the emitter needs of these options.
    pub fn emit_options(&self) -> EmitOptions {
        EmitOptions {
            format: self.format,
            controller: self.controller,
            budget: self.budget,
            machine: self.machine,
            step_share: self.step_share,
            override_feed: self.override_feed,
            judged_by: if self.method.writes_for_block_capped_planner() {
                fairpath::feed::plan::Corners::BlockCapped
            } else {
                fairpath::feed::plan::Corners::Blended
            },
        }
    }
}

/// Reads and parses a program; errors read `file:line:column: message`.
pub fn read_program(path: &Path) -> Result<Program> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    parse_program(path, &bytes)
}

/// Parses a program read with the default [`ParseOptions`] (the
/// block-delete switch off). A program without moves (tool changes,
/// coolant ...) is a program: callers say what they make of it.
pub fn parse_program(path: &Path, bytes: &[u8]) -> Result<Program> {
    parse_program_with(path, bytes, &ParseOptions::default())
}

/// [`parse_program`] with `opts` (the block-delete switch).
pub fn parse_program_with(path: &Path, bytes: &[u8], opts: &ParseOptions) -> Result<Program> {
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        bail!("{}: empty program", path.display());
    }
    fairpath_gcode::parse_with(bytes, opts).map_err(|e| anyhow!("{}:{e}", path.display()))
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
    /// Time spent in the step called `name` (zero if there was none).
    pub fn duration(&self, name: &str) -> std::time::Duration {
        self.done
            .iter()
            .filter(|(n, _)| *n == name)
            .map(|(_, d)| *d)
            .sum()
    }
    pub fn report(&self) -> String {
        self.done
            .iter()
            .map(|(n, d)| format!("  {n:<22} {:>9.3} s\n", d.as_secs_f64()))
            .collect()
    }
}

pub use fairpath::pipeline::{
    compare_runs, compare_runs_within, group_by_source, pair_runs, RunResult, SmoothResult,
    WrittenCheck, ENDPOINT_ROUNDING_SHARE,
};

/// Smooths every run with the budget left by the chord tolerance and
/// verifies the curves against that budget (the library's
/// [`fairpath::pipeline::smooth_runs`]): curves that fail are an error.
pub fn smooth_program(
    program: &Program,
    opts: &SmoothOptions,
    phases: &mut Phases,
) -> Result<SmoothResult, PipelineError> {
    fairpath::pipeline::smooth_runs_observed(
        program.runs(),
        opts.method.as_ref(),
        &opts.budget,
        &mut |stage| {
            phases.mark(match stage {
                Stage::Smoothed => "smooth",
                Stage::Verified => "verify curves",
            })
        },
    )
}

/// Planned times of one program (feed moves and rapids), s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Times {
    pub total: f64,
    pub feed: f64,
}

impl Times {
    fn of(sim: &Simulation) -> Times {
        Times {
            total: sim.time(),
            feed: sim.feed_time,
        }
    }
}

/// The three plans of a job: the input, the exact curves and the written
/// program, on the same machine with the same feeds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JobTimes {
    pub input: Times,
    pub exact: Times,
    pub written: Times,
}

/// The smoothed runs as runs.
fn smoothed_runs(result: &SmoothResult) -> Vec<Run> {
    result
        .runs
        .iter()
        .map(|r| Run::new(r.smoothed.pieces.clone()))
        .collect()
}

/// The planned time of the input, as `fairpath simulate` plans the file.
pub fn plan_input(program: &Program, opts: &SmoothOptions) -> Result<Times> {
    let motions = program.motions(&program.runs());
    let sim = simulate(&motions, &opts.machine, opts.override_feed, None)
        .context("planning the input")?;
    Ok(Times::of(&sim))
}

/// The planned time of the exact curves in the program, and the plan of
/// each smoothed run that the renderer shapes the written pieces for: at
/// the machine's maximum feed, so that the written program keeps the
/// curves' speed at any feed (a feed override above 100% included), not
/// just at the programmed one.
pub fn plan_curves(
    program: &Program,
    result: &SmoothResult,
    opts: &SmoothOptions,
) -> Result<(Times, Vec<fairpath::feed::plan::RunPlan>)> {
    let m = &opts.machine;
    let runs = smoothed_runs(result);
    let (motions, index) = program.motions_indexed(&runs);
    let exact = simulate(&motions, m, opts.override_feed, None).context("planning the curves")?;
    let plans = if opts.override_feed {
        index.iter().map(|&i| exact.plans[i].1.clone()).collect()
    } else {
        let feed_runs: Vec<Motion> = runs.into_iter().map(Motion::Feed).collect();
        simulate(&feed_runs, m, true, None)
            .context("planning the curves")?
            .plans
            .into_iter()
            .map(|p| p.1)
            .collect()
    };
    Ok((Times::of(&exact), plans))
}

/// The planned time of a written program's text, exactly as `fairpath
/// simulate` plans the file (`path` names it in errors).
pub fn plan_text(path: &Path, text: &str, opts: &SmoothOptions) -> Result<Times> {
    let motions = motions_of(path, text.as_bytes())?;
    let sim = simulate(&motions, &opts.machine, opts.override_feed, None)
        .context("planning the written program")?;
    Ok(Times::of(&sim))
}

/// The whole `fairpath smooth` job: read `input`, smooth, verify, plan,
/// render, write, verify the written text, plan it, and write `output`
/// only if it passes (through a temporary file renamed over `output`).
/// Returns the summary; on a verification failure prints it to stderr and
/// returns an error, leaving no output file.
pub fn smooth_file(
    input: &Path,
    output: &Path,
    opts: &SmoothOptions,
) -> Result<crate::summary::Summary> {
    let started = std::time::Instant::now();
    let mut phases = Phases::new();
    let program = read_program(input)?;
    phases.mark("read");
    warn_passthrough(input, &program);
    let result = smooth_program(&program, opts, &mut phases).map_err(|e| match e {
        e @ PipelineError::NotVerified { .. } => {
            anyhow!("refusing to write {}: {e}", output.display())
        }
        e => e.into(),
    })?;
    let input_times = plan_input(&program, opts)?;
    let (exact_times, plans) = plan_curves(&program, &result, opts)?;
    phases.mark("plan input and curves");
    let smoothed: Vec<Vec<Piece>> = result
        .runs
        .iter()
        .map(|r| r.smoothed.pieces.clone())
        .collect();
    let emitted = emit(&program, &smoothed, &plans, &opts.emit_options())?;
    phases.mark("render, write, check");
    let written_times = plan_text(output, &emitted.text, opts)?;
    phases.mark("plan written");
    let times = JobTimes {
        input: input_times,
        exact: exact_times,
        written: written_times,
    };
    let mut summary =
        crate::summary::Summary::new(input, output, opts, &program, &result, &emitted, times);
    summary.elapsed = started.elapsed();
    if std::env::var_os("FAIRPATH_TIMING").is_some() {
        eprint!("{}", phases.report());
    }
    if !emitted.check.within {
        eprint!("{}", summary.text());
        bail!(
            "refusing to write {}: the output leaves the tolerance ({:.6} mm > {} mm) or moves a run endpoint",
            output.display(),
            emitted.check.max_deviation,
            emitted.budget.written()
        );
    }
    if program.is_empty() {
        // Nothing to smooth (tool changes, coolant ...): the program as it
        // is, byte for byte.
        let bytes =
            std::fs::read(input).with_context(|| format!("cannot read {}", input.display()))?;
        eprintln!(
            "note: {}: the program has no moves: copied unchanged",
            input.display()
        );
        summary.lines_out = summary.lines_in;
        crate::output::write_atomically(output, &bytes)?;
        return Ok(summary);
    }
    crate::output::write_atomically(output, emitted.text.as_bytes())?;
    Ok(summary)
}

/// Most ranges of passed-through lines [`warn_passthrough`] lists.
const PASSTHROUGH_LISTED: usize = 8;

/// Warns on stderr about the lines passed through verbatim (canned cycles,
/// other dialects' words): they are run as written, not smoothed.
fn warn_passthrough(input: &Path, program: &Program) {
    let notes = program.passthrough();
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
        input.display(),
        listed.join(", "),
        if more > 0 {
            format!(" and {more} more")
        } else {
            String::new()
        }
    );
}
