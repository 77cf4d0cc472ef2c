//! What choosing the renderings of a part ([`super::choose`]) and writing
//! them ([`super::write`]) share: the part, its curves and their plans,
//! the options with the budget the whole program is written with, and how
//! a run is rendered and timed.

use super::{
    EmitError, Result, LINES_CANDIDATE_SHARE, LONG_RUN_PIECES, PARALLEL_FEEDS_PIECES,
    RENDER_GROUP_PARTS, RENDER_PART_PIECES,
};
use crate::facts::ProgramFacts;
use crate::pipeline::written::{forms, render_options, write_options, PLANAR_MM};
use crate::pipeline::{EmitOptions, RenderMemo};
use crate::RenderedParts;
use crate::{Format, GcodeWriteOptions, Program, Units};
use fairpath::feed::plan::{plan_run, PlanOptions, RunPlan};
use fairpath::feed::windowed::{plan_time_windowed, PlanWindows, WindowedTimer};
use fairpath::feed::FeedError;
use fairpath::path::Piece;
use fairpath::pipeline::par_map;
use fairpath::render::{
    linuxcnc_g5_2_motion, render_range, render_run, CurveForm, LineAbsorber, PlannedSpeed,
    RenderOptions, RenderStats, Rendered,
};
use std::sync::{Arc, Mutex, OnceLock};

/// What is written for one run.
#[derive(Clone, Debug)]
pub(super) struct Choice {
    /// The form rendered, or `None`: the original lines.
    pub(super) form: Option<CurveForm>,
    pub(super) chord: f64,
    /// The rendered pieces; emptied once written (the text holds them),
    /// rendered again from `form` and `chord` if the text is written again.
    pub(super) pieces: Vec<Piece>,
    pub(super) stats: RenderStats,
    /// The planned speed of each rendered piece ([`Rendered::speeds`]).
    pub(super) speeds: Vec<f64>,
    /// Pieces of the rendering (`pieces.len()` until they are written).
    pub(super) count: usize,
    /// Rendered part after part as it is written and read back part after
    /// part as it is checked ([`Emitter::streams`]): `pieces` stays empty;
    /// `stats` and `count` are known once it is written.
    pub(super) streamed: bool,
    /// Curves per part where it is rendered part after part
    /// ([`RENDER_PART_PIECES`], fewer where each curve renders to many
    /// pieces: [`Emitter::streamed_times`]).
    pub(super) part_pieces: usize,
    /// The curvature step share it was rendered with
    /// ([`fairpath::render::RenderOptions::step_share`]): `None` for the
    /// options' ([`EmitOptions::step_share`]), else the finer one tried for
    /// arcs ([`super::FINER_STEP`]).
    pub(super) step_share: Option<f64>,
}

impl Choice {
    /// The run as the program wrote it.
    pub(super) fn original(chord: f64) -> Choice {
        Choice {
            form: None,
            chord,
            pieces: Vec::new(),
            stats: RenderStats::default(),
            speeds: Vec::new(),
            count: 0,
            streamed: false,
            part_pieces: RENDER_PART_PIECES,
            step_share: None,
        }
    }

    /// The run to be rendered in `form` with output share `chord` as it is
    /// written ([`Choice::streamed`]).
    pub(super) fn streamed(form: CurveForm, chord: f64) -> Choice {
        Choice {
            form: Some(form),
            streamed: true,
            ..Choice::original(chord)
        }
    }

    /// The run rendered in `form` with output share `chord` and step
    /// share `step_share` ([`Choice::step_share`]).
    fn rendered(form: CurveForm, chord: f64, step_share: Option<f64>, r: Rendered) -> Choice {
        Choice {
            form: Some(form),
            chord,
            count: r.pieces.len(),
            pieces: r.pieces,
            stats: r.stats,
            speeds: r.speeds,
            streamed: false,
            part_pieces: RENDER_PART_PIECES,
            step_share,
        }
    }
}

/// A part's curves, what they are written with and for, and how a run is
/// rendered and timed.
pub(super) struct Emitter<'a> {
    pub(super) program: &'a Program,
    pub(super) smoothed: &'a [Vec<Piece>],
    pub(super) plans: &'a [RunPlan],
    /// The options, with the budget the program is written with
    /// ([`EmitOptions::budget_for_blending`]).
    pub(super) opts: EmitOptions,
    pub(super) wo: GcodeWriteOptions,
    /// The forms the format can say, in the order they are tried.
    pub(super) forms: Vec<CurveForm>,
    /// The feeds a rendering must be faster at than the program's own run:
    /// the machine's maximum (`true`), then the programmed ones unless
    /// feeds are overridden.
    pub(super) feeds: Vec<bool>,
    /// The renderings `auto`'s objective made ([`RenderMemo`]), and the
    /// units it rendered in (those of the program's first run).
    pub(super) memo: Option<&'a RenderMemo>,
    pub(super) memo_units: Units,
    /// Plans made here where none was given ([`Emitter::plan`]).
    lazy: Vec<OnceLock<core::result::Result<RunPlan, FeedError>>>,
    /// Per run, the speed its plan was sampled to before the plan was
    /// dropped ([`super::take_long_run_speeds`]), handed to the first
    /// rendering that asks for it.
    given: Vec<Mutex<Option<Arc<PlannedSpeed>>>>,
}

impl<'a> Emitter<'a> {
    /// For G-code formats (JSON writes the curves as they are).
    pub(super) fn new(
        program: &'a Program,
        facts: &ProgramFacts,
        smoothed: &'a [Vec<Piece>],
        plans: &'a [RunPlan],
        opts: &EmitOptions,
    ) -> Result<Emitter<'a>> {
        let opts = EmitOptions {
            budget: opts
                .budget_for_blending(&facts.blending)
                .map_err(EmitError::Blend)?,
            ..*opts
        };
        let mut wo = write_options(&opts, facts.nurbs_degree);
        wo.arcs = wo.arcs.map(|_| facts.arc_words);
        Ok(Emitter {
            program,
            smoothed,
            plans,
            memo: None,
            memo_units: facts.render_units(),
            lazy: (0..smoothed.len()).map(|_| OnceLock::new()).collect(),
            given: Vec::new(),
            forms: forms(opts.format, opts.controller, facts.nurbs_degree),
            feeds: if opts.override_feed {
                vec![true]
            } else {
                vec![true, false]
            },
            opts,
            wo,
        })
    }

    /// Run `k` rendered in `form` with output share `chord`.
    pub(super) fn render(
        &self,
        k: usize,
        form: CurveForm,
        chord: f64,
        step_share: Option<f64>,
    ) -> Result<Choice> {
        let (ro, speed) = self.render_setup(k, form, chord, step_share)?;
        let pieces = &self.smoothed[k];
        if pieces.len() < PARALLEL_FEEDS_PIECES {
            let error = |source| EmitError::Render { run: k, source };
            let r = render_run(pieces, &speed, &ro).map_err(error)?;
            return Ok(Choice::rendered(form, chord, step_share, r));
        }
        // A long run in parts side by side, joined as they come.
        let group = RENDER_GROUP_PARTS;
        let mut parts = PartsRenderer::new(k, pieces, ro, speed, (group, RENDER_PART_PIECES));
        let mut joined = Rendered::default();
        while let Some((p, v)) = parts.next_part() {
            joined.pieces.extend(p);
            joined.speeds.extend(v);
        }
        if let Some(e) = parts.error {
            return Err(e);
        }
        joined.stats = parts.stats;
        Ok(Choice::rendered(form, chord, step_share, joined))
    }

    /// How run `k` is rendered in `form` with output share `chord` and
    /// step share `step_share` ([`Choice::step_share`]): the options and
    /// the speed the renderer shapes it by (`auto`'s objective's, where it
    /// kept a rendering of these pieces; else their plan's).
    pub(super) fn render_setup(
        &self,
        k: usize,
        form: CurveForm,
        chord: f64,
        step_share: Option<f64>,
    ) -> Result<(RenderOptions, Arc<PlannedSpeed>)> {
        let (program, smoothed) = (self.program, self.smoothed);
        let (opts, wo) = (&self.opts, &self.wo);
        let units = program.run_spans()[k].units;
        let mut ro = render_options(opts, form, chord, units, wo);
        if let Some(share) = step_share {
            ro.step_share = share;
        }
        // A given speed goes to the first rendering (the run's plan was
        // dropped for it: a form tried after that plans the run again).
        let given = || self.given.get(k)?.lock().ok()?.take();
        let speed = match self
            .memo
            .and_then(|m| m.speed_of(&smoothed[k]))
            .or_else(given)
        {
            Some(s) => s,
            None => Arc::new(PlannedSpeed::new(
                smoothed[k].len(),
                self.plan(k)?,
                opts.machine.period,
            )),
        };
        Ok((ro, speed))
    }

    /// Whether a rendering may be made as it is written (always but in
    /// the tests that compare with rendering it whole).
    pub(super) fn may_stream(&self) -> bool {
        #[cfg(test)]
        if super::tests::NO_STREAMING.with(|n| n.get()) {
            return false;
        }
        true
    }

    /// Run `k` rendered in `form` at `chord` part after part, `part_pieces`
    /// curves a part, and timed at each of [`Emitter::feeds`] as the parts
    /// come ([`WindowedTimer`]: the times [`Emitter::time`] plans of the
    /// whole rendering, to the bit), the parts dropped once timed: what a
    /// rendering of many pieces costs in memory is a group of parts and a
    /// window. `None` where the windows do not stitch (the caller renders
    /// the run whole).
    pub(super) fn streamed_times(
        &self,
        k: usize,
        (form, chord): (CurveForm, f64),
        part_pieces: usize,
    ) -> Result<Option<Vec<f64>>> {
        let (ro, speed) = self.render_setup(k, form, chord, None)?;
        let windows = PlanWindows::DEFAULT;
        let corners = self.opts.judged_by;
        let Some(timers) = self
            .feeds
            .iter()
            .map(|&f| WindowedTimer::new(&self.plan_options(f), corners, windows).map(Mutex::new))
            .collect::<Option<Vec<_>>>()
        else {
            return Ok(None);
        };
        let group = super::streamed_group_parts();
        let pieces = &self.smoothed[k];
        let mut parts = PartsRenderer::new(k, pieces, ro, speed, (group, part_pieces));
        while let Some((p, _)) = parts.next_part() {
            let pushed = par_map(timers.len(), |i| {
                let mut t = timers[i].lock().unwrap_or_else(|e| e.into_inner());
                t.push(&p)
            });
            for r in pushed {
                r.map_err(EmitError::Plan)?;
            }
        }
        if let Some(e) = parts.error {
            return Err(e);
        }
        timers
            .into_iter()
            .map(|t| {
                let t = t.into_inner().unwrap_or_else(|e| e.into_inner());
                t.finish().map_err(EmitError::Plan)
            })
            .collect()
    }

    /// Whether run `k`'s first candidate in `form` at `chord` is rendered
    /// as it is written, part after part ([`Choice::streamed`]): a long
    /// run's candidate that is timed only as written (arcs, whose G1
    /// alternative is tried only where they fall back to G1 on many blocks,
    /// or the format's only form), where `auto`'s objective kept no
    /// rendering of it.
    pub(super) fn streams(&self, k: usize, form: CurveForm, chord: f64) -> bool {
        self.may_stream()
            && !self.goes_on(k)
            && self.smoothed[k].len() >= LONG_RUN_PIECES
            && self.memo.is_none()
            && chord == self.opts.budget.output
            && (form == CurveForm::Arcs || (self.forms.len() == 1 && form == CurveForm::Lines))
    }

    /// Whether run `k` goes on from the part before or into the next (a
    /// long run cut into windows, [`crate::interp::RunWindows`]): its
    /// written pieces are read back and held, for the plan carried across
    /// the parts ([`crate::pipeline::CarriedPlan`]), never rendered as
    /// they are written.
    pub(super) fn goes_on(&self, k: usize) -> bool {
        let p = self.program;
        let last = p.run_spans().len().checked_sub(1);
        (k == 0 && p.window_continued()) || (Some(k) == last && p.window_cut())
    }

    /// Whether run `k` is chosen for as a long run: of at least
    /// [`LONG_RUN_PIECES`] pieces, or a window of a longer run
    /// ([`Emitter::goes_on`]), which is written as the run it is part of
    /// would be.
    pub(super) fn is_long(&self, k: usize) -> bool {
        self.smoothed[k].len() >= LONG_RUN_PIECES || self.goes_on(k)
    }

    /// How a run is planned at the maximum feed (`true`) or the
    /// programmed ones: on the user's machine, from rest to rest, with the
    /// whole look-ahead.
    pub(super) fn plan_options(&self, override_feed: bool) -> PlanOptions {
        PlanOptions {
            limits: self.opts.machine,
            override_feed,
            window: None,
            ends: Default::default(),
        }
    }

    /// The planned time of a run's pieces at the maximum feed (`true`) or
    /// the programmed ones.
    pub(super) fn time(&self, pieces: &[Piece], override_feed: bool) -> Result<f64> {
        let opts = &self.opts;
        let po = self.plan_options(override_feed);
        // Window by window on a long run (the written runs of a raster hold
        // millions of blocks): the same time, in a window's memory.
        plan_time_windowed(pieces, &po, opts.judged_by, PlanWindows::DEFAULT)
            .map_err(EmitError::Plan)
    }

    /// A rendering's time: its G5.2 blocks as LinuxCNC runs them (as the
    /// written text reads back).
    pub(super) fn rendered_time(&self, c: &Choice, override_feed: bool) -> Result<f64> {
        if self.opts.format == Format::G5_2 && matches!(c.form, Some(CurveForm::Nurbs(_))) {
            self.time(&linuxcnc_g5_2_motion(&c.pieces, PLANAR_MM), override_feed)
        } else {
            self.time(&c.pieces, override_feed)
        }
    }

    /// A run's times at each feed (`t(feed)`), side by side for a long run
    /// of `len` pieces.
    pub(super) fn at_feeds(
        &self,
        len: usize,
        t: &(dyn Fn(bool) -> Result<f64> + Sync),
    ) -> Result<Vec<f64>> {
        let feeds = &self.feeds;
        if len >= PARALLEL_FEEDS_PIECES && feeds.len() > 1 {
            par_map(feeds.len(), |i| t(feeds[i])).into_iter().collect()
        } else {
            feeds.iter().map(|&f| t(f)).collect()
        }
    }

    /// The same, rendering with `speeds` ([`super::take_long_run_speeds`]:
    /// per run, `None` or the speed its plan was sampled to, the plan
    /// itself dropped).
    pub(super) fn with_speeds(mut self, speeds: Vec<Option<Arc<PlannedSpeed>>>) -> Emitter<'a> {
        self.given = speeds.into_iter().map(Mutex::new).collect();
        self
    }

    /// The plan the renderer shapes run `k` by: the one given, or where
    /// none was made (its rendering was to come from [`Emitter::memo`]:
    /// [`crate::pipeline::plan_input_and_curves_from`]) made here, once.
    fn plan(&self, k: usize) -> Result<&RunPlan> {
        if !self.plans[k].segments.is_empty() {
            return Ok(&self.plans[k]);
        }
        let made =
            self.lazy[k].get_or_init(|| plan_run(&self.smoothed[k], &self.plan_options(true)));
        made.as_ref().map_err(|e| EmitError::Plan(e.clone()))
    }

    /// The chord of the all-G1 alternative to arcs where the budget keeps
    /// a blending share: the finer chord `--format g1` renders at
    /// ([`fairpath::budget::ToleranceBudget::finer_lines_output`]), within
    /// this format's output share; `None` without a blending share.
    ///
    /// Why: where the controller blends the corners of G1 moves, lines
    /// cut finer turn less at each vertex and plan faster. Where the arcs
    /// fell back to lines on every block, the alternative at the arcs'
    /// chord is the same rendering and cannot win:
    /// `random_lines_0.001in.ngc` (its `G64` blends) was written slower in
    /// arcs than with `--format g1` (measurements: docs/tuning.md,
    /// `Emitter::finer_lines_chord`).
    pub(super) fn finer_lines_chord(&self) -> Option<f64> {
        self.opts.budget.finer_lines_output()
    }

    /// Run `k` rendered in the `i`-th of [`Emitter::forms`] at `chord`
    /// (the output share, or [`Emitter::finer_lines_chord`]); at the output
    /// share as `auto`'s objective rendered it if it kept that rendering
    /// ([`RenderMemo::take`]: the same pieces, options and plan, so the same
    /// rendering), with its time at the user's feeds; else rendered here.
    pub(super) fn first_render(
        &self,
        k: usize,
        i: usize,
        chord: f64,
    ) -> Result<(Choice, Option<f64>)> {
        let form = self.forms[i];
        // (`auto`'s objective renders at the output share.)
        let same_units = self.program.run_spans()[k].units == self.memo_units
            && chord == self.opts.budget.output;
        if let Some((r, t)) = self
            .memo
            .filter(|_| same_units)
            .and_then(|m| m.take(&self.smoothed[k], i))
        {
            return Ok((Choice::rendered(form, chord, None, r), Some(t)));
        }
        Ok((self.render(k, form, chord, None)?, None))
    }

    /// Whether a rendering of run `k` is a long run's whose arcs fell back
    /// to G1 on few of its curves (the all-G1 candidate is not tried on
    /// it). Counted in curves, not blocks: a curve that falls back is
    /// written as many short lines, and the fewer blocks the arcs take
    /// elsewhere (chains of arcs, [`fairpath::render::RenderStats::chained`])
    /// the larger those lines' share of the blocks, for the same curves.
    pub(super) fn long_with_few_lines(&self, k: usize, c: &Choice) -> bool {
        let curves = self.smoothed[k].len();
        self.is_long(k) && (c.stats.fallback_pieces as f64) < LINES_CANDIDATE_SHARE * curves as f64
    }
}

/// A long run's rendering, a group of parts at a time (each group's parts
/// side by side), its short lines merged as [`render_run`] merges a whole
/// run's ([`LineAbsorber`]): the writer takes it part after part
/// ([`RenderedParts`]), so that the rendering is never held whole.
pub(super) struct PartsRenderer<'e> {
    k: usize,
    pieces: &'e [Piece],
    ro: RenderOptions,
    speed: Arc<PlannedSpeed>,
    /// The next part to render, how many are rendered side by side, and
    /// the pieces of a part.
    next: usize,
    group: usize,
    part_pieces: usize,
    absorber: Option<LineAbsorber>,
    /// What the parts given so far hold.
    pub(super) stats: RenderStats,
    pub(super) count: usize,
    /// The first error: no part is given after it.
    pub(super) error: Option<EmitError>,
}

impl<'e> PartsRenderer<'e> {
    /// Run `k`, `pieces`, rendered with `ro` by `speed`, `group` parts
    /// of `part_pieces` pieces at a time.
    pub(super) fn new(
        k: usize,
        pieces: &'e [Piece],
        ro: RenderOptions,
        speed: Arc<PlannedSpeed>,
        (group, part_pieces): (usize, usize),
    ) -> PartsRenderer<'e> {
        PartsRenderer {
            k,
            pieces,
            absorber: Some(LineAbsorber::new(&ro)),
            ro,
            speed,
            next: 0,
            group: group.max(1),
            part_pieces: part_pieces.max(1),
            stats: RenderStats::default(),
            count: 0,
            error: None,
        }
    }
}

impl RenderedParts for PartsRenderer<'_> {
    fn next_part(&mut self) -> Option<(Vec<Piece>, Vec<f64>)> {
        if self.error.is_some() {
            return None;
        }
        let (pieces, speed, ro) = (self.pieces, &*self.speed, &self.ro);
        let size = self.part_pieces;
        let parts = pieces.len().div_ceil(size);
        if self.next >= parts {
            let last = self.absorber.take()?.finish();
            self.count += last.pieces.len();
            return (!last.pieces.is_empty()).then_some((last.pieces, last.speeds));
        }
        let group = self.next;
        let in_group = self.group.min(parts - group);
        let rendered = par_map(in_group, |i| {
            let j = group + i;
            let end = ((j + 1) * size).min(pieces.len());
            render_range(pieces, j * size..end, speed, ro)
        });
        self.next += in_group;
        let mut joined = Rendered::default();
        for r in rendered {
            match r {
                Ok(r) => {
                    joined.pieces.extend(r.pieces);
                    joined.speeds.extend(r.speeds);
                    joined.stats.add(&r.stats);
                }
                Err(source) => {
                    self.error = Some(EmitError::Render {
                        run: self.k,
                        source,
                    });
                    return None;
                }
            }
        }
        let out = self.absorber.as_mut()?.push(joined);
        self.stats.add(&out.stats);
        self.count += out.pieces.len();
        Some((out.pieces, out.speeds))
    }
}
