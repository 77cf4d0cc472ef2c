//! What `auto` minimises, injected by the caller: the user's machine.
//!
//! `auto` smooths each run several ways and keeps the cheapest; what
//! "cheapest" means is not the method's business. A CAM system ranks by
//! the planned time on the machine that will cut the part, a researcher
//! perhaps by peak curvature. The method only asks an [`Objective`].
//!
//! Two are given here: [`PlannedTime`], the time of the exact curves (what
//! a program of exact curves, the JSON output, carries), and
//! [`WrittenTime`], the time of the curves as a G-code writer will render
//! them (what a G-code program carries).

use super::written_choice::WriterTries;
use crate::feed::limits::MachineLimits;
use crate::feed::plan::{plan_run, Corners, PlanOptions};
use crate::feed::windowed::{plan_time_windowed, PlanWindows, WindowedTimer};
use crate::geom::tube_fair::PeakPass;
use crate::geom::Curve;
use crate::path::Piece;
use crate::render::{
    linuxcnc_g5_2_motion, render_range, render_run, CurveForm, LineAbsorber, PlannedSpeed,
    RenderOptions, RenderStats, Rendered,
};
use crate::smooth::FairOptions;
use alloc::sync::Arc;
use alloc::vec::Vec;

/// A cost of running a smoothed run (lower is better).
pub trait Objective: core::fmt::Debug + Send + Sync {
    /// The cost of `pieces` (one continuous run), or `None` when it cannot
    /// be run at all (the planner rejects it); such candidates are kept only
    /// when no other can be run.
    fn cost(&self, pieces: &[Piece]) -> Option<f64>;

    /// A lower bound of [`Objective::cost`] that is cheaper to compute, or
    /// `None` (the default) when there is none: then every candidate is
    /// costed. With a bound, `auto` costs the candidates in the order of
    /// their bounds and stops where a bound exceeds the least cost found,
    /// which keeps the cheapest wherever the bound holds.
    fn bound(&self, _pieces: &[Piece]) -> Option<f64> {
        None
    }

    /// The share of a candidate's cost its [`Objective::bound`] may lie
    /// below it by design (0, the default, for a bound close to the
    /// cost): candidates whose bounds lie within it of the least bound
    /// still in the race are most likely all costed, so `auto` costs them
    /// side by side.
    fn bound_slack(&self) -> f64 {
        0.0
    }

    /// The cost of `pieces` written exactly as they are (not rendered), or
    /// `None` (the default) when the objective does not say. For a run as
    /// the program wrote it, that is what a writer that keeps the run
    /// costs; G-code writers keep a run whose rendering is not
    /// [`KEEP_MARGIN`] cheaper. `auto` reads it to try the corner methods
    /// on the curves as written where its curvature-continuous candidates
    /// would be kept so (see [`super::Auto`]).
    fn as_written(&self, _pieces: &[Piece]) -> Option<f64> {
        None
    }

    /// Whether a writer writes `candidate`, of cost `cost`
    /// ([`Objective::cost`]), in place of `run`, which costs `own` as
    /// the program wrote it ([`Objective::as_written`]). By default where
    /// it costs [`KEEP_MARGIN`] less; an objective whose writer judges a
    /// run at more than the feeds it costs at says so here
    /// ([`WrittenTime`]: also at the machine's maximum feed). `auto` reads
    /// it to tell whether its best curvature-continuous candidate would be
    /// kept as the program wrote it (see [`super::Auto`]).
    fn written_instead(&self, _candidate: &[Piece], cost: f64, _run: &[Piece], own: f64) -> bool {
        cost * (1.0 + KEEP_MARGIN) <= own
    }

    /// Whether a writer that keeps `candidate` from its forms
    /// ([`Objective::written_instead`] false) writes it as G1 in place of
    /// `run` (costing `own` as written) all the same: the G-code writer
    /// tries its all-G1 rendering on every run whose other forms do not
    /// gain ([`WrittenTime::lines_alternative`]). None by default.
    fn written_as_lines(&self, _candidate: &[Piece], _run: &[Piece], _own: f64) -> bool {
        false
    }

    /// Whether `a` is the better of two smoothings of one run, `b` the
    /// other: by default where it costs less ([`Objective::cost`]; one
    /// that cannot be run is never better). An objective whose writer
    /// judges at more than the feeds it costs at says so here
    /// ([`PlannedTime`] at the programmed feeds: also at the machine's
    /// maximum feed, as the G-code writers judge a run). `fair` reads it
    /// to choose between its two smoothings of a run with arcs or curves
    /// it cannot fair itself ([`crate::smooth::FairAlternatives`]).
    fn prefers(&self, a: &[Piece], b: &[Piece]) -> bool {
        match (self.cost(a), self.cost(b)) {
            (Some(ca), Some(cb)) => ca < cb,
            (Some(_), None) => true,
            _ => false,
        }
    }

    /// What a fairing inside the tolerance tube should lower for this
    /// objective ([`crate::smooth::FairOptions::peak_pass`]), or `None`
    /// (the default) when the objective does not say: then the default
    /// machine's caps ([`PeakPass::DEFAULT_MACHINE`]).
    fn peak_pass(&self) -> Option<PeakPass> {
        None
    }

    /// Whether the objective runs every move at the machine's maximum
    /// feed, whatever the program's feeds (false, the default: the
    /// programmed feeds): a fairing's peak pass then works up to that
    /// feed ([`crate::smooth::FairOptions::programmed_feeds`]).
    fn feeds_overridden(&self) -> bool {
        false
    }

    /// The cost of `pieces` (of cost `cost`, [`Objective::cost`]) as a
    /// writer finally writes them, where it tries more than the objective
    /// ranks by: `cost` by default. [`WrittenTime`] with
    /// [`WrittenTime::writer_tries`]: the time of the rendering the
    /// writer chooses among those and its own. `auto` reads it to choose
    /// among the candidates nearest its best ([`super::FINAL_COST_MARGIN`]).
    fn final_cost(&self, _pieces: &[Piece], cost: f64) -> f64 {
        cost
    }
}

/// A run is rewritten only if its smoothing costs at least this share less
/// than the run as the program wrote it: the writers' rule (the rounding
/// of written coordinates can cost a few parts in ten thousand, and at an
/// equal time a rendering would trade the program's corners for more
/// blocks, for nothing).
pub const KEEP_MARGIN: f64 = 1e-3;

/// Share of its time by which a writer's rendering at its finer curvature
/// step ([`super::WriterTries::finer_share`]) must plan faster than the one
/// it would replace, at every feed the writer judges at, to be written
/// instead. The renderings are judged as rendered, and the finer one's
/// plan drifts further from its written text's (its more, shorter pieces
/// read back with rounded coordinates): on a chirp smoothed by
/// `bspline-corner` (`fairpath_gcode`'s test
/// `the_finer_step_is_never_slower`, amplitude 8, growth 1, F3000) the
/// finer arcs were judged 0.10% faster (0.16% at the programmed feed)
/// and read back 0.21% slower; [`KEEP_MARGIN`] let that through. 0.5%
/// also turned away finer renderings that read back faster (measurements:
/// docs/tuning.md, `FINER_KEEP_MARGIN`).
pub const FINER_KEEP_MARGIN: f64 = 2e-3;

/// The machining time (s) planned by the jerk-limited look-ahead planner
/// ([`plan_run`]) on one machine: `auto`'s objective in the CLI, with the
/// user's `--machine`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlannedTime {
    pub plan: PlanOptions,
}

impl PlannedTime {
    /// The time on `limits`, at the machine's maximum feed when
    /// `override_feed` (so the choice depends on the geometry, not on a
    /// feed the program may set low) or at the programmed feeds.
    pub fn new(limits: MachineLimits, override_feed: bool) -> Self {
        PlannedTime {
            plan: PlanOptions {
                limits,
                override_feed,
                window: None,
                ends: Default::default(),
            },
        }
    }
}

impl Default for PlannedTime {
    /// The machine of seed 003's simulations (400 mm/s, 4000 mm/s^2,
    /// 20000 mm/s^3, 1 ms; [`MachineLimits::thesis`]) at its maximum feed:
    /// a reference machine for callers that have none of their own.
    fn default() -> Self {
        PlannedTime::new(MachineLimits::thesis(), true)
    }
}

/// What a fairing should lower on the machine `m`: the speed caps of its
/// full model ([`PeakPass::SpeedCaps`]: its maximum feed, normal
/// acceleration and jerk), or, where the machine caps curves by their
/// normal acceleration alone (`jerk_on_curves` off, the thesis' model),
/// the curvature, whose highest value then sets the lowest cap.
pub fn peak_pass_for(m: &MachineLimits) -> PeakPass {
    if m.jerk_on_curves {
        PeakPass::SpeedCaps {
            max_feed: m.max_feed,
            normal_acc: m.normal_acc,
            jerk: m.jerk,
            period: m.period,
        }
    } else {
        PeakPass::Curvature
    }
}

/// `options` with the default peak pass ([`PeakPass::DEFAULT_MACHINE`])
/// replaced by what `objective` says a fairing should lower
/// ([`Objective::peak_pass`]): `fair`, alone or as `auto`'s candidate,
/// lowers the demand of the user's machine, not of the default one (a
/// pass set to anything else is kept).
///
/// Where the objective overrides the program's feeds
/// ([`Objective::feeds_overridden`]), the pass also works up to the
/// machine's maximum feed, not each curve's programmed one
/// ([`FairOptions::programmed_feeds`] off): at `--override-feed` the
/// machine runs `fair`'s curves at up to that feed.
pub fn fair_on(options: FairOptions, objective: &dyn Objective) -> FairOptions {
    let options = FairOptions {
        programmed_feeds: options.programmed_feeds && !objective.feeds_overridden(),
        ..options
    };
    match objective.peak_pass() {
        Some(pass) if options.peak_pass == PeakPass::DEFAULT_MACHINE => FairOptions {
            peak_pass: pass,
            ..options
        },
        _ => options,
    }
}

impl Objective for PlannedTime {
    fn cost(&self, pieces: &[Piece]) -> Option<f64> {
        plan_run(pieces, &self.plan).ok().map(|p| p.time)
    }
    fn peak_pass(&self) -> Option<PeakPass> {
        Some(peak_pass_for(&self.plan.limits))
    }
    fn feeds_overridden(&self) -> bool {
        self.plan.override_feed
    }

    /// Less at the objective's feeds and, where those are the programmed
    /// ones, at the machine's maximum feed too: the G-code writers keep a
    /// run as the program wrote it unless its rendering is faster at every
    /// feed, so a smoothing faster at the programmed feed but slower at an
    /// override would be no gain.
    fn prefers(&self, a: &[Piece], b: &[Piece]) -> bool {
        let less = |plan: &PlanOptions| match (plan_run(a, plan), plan_run(b, plan)) {
            (Ok(pa), Ok(pb)) => pa.time < pb.time,
            (Ok(_), Err(_)) => true,
            _ => false,
        };
        let at_maximum = PlanOptions {
            override_feed: true,
            ..self.plan
        };
        less(&self.plan) && (self.plan.override_feed || less(&at_maximum))
    }

    /// The same plan: the run's pieces are what is run.
    fn as_written(&self, pieces: &[Piece]) -> Option<f64> {
        self.cost(pieces)
    }
}

/// How the objective plans a long run's time ([`plan_time_windowed`]:
/// the same time as the whole plan; a section of a raster rendered as
/// arcs holds hundreds of thousands of blocks).
const WINDOWS: PlanWindows = PlanWindows::DEFAULT;

/// The time (s) of the program a G-code writer will write for the run:
/// the exact curves planned at the machine's maximum feed ([`plan_run`],
/// the speed the writer's renderer shapes the written pieces by), rendered
/// in each form the output format allows ([`render_run`]), and the fastest
/// rendering planned at the user's feeds as the writer judges it
/// ([`plan_time_windowed`], the whole plan's time in a window's memory,
/// with [`WrittenTime::corners`]).
///
/// What the user runs is the written program, not the exact curves: a
/// candidate whose curves plan fastest can render into more, shorter
/// pieces with curvature steps at their joints, or into G1 lines where
/// arcs cannot follow it, and run slower as written than another. The
/// exact curves' time at the same feeds, less [`WrittenTime::render_gain`]
/// of it, is the cheap bound ([`Objective::bound`]): the renderer aims to
/// keep the speed of the curves, not to pass it, but an arc through a
/// curvature peak has the mean curvature of its stretch, below the peak,
/// and is passed a little faster (as `bspline-fit`'s arcs of
/// `surface-raster.ngc` are; measurements: docs/tuning.md, `RENDER_GAIN`).
/// Where a rendering gains more
/// than that share, `auto` may pass over a candidate that was slightly
/// cheaper as written.
///
/// The writer also keeps a run as the program wrote it where every
/// rendering plans slower than that; this is the same for every candidate
/// of a run, so it is not part of the cost.
#[derive(Clone, Debug)]
pub struct WrittenTime {
    /// The plan whose speed the renderer reads: the writer plans the
    /// curves at the machine's maximum feed.
    pub shape: PlanOptions,
    /// The plan of the renderings (and of the bound): the user's machine
    /// and feeds.
    pub plan: PlanOptions,
    /// The renderings the format allows, in the writer's order. A
    /// [`CurveForm::Lines`] rendering after another is tried only where
    /// an earlier one fell back to lines (as the writer does).
    pub renders: Vec<RenderOptions>,
    /// How the writer's judge passes the corners of a rendering.
    pub corners: Corners,
    /// Told of every rendering costed, with its time: a writer that
    /// renders the chosen candidate with the same options can take it
    /// from there instead of rendering and planning it again.
    pub observer: Option<Arc<dyn RenderObserver>>,
    /// Largest share of its curves' time a rendering is taken to gain
    /// (in `[0, 1)`): the bound is the curves' time times `1 -
    /// render_gain`. Larger keeps more candidates in the race (more
    /// rendering and planning); [`RENDER_GAIN`] by default.
    pub render_gain: f64,
    /// Largest rendering (pieces) kept whole while it is costed, to hand
    /// to [`WrittenTime::observer`]; `None` (the default) keeps every one.
    ///
    /// Each candidate is rendered [`COST_PART_PIECES`] curves at a time,
    /// and the parts are timed as they come ([`WindowedTimer`]: the time
    /// of the whole rendering, to the bit); what is held of a rendering is
    /// what the observer is to be handed. Without an observer, or past
    /// this bound, that is a part and a planning window, whatever the
    /// run's length; but a writer then renders the chosen candidate again.
    /// `auto` on `surface-raster-large.ngc` at 0.05 mm with a bound of
    /// 100,000 pieces wrote the same program in less memory but more CPU
    /// time (the writer's second rendering of its arcs); hence not the
    /// default (measurements: docs/tuning.md,
    /// `WrittenTime::kept_rendering_pieces`).
    pub kept_rendering_pieces: Option<usize>,
    /// The writer's all-G1 rendering of a run whose other renderings do
    /// not gain on it ([`CurveForm::Lines`] options; `None`: the format
    /// has none). [`Objective::cost`] does not render it (it rarely wins
    /// and would double the cost of ranking), but the writer tries it on
    /// every run whose arcs do not win, so
    /// [`Objective::written_as_lines`] judges it (LinuxCNC's
    /// `Curva_Chitarra_p1.ngc` at 0.05 mm: `fair`'s curves lose as arcs at
    /// the maximum feed and gain as G1 at both feeds, and `auto` kept the
    /// run as written, slower than `fair`).
    pub lines_alternative: Option<RenderOptions>,
    /// What the writer tries beyond these renderings: its all-G1
    /// alternative and a finer curvature step (`None`, the default: not
    /// known). [`Objective::cost`] does not render them (it would render
    /// and plan every candidate two to four times more);
    /// [`Objective::final_cost`] does, for the candidates `auto` finds
    /// nearest its best ([`super::FINAL_COST_MARGIN`]).
    pub writer_tries: Option<WriterTries>,
}

/// Curves rendered at a time where [`WrittenTime`] costs a candidate: the
/// renderer's chains of arcs ([`crate::render::CHAIN_PIECES`]), so that
/// the parts render as the whole.
pub const COST_PART_PIECES: usize = crate::render::CHAIN_PIECES;

/// The default [`WrittenTime::render_gain`]: 30%. On the reference
/// programs a written program plans at most a few percent faster than its
/// curves (`scripts/render-gain.sh`, `docs/render-gain.md`); on dense 3D
/// zigzag rasters far more: a fit whose passes the renderer writes as G1
/// (they bend out of their plane, where helical arcs would kink), or a
/// corner method's transition at every vertex of a pass, rendered as the
/// pass's lines again, which the planner blends at its junction
/// deviation, where the exact curves' curvature ramps cap the speed. A
/// candidate so pruned was written faster than `auto`'s choice. What it
/// costs: the candidates whose curves plan within 30% of the fastest
/// rendering are rendered and planned too (measurements: docs/tuning.md,
/// `RENDER_GAIN`).
pub const RENDER_GAIN: f64 = 0.3;

impl PartialEq for WrittenTime {
    /// The same options (and the same observer, if any).
    fn eq(&self, o: &Self) -> bool {
        self.shape == o.shape
            && self.plan == o.plan
            && self.render_gain == o.render_gain
            && self.kept_rendering_pieces == o.kept_rendering_pieces
            && self.renders == o.renders
            && self.corners == o.corners
            && self.lines_alternative == o.lines_alternative
            && self.writer_tries == o.writer_tries
            && match (&self.observer, &o.observer) {
                (None, None) => true,
                (Some(a), Some(b)) => Arc::ptr_eq(a, b),
                _ => false,
            }
    }
}

/// What [`WrittenTime`] tells of each rendering it costs: the candidate's
/// pieces, the index of the rendering's options in
/// [`WrittenTime::renders`], the rendering itself (given away: the cost
/// needs only its time), its time on [`WrittenTime::plan`] and the speed
/// it was rendered by (the curves planned on [`WrittenTime::shape`]: a
/// writer that renders the pieces again, with another form or chord, can
/// take it instead of planning them again); and of each
/// bound it computes (the candidate's curves planned on
/// [`WrittenTime::plan`], [`Objective::bound`]).
pub trait RenderObserver: Send + Sync + core::fmt::Debug {
    fn rendered(
        &self,
        pieces: &[Piece],
        render: usize,
        rendering: Rendered,
        time: f64,
        speed: &Arc<PlannedSpeed>,
    );
    fn bounded(&self, _pieces: &[Piece], _time: f64) {}
}

impl WrittenTime {
    /// The written time on `limits`, at the machine's maximum feed when
    /// `override_feed` or at the programmed feeds, of the renderings
    /// `renders` judged with blended corners.
    pub fn new(limits: MachineLimits, override_feed: bool, renders: Vec<RenderOptions>) -> Self {
        WrittenTime {
            shape: PlannedTime::new(limits, true).plan,
            plan: PlannedTime::new(limits, override_feed).plan,
            renders,
            corners: Corners::Blended,
            observer: None,
            render_gain: RENDER_GAIN,
            kept_rendering_pieces: None,
            lines_alternative: None,
            writer_tries: None,
        }
    }

    /// Whether [`WrittenTime::lines_alternative`] of `candidate` plans
    /// `margin` faster than the run as written (`own` on
    /// [`WrittenTime::plan`], `own_max` on [`WrittenTime::shape`] where
    /// the two differ) at every feed the writer judges at.
    fn lines_gain(
        &self,
        candidate: &[Piece],
        (own, own_max): (f64, Option<f64>),
        margin: f64,
    ) -> bool {
        let Some(ro) = &self.lines_alternative else {
            return false;
        };
        let Some(speed) = self.shaping_speed(candidate) else {
            return false;
        };
        let Ok(r) = render_run(candidate, &speed, ro) else {
            return false;
        };
        let gains = |t: Option<f64>, own: f64| t.is_some_and(|t| t * (1.0 + margin) <= own);
        gains(self.rendered_time(&r.pieces, ro.form), own)
            && own_max
                .is_none_or(|m| gains(self.rendered_time_on(&r.pieces, ro.form, &self.shape), m))
    }

    /// The speed the renderer reads for `pieces`: planned on
    /// [`WrittenTime::shape`], as the writer plans the curves.
    pub(super) fn shaping_speed(&self, pieces: &[Piece]) -> Option<Arc<PlannedSpeed>> {
        let plan = plan_run(pieces, &self.shape).ok()?;
        Some(Arc::new(PlannedSpeed::new(
            pieces.len(),
            &plan,
            self.shape.limits.period,
        )))
    }

    /// The time of `run` as written on [`WrittenTime::shape`], where the
    /// writer judges it there too (`Some(None)`: the user's feeds are the
    /// machine's maximum); `None` where it cannot be planned.
    fn own_at_max(&self, run: &[Piece]) -> Option<Option<f64>> {
        if self.plan == self.shape {
            return Some(None);
        }
        plan_time_windowed(run, &self.shape, self.corners, WINDOWS)
            .ok()
            .map(Some)
    }

    /// The planned time of a rendering on [`WrittenTime::plan`] (LinuxCNC's
    /// G5.2 blocks as LinuxCNC runs them).
    pub(super) fn rendered_time(&self, pieces: &[Piece], form: CurveForm) -> Option<f64> {
        self.rendered_time_on(pieces, form, &self.plan)
    }

    /// [`WrittenTime::rendered_time`] planned on `plan`.
    pub(super) fn rendered_time_on(
        &self,
        pieces: &[Piece],
        form: CurveForm,
        plan: &PlanOptions,
    ) -> Option<f64> {
        let time = |p: &[Piece]| plan_time_windowed(p, plan, self.corners, WINDOWS).ok();
        match form {
            CurveForm::Nurbs(lim) if lim.linuxcnc_g5_2 => {
                time(&linuxcnc_g5_2_motion(pieces, lim.planar_mm.unwrap_or(0.0)))
            }
            _ => time(pieces),
        }
    }

    /// [`Objective::cost`] of `pieces`, each form rendered whole (where
    /// [`WrittenTime::cost_in_parts`] cannot plan it in windows).
    fn cost_whole(&self, pieces: &[Piece]) -> Option<f64> {
        let mut best: Option<f64> = None;
        self.each_rendering(pieces, |i, ro, r, speed| {
            if let Some(t) = self.rendered_time(&r.pieces, ro.form) {
                if best.is_none_or(|b| t < b) {
                    best = Some(t);
                }
                if let Some(o) = &self.observer {
                    o.rendered(pieces, i, r, t, speed);
                }
            }
            true
        })?;
        best
    }

    /// [`Objective::cost`] of `pieces`, each form rendered and timed part
    /// after part (see [`WrittenTime::kept_rendering_pieces`]); `None` where the
    /// parts' windows did not stitch or windows do not apply (the run must
    /// be planned whole).
    fn cost_in_parts(&self, pieces: &[Piece]) -> Option<Option<f64>> {
        let mut best: Option<f64> = None;
        // (A form that cannot render them leaves the candidate without a
        // cost; windows that do not stitch, or do not apply, leave it to
        // be costed whole.)
        let (mut failed, mut whole_plan) = (false, false);
        let planned = self.each_form(pieces, |i, ro, speed| {
            let Some(timer) = WindowedTimer::new(&self.plan, self.corners, WINDOWS) else {
                whole_plan = true;
                return None;
            };
            let mut timer = Some(timer);
            let mut absorber = LineAbsorber::new(ro);
            // The rendering while it is small enough to keep (for the
            // observer), timed whole at the end as `cost_whole` times it;
            // once it grows past that, what it held and every part after
            // are timed as they come (its G5.2 blocks as LinuxCNC runs
            // them, as `WrittenTime::rendered_time` plans them). Where a
            // part cannot be planned, the form has no time and is
            // rendered on for its stats.
            let mut whole = self.observer.as_ref().map(|_| Rendered::default());
            let mut stats = RenderStats::default();
            let mut push = |pieces: &[Piece]| {
                let motion = match ro.form {
                    CurveForm::Nurbs(lim) if lim.linuxcnc_g5_2 => {
                        Some(linuxcnc_g5_2_motion(pieces, lim.planar_mm.unwrap_or(0.0)))
                    }
                    _ => None,
                };
                let to_time = motion.as_deref().unwrap_or(pieces);
                if timer.as_mut().is_some_and(|t| t.push(to_time).is_err()) {
                    timer = None;
                }
            };
            let mut take = |out: Rendered, whole: &mut Option<Rendered>| {
                stats.add(&out.stats);
                match whole {
                    Some(w)
                        if self
                            .kept_rendering_pieces
                            .is_none_or(|n| w.pieces.len() + out.pieces.len() <= n) =>
                    {
                        w.pieces.extend(out.pieces);
                        w.speeds.extend(out.speeds);
                        w.stats.add(&out.stats);
                    }
                    Some(w) => {
                        push(&core::mem::take(&mut w.pieces));
                        *whole = None;
                        push(&out.pieces);
                    }
                    None => push(&out.pieces),
                }
            };
            let mut start = 0;
            while start < pieces.len() {
                let end = (start + COST_PART_PIECES).min(pieces.len());
                let Ok(part) = render_range(pieces, start..end, speed, ro) else {
                    failed = true;
                    return None;
                };
                take(absorber.push(part), &mut whole);
                start = end;
            }
            take(absorber.finish(), &mut whole);
            let fell_back = stats.fallback_lines > 0;
            let time = match (&whole, timer.map(WindowedTimer::finish)) {
                (Some(w), _) => self.rendered_time(&w.pieces, ro.form),
                (None, Some(Ok(None))) => {
                    whole_plan = true;
                    return None;
                }
                (None, Some(Ok(t))) => t,
                (None, Some(Err(_)) | None) => None,
            };
            let Some(t) = time else {
                return Some(fell_back);
            };
            if best.is_none_or(|b| t < b) {
                best = Some(t);
            }
            if let (Some(o), Some(mut w)) = (&self.observer, whole) {
                // (Held until the writer takes it: no room to spare.)
                w.pieces.shrink_to_fit();
                w.speeds.shrink_to_fit();
                o.rendered(pieces, i, w, t, speed);
            }
            Some(fell_back)
        });
        if whole_plan {
            return None;
        }
        Some(if planned.is_none() || failed {
            None
        } else {
            best
        })
    }

    /// Calls `form` with each form of [`WrittenTime::renders`] the writer
    /// tries, with its index and the speed of the curves planned on
    /// [`WrittenTime::shape`] (what the renderer shapes by): a
    /// [`CurveForm::Lines`] form after another only where an earlier
    /// one's rendering fell back to lines, which `form` returns, or `None`
    /// to stop. `None` where the curves cannot be planned.
    fn each_form(
        &self,
        pieces: &[Piece],
        mut form: impl FnMut(usize, &RenderOptions, &Arc<PlannedSpeed>) -> Option<bool>,
    ) -> Option<()> {
        let speed = self.shaping_speed(pieces)?;
        let mut fell_back = false;
        for (i, ro) in self.renders.iter().enumerate() {
            if i > 0 && ro.form == CurveForm::Lines && !fell_back {
                continue;
            }
            match form(i, ro, &speed) {
                Some(f) => fell_back |= f,
                None => break,
            }
        }
        Some(())
    }

    /// Renders `pieces` whole in each form the writer tries
    /// ([`WrittenTime::each_form`]) and hands each rendering to `each`
    /// (with its index and options, and the speed), until `each` returns
    /// false. `None` where the curves cannot be planned or a form cannot
    /// render them.
    pub(super) fn each_rendering(
        &self,
        pieces: &[Piece],
        mut each: impl FnMut(usize, &RenderOptions, Rendered, &Arc<PlannedSpeed>) -> bool,
    ) -> Option<()> {
        let mut failed = false;
        self.each_form(pieces, |i, ro, speed| {
            let Ok(r) = render_run(pieces, speed, ro) else {
                failed = true;
                return None;
            };
            let fell_back = r.stats.fallback_lines > 0;
            each(i, ro, r, speed).then_some(fell_back)
        })?;
        (!failed).then_some(())
    }
}

impl Objective for WrittenTime {
    fn peak_pass(&self) -> Option<PeakPass> {
        Some(peak_pass_for(&self.plan.limits))
    }
    fn feeds_overridden(&self) -> bool {
        self.plan.override_feed
    }
    fn cost(&self, pieces: &[Piece]) -> Option<f64> {
        // Every rendering handed over whole: rendered whole (in parts,
        // joined, it took a little more room and time).
        let keeps_all = self.observer.is_some() && self.kept_rendering_pieces.is_none();
        match (!keeps_all).then(|| self.cost_in_parts(pieces)).flatten() {
            Some(cost) => cost,
            None => self.cost_whole(pieces),
        }
    }

    fn bound(&self, pieces: &[Piece]) -> Option<f64> {
        let time = plan_time_windowed(pieces, &self.plan, Corners::Blended, WINDOWS).ok()?;
        if let Some(o) = &self.observer {
            o.bounded(pieces, time);
        }
        Some(time * (1.0 - self.render_gain))
    }

    fn bound_slack(&self) -> f64 {
        self.render_gain
    }

    /// The pieces planned as they are, as the writer judges the run it
    /// keeps as the program wrote it.
    fn as_written(&self, pieces: &[Piece]) -> Option<f64> {
        plan_time_windowed(pieces, &self.plan, self.corners, WINDOWS).ok()
    }

    /// The G-code writer's rule: a run is rewritten where one rendering of
    /// it plans [`rewrite_margin`] faster than the run as written at every
    /// feed the writer judges at: the user's, and, where those are the
    /// programmed feeds, the machine's maximum (so that a feed override
    /// never makes the written program slower). [`Objective::cost`] costs
    /// the user's feeds only; a candidate that gains there and loses at
    /// the maximum feed is written as the program wrote it (LinuxCNC's
    /// `arc_splitting_0.90.ngc` at 0.05 mm: `auto`'s fits gained at its
    /// F100 and lost at 400 mm/s, so the run was kept, slower than
    /// `bspline-corner`'s; measurements: docs/tuning.md,
    /// `WrittenTime::written_instead`). The forms are rendered as
    /// [`Objective::cost`] renders them, each judged at both feeds.
    fn written_instead(&self, candidate: &[Piece], cost: f64, run: &[Piece], own: f64) -> bool {
        self.forms_gain(candidate, cost, run, own, rewrite_margin(run))
    }

    /// The writer's all-G1 rendering ([`WrittenTime::lines_alternative`])
    /// judged as [`Objective::written_instead`] judges the forms: at every
    /// feed the writer judges at, by [`rewrite_margin`].
    fn written_as_lines(&self, candidate: &[Piece], run: &[Piece], own: f64) -> bool {
        self.own_at_max(run)
            .is_some_and(|m| self.lines_gain(candidate, (own, m), rewrite_margin(run)))
    }

    /// The rendering the writer chooses ([`WrittenTime::writer_tries`]).
    fn final_cost(&self, pieces: &[Piece], cost: f64) -> f64 {
        self.writer_cost(pieces, cost)
    }
}

/// The margin by which the writer rewrites run `run` (its pieces as the
/// program wrote them): none on a run with a spline (a fairing of it, at a
/// feed its ripples do not slow, is rewritten when it plans no slower: what
/// changes is the curvature, which it lowers), [`KEEP_MARGIN`] on others
/// (at an equal time a rendering would trade the program's corners for more
/// blocks, for nothing). The writer's rule (`fairpath_gcode`'s
/// `emit::choose_run`), which [`Objective::written_instead`] must follow.
pub fn rewrite_margin(run: &[Piece]) -> f64 {
    let splines = run.iter().any(|p| matches!(p.curve, Curve::Nurbs(_)));
    if splines {
        0.0
    } else {
        KEEP_MARGIN
    }
}

impl WrittenTime {
    /// [`Objective::written_instead`] by the forms of
    /// [`WrittenTime::renders`] alone.
    fn forms_gain(
        &self,
        candidate: &[Piece],
        cost: f64,
        run: &[Piece],
        own: f64,
        margin: f64,
    ) -> bool {
        if cost * (1.0 + margin) > own {
            return false;
        }
        let Some(own_max) = self.own_at_max(run) else {
            return false;
        };
        let Some(own_max) = own_max else {
            return true;
        };
        let gains = |t: Option<f64>, own: f64| t.is_some_and(|t| t * (1.0 + margin) <= own);
        let mut written = false;
        let rendered = self.each_rendering(candidate, |_, ro, r, _| {
            written = gains(self.rendered_time(&r.pieces, ro.form), own)
                && gains(
                    self.rendered_time_on(&r.pieces, ro.form, &self.shape),
                    own_max,
                );
            !written
        });
        rendered.is_some() && written
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{corner_curves, render_options};
    use super::*;
    use std::sync::Mutex;

    /// Records each rendering handed over: its options' index, its
    /// pieces, its time.
    #[derive(Debug, Default)]
    struct Recorder(Mutex<Vec<(usize, Vec<Piece>, f64)>>);

    impl RenderObserver for Recorder {
        fn rendered(
            &self,
            _: &[Piece],
            render: usize,
            r: Rendered,
            time: f64,
            _: &Arc<PlannedSpeed>,
        ) {
            self.0.lock().unwrap().push((render, r.pieces, time));
        }
    }

    fn written_time(observer: &Arc<Recorder>, kept: Option<usize>) -> WrittenTime {
        let ro = render_options;
        let mut w = WrittenTime::new(
            MachineLimits::thesis(),
            false,
            vec![ro(CurveForm::Arcs), ro(CurveForm::Lines)],
        );
        w.observer = Some(observer.clone() as Arc<dyn RenderObserver>);
        w.kept_rendering_pieces = kept;
        w
    }

    /// A candidate is costed part after part to the bit of its rendering
    /// costed whole, planned in windows where it is long; a rendering
    /// larger than [`WrittenTime::kept_rendering_pieces`] is not handed
    /// over (nor held), a smaller one is, as rendered whole, and by
    /// default every one is; without an observer, none is.
    #[test]
    fn a_candidate_costed_in_parts_costs_what_it_costs_rendered_whole() {
        for (points, kept) in [(300, None), (300, Some(1000)), (6000, Some(20_000))] {
            let pieces = corner_curves(points);
            let (parts, whole) = (Arc::new(Recorder::default()), Arc::new(Recorder::default()));
            let in_parts = written_time(&parts, kept).cost_in_parts(&pieces);
            let t = written_time(&whole, kept).cost_whole(&pieces);
            assert!(t.is_some());
            assert_eq!(in_parts, Some(t), "{points} points");
            // Without an observer (nothing kept), costed in parts.
            let mut bare = written_time(&parts, kept);
            bare.observer = None;
            assert_eq!(bare.cost(&pieces), t, "{points} points");
            let whole = whole.0.lock().unwrap();
            let largest = whole.iter().map(|r| r.1.len()).max().unwrap();
            if points == 6000 {
                // Long enough to be planned in windows.
                assert!(WINDOWS.windows(largest), "{largest} pieces rendered");
            }
            // Only the default keeps these.
            let dropped = kept.is_some_and(|n| largest > n);
            assert_eq!(dropped, kept.is_some(), "{largest}");
            if dropped {
                assert!(parts.0.lock().unwrap().is_empty());
            } else {
                assert_eq!(*parts.0.lock().unwrap(), *whole);
            }
        }
    }

    /// `fair`'s default pass becomes the objective's machine's: its speed
    /// caps, or the curvature in the thesis' model; a pass the user set
    /// stays, and an objective that says nothing leaves the default.
    #[test]
    fn the_default_fairing_pass_lowers_the_jobs_machines_demand() {
        let mut m = MachineLimits::thesis();
        m.jerk = 5000.0;
        m.max_feed = 150.0;
        let on = |m: MachineLimits, o: FairOptions| fair_on(o, &PlannedTime::new(m, true));
        let d = FairOptions::default();
        assert_eq!(
            on(m, d).peak_pass,
            PeakPass::SpeedCaps {
                max_feed: 150.0,
                normal_acc: m.normal_acc,
                jerk: 5000.0,
                period: m.period,
            }
        );
        assert_eq!(
            on(MachineLimits::thesis(), d).peak_pass,
            PeakPass::DEFAULT_MACHINE
        );
        m.jerk_on_curves = false;
        assert_eq!(on(m, d).peak_pass, PeakPass::Curvature);
        let off = FairOptions {
            peak_pass: PeakPass::Off,
            ..d
        };
        assert_eq!(on(m, off).peak_pass, PeakPass::Off);
        #[derive(Debug)]
        struct Silent;
        impl Objective for Silent {
            fn cost(&self, _: &[Piece]) -> Option<f64> {
                None
            }
        }
        assert_eq!(fair_on(d, &Silent).peak_pass, PeakPass::DEFAULT_MACHINE);
        // Where the objective overrides the feeds, the pass works up to the
        // machine's maximum feed; at the programmed feeds, up to each one.
        assert!(!on(m, d).programmed_feeds);
        let at_feeds = fair_on(d, &PlannedTime::new(m, false));
        assert!(at_feeds.programmed_feeds);
        assert!(fair_on(d, &Silent).programmed_feeds);
    }
}
