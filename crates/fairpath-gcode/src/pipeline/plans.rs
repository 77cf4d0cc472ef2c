//! The planned times of a job: the input, the exact curves and the written
//! program, each exactly as `fairpath simulate` plans the file (the same
//! plan of every motion, the times added in the same order, so the same
//! figures to the last bit), but made on all cores and without copies of
//! the runs or of the plans `simulate` keeps for its report; and the plan
//! of each smoothed run at the machine's maximum feed, which the renderer
//! shapes the written pieces by.

use super::{PlanError, SmoothOptions, SmoothResult};
use crate::Program;
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{plan_rapid, plan_run, Corners, PlanOptions, RunPlan};
use fairpath::feed::program::{run_time, simulate, ProgramPlanError, Simulation};
use fairpath::feed::windowed::{plan_time_windowed, PlanWindows, WindowedTimer};
use fairpath::geom::{Curve, Line};
use fairpath::path::{Piece, Run};
use fairpath::pipeline::par_map;

type Result<T, E = PlanError> = core::result::Result<T, E>;

/// Accuracy (mm) of a rapid's length, as `simulate` measures it.
const RAPID_LENGTH_ACCURACY_MM: f64 = 1e-6;

/// Planned times of one program (feed moves and rapids), s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Times {
    pub total: f64,
    pub feed: f64,
}

impl Times {
    pub(crate) fn of(sim: &Simulation) -> Times {
        Times {
            total: sim.time(),
            feed: sim.feed_time,
        }
    }
}

/// Planned times of the motions of a program so far (s), feed moves and
/// rapids apart, added motion by motion in program order as `simulate`
/// adds them: the sums a program planned part by part carries from one
/// part to the next, so that its times are those of the whole to the bit.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TimeSums {
    pub feed: f64,
    pub rapid: f64,
}

impl TimeSums {
    /// The times these sums make.
    pub fn times(&self) -> Times {
        Times {
            total: self.feed + self.rapid,
            feed: self.feed,
        }
    }
}

/// How `simulate` plans a run: on `machine`, at its maximum feed or the
/// programmed ones, from rest to rest, with the whole look-ahead.
fn whole_run_options(machine: &MachineLimits, override_feed: bool) -> PlanOptions {
    PlanOptions {
        limits: *machine,
        override_feed,
        window: None,
        ends: Default::default(),
    }
}

/// The plans of a run that goes on from one part to the next (a long run
/// cut into windows: [`crate::interp::RunWindows`]): the input's and the
/// curves', each made a window at a time as the parts come
/// ([`CarriedPlan`]) and its time added where the run ends, in program
/// order; each part's own plans (the renderer's, the writer's choices)
/// plan its window from rest to rest.
#[derive(Default)]
pub struct RunCarry {
    input: Option<CarriedPlan>,
    exact: Option<CarriedPlan>,
}

/// The plan of a run that goes on into the next part: made a window at a
/// time ([`WindowedTimer`], which plans as [`plan_time_windowed`] does, in
/// the same windows, so the time is the one `simulate` gives the whole
/// run, [`run_time`], wherever its windows stitch; elsewhere
/// [`PlanError::Unstitched`]).
#[derive(Clone)]
pub struct CarriedPlan {
    timer: WindowedTimer,
    /// The piece before the cut, not yet planned: where it is a line of
    /// the cut line and the next part's run starts with one, the two are
    /// planned as one line (a part's reading splits the cut line; the
    /// program does not, nor do curves that keep it straight there).
    half: Option<Piece>,
}

#[cfg(test)]
std::thread_local! {
    /// The written plan of a run cut into windows is taken for one that
    /// does not stitch (on this thread).
    pub(crate) static UNSTITCH_WRITTEN: core::cell::Cell<bool> =
        const { core::cell::Cell::new(false) };
}

/// The windows the carried plans (the input's, the curves' and the
/// written text's) are made in: those every run's time is planned in
/// ([`PlanWindows::DEFAULT`], [`run_time`]), so that a run cut into parts
/// has the time `simulate` gives the whole file. (Smaller windows held
/// less, but their stitches differ from the default's where windows are
/// not the whole plan: `fairpath::feed::windowed`.)
const CARRIED_WINDOWS: PlanWindows = PlanWindows::DEFAULT;

/// How [`carry_runs`] takes a part's runs.
struct Carrying<'a> {
    outline: &'a [MotionOutline],
    runs: &'a [&'a [Piece]],
    /// The part ends in a window's cut: its last run goes on.
    cut: bool,
    /// Whether the piece held back before the cut and the first piece of
    /// the run going on are planned as one line: `None`, where they are
    /// line pieces of the same line (the input's and the curves' plans:
    /// the cut line's two halves); `Some(join)` as given (the written
    /// plan: where the cut line was dropped).
    join: Option<bool>,
    po: &'a PlanOptions,
    /// The windows the plan is made in.
    windows: PlanWindows,
    what: &'static str,
}

/// Sets motion `j`'s time in `done` to `t` (a run not planned for its
/// part gets its time here).
fn set_time(done: &mut [Option<Done>], j: usize, t: f64) {
    match &mut done[j] {
        Some(d) => d.0 = t,
        None => done[j] = Some((t, 0.0, None)),
    }
}

/// Sets in `done` the times `carried` gives (those [`carry_runs`] set in
/// an empty `done`).
fn set_carried(done: &mut [Option<Done>], carried: &[Option<Done>]) {
    for (j, c) in carried.iter().enumerate() {
        if let Some((t, _, _)) = c {
            set_time(done, j, *t);
        }
    }
}

/// An empty `done` for `n` motions.
fn alloc_done(n: usize) -> Vec<Option<Done>> {
    (0..n).map(|_| None).collect()
}

/// Gives the runs of a part that go on across parts their times in
/// `done`: the first, where `carry` holds the run it goes on (its pieces
/// join the plan, and where the run ends here its time is the carried
/// plan's); the last, where the part is cut (its pieces start or join the
/// plan carried on, and it adds nothing here).
fn carry_runs(
    done: &mut [Option<Done>],
    carry: &mut Option<CarriedPlan>,
    c: Carrying<'_>,
) -> Result<()> {
    let at: Vec<(usize, usize)> = c
        .outline
        .iter()
        .enumerate()
        .filter_map(|(j, m)| match m {
            MotionOutline::Run(k) => Some((j, *k)),
            _ => None,
        })
        .collect();
    let what = c.what;
    let error = |pieces: &[Piece], source| PlanError::Plan {
        what,
        source: ProgramPlanError::Run {
            line: pieces.first().map_or(0, |p| p.source_lines.0),
            source,
        },
    };
    // Pushes a run's pieces, the cut line's halves joined where asked (a
    // line piece of the cut line on either side of the cut is one line),
    // the last held back where it may be the first of them.
    let push = |plan: &mut CarriedPlan, pieces: &[Piece], cut_after: bool| -> Result<()> {
        let mut pieces = pieces;
        if let Some(half) = plan.half.take() {
            let join = c.join.unwrap_or(true);
            let same = |first: &Piece| c.join.is_some() || first.source_lines == half.source_lines;
            let joined = match (pieces.first(), &half.curve) {
                (Some(first), Curve::Line(a)) if join && same(first) => match &first.curve {
                    Curve::Line(b) => Some(Piece {
                        curve: Curve::Line(Line::new(a.p0, b.p1)),
                        ..first.clone()
                    }),
                    _ => None,
                },
                _ => None,
            };
            match joined {
                Some(whole) => {
                    plan.timer.push(&[whole]).map_err(|e| error(pieces, e))?;
                    pieces = &pieces[1..];
                }
                None => plan.timer.push(&[half]).map_err(|e| error(pieces, e))?,
            }
        }
        if cut_after {
            if let Some((last, rest)) = pieces.split_last() {
                if matches!(last.curve, Curve::Line(_)) {
                    plan.half = Some(last.clone());
                    pieces = rest;
                }
            }
        }
        plan.timer.push(pieces).map_err(|e| error(pieces, e))
    };
    let Some(&(j_last, k_last)) = at.last() else {
        return Ok(());
    };
    if let Some(plan) = carry.as_mut() {
        let (j, k) = at[0];
        let goes_on = c.cut && at.len() == 1;
        push(plan, c.runs[k], goes_on)?;
        if goes_on {
            set_time(done, j, 0.0);
            return Ok(());
        }
        let plan = carry.take().expect("held");
        debug_assert!(plan.half.is_none());
        let t = plan
            .timer
            .finish()
            .map_err(|e| error(c.runs[k], e))?
            .ok_or(PlanError::Unstitched { what })?;
        set_time(done, j, t);
    }
    if c.cut {
        let timer = WindowedTimer::new(c.po, Corners::Blended, c.windows)
            .ok_or(PlanError::Unstitched { what })?;
        let mut plan = CarriedPlan { timer, half: None };
        push(&mut plan, c.runs[k_last], true)?;
        set_time(done, j_last, 0.0);
        *carry = Some(plan);
    }
    Ok(())
}

/// The three plans of a job: the input, the exact curves and the written
/// program, on the same machine with the same feeds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JobTimes {
    pub input: Times,
    pub exact: Times,
    pub written: Times,
}

pub use crate::program::{into_outline_and_runs, MotionOutline};

/// The motions of `program` in order, as [`Program::motions`] makes them,
/// with its runs by index: what planning it needs once the program itself
/// is dropped.
pub fn outline(program: &Program) -> Vec<MotionOutline> {
    let spans = program.run_spans();
    let moves = program.moves();
    let mut out = Vec::with_capacity(2 * spans.len() + 1);
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

/// What planning a program's motions gives: its times, and with
/// `keep_plans` the plan of each run (in run order).
struct Planned {
    sums: TimeSums,
    plans: Vec<RunPlan>,
}

/// One motion's plan: feed time, rapid time, and the run's plan where kept
/// (with the run's index).
type Done = (f64, f64, Option<(usize, RunPlan)>);

/// The times of the motions of `outline` with run `k`'s pieces taken from
/// `runs[k]`, planned on all cores and added in order as `simulate` adds
/// them; run `k`'s time is `known[k]` where that is `Some` (a plan with the
/// same options, already made). `what` names the step in errors.
#[allow(clippy::too_many_arguments)]
fn plan_outline(
    start: TimeSums,
    outline: &[MotionOutline],
    runs: &[&[Piece]],
    known: &[Option<f64>],
    machine: &MachineLimits,
    override_feed: bool,
    keep_plans: bool,
    what: &'static str,
) -> Result<Planned> {
    let done = motion_times(
        outline,
        runs,
        known,
        &[],
        machine,
        override_feed,
        keep_plans,
        what,
    )?;
    Ok(add_up(
        start,
        done.into_iter().map(|d| d.unwrap_or((0.0, 0.0, None))),
    ))
}

/// Each motion's plan, as [`plan_outline`] makes them, in order; `None`
/// for a run `k` with `skip[k]` (planned elsewhere).
#[allow(clippy::too_many_arguments)]
fn motion_times(
    outline: &[MotionOutline],
    runs: &[&[Piece]],
    known: &[Option<f64>],
    skip: &[bool],
    machine: &MachineLimits,
    override_feed: bool,
    keep_plans: bool,
    what: &'static str,
) -> Result<Vec<Option<Done>>> {
    let error = |source| PlanError::Plan { what, source };
    let po = whole_run_options(machine, override_feed);
    par_map(outline.len(), |j| {
        let feed_run = |k: Option<usize>, pieces: &[Piece]| -> Result<Option<Done>> {
            if k.is_some_and(|k| skip.get(k).copied().unwrap_or(false)) {
                return Ok(None);
            }
            if let Some(t) = k.and_then(|k| known.get(k).copied().flatten()) {
                return Ok(Some((t, 0.0, None)));
            }
            let line = pieces.first().map(|p| p.source_lines.0).unwrap_or(0);
            let run_error = |source| error(ProgramPlanError::Run { line, source });
            match k.filter(|_| keep_plans) {
                Some(k) => {
                    let plan = plan_run(pieces, &po).map_err(run_error)?;
                    let time = run_time(pieces, &po, &plan).map_err(run_error)?;
                    Ok(Some((time, 0.0, Some((k, plan)))))
                }
                None => {
                    // Window by window on a long run, in a window's
                    // memory: `simulate`'s time ([`run_time`]).
                    let time =
                        plan_time_windowed(pieces, &po, Corners::Blended, PlanWindows::DEFAULT)
                            .map_err(run_error)?;
                    Ok(Some((time, 0.0, None)))
                }
            }
        };
        match &outline[j] {
            MotionOutline::Run(k) => feed_run(Some(*k), runs[*k]),
            MotionOutline::Pinned(p) => feed_run(None, core::slice::from_ref(p)),
            MotionOutline::Rapid(p) => {
                let len = p.curve.length(RAPID_LENGTH_ACCURACY_MM);
                if len.is_nan() || len <= 0.0 {
                    return Ok(Some((0.0, 0.0, None)));
                }
                let prof = plan_rapid(len, machine)
                    .map_err(|source| error(ProgramPlanError::Rapid(source)))?;
                Ok(Some((0.0, prof.duration(), None)))
            }
        }
    })
    .into_iter()
    .collect()
}

/// The motions' times added in order, as `simulate` adds them, and the
/// plans kept.
fn add_up(start: TimeSums, done: impl Iterator<Item = Done>) -> Planned {
    let TimeSums {
        mut feed,
        mut rapid,
    } = start;
    let mut plans = Vec::new();
    for (f, r, plan) in done {
        feed += f;
        rapid += r;
        if let Some((k, plan)) = plan {
            debug_assert_eq!(k, plans.len());
            plans.push(plan);
        }
    }
    Planned {
        sums: TimeSums { feed, rapid },
        plans,
    }
}

/// The planned time of the input, as `fairpath simulate` plans the file.
pub fn plan_input(program: &Program, opts: &SmoothOptions) -> Result<Times> {
    let runs = program.runs();
    let pieces: Vec<&[Piece]> = runs.iter().map(|r| r.pieces.as_slice()).collect();
    let (m, o) = (&opts.machine, opts.override_feed);
    let what = "the input";
    let start = TimeSums::default();
    Ok(
        plan_outline(start, &outline(program), &pieces, &[], m, o, false, what)?
            .sums
            .times(),
    )
}

/// The planned time of the exact curves in the program, and the plan of
/// each smoothed run that the renderer shapes the written pieces for: at
/// the machine's maximum feed, so that the written program keeps the
/// curves' speed at any feed (a feed override above 100% included), not
/// just at the programmed one. A run smoothed into itself is written as
/// the program wrote it, never rendered ([`crate::emit::emit`]): its plan
/// is empty.
pub fn plan_curves(
    program: &Program,
    result: &SmoothResult,
    opts: &SmoothOptions,
) -> Result<(Times, Vec<RunPlan>)> {
    let none = TimeSums::default();
    let (_, exact, plans) = plan_job(program, result, opts, None, none, None, None)?;
    Ok((exact.times(), plans))
}

/// [`plan_input`] (from the runs already read) and [`plan_curves`], made
/// side by side.
pub fn plan_input_and_curves(
    program: &Program,
    result: &SmoothResult,
    opts: &SmoothOptions,
) -> Result<(Times, Times, Vec<RunPlan>)> {
    let none = TimeSums::default();
    let (input, exact, plans) =
        plan_input_and_curves_from(program, result, opts, none, none, None)?;
    Ok((input.times(), exact.times(), plans))
}

/// [`plan_input_and_curves`] of `program`, a part of a program, with the
/// times of the parts before it: the sums of the input and of the curves
/// so far ([`TimeSums`]), which it returns with its own added. A run whose
/// rendering `memo` holds gets no renderer's plan (an empty one: the
/// writer takes the rendering, and plans the run itself if it must
/// render it after all).
pub fn plan_input_and_curves_from(
    program: &Program,
    result: &SmoothResult,
    opts: &SmoothOptions,
    input: TimeSums,
    exact: TimeSums,
    memo: Option<&super::RenderMemo>,
) -> Result<(TimeSums, TimeSums, Vec<RunPlan>)> {
    let mut carry = RunCarry::default();
    plan_input_and_curves_carried(program, result, opts, (input, exact), memo, &mut carry)
}

/// [`plan_input_and_curves_from`] of a part whose first run may go on
/// from the part before and whose last may go on into the next
/// ([`Program::window_cut`]): their plans are carried in `carry`
/// ([`RunCarry`]).
pub fn plan_input_and_curves_carried(
    program: &Program,
    result: &SmoothResult,
    opts: &SmoothOptions,
    (input, exact): (TimeSums, TimeSums),
    memo: Option<&super::RenderMemo>,
    carry: &mut RunCarry,
) -> Result<(TimeSums, TimeSums, Vec<RunPlan>)> {
    let (input, exact, plans) =
        plan_job(program, result, opts, Some(input), exact, memo, Some(carry))?;
    Ok((input.expect("the input is planned"), exact, plans))
}

/// The plans of [`plan_input_and_curves`] (the input only with `input`),
/// as tasks side by side: each task plans its runs on all cores, and two
/// tasks at a time keep both cores of a small machine busy where one long
/// run would leave one idle; more at once would only hold more plans.
fn plan_job(
    program: &Program,
    result: &SmoothResult,
    opts: &SmoothOptions,
    input_from: Option<TimeSums>,
    exact_from: TimeSums,
    memo: Option<&super::RenderMemo>,
    carry: Option<&mut RunCarry>,
) -> Result<(Option<TimeSums>, TimeSums, Vec<RunPlan>)> {
    let input = input_from.is_some();
    #[derive(Clone, Copy)]
    enum Task {
        Input,
        /// The curves at the user's feeds (with the plans, when those are
        /// the renderer's: feeds overridden).
        Exact,
        /// The renderer's plans, at the maximum feed.
        Plans,
    }
    let (m, override_feed) = (&opts.machine, opts.override_feed);
    let outline = outline(program);
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
    let renderer_plans = || -> Result<Vec<RunPlan>> {
        let po = whole_run_options(m, true);
        par_map(curves.len(), |k| {
            // Not rendered (smoothed into itself), or rendered already by
            // `auto`'s objective (the writer plans it if it must render it
            // after all).
            if result.runs[k].original.pieces == curves[k]
                || memo.is_some_and(|m| m.holds(curves[k], 0))
            {
                return Ok(RunPlan::default());
            }
            let line = curves[k].first().map(|p| p.source_lines.0).unwrap_or(0);
            plan_run(curves[k], &po).map_err(|source| PlanError::Plan {
                what: "the curves",
                source: ProgramPlanError::Run { line, source },
            })
        })
        .into_iter()
        .collect()
    };
    // A run smoothed into itself (every run with `none`) is planned once,
    // for the input, and its time counted for the curves too: the same
    // pieces plan to the same bits. Not where the curves' plans are kept
    // (feeds overridden: they are the renderer's).
    let shared: Vec<bool> = if input && !override_feed {
        result
            .runs
            .iter()
            .map(|r| r.original.pieces == r.smoothed.pieces)
            .collect()
    } else {
        Vec::new()
    };
    // The runs that go on across parts: their times are the carried
    // plans' (`carry_runs`), not planned here.
    let continued = carry.as_ref().is_some_and(|c| c.input.is_some());
    let n_runs = result.runs.len();
    let goes_on: Vec<bool> = (0..n_runs)
        .map(|k| (k == 0 && continued) || (k + 1 == n_runs && program.window_cut()))
        .collect();
    let any_goes_on = goes_on.iter().any(|&g| g);
    let skip_exact: Vec<bool> = if any_goes_on && !override_feed {
        (0..n_runs)
            .map(|k| goes_on[k] || shared.get(k).copied().unwrap_or(false))
            .collect()
    } else {
        shared.clone()
    };
    let skip_input: &[bool] = if any_goes_on { &goes_on } else { &[] };
    enum Out {
        Motions(Vec<Option<Done>>),
        Plans(Vec<RunPlan>),
    }
    // The runs that go on across parts are timed by the plans carried
    // across the parts (`carry_runs`): the input's and the curves', side
    // by side with the tasks, which they do not need (each sets only the
    // times of the runs that go on, applied below).
    let cut = program.window_cut();
    let po = whole_run_options(m, override_feed);
    let carried = carry.filter(|c| c.input.is_some() || cut);
    let originals: Vec<&[Piece]> = result
        .runs
        .iter()
        .map(|r| r.original.pieces.as_slice())
        .collect();
    let (originals, curves_ref) = (&originals, &curves);
    let carrying = |runs, what| Carrying {
        outline: &outline,
        runs,
        cut,
        join: None,
        po: &po,
        windows: CARRIED_WINDOWS,
        what,
    };
    let n_motions = outline.len();
    type Carried = Result<Vec<Option<Done>>>;
    let (done, carried): (_, Option<(Option<Carried>, Carried)>) = std::thread::scope(|sc| {
        let carries = carried.map(|c| {
            let RunCarry {
                input: ci,
                exact: ce,
            } = c;
            let times = move |runs, what, plan: &mut Option<CarriedPlan>| -> Carried {
                let mut t = alloc_done(n_motions);
                carry_runs(&mut t, plan, carrying(runs, what)).map(|()| t)
            };
            let hi = input.then(|| sc.spawn(move || times(originals, "the input", ci)));
            let he = sc.spawn(move || times(curves_ref, "the curves", ce));
            (hi, he)
        });
        let done: Vec<Result<Out>> = par_map(tasks.len(), |i| match tasks[i] {
            Task::Input => {
                let what = "the input";
                let o = override_feed;
                motion_times(&outline, originals, &[], skip_input, m, o, false, what)
                    .map(Out::Motions)
            }
            Task::Exact => {
                let what = "the curves";
                let keep = override_feed;
                // The curves `auto`'s objective planned already (at the same
                // feeds, with the same options: not where the plans are kept).
                let known: Vec<Option<f64>> = match memo.filter(|_| !keep) {
                    Some(m) => curves.iter().map(|c| m.bound_of(c)).collect(),
                    None => Vec::new(),
                };
                motion_times(
                    &outline,
                    &curves,
                    &known,
                    &skip_exact,
                    m,
                    override_feed,
                    keep,
                    what,
                )
                .map(Out::Motions)
            }
            Task::Plans => renderer_plans().map(Out::Plans),
        });
        let join = |h: std::thread::ScopedJoinHandle<'_, Carried>| {
            h.join().unwrap_or_else(|e| std::panic::resume_unwind(e))
        };
        let carried = carries.map(|(hi, he)| (hi.map(join), join(he)));
        (done, carried)
    });
    let (mut input_done, mut exact_done, mut plans) = (None, None, Vec::new());
    for (task, d) in tasks.into_iter().zip(done) {
        match (task, d?) {
            (Task::Input, Out::Motions(m)) => input_done = Some(m),
            (Task::Exact, Out::Motions(m)) => exact_done = Some(m),
            (_, Out::Plans(p)) => plans = p,
            _ => unreachable!("each task gives its kind"),
        }
    }
    let mut exact_done = exact_done.expect("the curves are planned");
    if let Some((input_carried, exact_carried)) = carried {
        // The curves' runs that go on across parts are planned for the
        // curves too (their windows may be smoothed into themselves in
        // one part and not in the next).
        for (j, d) in exact_done.iter_mut().enumerate() {
            if d.is_none() {
                *d = input_done.as_ref().and_then(|i| i[j].clone());
            }
        }
        if let (Some(done), Some(times)) = (&mut input_done, input_carried) {
            set_carried(done, &times?);
        }
        set_carried(&mut exact_done, &exact_carried?);
    }
    // The curves' shared runs take the input's times, motion by motion.
    let exact_planned = add_up(
        exact_from,
        exact_done.into_iter().enumerate().map(|(j, d)| {
            d.or_else(|| {
                input_done
                    .as_ref()
                    .and_then(|i| i[j].as_ref())
                    .map(|(f, r, _)| (*f, *r, None))
            })
            .expect("a shared run is planned for the input")
        }),
    );
    if override_feed {
        plans = exact_planned.plans;
    }
    let input_sums = input_done.map(|d| {
        let start = input_from.unwrap_or_default();
        add_up(
            start,
            d.into_iter().map(|x| x.expect("the input skips nothing")),
        )
        .sums
    });
    Ok((input_sums, exact_planned.sums, plans))
}

/// The planned time of a written program's text, exactly as `fairpath
/// simulate` plans the file (G-code, or fairpath's JSON).
pub fn plan_text(text: &str, opts: &SmoothOptions) -> Result<Times> {
    let is_json = text.bytes().find(|b| !b.is_ascii_whitespace()) == Some(b'{');
    if is_json {
        let motions = crate::json_motions(text).map_err(PlanError::ReadWrittenJson)?;
        let sim =
            simulate(&motions, &opts.machine, opts.override_feed, None).map_err(|source| {
                PlanError::Plan {
                    what: "the written program",
                    source,
                }
            })?;
        return Ok(Times::of(&sim));
    }
    let (outline, runs) = crate::read_motion(text.as_bytes()).map_err(PlanError::ReadWritten)?;
    let pieces: Vec<&[Piece]> = runs.iter().map(|r| r.pieces.as_slice()).collect();
    let (m, o) = (&opts.machine, opts.override_feed);
    let what = "the written program";
    let start = TimeSums::default();
    Ok(
        plan_outline(start, &outline, &pieces, &[], m, o, false, what)?
            .sums
            .times(),
    )
}

/// The written G-code as the writer's check read it back: its motions,
/// its runs, and the time of each run at the user's feeds where the check
/// already planned it exactly as `fairpath simulate` does (else `None`).
#[derive(Clone, Debug)]
pub struct WrittenReading {
    pub outline: Vec<MotionOutline>,
    pub runs: Vec<Run>,
    pub run_times: Vec<Option<f64>>,
}

/// [`plan_text`] of a written G-code program from the reading its check
/// made ([`crate::emit::Emitted::reading`]): no second reading of the
/// text, and the runs the check planned at the user's feeds not planned
/// again. The same figures as [`plan_text`].
pub fn plan_written(reading: &WrittenReading, opts: &SmoothOptions) -> Result<Times> {
    Ok(plan_written_from(reading, opts, TimeSums::default())?.times())
}

/// [`plan_written`] of the reading of a written part of a program, with
/// the sums of the parts before it ([`TimeSums`]); returns them with its
/// own added.
pub fn plan_written_from(
    reading: &WrittenReading,
    opts: &SmoothOptions,
    start: TimeSums,
) -> Result<TimeSums> {
    plan_written_carried(reading, opts, start, &mut None, (false, false))
}

/// [`plan_written_from`] of a part whose first run may go on from the
/// part before (`carry` then holds its plan) and whose last goes on into
/// the next where the part is `cut` ([`Program::window_cut`]): see
/// [`RunCarry`]. A run that goes on must be held by the reading.
/// `dropped`: the cut line the part before held back was dropped (the
/// run was kept as written on both sides of the cut:
/// [`crate::write_gcode::WriterCarry::cut_line`]), so the written text
/// goes on with the program's own cut line from the line before the cut.
pub fn plan_written_carried(
    reading: &WrittenReading,
    opts: &SmoothOptions,
    start: TimeSums,
    carry: &mut Option<CarriedPlan>,
    (cut, dropped): (bool, bool),
) -> Result<TimeSums> {
    let pieces: Vec<&[Piece]> = reading.runs.iter().map(|r| r.pieces.as_slice()).collect();
    let (m, o) = (&opts.machine, opts.override_feed);
    let what = "the written program";
    let known = &reading.run_times;
    let outline = &reading.outline;
    // The runs that go on across parts: timed by the carried plan, not
    // here (their first and last runs where a part starts or ends at a cut).
    let ends: Vec<usize> = outline
        .iter()
        .filter_map(|m| match m {
            MotionOutline::Run(k) => Some(*k),
            _ => None,
        })
        .collect();
    let goes_on = [
        ends.first().filter(|_| carry.is_some()),
        ends.last().filter(|_| cut),
    ];
    let mut skip = vec![false; pieces.len()];
    for &&k in goes_on.iter().flatten() {
        skip[k] = true;
    }
    let mut done = motion_times(outline, &pieces, known, &skip, m, o, false, what)?;
    #[cfg(test)]
    if cut && UNSTITCH_WRITTEN.with(|u| u.get()) {
        return Err(PlanError::Unstitched { what });
    }
    if carry.is_some() || cut {
        let po = whole_run_options(m, o);
        // (A run checked as it was read holds no pieces.)
        let held = |k: usize| {
            !reading.runs[k].pieces.is_empty() || known.get(k).copied().flatten().is_none()
        };
        if goes_on.iter().flatten().any(|&&k| !held(k)) {
            return Err(PlanError::Unstitched { what });
        }
        let c = Carrying {
            outline,
            runs: &pieces,
            cut,
            join: Some(dropped),
            po: &po,
            windows: CARRIED_WINDOWS,
            what,
        };
        carry_runs(&mut done, carry, c)?;
    }
    Ok(add_up(
        start,
        done.into_iter().map(|d| d.unwrap_or((0.0, 0.0, None))),
    )
    .sums)
}
