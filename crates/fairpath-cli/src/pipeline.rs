//! The main job, step by step: read, smooth each run, verify the curves,
//! plan the input and the curves, render and write what the controller
//! will run ([`crate::emit`]), verify what was written by reading it back,
//! and plan it as `fairpath simulate` would.

use crate::emit::{emit, EmitOptions};
use crate::parallel::par_map;
use crate::parallel::verify_runs;
use crate::simulate::{motions_of, simulate, Simulation};
use crate::{Controller, Format};
use anyhow::{anyhow, bail, Context, Result};
use fairpath::budget::ToleranceBudget;
use fairpath::choose::{self, PlannedTime};
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{plan_rapid, plan_run, PlanOptions, RunPlan};
use fairpath::path::{Piece, Run};
use fairpath::render::arcs::STEP_SHARE;
use fairpath::smooth::{self, SmoothedRun, Smoother};
use fairpath::verify::{RunReport, VerifyOptions};
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

/// The planned times of `program` with its runs' pieces replaced by
/// `runs` (in the order of `Program::runs`; pinned moves and rapids as the
/// program has them), exactly as [`simulate`] sums them (same plans, same
/// order of addition), without keeping copies of the runs or their plans:
/// the motions are planned on all cores, the times added in order. With
/// `keep_plans`, also the plan of each of `runs`. `what` names the step in
/// errors.
fn plan_program(
    program: &Program,
    runs: &[&[Piece]],
    machine: &MachineLimits,
    override_feed: bool,
    keep_plans: bool,
    what: &'static str,
) -> Result<(Times, Vec<RunPlan>)> {
    let outline = outline(program);
    plan_program_known(
        &outline,
        runs,
        &[],
        machine,
        override_feed,
        keep_plans,
        what,
    )
}

/// One motion of a program as [`simulate`] plans it, without the program.
#[derive(Clone, Debug)]
pub enum MotionOutline {
    /// Run `k` (in the order of `Program::runs`).
    Run(usize),
    Rapid(Piece),
    /// A feed move that is a motion of its own (pinned).
    Pinned(Piece),
}

/// The motions of `program` in order, as [`crate::simulate::gcode_motions`]
/// makes them, with its runs by index: what planning it needs once the
/// program itself is dropped.
pub fn outline(program: &Program) -> Vec<MotionOutline> {
    let mut out = Vec::with_capacity(2 * program.run_spans().len() + 1);
    let spans = program.run_spans();
    let moves = program.moves();
    let (mut next_run, mut mi) = (0, 0);
    while mi < moves.len() {
        if next_run < spans.len() && spans[next_run].moves.start == mi {
            out.push(MotionOutline::Run(next_run));
            mi = spans[next_run].moves.end;
            next_run += 1;
            continue;
        }
        let p = &moves[mi].piece;
        out.push(if p.rapid {
            MotionOutline::Rapid(p.clone())
        } else {
            MotionOutline::Pinned(p.clone())
        });
        mi += 1;
    }
    out
}

/// [`plan_program`], with the time of run `k` taken from `known[k]` where
/// it is `Some` (a plan with the same options, already made).
fn plan_program_known(
    outline: &[MotionOutline],
    runs: &[&[Piece]],
    known: &[Option<f64>],
    machine: &MachineLimits,
    override_feed: bool,
    keep_plans: bool,
    what: &'static str,
) -> Result<(Times, Vec<RunPlan>)> {
    enum Job<'a> {
        Run(usize, &'a [Piece]),
        Rapid(&'a Piece),
    }
    let jobs: Vec<Job> = outline
        .iter()
        .map(|m| match m {
            MotionOutline::Run(k) => Job::Run(*k, runs[*k]),
            MotionOutline::Rapid(p) => Job::Rapid(p),
            MotionOutline::Pinned(p) => Job::Run(usize::MAX, std::slice::from_ref(p)),
        })
        .collect();
    let po = PlanOptions {
        limits: *machine,
        override_feed,
        window: None,
    };
    // (feed time, rapid time, the plan kept).
    type Planned = (f64, f64, Option<(usize, RunPlan)>);
    let planned: Vec<Result<Planned>> = par_map(jobs.len(), |j| match jobs[j] {
        Job::Run(k, pieces) => {
            if let (false, Some(Some(t))) = (keep_plans, known.get(k)) {
                return Ok((*t, 0.0, None));
            }
            let line = pieces.first().map(|p| p.source_lines.0).unwrap_or(0);
            let plan = plan_run(pieces, &po)
                .map_err(|e| anyhow!("planning the run at line {line}: {e}"))
                .context(what)?;
            let time = plan.time;
            Ok((
                time,
                0.0,
                (keep_plans && k != usize::MAX).then_some((k, plan)),
            ))
        }
        Job::Rapid(p) => {
            let len = p.curve.length(1e-6);
            if len.is_nan() || len <= 0.0 {
                return Ok((0.0, 0.0, None));
            }
            let prof = plan_rapid(len, machine)
                .map_err(|e| anyhow!("planning a rapid: {e}"))
                .context(what)?;
            Ok((0.0, prof.duration(), None))
        }
    });
    drop(jobs);
    let (mut feed, mut rapid) = (0.0, 0.0);
    let mut plans: Vec<RunPlan> = Vec::with_capacity(if keep_plans { runs.len() } else { 0 });
    for r in planned {
        let (f, r, plan) = r?;
        feed += f;
        rapid += r;
        if let Some((k, plan)) = plan {
            debug_assert_eq!(k, plans.len());
            plans.push(plan);
        }
    }
    Ok((
        Times {
            total: feed + rapid,
            feed,
        },
        plans,
    ))
}

/// The planned time of the input, as `fairpath simulate` plans the file.
pub fn plan_input(program: &Program, opts: &SmoothOptions) -> Result<Times> {
    let runs = program.runs();
    let pieces: Vec<&[Piece]> = runs.iter().map(|r| r.pieces.as_slice()).collect();
    let what = "planning the input";
    Ok(plan_program(
        program,
        &pieces,
        &opts.machine,
        opts.override_feed,
        false,
        what,
    )?
    .0)
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
    let (_, exact, plans) = plan_input_and_curves(program, result, opts, false)?;
    Ok((exact, plans))
}

/// [`plan_curves`], and with `input` the planned time of the input
/// ([`plan_input`], from the runs already read): the plans are made side
/// by side, two at a time on the two cores this is written for (more at
/// once would only hold more plans in memory), without copies of the runs.
fn plan_input_and_curves(
    program: &Program,
    result: &SmoothResult,
    opts: &SmoothOptions,
    input: bool,
) -> Result<(Option<Times>, Times, Vec<RunPlan>)> {
    #[derive(Clone, Copy)]
    enum Task {
        Input,
        /// The curves at the programmed feeds (with the plans when those
        /// are the renderer's: feeds overridden).
        Exact,
        /// The renderer's plans, at the maximum feed.
        Plans,
    }
    let (m, override_feed) = (&opts.machine, opts.override_feed);
    let curves: Vec<&[Piece]> = result
        .runs
        .iter()
        .map(|r| r.smoothed.pieces.as_slice())
        .collect();
    let mut tasks = Vec::new();
    if input {
        tasks.push(Task::Input);
    }
    tasks.push(Task::Exact);
    if !override_feed {
        tasks.push(Task::Plans);
    }
    let what = "planning the curves";
    let renderer_plans = || -> Result<Vec<RunPlan>> {
        par_map(curves.len(), |k| {
            // A run smoothed into itself is written as the program wrote
            // it, never rendered ([`crate::emit::emit`]): no plan.
            if result.runs[k].original.pieces == curves[k] {
                return Ok(RunPlan::default());
            }
            let po = PlanOptions {
                limits: *m,
                override_feed: true,
                window: None,
            };
            let line = curves[k].first().map(|p| p.source_lines.0).unwrap_or(0);
            plan_run(curves[k], &po)
                .map_err(|e| anyhow!("planning the run at line {line}: {e}"))
                .context(what)
        })
        .into_iter()
        .collect()
    };
    let done: Vec<Result<(Times, Vec<RunPlan>)>> = par_map(tasks.len(), |i| match tasks[i] {
        Task::Input => {
            let runs: Vec<&[Piece]> = result
                .runs
                .iter()
                .map(|r| r.original.pieces.as_slice())
                .collect();
            plan_program(
                program,
                &runs,
                m,
                override_feed,
                false,
                "planning the input",
            )
        }
        // Feeds overridden: the plans at the programmed feeds are the
        // renderer's.
        Task::Exact => plan_program(program, &curves, m, override_feed, override_feed, what),
        Task::Plans => Ok((
            Times {
                total: 0.0,
                feed: 0.0,
            },
            renderer_plans()?,
        )),
    });
    let mut input_times = None;
    let mut exact = Times {
        total: 0.0,
        feed: 0.0,
    };
    let mut plans = Vec::new();
    for (task, r) in tasks.into_iter().zip(done) {
        let (times, p) = r?;
        match task {
            Task::Input => input_times = Some(times),
            Task::Exact => {
                exact = times;
                if override_feed {
                    plans = p;
                }
            }
            Task::Plans => plans = p,
        }
    }
    Ok((input_times, exact, plans))
}

/// The planned time of a written program's text, exactly as `fairpath
/// simulate` plans the file (`path` names it in errors).
pub fn plan_text(path: &Path, text: &str, opts: &SmoothOptions) -> Result<Times> {
    let bytes = text.as_bytes();
    if bytes.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'{') {
        let motions = motions_of(path, bytes)?;
        let sim = simulate(&motions, &opts.machine, opts.override_feed, None)
            .context("planning the written program")?;
        return Ok(Times::of(&sim));
    }
    let program = parse_program(path, bytes)?;
    let runs = program.runs();
    let pieces: Vec<&[Piece]> = runs.iter().map(|r| r.pieces.as_slice()).collect();
    let what = "planning the written program";
    Ok(plan_program(
        &program,
        &pieces,
        &opts.machine,
        opts.override_feed,
        false,
        what,
    )?
    .0)
}

/// The planned time of what [`emit`] wrote, exactly as [`plan_text`]
/// plans `emitted.text`: from the reading the writer's check made (taken
/// out of `emitted`), without reading the text again or planning again
/// the runs the check planned the same way.
pub fn plan_written(
    path: &Path,
    emitted: &mut crate::emit::Emitted,
    opts: &SmoothOptions,
) -> Result<Times> {
    let Some(reading) = emitted.reading.take() else {
        return plan_text(path, &emitted.text, opts);
    };
    if emitted.text.bytes().all(|b| b.is_ascii_whitespace()) {
        bail!("{}: empty program", path.display());
    }
    let pieces: Vec<&[Piece]> = reading.runs.iter().map(|r| r.pieces.as_slice()).collect();
    let what = "planning the written program";
    let m = &opts.machine;
    let known = &reading.run_times;
    let outline = &reading.outline;
    Ok(plan_program_known(outline, &pieces, known, m, opts.override_feed, false, what)?.0)
}

/// Groups feed pieces (from JSON) into the original runs by the input lines
/// they name.
pub fn group_by_source(original: &[Run], pieces: &[Piece]) -> Vec<Run> {
    // Feed pieces by first line: each run takes those from its first line
    // on, up to its last (a piece's lines never run backwards), in their
    // order (no scan of every piece per run).
    let mut by_line: Vec<usize> = (0..pieces.len()).filter(|&i| !pieces[i].rapid).collect();
    if by_line
        .iter()
        .any(|&i| pieces[i].source_lines.0 > pieces[i].source_lines.1)
    {
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
        .all(|p| matches!(&p.curve, fairpath::Curve::Line(l) if l.p0 == l.p1))
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
pub fn pair_runs(original: &[Run], candidate: &[Run]) -> Result<Vec<(usize, usize)>> {
    let o: Vec<usize> = (0..original.len())
        .filter(|&i| !is_zero_length(&original[i]))
        .collect();
    let c: Vec<usize> = (0..candidate.len())
        .filter(|&i| !candidate[i].pieces.is_empty() && !is_zero_length(&candidate[i]))
        .collect();
    if o.len() != c.len() {
        bail!(
            "the smoothed program has {} runs of feed moves where the original has {}",
            c.len(),
            o.len()
        );
    }
    Ok(o.into_iter().zip(c).collect())
}

/// Pairs runs ([`pair_runs`]) and verifies each pair.
pub fn compare_runs(original: &[Run], candidate: &[Run], tolerance: f64) -> Result<WrittenCheck> {
    compare_runs_within(original, candidate, tolerance, 0.0)
}

/// Run end points count as equal within this share of the tolerance: the
/// rounding of the input's own reading (1,000 G91 moves of 0.0005 in sum
/// to 12.700000000000152 mm in f64; the written `X0.5` reads as 12.7:
/// `straight_segments.ngc`), far below any machine's resolution.
pub const ENDPOINT_ROUNDING_SHARE: f64 = 1e-9;

/// [`compare_runs`], with run end points that may differ by up to
/// `endpoint_slack` mm (0: equal up to [`ENDPOINT_ROUNDING_SHARE`] of the
/// tolerance).
pub fn compare_runs_within(
    original: &[Run],
    candidate: &[Run],
    tolerance: f64,
    endpoint_slack: f64,
) -> Result<WrittenCheck> {
    let pairs_idx = pair_runs(original, candidate)?;
    let mut out = WrittenCheck {
        within: true,
        max_deviation: 0.0,
        endpoint_failures: 0,
        runs_checked: 0,
        failed_runs: Vec::new(),
    };
    let pairs: Vec<(&[Piece], &[Piece])> = pairs_idx
        .iter()
        .map(|&(a, b)| {
            (
                original[a].pieces.as_slice(),
                candidate[b].pieces.as_slice(),
            )
        })
        .collect();
    for (k, rep) in verify_runs(&pairs, &VerifyOptions::new(tolerance))
        .into_iter()
        .enumerate()
    {
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
    Ok(out)
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
    let result = smooth_program(&program, opts, &mut phases)?;
    // Curves that leave their share are a smoother's fault: nothing
    // written from them can be trusted.
    if let Some(bad) = result.runs.iter().find(|r| !r.report.within(opts.budget())) {
        let line = bad.original.pieces.first().map_or(0, |p| p.source_lines.0);
        bail!(
            "refusing to write {}: the smoothed curves of the run starting at line {line} leave \
             the smoothing share of the tolerance ({:.6} mm > {} mm) or move a run endpoint",
            output.display(),
            bad.report.deviation_bound,
            opts.budget()
        );
    }
    // The input and the curves planned side by side, from the runs
    // already read (no copies).
    let (input_times, exact_times, plans) = plan_input_and_curves(&program, &result, opts, true)?;
    let input_times = input_times.expect("the input is planned");
    phases.mark("plan input and curves");
    // The smoothed pieces lent to the emitter and put back for the
    // summary (no copy).
    let mut result = result;
    let smoothed: Vec<Vec<Piece>> = result
        .runs
        .iter_mut()
        .map(|r| std::mem::take(&mut r.smoothed.pieces))
        .collect();
    let emitted = emit(&program, &smoothed, &plans, &opts.emit_options());
    drop(plans);
    for (r, pieces) in result.runs.iter_mut().zip(smoothed) {
        r.smoothed.pieces = pieces;
    }
    let mut emitted = emitted?;
    phases.mark("render, write, check");
    let written_times = plan_written(output, &mut emitted, opts)?;
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
