//! Method `auto` (the default): for each run, the smoothing that the feed
//! planner runs fastest, always within the tolerance and G2 but at
//! reversals and near-reversals (with
//! [`AutoOptions::curves_as_written`], G2 unless a corner method that
//! keeps the corners next to arcs plans faster: the last two candidates
//! below).
//!
//! Candidates for a run:
//!
//! * **fit**: `bspline-fit` (dense sections fitted, sparse corners blended;
//!   seeds 002 and 000) on the run with its arcs and curves sampled as
//!   chords within `arc_share * tolerance` of them, with the rest of the
//!   tolerance. Sampled arcs are dense sections like any CAM sampling, so
//!   they are fitted together with their neighbours and the joints between
//!   lines and arcs, and between arcs, become G2 as well (a tangent joint
//!   of a line and an arc, or of two arcs, still jumps in curvature, which
//!   slows the machine as much as a corner of small angle). The chords lie
//!   within `arc_share * tolerance` of the arc and the fit within the rest
//!   of the chords, so the fit is within the tolerance of the arc.
//! * **fit, wide wiggles**: the same with [`WIDE_WIGGLE_PER_TOL`](super::candidates::WIDE_WIGGLE_PER_TOL), when it
//!   makes some vertex dense that the default rule does not (a zigzag whose
//!   midline lies within the tolerance).
//! * **fit, through corners**, on runs of at most [`THROUGH_MAX_PIECES`]
//!   pieces (after sampling): every vertex up to [`THROUGH_MAX_TURN`](crate::smooth::THROUGH_MAX_TURN) is
//!   dense, so the fit runs through the corners (next to arcs, or between
//!   lines) instead of meeting zero-curvature corner transitions there.
//! * **fit, jerk-faired**, on the same runs: `bspline-fit` with the jerk
//!   term [`JERK_FAIRNESS`](super::candidates::JERK_FAIRNESS), which spreads the curvature ramps of sampled
//!   arcs between corners over more length; and through corners with a
//!   lighter jerk term, [`THROUGH_JERK_FAIRNESS`](super::candidates::THROUGH_JERK_FAIRNESS). These are offered on
//!   runs of lines too (the survey found each chosen somewhere).
//! * the corner methods `bspline-corner`, `lotm` and `ctm`: on the run as
//!   it is when it has only lines; on the same sampled run (with the same
//!   share of the tolerance) when it has arcs, so that they too leave no
//!   joint next to an arc that is not G2. `ctm` (seed 001's baseline) with
//!   its default coefficient makes `bspline-corner`'s uniform cubic
//!   B-splines, but sizes them differently (each segment shared between
//!   two transitions split in halves, where `bspline-corner` gives each
//!   corner the room the one before left): on LinuxCNC's
//!   `tight-corner-tolerance.ngc` at 0.1 mm, a star of near-reversals,
//!   its program plans 75.738 s where every other candidate was kept as
//!   the run was written (77.198 s). Last in the table, so it wins only
//!   where strictly faster.
//! * **bspline-corner, outer edges**, on runs of at most
//!   [`THROUGH_MAX_PIECES`] pieces: `bspline-corner` on the run with its
//!   corners moved outward ([`crate::smooth::outer_guide`]), with the
//!   tolerance raised by the shift, so that each transition starts on the
//!   band's outer edge and cuts across to its inner edge (about twice the
//!   depth, issue 21's "use the band"), verified against the run and
//!   `bspline-corner` itself where it does not stay in the band
//!   ([`OUTER_SHIFT_SHARES`](super::candidates::OUTER_SHIFT_SHARES)). It gains most where corners turn by
//!   half a radian to a radian between moves long enough for the deeper
//!   cut, as an engraving's glyphs do; last in the table, so it wins only
//!   where strictly faster.
//! * **fair**: method `fair` (seed 003, the thesis' fairing inside the
//!   tolerance tube) with its default options. On a run with B-spline
//!   pieces it works on the run as it is, with the whole tolerance: the
//!   splines are faired in place (no other candidate keeps them; the
//!   others refit their samples), its lines fitted then faired. On other
//!   runs of at most [`FAIR_MAX_PIECES`] pieces (after sampling) it fits
//!   the same lines as the fits and fairs the fits in the rest of the
//!   band; longer runs of lines do not get it (its work grows with the
//!   fits' length: `docs/auto-fair.md`).
//! * **fair, through shallow corners**: the same, its lines fitted
//!   through every vertex the sections would take as dense but for its
//!   segments' lengths ([`crate::smooth::LineFit::ThroughShallowCorners`],
//!   which method `fair` also tries by default), on runs of at most
//!   [`THROUGH_MAX_PIECES`] pieces where that makes some vertex dense that
//!   the sections leave sparse.
//! * **fair, straightened**, on runs with a B-spline piece: method `fair`
//!   with its straightening forced on in the sliding tube
//!   ([`FairOptions::straightened`]), which method `fair` judges there by
//!   default ([`crate::smooth::Straighten::Judged`]): offered so that
//!   `auto` stays no slower than `fair` (the fallback below tries it
//!   too).
//! * **as is**: the run untouched, when every joint in it is already G2
//!   (one arc between two `S` words of a plasma program, say): sampled and
//!   refitted, an arc's curvature ripples and can plan slower. Last in the
//!   list, so it wins only when strictly faster.
//! * **bspline-corner, curves as written** and **lotm, curves as
//!   written**, on runs with an arc or curve: the corner method on the run
//!   as it is, with the whole tolerance, as the method alone writes it:
//!   the arcs kept, the corners between lines replaced, the corners next
//!   to an arc kept (not G2). On a run of tight arcs and short lines the
//!   sampled arcs get a transition at every chord and plan far slower
//!   (LinuxCNC's `tort.ngc`, lines 83-90; measurements: docs/tuning.md,
//!   `AutoOptions::curves_as_written`). Offered
//!   with [`AutoOptions::curves_as_written`] beside the others (after
//!   them, so they win only when strictly faster). By default only as a
//!   fallback, where the best G2 candidate would leave the run as the
//!   program wrote it, by the objective ([`Objective::as_written`]): the
//!   writer would not write its rendering ([`Objective::written_instead`]:
//!   not [`super::KEEP_MARGIN`] cheaper than the run as written at every
//!   feed the writer judges at, the user's and the machine's maximum; on
//!   LinuxCNC's `arc_splitting_0.90.ngc` the fits gain at its F100 and
//!   lose at 400 mm/s), or its curves themselves are no cheaper
//!   (then the rendering's gain is one the rounding of the written
//!   coordinates can take away: the G2 fit of `tort.ngc`'s lines 83-90
//!   renders faster than the run, but its curves plan slower, and so does
//!   its text read back, so it was kept as written; measurements:
//!   docs/tuning.md, `AutoOptions::curves_as_written`). The run
//!   as written keeps every corner, these only those next to an arc:
//!   where they would be written, and are cheaper than the best G2
//!   candidate where that may still be written, they are kept, and `auto`
//!   is no slower than `bspline-corner` or `lotm` alone. The fallback
//!   also tries method `fair` on the curves as written, both of its
//!   smoothings ([`crate::smooth::FairAlternatives`]: the arcs kept, or
//!   sampled within its own share of the tolerance and faired with its
//!   peak pass), under the same rule: where the best G2 candidate would
//!   be kept as written, `fair`'s may be written (LinuxCNC's `cap.ngc`,
//!   rounded rectangles of tangent arcs, at 0.01 mm). Where none of the
//!   fallback's candidates would be written from its forms either, the
//!   cheapest the writer would write as G1 ([`Objective::written_as_lines`]:
//!   the writer tries G1 on every run whose arcs do not win) is kept
//!   (LinuxCNC's `Curva_Chitarra_p1.ngc`, whose `fair` curves gain only as
//!   G1). Not earlier: judged for the best G2 candidate, it skipped the
//!   fallback where a corner method on the curves as written is written
//!   faster (`helix_slowdown.ngc`).
//!
//! The candidates are a table, [`CANDIDATES`]: each row says how the
//! candidate smooths and when it is offered. The measurements that chose
//! the constants are in `docs/tuning.md`, not here.
//!
//! Each candidate is ranked by the [`Objective`] the caller injects
//! ([`Auto::new`]): for a G-code output the time of the program as written
//! on the user's machine ([`super::WrittenTime`]: the curves rendered as
//! the writer renders them), for output of the exact curves their planned
//! time ([`PlannedTime`], programmed feeds overridden to the machine's
//! maximum so that the choice depends on the geometry, not on a feed the
//! program may set low). The cheapest is kept; a tie goes to the earlier
//! candidate. A candidate the objective cannot cost is kept only when none
//! can. Where the objective has a cheap lower bound, candidates are costed
//! in its order and only while they can still win
//! ([`super::ranking`]).
//!
//! **Sections.** A run of up to [`SECTION_MAX_PIECES`] pieces is also cut
//! at the middle of every line longer than a length
//! ([`split_at_long_lines`]; each of [`AutoOptions::section_lines`], 5, 3
//! and 1 mm by default, gives one mix) and each section gets its own fastest
//! candidate (planned from rest to rest). At a cut every candidate must
//! meet the line G2 (tangent along it, zero curvature): fits keep the cut
//! halves as lines ([`BsplineFitOptions::line_at_start`](crate::smooth::BsplineFitOptions::line_at_start)), and a candidate
//! that does not is not eligible there. A raster whose passes want fits
//! and whose step-overs want corner transitions, or a program of lines
//! and of arcs between corners, then gets the best of both. The mix is
//! planned as one run and kept only when it is faster than the best
//! candidate for the whole run (and than the mixes of the other lengths),
//! so `auto` stays no slower than any candidate; a mix whose cheap bound
//! ([`Objective::bound`]) is not below the best time found is not costed.
//!
//! **As the writer writes.** The objective costs each candidate by the
//! renderings a writer makes first; a G-code writer then also tries its
//! all-G1 alternative and a finer curvature step, which gain more on one
//! smoothing than on another. The candidates and mixes that came within
//! [`AutoOptions::final_cost_margin`] of the best (10% by default; at most
//! [`FINAL_COST_CONTENDERS`](super::FINAL_COST_CONTENDERS), the cheapest,
//! a smoothing reached twice counted once) are judged again by
//! [`Objective::final_cost`], the time of what the writer would write,
//! and the least of those is kept
//! ([`super::written_choice`]). Only for a run the writer takes whole:
//! the runs between near-reversals (below) are parts of one, which the
//! writer renders as one, so there the split and the whole run's best
//! are judged so instead.
//!
//! **Near-reversals.** A run of up to [`SECTION_MAX_PIECES`] pieces that
//! turns by [`AutoOptions::reversal_turn`] or more at some vertex (160
//! degrees by default), and has at most [`REVERSAL_PIECES_PER_CUT`](super::REVERSAL_PIECES_PER_CUT)
//! pieces per such vertex, is also smoothed as the runs between those
//! vertices, each as above but offered only the candidates the whole
//! run's best smoothing chose and the plain fit, the vertices kept as
//! corners (reported as reversals); that is kept where it plans faster
//! than the best smoothing of the whole run ([`super::reversals`]: any G2
//! turn there is a near-cusp). The two corners of a narrow U-turn (at
//! most [`AutoOptions::u_turn_width`] apart, 3 mm by default, together
//! turning by `reversal_turn` or more: the step-over of a zigzag) are cut
//! the same way ([`super::u_turn_cuts`]).

use super::auto_options::AutoOptions;
use super::candidate_threads::map_candidates;
use super::candidates::{
    has_splines, is_corner_method, is_fair, is_g2, shallow_sections, widens_sections, Candidate,
    CandidateList, Input, Kind, Offered, SectionRule, CANDIDATES, FAIR, FAIR_CURVES_AS_WRITTEN,
    FAIR_MAX_PIECES, FAIR_STRAIGHTENED, THROUGH_MAX_PIECES,
};
use super::objective::{fair_on, Objective, PlannedTime, KEEP_MARGIN};
use super::ranking::Ranking;
use super::reversals::{cut_sets_bounded, reversal_cuts, split_at};
use super::sections::{
    meets_cut_lines, split_at_long_lines, Mix, SectionCache, MIXES, SECTION_MAX_PIECES,
};
use super::written_choice::fastest_written;
use crate::geom::{Curve, JointTolerances, ParamCurve};
use crate::path::{Piece, Run};
use crate::smooth::{
    check_tolerance, CornerReason, Fair, FairOptions, KeptCorner, RunMemo, SmoothError,
    SmoothedRun, Smoother,
};
use alloc::sync::Arc;
use alloc::vec::Vec;

/// Share of the tolerance that the chords of sampled arcs may take (see
/// [`crate::budget`]).
pub use crate::budget::ARC_SAMPLING_SHARE as ARC_SHARE;

/// The `auto` method (see the module documentation).
#[derive(Clone, Debug)]
pub struct Auto {
    pub options: AutoOptions,
    /// What the candidates are ranked by.
    pub objective: Arc<dyn Objective>,
}

impl Auto {
    /// `auto` with `options`, ranking its candidates by `objective`.
    pub fn new(options: AutoOptions, objective: Arc<dyn Objective>) -> Self {
        Auto { options, objective }
    }
}

impl Default for Auto {
    /// Default options, ranked by [`PlannedTime::default`] (the reference
    /// machine of seed 003: pass your own with [`Auto::new`]).
    fn default() -> Self {
        Auto::new(AutoOptions::default(), Arc::new(PlannedTime::default()))
    }
}

/// `run` with every piece that is not a line replaced by chords within
/// `chord` mm of it (exact end points; each chord keeps the piece's input
/// lines and feed; [`Run::sampled`]).
pub fn sample_curves(run: &Run, chord: f64) -> Run {
    run.sampled(chord, |_| true)
}

impl Auto {
    /// The candidates for `run` with the run they smooth and its tolerance
    /// (see the module documentation).
    fn plan_candidates<'a>(
        &self,
        run: &'a Run,
        tolerance: f64,
    ) -> Result<CandidateList<'a>, SmoothError> {
        self.options.validate()?;
        let share = self.options.arc_share;
        // The candidates of a run with arcs get the rest of the tolerance.
        check_tolerance(tolerance * (1.0 - share))?;
        let has_curves = run
            .pieces
            .iter()
            .any(|p| !matches!(p.curve, Curve::Line(_)));
        // With arcs or curves, every candidate works on the run sampled as
        // chords, with what the chords leave of the tolerance.
        let (input, tol) = if has_curves {
            let chord = share * tolerance;
            (Input::Sampled(sample_curves(run, chord)), tolerance - chord)
        } else {
            (Input::Lines(run), tolerance)
        };
        let wide = SectionRule::WideWiggles.options();
        let mut out = Vec::new();
        for (i, row) in CANDIDATES.iter().enumerate() {
            if self.options.leave_out.contains_row(i) {
                continue;
            }
            let offered = match row.offered {
                Offered::Always => true,
                Offered::WhenItWidens => widens_sections(input.run(), tol, &wide),
                Offered::OnShortRuns => input.run().pieces.len() <= THROUGH_MAX_PIECES,
                Offered::AlreadyG2 => is_g2(run, tolerance),
                Offered::OnCurves => has_curves && self.options.curves_as_written,
                Offered::OnSplinesOrShortRuns => {
                    has_splines(run) || input.run().pieces.len() <= FAIR_MAX_PIECES
                }
                Offered::OnSplines => has_splines(run),
                Offered::WhenShallowCornersWiden => {
                    input.run().pieces.len() <= THROUGH_MAX_PIECES
                        && widens_sections(input.run(), tol, &shallow_sections())
                }
            };
            if offered {
                let candidate = match row.kind.candidate() {
                    Candidate::Fair(o) => Candidate::Fair(fair_on(o, self.objective.as_ref())),
                    c => c,
                };
                out.push((row.name, candidate));
            }
        }
        Ok((input, tol, out))
    }

    /// The candidates for `run` (see the module documentation), each with
    /// its name, smoothed one after the other.
    pub fn candidates(
        &self,
        run: &Run,
        tolerance: f64,
    ) -> Result<Vec<(&'static str, SmoothedRun)>, SmoothError> {
        let (input, tol, list) = self.plan_candidates(run, tolerance)?;
        let memo = RunMemo::default();
        list.iter()
            .map(|(name, c)| {
                let cand = c.smooth((run, tolerance), input.run(), tol, (false, false), &memo)?;
                Ok((*name, cand))
            })
            .collect()
    }
}

/// How far above the best candidate's cost (as a share of it) a `fair`
/// candidate made without the peak pass may come and still be made again
/// with it ([`Auto::fair_with_peak_pass`]): above the 1.3% the pass made
/// up on `spiral_tight_circular.ngc` (measurements: docs/tuning.md,
/// `Auto::fair_with_peak_pass`).
const FAIR_PEAK_MARGIN: f64 = 0.02;

impl Auto {
    /// Every candidate for `run`, smoothed (the fits and fairings shared
    /// through `memo`), to be ranked by the objective.
    pub(super) fn ranked_candidates<'s, 'r>(
        &'s self,
        run: &'r Run,
        tolerance: f64,
        cut_ends: (bool, bool),
        memo: &RunMemo,
    ) -> Result<(Ranking<'s>, CandidateList<'r>), SmoothError> {
        let (input, tol, list) = self.plan_candidates(run, tolerance)?;
        let smoothed = map_candidates(list.len(), |i| {
            let mut cand = list[i]
                .1
                .smooth((run, tolerance), input.run(), tol, cut_ends, memo)?;
            cand.chosen = alloc::vec![list[i].0];
            Ok(cand)
        })
        .into_iter()
        .collect::<Result<Vec<SmoothedRun>, SmoothError>>()?;
        let ranking = Ranking::new(self.objective.as_ref(), smoothed);
        Ok((ranking, (input, tol, list)))
    }
}

impl Smoother for Auto {
    fn name(&self) -> &'static str {
        "auto"
    }

    fn smooth_run(&self, run: &Run, tolerance: f64) -> Result<SmoothedRun, SmoothError> {
        check_tolerance(tolerance)?;
        self.options.validate()?;
        let (time, best, in_place_of_kept, cheapest) = self.smooth_whole(run, tolerance, true)?;
        // Split at its near-reversals where that costs less; of the two,
        // where they come near, the one the writer writes faster.
        let chosen = match self.between_reversals(run, (time, &best), &cheapest, tolerance)? {
            Some((t, split)) => {
                let whole = time.map(|tw| (tw, best)).into_iter().collect();
                self.finally_written(Some(t), split, whole)
            }
            None => (time, best),
        };
        Ok(self.unless_kept(run, chosen, in_place_of_kept).1)
    }

    /// A window of a longer run: its fastest candidate that meets the cut
    /// lines G2 (fits keep their halves as lines, as at a section's cut),
    /// the fastest of all where none does; as for a run longer than
    /// [`SECTION_MAX_PIECES`] (the longer run is), without sections or
    /// near-reversals.
    fn smooth_window(
        &self,
        run: &Run,
        tolerance: f64,
        cut: (bool, bool),
    ) -> Result<SmoothedRun, SmoothError> {
        if cut == (false, false) {
            return self.smooth_run(run, tolerance);
        }
        check_tolerance(tolerance)?;
        self.options.validate()?;
        let memo = RunMemo::default();
        let (mut ranking, _) = self.ranked_candidates(run, tolerance, cut, &memo)?;
        let direction = |p: Option<&Piece>| match p.map(|p| &p.curve) {
            Some(Curve::Line(l)) => Some(l.p1 - l.p0),
            _ => None,
        };
        let before = direction(run.pieces.first()).filter(|_| cut.0);
        let after = direction(run.pieces.last()).filter(|_| cut.1);
        let jt = JointTolerances::from_tolerance(tolerance);
        let i = match ranking.cheapest(|c| meets_cut_lines(c, (before, after), jt)) {
            Some(i) => i,
            None => ranking.fastest(|_| true).ok_or(SmoothError::NoCandidate)?.1,
        };
        Ok(core::mem::take(&mut ranking.cands[i]))
    }
}

/// [`Auto::smooth_whole`]'s answer: the best's cost and the best; the
/// cheapest candidate the writer would write where it would keep the
/// run as written in place of the best, with its cost; and the candidates
/// the cheapest by cost chose (before the writer's judgement picked among
/// those near it: [`Auto::between_reversals`] offers both's).
type WholeRun = (
    Option<f64>,
    SmoothedRun,
    Option<(f64, SmoothedRun)>,
    Vec<&'static str>,
);

impl Auto {
    /// The cheapest smoothing of `run` as one run, with its cost: the
    /// candidates, the section mixes and the fallback (see the module
    /// documentation). With `written`, of the candidates and mixes near
    /// the best, the one the writer writes fastest ([`fastest_written`]):
    /// for a run the writer takes whole, not for a part of one (the
    /// writer's renderings are the whole run's); and then, where the best
    /// would be kept as written, the cheapest candidate the writer would
    /// write with its cost ([`Auto::written_in_place_of_kept`]).
    fn smooth_whole(
        &self,
        run: &Run,
        tolerance: f64,
        written: bool,
    ) -> Result<WholeRun, SmoothError> {
        let lines = self.options.section_lines;
        // The fits and fairings of the run and of its sections, shared
        // between the candidates, the sections that cut a stretch alike
        // and the fallback.
        let memo = RunMemo::default();
        let (mut ranking, list) = self.ranked_candidates(run, tolerance, (false, false), &memo)?;
        let (mut time, i) = ranking.fastest(|_| true).ok_or(SmoothError::NoCandidate)?;
        // Where the best would be kept as written, the cheapest candidate
        // the writer would write, handed back with the best: it replaces
        // the final choice where the writer would still keep the run as
        // written ([`Auto::unless_kept`]; after the near-reversals, which
        // offer the candidates the best chose).
        let in_place_of_kept = written
            .then(|| self.written_in_place_of_kept(run, &mut ranking, (time, i)))
            .flatten()
            .map(|(t, k)| (t, ranking.cands[k].clone()));
        let peaked = self.fair_with_peak_pass(run, &list, &ranking, time, &memo)?;
        drop(list);
        // The candidates costed near the best, to be judged again as the
        // writer finally writes them ([`fastest_written`]).
        let mut others = match time {
            Some(t) if written => ranking.near(i, t * (1.0 + self.options.final_cost_margin)),
            _ => Vec::new(),
        };
        let mut best = core::mem::take(&mut ranking.cands[i]);
        drop(ranking);
        if let Some((t, cand)) = peaked {
            if let (Some(tb), true) = (time, written) {
                others.push((tb, core::mem::replace(&mut best, cand)));
            } else {
                best = cand;
            }
            time = Some(t);
        }
        if run.pieces.len() > SECTION_MAX_PIECES {
            let cheapest = best.chosen.clone();
            let (time, best) = self.finally_written(time, best, others);
            return Ok((time, best, in_place_of_kept, cheapest));
        }
        let mut cache = SectionCache::default();
        let mut tried: Vec<usize> = Vec::new();
        for line in lines {
            let sections = split_at_long_lines(run, line);
            // A length that cuts where a longer one did gives the same mix.
            if sections.len() < 2 || tried.contains(&sections.len()) {
                continue;
            }
            tried.push(sections.len());
            // Each section's fastest candidate; where that was `fair`
            // somewhere, also the fastest but `fair`; where a mix with a
            // corner method became the fastest, also the fastest fit
            // ([`Mix`]).
            let mut wanted = [true, false, false];
            for mix in MIXES {
                let k = mix as usize;
                if !wanted[k] {
                    continue;
                }
                let Some(mixed) =
                    self.smooth_sections(&sections, tolerance, (&mut cache, &memo), mix)?
                else {
                    // `fair` may have left a cut joint not G2: try without.
                    wanted[Mix::WithoutFair as usize] |= mix == Mix::All;
                    continue;
                };
                wanted[Mix::WithoutFair as usize] |= mixed.chosen.iter().any(|n| is_fair(n));
                // A mix whose cheap bound is not below the best time found
                // cannot be kept: not costed.
                if let (Some(b), Some(tw)) = (self.objective.bound(&mixed.pieces), time) {
                    if b >= tw {
                        continue;
                    }
                }
                let t = self.objective.cost(&mixed.pieces);
                if let (Some(t), Some(tw)) = (t, time) {
                    if t < tw {
                        wanted[Mix::FitsOnly as usize] |=
                            mixed.chosen.iter().any(|n| is_corner_method(n));
                        let before = core::mem::replace(&mut best, mixed);
                        if written {
                            others.push((tw, before));
                        }
                        time = Some(t);
                    } else if written {
                        others.push((t, mixed));
                    }
                }
            }
        }
        let cheapest = best.chosen.clone();
        (time, best) = self.finally_written(time, best, others);
        if let Some((t, kept)) =
            self.curves_as_written_fallback(run, tolerance, (&best, time), &memo)?
        {
            (time, best) = (Some(t), kept);
        }
        Ok((time, best, in_place_of_kept, cheapest))
    }

    /// `best` (of cost `time`), or `alternative` (one the writer would
    /// write, [`Auto::written_in_place_of_kept`]) where the writer would
    /// keep `run` as the program wrote it in place of `best`
    /// ([`Objective::written_instead`] false) and `alternative` costs
    /// [`KEEP_MARGIN`] less than the run as written and than the best as
    /// the writer finally writes it ([`Objective::final_cost`]).
    fn unless_kept(
        &self,
        run: &Run,
        (time, best): (Option<f64>, SmoothedRun),
        alternative: Option<(f64, SmoothedRun)>,
    ) -> (Option<f64>, SmoothedRun) {
        let Some((ta, alt)) = alternative else {
            return (time, best);
        };
        let objective = self.objective.as_ref();
        let Some(own) = objective.as_written(&run.pieces) else {
            return (time, best);
        };
        // Kept as written by the objective's rule, and the alternative
        // cheaper, by the writers' margin, than what the writer makes of
        // the best with all its tries (it may write it all the same, at
        // a finer step: on one of 56 generated programs a mix of
        // sections the objective judged kept was written nine parts in a
        // million faster than the alternative; docs/tuning.md).
        let replaced = match time {
            None => true,
            Some(t) => {
                !objective.written_instead(&best.pieces, t, &run.pieces, own)
                    && ta * (1.0 + KEEP_MARGIN) < own.min(objective.final_cost(&best.pieces, t))
            }
        };
        if replaced {
            (Some(ta), alt)
        } else {
            (time, best)
        }
    }

    /// Where the ranking's cheapest candidate `best` (of cost `time`)
    /// would leave `run` as the program wrote it ([`Objective::written_instead`]
    /// false), every candidate costed and the cheapest the writer would
    /// write, with its cost; `None` where the best would be written, or
    /// none would.
    ///
    /// Why: the ranking skips the candidates whose [`Objective::bound`]
    /// (their curves' planned time, less the share a rendering has been
    /// measured to gain) exceeds the least cost found, and a rendering can
    /// gain far more than that share. A corner method on a dense 3D raster
    /// puts a short transition at every vertex of a pass, where the
    /// curvature ramps cap the exact curves' speed; rendered within the
    /// output's share they become the pass's lines again, which the
    /// planner blends at its junction deviation: the curves plan twice as
    /// long as their program (`scripts/random-programs.py /tmp/gras 8
    /// 9702 raster`, `r001_raster.ngc`). There the fit the ranking kept
    /// lost on its rendering (its passes bend out of their plane next to
    /// the step-overs, so they are written as G1), the run was kept as
    /// the program wrote it, and `bspline-corner` and `ctm` alone wrote
    /// faster programs.
    fn written_in_place_of_kept(
        &self,
        run: &Run,
        ranking: &mut Ranking,
        (time, best): (Option<f64>, usize),
    ) -> Option<(f64, usize)> {
        let t = time?;
        let objective = self.objective.as_ref();
        let own = objective.as_written(&run.pieces)?;
        if objective.written_instead(&ranking.cands[best].pieces, t, &run.pieces, own) {
            return None;
        }
        ranking
            .cheapest_kept_aside(|c, t| objective.written_instead(&c.pieces, t, &run.pieces, own))
    }

    /// `best` (of cost `time`), or the one of `others` (each with its
    /// cost) near it that the writer writes fastest ([`fastest_written`]).
    fn finally_written(
        &self,
        time: Option<f64>,
        best: SmoothedRun,
        others: Vec<(f64, SmoothedRun)>,
    ) -> (Option<f64>, SmoothedRun) {
        match time {
            Some(t) => {
                let margin = self.options.final_cost_margin;
                let (t, best) = fastest_written(self.objective.as_ref(), margin, (t, best), others);
                (Some(t), best)
            }
            None => (None, best),
        }
    }

    /// `fair`'s candidates on a run of lines (or of sampled arcs) made
    /// again with the peak pass, where their cost without it came within
    /// [`FAIR_PEAK_MARGIN`] of `time`, the best cost of `ranking`: the
    /// cheapest of them with its cost, where that is below `time`.
    ///
    /// Why: the candidates fair such runs without the peak pass (see
    /// [`Candidate::smooth`]), which method `fair` runs; where `fair` is
    /// the fastest single method, `auto` was slower than it by what the
    /// pass gains (`spiral_tight_circular.ngc` at 0.05 mm: a run whose
    /// `fair` candidate came 1.3% behind the best fit, and 0.13% ahead of
    /// it with the pass). Made again only where a `fair` candidate is
    /// near the best, the pass costs little where it cannot change the
    /// choice (measurements: docs/tuning.md, `Auto::fair_with_peak_pass`).
    fn fair_with_peak_pass(
        &self,
        run: &Run,
        (input, tol, list): &CandidateList,
        ranking: &Ranking,
        time: Option<f64>,
        memo: &RunMemo,
    ) -> Result<Option<(f64, SmoothedRun)>, SmoothError> {
        let Some(time) = time else {
            return Ok(None);
        };
        // (On a run with a B-spline `fair` works in place, with the pass.)
        if has_splines(run) || self.objective.peak_pass().is_none() {
            return Ok(None);
        }
        let near: Vec<&'static str> = ranking
            .cands
            .iter()
            .enumerate()
            .filter(|(k, c)| {
                c.chosen.len() == 1
                    && is_fair(c.chosen[0])
                    && ranking
                        .cost_of(*k)
                        .flatten()
                        .is_some_and(|t| t <= time * (1.0 + FAIR_PEAK_MARGIN))
            })
            .map(|(_, c)| c.chosen[0])
            .collect();
        if near.is_empty() {
            return Ok(None);
        }
        // The rows as the ranking's candidates were made from them (`list`,
        // with the objective's peak pass: `fair_on`).
        let mut best: Option<(f64, SmoothedRun)> = None;
        for (name, c) in list {
            let Candidate::Fair(o) = c else { continue };
            if !near.contains(name) {
                continue;
            }
            let mut cand = Fair { options: *o }.smooth_run_with(input.run(), *tol, memo)?;
            cand.chosen = alloc::vec![*name];
            if let Some(t) = self.objective.cost(&cand.pieces) {
                if t < best.as_ref().map_or(time, |b| b.0) {
                    best = Some((t, cand));
                }
            }
        }
        Ok(best)
    }

    /// `run` smoothed as the runs between its near-reversals, or between
    /// those and the corners of its narrow U-turns ([`cut_sets_bounded`]:
    /// the cheaper), each by [`Auto::smooth_whole`], those vertices
    /// kept as corners, with its cost, where that costs less than `time`
    /// (the best smoothing of the whole run); `None` where there is no such vertex,
    /// the run is longer than [`SECTION_MAX_PIECES`] or than
    /// [`REVERSAL_PIECES_PER_CUT`](super::REVERSAL_PIECES_PER_CUT) pieces per such vertex, or it costs no
    /// less.
    fn between_reversals(
        &self,
        run: &Run,
        (time, whole): (Option<f64>, &SmoothedRun),
        cheapest: &[&'static str],
        tolerance: f64,
    ) -> Result<Option<(f64, SmoothedRun)>, SmoothError> {
        let Some(time) = time else {
            return Ok(None);
        };
        if run.pieces.len() > SECTION_MAX_PIECES {
            return Ok(None);
        }
        let sets = cut_sets_bounded(
            run,
            self.options.reversal_turn,
            tolerance,
            self.options.u_turn_width,
        );
        if sets.is_empty() {
            return Ok(None);
        }
        // The runs between get the candidates the whole run's best
        // smoothing chose somewhere, and the plain fit: every candidate
        // again would double `auto`'s work on such runs for gains the
        // survey did not find (docs/tuning.md, `REVERSAL_TURN`). Also
        // those the cheapest by cost chose (`cheapest`), where the
        // writer's judgement kept another: on `line-contouring-xz.ngc`
        // with `final_cost_margin` 0.03 the one kept was the plain fit
        // alone, and offered only that, the runs between its U-turns
        // wrote 12.889 s against 12.489 s (docs/tuning.md,
        // `FINAL_COST_CONTENDERS`).
        let mut leave_out = self.options.leave_out;
        for (k, row) in CANDIDATES.iter().enumerate() {
            if row.name != "bspline-fit"
                && !whole.chosen.contains(&row.name)
                && !cheapest.contains(&row.name)
            {
                leave_out.insert_row(k);
            }
        }
        if leave_out.holds_every_one_always_offered() {
            // (The user left the plain fit out, and the whole run's best
            // took none of the others offered everywhere.)
            return Ok(None);
        }
        let between = Auto {
            options: AutoOptions {
                leave_out,
                ..self.options
            },
            objective: self.objective.clone(),
        };
        // The cuts that are near-reversals; the others are U-turns'
        // corners.
        let reversals = reversal_cuts(run, self.options.reversal_turn, tolerance);
        let mut best: Option<(f64, SmoothedRun)> = None;
        for cuts in &sets {
            let mut out = SmoothedRun::default();
            for (i, part) in split_at(run, cuts).iter().enumerate() {
                let (_, best, _, _) = between.smooth_whole(part, tolerance, false)?;
                if i > 0 {
                    let before = &run.pieces[cuts[i - 1] - 1];
                    let reason = if reversals.contains(&cuts[i - 1]) {
                        CornerReason::Reversal
                    } else {
                        CornerReason::UTurn
                    };
                    out.kept_corners.push(KeptCorner {
                        at: before.curve.end(),
                        source_line: before.source_lines.1,
                        reason,
                    });
                }
                out.append(&best);
            }
            let to_beat = best.as_ref().map_or(time, |b| b.0);
            if self
                .objective
                .bound(&out.pieces)
                .is_some_and(|b| b >= to_beat)
            {
                continue;
            }
            if let Some(t) = self.objective.cost(&out.pieces).filter(|&t| t < to_beat) {
                best = Some((t, out));
            }
        }
        Ok(best)
    }
}

impl Auto {
    /// The corner methods on the curves as written ([`Kind::CornerInPlace`]
    /// rows of [`CANDIDATES`]), and `fair`'s two smoothings of the run
    /// (unless left out), for a run with an arc or curve, when they are
    /// not offered beside the others and `best`, the best G2 candidate
    /// costing `time`, would leave the run as the program wrote it (see
    /// the module documentation); the cheapest of them that would itself
    /// be written (is [`KEEP_MARGIN`] cheaper than the run as written at
    /// every feed the writer judges at), if it costs less than `time`.
    /// `None`: nothing to change.
    fn curves_as_written_fallback(
        &self,
        run: &Run,
        tolerance: f64,
        (best, time): (&SmoothedRun, Option<f64>),
        memo: &RunMemo,
    ) -> Result<Option<(f64, SmoothedRun)>, SmoothError> {
        let has_curves = run
            .pieces
            .iter()
            .any(|p| !matches!(p.curve, Curve::Line(_)));
        if self.options.curves_as_written || !has_curves {
            return Ok(None);
        }
        let Some(own) = self.objective.as_written(&run.pieces) else {
            return Ok(None);
        };
        // Whether the writer would write the best G2 candidate, by the
        // objective (at every feed the writer judges a run at).
        let objective = self.objective.as_ref();
        let rendered_gains =
            time.is_some_and(|t| objective.written_instead(&best.pieces, t, &run.pieces, own));
        if rendered_gains && objective.as_written(&best.pieces).is_some_and(|c| c < own) {
            return Ok(None);
        }
        // What a corner candidate must beat: the best G2 candidate where
        // the writer may still write it (its rendering gains, its curves
        // do not), else only the run as written.
        let beat = time.filter(|_| rendered_gains);
        let rows: Vec<_> = CANDIDATES
            .iter()
            .enumerate()
            .filter(|(i, r)| {
                matches!(r.kind, Kind::CornerInPlace(_)) && !self.options.leave_out.contains_row(*i)
            })
            .map(|(_, r)| r)
            .collect();
        let mut smoothed = map_candidates(rows.len(), |i| {
            let mut cand = rows[i].kind.candidate().smooth(
                (run, tolerance),
                run,
                tolerance,
                (false, false),
                memo,
            )?;
            cand.chosen = alloc::vec![rows[i].name];
            Ok(cand)
        })
        .into_iter()
        .collect::<Result<Vec<SmoothedRun>, SmoothError>>()?;
        // And method `fair` on the curves as written, both of its
        // smoothings (the arcs kept, or sampled within its own share and
        // faired with its peak pass): where the best G2 candidate would be
        // kept as written, one of them may be written (LinuxCNC's
        // `cap.ngc` at 0.01 mm; measurements: docs/tuning.md,
        // `JudgedFair`).
        // And straightened, where method `fair` judges that
        // (`Straighten::Judged`: runs with a B-spline).
        let options = fair_on(FairOptions::default(), objective);
        let fairs = [
            (FAIR, options, true),
            (FAIR_STRAIGHTENED, options.straightened(), has_splines(run)),
        ];
        for (name, options, offered) in fairs {
            if !offered || self.options.leave_out.contains(name) {
                continue;
            }
            let alt = Fair { options }.alternatives_with(run, tolerance, memo)?;
            let named = [FAIR_CURVES_AS_WRITTEN, name];
            for (mut cand, name) in core::iter::once(alt.kept).chain(alt.sampled).zip(named) {
                cand.chosen = alloc::vec![name];
                smoothed.push(cand);
            }
        }
        // Those whose cheap bound already says they would not be kept are
        // not costed.
        let could_win = |c: &SmoothedRun| {
            objective
                .bound(&c.pieces)
                .is_none_or(|b| b * (1.0 + KEEP_MARGIN) <= own && beat.is_none_or(|tw| b < tw))
        };
        let smoothed: Vec<SmoothedRun> = smoothed.into_iter().filter(could_win).collect();
        if smoothed.is_empty() {
            return Ok(None);
        }
        let mut ranking = Ranking::new(objective, smoothed);
        // The cheapest that would be written: cheaper than the run as
        // written by the writer's rule (else the run is written as the
        // program wrote it either way, and the G2 curves stay what `auto`
        // reports), and kept only where it is also cheaper than the best
        // G2 candidate where that may be written.
        // Where none would be written from its forms and no G2 candidate
        // may be, the cheapest the writer would write as G1 (it tries G1
        // on every run whose arcs do not win: LinuxCNC's
        // `Curva_Chitarra_p1.ngc`, where `fair`'s curves gain only so).
        let Some((t, i)) = ranking
            .cheapest_kept(|c, t| objective.written_instead(&c.pieces, t, &run.pieces, own))
            .or_else(|| {
                beat.is_none().then(|| {
                    ranking.cheapest_kept(|c, _| {
                        objective.written_as_lines(&c.pieces, &run.pieces, own)
                    })
                })?
            })
        else {
            return Ok(None);
        };
        if beat.is_some_and(|tw| t >= tw) {
            return Ok(None);
        }
        Ok(Some((t, core::mem::take(&mut ranking.cands[i]))))
    }
}

#[cfg(test)]
mod tests;
