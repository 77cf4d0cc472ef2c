//! The main job, step by step: read, smooth each run, verify the curves,
//! plan the input and the curves, render and write what the controller
//! will run ([`crate::emit`]), verify what was written by reading it back,
//! and plan it as `fairpath simulate` would. Here are the steps below the
//! writing: the options ([`SmoothOptions`], and [`EmitOptions`], what the
//! writer gets of them), smoothing and verifying the curves (the library's
//! [`fairpath::pipeline`]), the plans, and the check of a written text read
//! back ([`compare_runs`]). [`crate::entry`] puts them and [`crate::emit`]
//! together: [`crate::smooth_program`] is the entry point, and its halves
//! are public for callers that share them between jobs (`fairpath compare`
//! writes one smoothing in several formats).

use crate::{Controller, Format, Program};
use fairpath::budget::{BudgetError, ToleranceBudget};
use fairpath::choose::{self, Method, PlannedTime};
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::Corners;
use fairpath::geom::Curve;
use fairpath::path::{Piece, Run};
use fairpath::pipeline::{verify_runs_measuring, PipelineError, Stage};
use fairpath::render::arcs::STEP_SHARE;
use fairpath::smooth::{self, Smoother};
use fairpath::verify::{Measures, RunReport, VerifyOptions};
use std::sync::Arc;

mod error;
pub(crate) mod plans;
mod render_memo;
pub mod written;

pub use render_memo::RenderMemo;

pub use error::{OptionsError, PlanError};
pub use fairpath::pipeline::{RunResult, SmoothResult};
pub use plans::{
    into_outline_and_runs, outline, plan_curves, plan_input, plan_input_and_curves,
    plan_input_and_curves_carried, plan_input_and_curves_from, plan_text, plan_written,
    plan_written_carried, plan_written_from, CarriedPlan, JobTimes, MotionOutline, RunCarry,
    TimeSums, Times, WrittenReading,
};

/// What the user asked for.
///
/// One [`ToleranceBudget`], built and validated once by
/// [`SmoothOptions::new`], the method, the format and controller, and the
/// machine the times are planned for.
pub struct SmoothOptions {
    /// How the tolerance is shared: smoothing, writing, the controller's
    /// blending.
    budget: ToleranceBudget,
    method_name: String,
    method: Box<dyn Smoother>,
    /// The method with its options, from which [`SmoothOptions::method_for`]
    /// builds `auto` ranking by what will be written for a program; `None`
    /// for a method given by [`SmoothOptions::set_method`] (used as it is).
    spec: Option<Method>,
    format: Format,
    controller: Controller,
    /// The machine the times are planned for, and the render shaped for.
    machine: MachineLimits,
    /// Plan every feed move at the machine's maximum feed.
    override_feed: bool,
    /// See [`fairpath::render::RenderOptions::step_share`].
    step_share: f64,
    /// Long runs cut into windows by the job in parts, or not
    /// ([`crate::interp::RunWindows`]).
    run_windows: Option<crate::interp::RunWindows>,
}

impl SmoothOptions {
    /// Options for `tolerance` mm with output share `output` (default
    /// [`Format::default_output_share`] of the tolerance), `method`, `format` (default: the
    /// controller's), on the default machine with programmed feeds.
    pub fn new(
        tolerance: f64,
        output: Option<f64>,
        method: &str,
        format: Option<Format>,
        controller: Controller,
    ) -> Result<Self, OptionsError> {
        smooth::check_tolerance(tolerance).map_err(|_| OptionsError::Tolerance(tolerance))?;
        let format = format.unwrap_or(controller.default_format());
        let output = output.unwrap_or(format.default_output_share() * tolerance);
        let most = fairpath::budget::MAX_OUTPUT_SHARE * tolerance;
        if !(output.is_finite() && output > 0.0 && output <= most) {
            return Err(OptionsError::OutputShare {
                value: output,
                half: most,
            });
        }
        let blend = EmitOptions::blend_share(controller, format, output);
        let budget = ToleranceBudget::new(tolerance, Some(output - blend), blend)
            .map_err(|source| OptionsError::Budget { tolerance, source })?;
        // `auto` gives a share of the smoothing budget to the chords of
        // sampled arcs.
        let inner = budget.smoothing() * (1.0 - choose::ARC_SHARE);
        smooth::check_tolerance(inner).map_err(|_| OptionsError::NothingLeft {
            tolerance,
            output,
            left: inner,
        })?;
        let spec =
            Method::named(method).ok_or_else(|| OptionsError::UnknownMethod(method.to_string()))?;
        let machine = MachineLimits::thesis();
        Ok(SmoothOptions {
            budget,
            method_name: method.to_string(),
            method: spec.smoother(default_objective(&spec, machine, false)),
            spec: Some(spec),
            format,
            controller,
            machine,
            override_feed: false,
            step_share: STEP_SHARE,
            run_windows: None,
        })
    }

    /// Plans on `machine` (at the programmed feeds unless `override_feed`),
    /// and has `auto` rank its candidates by times planned on it (see
    /// [`SmoothOptions::method_for`]).
    pub fn set_machine(
        &mut self,
        machine: MachineLimits,
        override_feed: bool,
    ) -> Result<(), OptionsError> {
        machine.validate().map_err(OptionsError::Machine)?;
        self.machine = machine;
        self.override_feed = override_feed;
        if let Some(spec) = &self.spec {
            self.method = spec.smoother(default_objective(spec, machine, override_feed));
        }
        Ok(())
    }

    /// Smooths with `method`, one of the caller's, instead of the one named
    /// (used as it is: an `auto` of the caller's ranks by the objective it
    /// was given); the name stays for the report.
    pub fn set_method(&mut self, method: Box<dyn Smoother>) {
        self.method = method;
        self.spec = None;
    }

    /// Smooths with `method`, a method of the registry with options of its
    /// own (`auto` then ranks as [`SmoothOptions::method_for`] says); the
    /// name stays for the report.
    pub fn set_method_options(&mut self, method: Method) {
        self.method = method.smoother(default_objective(&method, self.machine, self.override_feed));
        self.spec = Some(method);
    }

    /// The method that smooths `program` where it is not
    /// [`SmoothOptions::method`] (`None`): `auto` ranking its candidates by
    /// the time of what these options write for `program`
    /// ([`written::objective_for`]: the written program's time at the
    /// user's feeds for a G-code format, the exact curves' time at the
    /// machine's maximum feed for JSON).
    pub fn method_for(&self, program: &Program) -> Option<Box<dyn Smoother>> {
        self.method_for_facts(&crate::ProgramFacts::of(program))
    }

    /// [`SmoothOptions::method_for`] a program whose whole has `facts`
    /// (the same for each of its parts).
    pub fn method_for_facts(&self, facts: &crate::ProgramFacts) -> Option<Box<dyn Smoother>> {
        self.method_with_memo(facts, None)
    }

    /// [`SmoothOptions::method_for_facts`], its objective telling `memo`
    /// of the renderings it makes (for the writer to take the chosen
    /// candidate's).
    pub fn method_with_memo(
        &self,
        facts: &crate::ProgramFacts,
        memo: Option<Arc<RenderMemo>>,
    ) -> Option<Box<dyn Smoother>> {
        match &self.spec {
            Some(m @ Method::Auto(_)) => {
                Some(m.smoother(written::objective_for(&self.emit_options(), facts, memo)))
            }
            _ => None,
        }
    }

    /// Whether the curves [`SmoothOptions::method_for`] smooths depend on
    /// the output format (`auto` ranks by what is written): a caller that
    /// writes one smoothing in several formats must smooth again for each.
    pub fn smooths_for_format(&self) -> bool {
        matches!(self.spec, Some(Method::Auto(_)))
    }

    /// See [`fairpath::render::RenderOptions::step_share`]: positive, or
    /// infinite.
    pub fn set_step_share(&mut self, step_share: f64) -> Result<(), OptionsError> {
        if step_share.is_nan() || step_share <= 0.0 {
            return Err(OptionsError::StepShare(step_share));
        }
        self.step_share = step_share;
        Ok(())
    }

    /// Cuts the long runs of a program processed in parts into windows
    /// (`None`, the default: not). A window of `lines` lines must hold at
    /// least one; `min_cut_mm` must be a positive length.
    pub fn set_run_windows(
        &mut self,
        windows: Option<crate::interp::RunWindows>,
    ) -> Result<(), OptionsError> {
        if let Some(w) = windows {
            if w.lines == 0 || !(w.min_cut_mm.is_finite() && w.min_cut_mm > 0.0) {
                return Err(OptionsError::RunWindows(w.lines, w.min_cut_mm));
            }
        }
        self.run_windows = windows;
        Ok(())
    }

    /// How long runs are cut into windows ([`SmoothOptions::set_run_windows`]).
    pub fn run_windows(&self) -> Option<crate::interp::RunWindows> {
        self.run_windows
    }

    /// The user's tolerance (mm).
    pub fn tolerance(&self) -> f64 {
        self.budget.total
    }

    /// How the tolerance is shared.
    pub fn budget(&self) -> ToleranceBudget {
        self.budget
    }

    /// The method's name, as asked for.
    pub fn method_name(&self) -> &str {
        &self.method_name
    }

    /// The method.
    pub fn method(&self) -> &dyn Smoother {
        self.method.as_ref()
    }

    pub fn format(&self) -> Format {
        self.format
    }

    pub fn controller(&self) -> Controller {
        self.controller
    }

    /// The machine the times are planned for.
    pub fn machine(&self) -> &MachineLimits {
        &self.machine
    }

    /// Whether every feed move is planned at the machine's maximum feed.
    pub fn override_feed(&self) -> bool {
        self.override_feed
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
                Corners::BlockCapped
            } else {
                Corners::Blended
            },
            keeps_every_run: self.method.keeps_every_run(),
        }
    }
}

type Result<T, E = PlanError> = core::result::Result<T, E>;

/// Shares of the output budget LinuxCNC's blending (`G64 P`) gets, for G1
/// output (every vertex is blended) and for the other G-code formats
/// (only corners that were kept are), from the tolerance ledger.
pub use fairpath::budget::{
    BLEND_SHARE_CURVES as CURVE_BLEND_SHARE, BLEND_SHARE_G1 as G1_BLEND_SHARE,
};

/// What to write, for whom.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmitOptions {
    pub format: Format,
    pub controller: Controller,
    pub budget: ToleranceBudget,
    pub machine: MachineLimits,
    /// See [`fairpath::render::RenderOptions::step_share`].
    pub step_share: f64,
    /// The feeds the user plans with: all at the machine's maximum
    /// (`true`), or as programmed. A run is rewritten only if it plans
    /// faster at the maximum feed and at these.
    pub override_feed: bool,
    /// How the controller's planner is modelled when renders are judged
    /// against the program's own runs: [`Corners::BlockCapped`] for a
    /// method that writes for LinuxCNC's S-curve planner (`arc-fit`).
    pub judged_by: Corners,
    /// The method keeps every run as the program wrote it (`none`): no
    /// run is rewritten, so no blending command is written around one,
    /// nor around the windows of a run cut into windows (the text is the
    /// program's).
    pub keeps_every_run: bool,
}

impl EmitOptions {
    /// The blending share of the tolerance for `controller` and `format`
    /// when the output share is `output` mm (0 when no blending mode is
    /// written).
    pub fn blend_share(controller: Controller, format: Format, output: f64) -> f64 {
        match (controller, format) {
            (_, Format::Json) | (Controller::Generic | Controller::Fanuc, _) => 0.0,
            (Controller::Linuxcnc, Format::G1) => G1_BLEND_SHARE * output,
            (Controller::Linuxcnc, _) => CURVE_BLEND_SHARE * output,
        }
    }

    /// The budget to write `program` with: `self.budget`, except where it
    /// has no blending share and the program's own path control at one of
    /// its runs blends beyond the share LinuxCNC would get
    /// ([`crate::write_gcode::PathControl::exceeds`]: `G64 P0.02`,
    /// a bare `G64`). A controller reading that program's `G64` blends the
    /// written blocks, so that share ([`EmitOptions::blend_share`] for
    /// LinuxCNC) is taken out of the output share and the writer writes
    /// `G64 P<share> Q0` around those runs: the smoothing share stays as the
    /// smoother used it, and smoothing + output + blending is still the
    /// tolerance.
    pub fn budget_for(&self, program: &Program) -> Result<ToleranceBudget, BudgetError> {
        self.budget_for_blending(&crate::write_gcode::PathBlending::of(program))
    }

    /// [`EmitOptions::budget_for`] of a program whose path controls at its
    /// runs are `blending` ([`crate::ProgramFacts::blending`]).
    pub fn budget_for_blending(
        &self,
        blending: &crate::write_gcode::PathBlending,
    ) -> Result<ToleranceBudget, BudgetError> {
        let b = self.budget;
        let blend = Self::blend_share(Controller::Linuxcnc, self.format, b.output);
        if b.blend > 0.0 || blend <= 0.0 || !blending.exceeds(blend) {
            return Ok(b);
        }
        ToleranceBudget::new(b.total, Some(b.output - blend), blend)
    }
}

/// Called with the name of each step of a job as it ends (a progress
/// display's hook).
pub type StepObserver = std::sync::Arc<dyn Fn(&'static str) + Send + Sync>;

/// Called with the lines of the program done and its lines in all, as a
/// job processed in parts ([`crate::smooth_in_parts`]) writes each part (a
/// progress bar's hook).
pub type LinesObserver = std::sync::Arc<dyn Fn(usize, usize) + Send + Sync>;

/// Wall-clock time of each step (printed with `FAIRPATH_TIMING=1`), and
/// an observer told of each step as it ends.
#[derive(Clone)]
pub struct Phases {
    last: std::time::Instant,
    /// Each step: its name, its wall time and the process's peak resident
    /// memory when it ended (where the system tells it).
    done: Vec<(&'static str, std::time::Duration, Option<u64>)>,
    observer: Option<StepObserver>,
    lines: Option<LinesObserver>,
}

impl core::fmt::Debug for Phases {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Phases")
            .field("done", &self.done)
            .field("observed", &self.observer.is_some())
            .finish()
    }
}

impl Default for Phases {
    fn default() -> Self {
        Phases::new()
    }
}

/// The process's peak resident set size so far (bytes): `VmHWM` of
/// `/proc/self/status` on Linux, `None` elsewhere or when unreadable.
fn peak_rss() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

impl Phases {
    pub fn new() -> Phases {
        Phases {
            last: std::time::Instant::now(),
            done: Vec::new(),
            observer: None,
            lines: None,
        }
    }

    /// [`Phases::observed`], also telling `lines` how many of the
    /// program's lines are done ([`Phases::lines_done`]).
    pub fn observed_with_lines(observer: StepObserver, lines: LinesObserver) -> Phases {
        Phases {
            lines: Some(lines),
            ..Phases::observed(observer)
        }
    }

    /// Tells the observer of lines that `done` of the program's `total`
    /// lines are done.
    pub fn lines_done(&self, done: usize, total: usize) {
        if let Some(o) = &self.lines {
            o(done, total);
        }
    }
    /// A clock that tells `observer` of each step as it ends.
    pub fn observed(observer: StepObserver) -> Phases {
        Phases {
            observer: Some(observer),
            ..Phases::new()
        }
    }
    /// A clock of its own for steps run beside these (on another thread),
    /// telling the same observer; [`Phases::merge`] puts them together.
    pub fn sibling(&self) -> Phases {
        Phases {
            observer: self.observer.clone(),
            lines: self.lines.clone(),
            ..Phases::new()
        }
    }

    /// The next step starts now (the time since the last mark was not
    /// this clock's: waiting for another thread).
    pub fn restart(&mut self) {
        self.last = std::time::Instant::now();
    }

    /// Adds `other`'s steps after these.
    pub fn merge(&mut self, other: Phases) {
        self.done.extend(other.done);
    }

    pub fn mark(&mut self, name: &'static str) {
        let now = std::time::Instant::now();
        self.done.push((name, now - self.last, peak_rss()));
        self.last = now;
        if let Some(o) = &self.observer {
            o(name);
        }
    }
    /// Time spent in the step called `name` (zero if there was none).
    pub fn duration(&self, name: &str) -> std::time::Duration {
        self.done
            .iter()
            .filter(|(n, _, _)| *n == name)
            .map(|(_, d, _)| *d)
            .sum()
    }
    /// One line per step: its wall time and, where known, the peak
    /// resident memory of the process when it ended (so the step that set
    /// the peak is the first to show it). A step marked several times (once
    /// per part of a program processed in parts) is one line: its times
    /// added, the peak when it last ended.
    pub fn report(&self) -> String {
        let mut steps: Vec<(&'static str, std::time::Duration, Option<u64>)> = Vec::new();
        for &(n, d, rss) in &self.done {
            match steps.iter_mut().find(|s| s.0 == n) {
                Some(s) => {
                    s.1 += d;
                    s.2 = rss.or(s.2);
                }
                None => steps.push((n, d, rss)),
            }
        }
        steps
            .iter()
            .map(|(n, d, rss)| match rss {
                Some(b) => format!(
                    "  {n:<22} {:>9.3} s   peak RSS {:>7.1} MB\n",
                    d.as_secs_f64(),
                    *b as f64 / (1u64 << 20) as f64
                ),
                None => format!("  {n:<22} {:>9.3} s\n", d.as_secs_f64()),
            })
            .collect()
    }
}

/// Smooths every run with the budget left by the chord tolerance and
/// verifies the curves against that budget (the library's
/// [`fairpath::pipeline::smooth_runs`]), with the method
/// [`SmoothOptions::method_for`] gives `program`: curves that fail are an
/// error. `phases` gets `smooth` and `verify curves`.
pub fn smooth_curves(
    program: &Program,
    opts: &SmoothOptions,
    phases: &mut Phases,
) -> Result<SmoothResult, PipelineError> {
    smooth_curves_with(program, &crate::ProgramFacts::of(program), opts, phases)
}

/// [`smooth_curves`] of `program`, a part of a program whose whole has
/// `facts`, or a whole one.
pub fn smooth_curves_with(
    program: &Program,
    facts: &crate::ProgramFacts,
    opts: &SmoothOptions,
    phases: &mut Phases,
) -> Result<SmoothResult, PipelineError> {
    smooth_curves_memo(program, facts, opts, phases, None)
}

/// [`smooth_curves_with`], `auto`'s objective telling `memo` of the
/// renderings it makes ([`RenderMemo`]).
pub fn smooth_curves_memo(
    program: &Program,
    facts: &crate::ProgramFacts,
    opts: &SmoothOptions,
    phases: &mut Phases,
    memo: Option<Arc<RenderMemo>>,
) -> Result<SmoothResult, PipelineError> {
    let runs = program.runs();
    if let Some(m) = &memo {
        m.expect_runs(&runs);
    }
    let for_program = opts.method_with_memo(facts, memo);
    // (A part's first and last runs may be windows of a longer run.)
    let cut = (program.window_continued(), program.window_cut());
    fairpath::pipeline::smooth_windows_observed(
        runs,
        cut,
        for_program.as_deref().unwrap_or(opts.method.as_ref()),
        &opts.budget,
        &mut |stage| {
            phases.mark(match stage {
                Stage::Smoothed => "smooth",
                Stage::Verified => "verify curves",
            })
        },
    )
}

/// Groups feed pieces (from JSON) into the original runs by the input lines
/// they name.
pub fn group_by_source(original: &[Run], pieces: &[Piece]) -> Vec<Run> {
    // Feed pieces by first line: each run takes those from its first line
    // on, up to its last, in their order (no scan of every piece per run).
    let mut by_line: Vec<usize> = (0..pieces.len()).filter(|&i| !pieces[i].rapid).collect();
    if by_line
        .iter()
        .any(|&i| pieces[i].source_lines.0 > pieces[i].source_lines.1)
    {
        // Lines that run backwards (not what the writer writes): the scan.
        return group_by_source_scan(original, pieces);
    }
    by_line.sort_by_key(|&i| pieces[i].source_lines.0);
    original
        .iter()
        .map(|run| {
            let lo = run.pieces.first().map(|p| p.source_lines.0).unwrap_or(0);
            let hi = run.pieces.last().map(|p| p.source_lines.1).unwrap_or(0);
            let from = by_line.partition_point(|&i| pieces[i].source_lines.0 < lo);
            let mut take: Vec<usize> = by_line[from..]
                .iter()
                .take_while(|&&i| pieces[i].source_lines.0 <= hi)
                .filter(|&&i| pieces[i].source_lines.1 <= hi)
                .copied()
                .collect();
            take.sort_unstable();
            Run::new(take.into_iter().map(|i| pieces[i].clone()).collect())
        })
        .collect()
}

/// [`group_by_source`] by a scan of every piece for each run.
fn group_by_source_scan(original: &[Run], pieces: &[Piece]) -> Vec<Run> {
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
        .all(|p| matches!(&p.curve, Curve::Line(l) if l.p0 == l.p1))
}

/// The runs of a candidate do not pair with the original's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "the smoothed program has {candidate} runs of feed moves where the original has {original}"
)]
pub struct RunCountMismatch {
    /// Runs of the original that move.
    pub original: usize,
    /// Runs of the candidate that move.
    pub candidate: usize,
}

/// The verdict on the written output.
#[derive(Clone, Debug, PartialEq)]
pub struct WrittenCheck {
    pub within: bool,
    pub max_deviation: f64,
    pub endpoint_failures: usize,
    pub runs_checked: usize,
    /// The runs (index in the original's `runs()`) that failed; `None`
    /// when the failure is not tied to runs.
    pub failed_runs: Vec<Option<usize>>,
}

/// The runs of `candidate` that stand for each run of `original`, in
/// order, as `(original index, candidate index)`: runs of zero length on
/// either side are skipped. An error when the counts differ.
pub fn pair_runs(
    original: &[Run],
    candidate: &[Run],
) -> Result<Vec<(usize, usize)>, RunCountMismatch> {
    pair_runs_streamed(original, candidate, &[])
}

/// [`pair_runs`], where the candidate runs `streamed` (sorted; read part
/// by part and holding no pieces, [`crate::interp::RunStream`]) move.
pub(crate) fn pair_runs_streamed(
    original: &[Run],
    candidate: &[Run],
    streamed: &[usize],
) -> Result<Vec<(usize, usize)>, RunCountMismatch> {
    let o: Vec<usize> = (0..original.len())
        .filter(|&i| !is_zero_length(&original[i]))
        .collect();
    let c: Vec<usize> = (0..candidate.len())
        .filter(|&i| {
            streamed.binary_search(&i).is_ok()
                || (!candidate[i].pieces.is_empty() && !is_zero_length(&candidate[i]))
        })
        .collect();
    if o.len() != c.len() {
        return Err(RunCountMismatch {
            original: o.len(),
            candidate: c.len(),
        });
    }
    Ok(o.into_iter().zip(c).collect())
}

/// Pairs runs ([`pair_runs`]) and verifies each pair.
pub fn compare_runs(
    original: &[Run],
    candidate: &[Run],
    tolerance: f64,
) -> Result<WrittenCheck, RunCountMismatch> {
    compare_runs_within(original, candidate, tolerance, 0.0)
}

/// Run end points count as equal within this share of the tolerance (see
/// the tolerance ledger).
pub use fairpath::budget::ENDPOINT_ROUNDING_SHARE;

/// [`compare_runs`], with run end points that may differ by up to
/// `endpoint_slack` mm (0: equal up to [`ENDPOINT_ROUNDING_SHARE`] of the
/// tolerance).
pub fn compare_runs_within(
    original: &[Run],
    candidate: &[Run],
    tolerance: f64,
    endpoint_slack: f64,
) -> Result<WrittenCheck, RunCountMismatch> {
    // The check needs the deviation and the end points only: the joints
    // and curvature of a long written run are not measured (nor held).
    compare(
        original,
        candidate,
        tolerance,
        endpoint_slack,
        Measures::Ends,
        &[],
    )
    .map(|(check, _)| check)
}

/// [`compare_runs`] where the candidate runs in `known` (sorted by
/// index) were measured as they were read (their pieces handed out part
/// by part, [`crate::interp::RunStream`]): paired as runs that move, their
/// reports taken as they are. Also returns the pairs.
pub(crate) fn compare_runs_known(
    original: &[Run],
    candidate: &[Run],
    tolerance: f64,
    known: &[(usize, RunReport)],
) -> Result<(WrittenCheck, Vec<(usize, usize)>), RunCountMismatch> {
    let (check, reports) = compare(original, candidate, tolerance, 0.0, Measures::Ends, known)?;
    let pairs = reports.iter().map(|r| (r.original, r.candidate)).collect();
    Ok((check, pairs))
}

/// One pair of runs verified: the indices of the original's and the
/// candidate's run and the verifier's report (where the largest distance
/// was found among it).
#[derive(Clone, Debug, PartialEq)]
pub struct PairReport {
    pub original: usize,
    pub candidate: usize,
    pub report: RunReport,
}

/// [`compare_runs_within`] with the report of every pair, for callers that
/// say where the candidate is farthest from the original (`fairpath check`).
pub fn compare_runs_reported(
    original: &[Run],
    candidate: &[Run],
    tolerance: f64,
    endpoint_slack: f64,
) -> Result<(WrittenCheck, Vec<PairReport>), RunCountMismatch> {
    compare(
        original,
        candidate,
        tolerance,
        endpoint_slack,
        Measures::All,
        &[],
    )
}

/// [`compare_runs_reported`], its reports measuring what `measures` says.
fn compare(
    original: &[Run],
    candidate: &[Run],
    tolerance: f64,
    endpoint_slack: f64,
    measures: Measures,
    known: &[(usize, RunReport)],
) -> Result<(WrittenCheck, Vec<PairReport>), RunCountMismatch> {
    let streamed: Vec<usize> = known.iter().map(|k| k.0).collect();
    let pairs_idx = pair_runs_streamed(original, candidate, &streamed)?;
    let known_of = |c: usize| streamed.binary_search(&c).ok().map(|i| known[i].1.clone());
    let mut out = WrittenCheck {
        within: true,
        max_deviation: 0.0,
        endpoint_failures: 0,
        runs_checked: 0,
        failed_runs: Vec::new(),
    };
    let measured: Vec<(usize, usize)> = pairs_idx
        .iter()
        .copied()
        .filter(|&(_, b)| known_of(b).is_none())
        .collect();
    let pairs: Vec<(&[Piece], &[Piece])> = measured
        .iter()
        .map(|&(a, b)| {
            (
                original[a].pieces.as_slice(),
                candidate[b].pieces.as_slice(),
            )
        })
        .collect();
    let mut measured =
        verify_runs_measuring(&pairs, &VerifyOptions::new(tolerance), measures).into_iter();
    let reports: Vec<RunReport> = pairs_idx
        .iter()
        .map(|&(_, b)| known_of(b).or_else(|| measured.next()))
        .collect::<Option<_>>()
        .expect("a report for every pair");
    for (k, rep) in reports.iter().enumerate() {
        out.max_deviation = out.max_deviation.max(rep.deviation_bound);
        let slack = endpoint_slack + ENDPOINT_ROUNDING_SHARE * tolerance;
        let moved = rep.start_gap > slack || rep.end_gap > slack;
        if moved {
            out.endpoint_failures += 1;
        }
        let within = rep.deviation_bound <= tolerance && !moved;
        if !within {
            out.within = false;
            out.failed_runs.push(Some(pairs_idx[k].0));
        }
        out.runs_checked += 1;
    }
    let reported = pairs_idx
        .iter()
        .zip(reports)
        .map(|(&(original, candidate), report)| PairReport {
            original,
            candidate,
            report,
        })
        .collect();
    Ok((out, reported))
}

/// The objective a method of the registry is built with before a program
/// is known ([`SmoothOptions::method_for`] gives `auto` the written
/// program's): `auto` ranks by the exact curves' time at the machine's
/// maximum feed; the others use it only for `fair`'s peak pass, which
/// lowers the machine's demand up to each curve's programmed feed unless
/// the user overrides the feeds (`choose::fair_on`).
fn default_objective(
    spec: &Method,
    machine: MachineLimits,
    override_feed: bool,
) -> Arc<dyn fairpath::choose::Objective> {
    let at_maximum_feed = override_feed || matches!(spec, Method::Auto(_));
    Arc::new(PlannedTime::new(machine, at_maximum_feed))
}
