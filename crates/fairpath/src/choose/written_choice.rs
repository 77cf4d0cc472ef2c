//! The writer's own choice of a run's rendering, as `auto` judges its
//! nearest candidates by it.
//!
//! [`WrittenTime`] costs a candidate by the renderings a G-code writer
//! makes first: each form the format allows at the default curvature
//! step. The writer then tries more (`fairpath_gcode`'s
//! `emit::choose_run`): the all-G1 alternative where the arcs fell back to
//! lines on some curve, and the winning form again at a finer curvature
//! step, kept where it plans [`FINER_KEEP_MARGIN`] faster at every feed it
//! judges at. What they gain differs between smoothings of one run: on
//! `3D_Chips.ngc` at 0.02 mm the mix of sections `auto` ranked 0.6% ahead
//! of its best whole-run fit gained 1.4% at the finer step and the fit
//! 2.2%, so the program `auto` wrote was slower than the fit alone; at
//! 0.1 mm the writer wrote the best candidate's main run as G1, faster
//! than any candidate's arcs at either step. Costing every candidate so
//! would render and plan each two to four times more; `auto` judges only
//! the candidates that come within [`FINAL_COST_MARGIN`] of its best, at
//! most [`FINAL_COST_CONTENDERS`] of them, by [`Objective::final_cost`]
//! (measurements: docs/tuning.md, `FINAL_COST_MARGIN`).

use super::objective::{Objective, WrittenTime, FINER_KEEP_MARGIN};
use crate::path::Piece;
use crate::render::{render_run, CurveForm, RenderOptions, Rendered};
use crate::smooth::SmoothedRun;
use alloc::vec::Vec;

/// What a G-code writer tries for a run beyond [`WrittenTime::renders`]
/// ([`WrittenTime::writer_tries`]; with [`WrittenTime::lines_alternative`],
/// its all-G1 rendering where the arcs fell back to lines).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WriterTries {
    /// The factor on the winning rendering's
    /// [`RenderOptions::step_share`] at which it is rendered again
    /// (`fairpath_gcode`'s `FINER_STEP`, 0.5), in `(0, 1)`.
    pub finer_share: f64,
    /// How many times the winning rendering is rendered again, each at
    /// `finer_share` of the share before and kept while it gains
    /// (`fairpath_gcode`'s `FINER_STEPS`, 2).
    pub finer_steps: usize,
    /// A run of at least this many curves is long: the writer renders it
    /// once (`fairpath_gcode`'s `LONG_RUN_PIECES`); a G1 alternative to
    /// arcs of at least this many pieces is rendered as it is written,
    /// and not again at the finer step.
    pub long_pieces: usize,
    /// The all-G1 alternative where the arcs rendering holds no arc (the
    /// writer's finer chord of G1 output), if the budget gives one; else
    /// [`WrittenTime::lines_alternative`].
    pub lines_without_arcs: Option<RenderOptions>,
}

/// Share of the best cost within which `auto`'s other candidates (whole
/// runs and mixes of sections) are judged again by
/// [`Objective::final_cost`]: 10%. The writer's tries (its all-G1
/// alternative, the finer step) can gain more on one candidate than on
/// another by several percent: on `r027_engrave.ngc` a mix of sections
/// costing 3.3% more than the best (which the writer wrote as costed)
/// was written 1.4% faster than it (measurements: docs/tuning.md,
/// `FINAL_COST_MARGIN`).
pub const FINAL_COST_MARGIN: f64 = 0.1;

/// Most candidates judged by [`Objective::final_cost`] for one run, the
/// best included: each costs the writer's renderings again (up to four,
/// each planned at up to two feeds). Six: the cost ranks the near
/// candidates loosely by what the writer finally writes (what the finer
/// step gains differs between a whole-run fit and a mix of sections), and
/// the fastest written was the fourth cheapest on `3D_Chips.ngc`'s main
/// run and up to the sixth on others (measurements: docs/tuning.md,
/// `FINAL_COST_CONTENDERS`).
pub const FINAL_COST_CONTENDERS: usize = 6;

/// Share of the best cost by which a contender's final cost must be below
/// the pick's to replace it: final costs plan the renderings the writer
/// is expected to make, not the program it writes (its rounding, its own
/// checks), and within a hair they rank by noise. On `arc-arc-test.ngc`
/// (LinuxCNC) a mix of sections costing 3.7% more than the best was
/// judged 7.6e-5 of the time faster and written 1.06% slower; at 1e-3
/// it is not taken, and the programs the margin was measured on lose at
/// most 2e-5 of their time (measurements: docs/tuning.md,
/// `FINAL_COST_MARGIN`).
pub const FINAL_TIE_SHARE: f64 = 1e-3;

/// Share of the best cost within which two contenders' costs are taken
/// for the same smoothing, and only the cheaper is judged by
/// [`Objective::final_cost`]: on `3D_Chips.ngc` one mix of sections
/// reached by two routes differed in the last bits of its pieces and
/// planned the same to 7e-15 of its time (judged twice, it took two of
/// the contenders' places), where the different contenders of that run
/// differed by 8e-4 of it and more.
pub const SAME_COST_SHARE: f64 = 1e-9;

/// A rendering the writer chose, with its options, its time at the
/// writer's first feed and at [`WrittenTime::plan`].
struct Chosen {
    ro: RenderOptions,
    rendered: Rendered,
    first: f64,
    plan: f64,
}

impl WrittenTime {
    /// [`Objective::final_cost`]: the time on [`WrittenTime::plan`] of the
    /// rendering the writer chooses for `pieces`, as `emit::choose_run`
    /// chooses for a run that is not long: each form of
    /// [`WrittenTime::renders`], then the all-G1 alternative where the
    /// best so far fell back to lines on some curve, each kept where it
    /// is faster at the writer's first feed (the machine's maximum); then
    /// the winner at the finer step where that plans [`FINER_KEEP_MARGIN`]
    /// faster at every feed the writer judges at ([`WrittenTime::plan`]
    /// and, where it differs, [`WrittenTime::shape`]), and finer again
    /// while each gains on the one before, up to
    /// [`WriterTries::finer_steps`] times: arcs that hold an arc, or G1
    /// that was not streamed. `cost` where the writer's tries
    /// are not known or a rendering fails. The writer's own test against
    /// the run as written is not made here: it is the same for every
    /// candidate. Where a spline rendering (G5.2, G6.2) wins, the writer
    /// tries nothing after it, and neither does this.
    pub(super) fn writer_cost(&self, pieces: &[Piece], cost: f64) -> f64 {
        let Some(tries) = self.writer_tries else {
            return cost;
        };
        if pieces.len() >= tries.long_pieces
            || !(tries.finer_share > 0.0 && tries.finer_share < 1.0)
        {
            return cost;
        }
        let Some(speed) = self.shaping_speed(pieces) else {
            return cost;
        };
        // The writer's first feed is the machine's maximum; where no
        // programmed feed is below it, the two plans are one.
        let one_feed = self.one_feed(pieces);
        let times = |r: &Rendered, ro: &RenderOptions| {
            let first = self.rendered_time_on(&r.pieces, ro.form, &self.shape)?;
            let plan = if one_feed {
                first
            } else {
                self.rendered_time_on(&r.pieces, ro.form, &self.plan)?
            };
            Some((first, plan))
        };
        let mut best: Option<Chosen> = None;
        let mut arcs_all_lines = false;
        let mut streamed = false;
        let forms = self.renders.iter().copied().map(|ro| (ro, false));
        let alternative = self.lines_alternative.map(|ro| (ro, true));
        for (ro, is_alternative) in forms.chain(alternative) {
            if let Some(b) = &best {
                let fell_back = b.rendered.stats.fallback_lines > 0 || b.rendered.stats.chained > 0;
                let nurbs = matches!(b.ro.form, CurveForm::Nurbs(_));
                if nurbs || (ro.form == CurveForm::Lines && !fell_back) {
                    continue;
                }
            }
            let ro = match tries.lines_without_arcs {
                Some(finer) if is_alternative && arcs_all_lines => finer,
                _ => ro,
            };
            let Ok(r) = render_run(pieces, &speed, &ro) else {
                return cost;
            };
            if ro.form == CurveForm::Arcs {
                arcs_all_lines = r.stats.arcs == 0;
            }
            let Some((first, plan)) = times(&r, &ro) else {
                continue;
            };
            if best.as_ref().is_some_and(|b| first >= b.first) {
                continue;
            }
            streamed = is_alternative
                && best
                    .as_ref()
                    .is_some_and(|b| b.rendered.pieces.len() >= tries.long_pieces);
            best = Some(Chosen {
                ro,
                rendered: r,
                first,
                plan,
            });
        }
        let Some(b) = best else {
            return cost;
        };
        let again = match b.ro.form {
            CurveForm::Arcs => b.rendered.stats.arcs > 0,
            CurveForm::Lines => !streamed,
            _ => false,
        };
        if !again {
            return b.plan;
        }
        let gains = |f: f64, d: f64| f * (1.0 + FINER_KEEP_MARGIN) < d;
        let (mut first, mut plan, mut share) = (b.first, b.plan, b.ro.step_share);
        for _ in 0..tries.finer_steps {
            share *= tries.finer_share;
            let fro = RenderOptions {
                step_share: share,
                ..b.ro
            };
            let Ok(fine) = render_run(pieces, &speed, &fro) else {
                break;
            };
            match times(&fine, &fro) {
                Some((f, p)) if gains(f, first) && gains(p, plan) => (first, plan) = (f, p),
                _ => break,
            }
        }
        plan
    }
}

impl WrittenTime {
    /// Whether `pieces`, and any rendering of them (which keeps their
    /// feeds), plan the same on [`WrittenTime::plan`] as on
    /// [`WrittenTime::shape`]: the same options, or options that differ
    /// only in overriding the feeds and no programmed feed below the
    /// machine's maximum (the planner caps each feed at it,
    /// [`crate::feed::limits::speed_cap`]).
    fn one_feed(&self, pieces: &[Piece]) -> bool {
        let overridden = crate::feed::plan::PlanOptions {
            override_feed: true,
            ..self.plan
        };
        let max = self.plan.limits.max_feed;
        self.plan == self.shape
            || (overridden == self.shape
                && pieces
                    .iter()
                    .all(|p| p.feed.is_none_or(|f| f / 60.0 >= max)))
    }
}

/// Of `best` (cost `time`) and `others` (each with its cost), the one the
/// writer writes fastest by [`Objective::final_cost`], with its cost by
/// [`Objective::cost`]: the others considered are those within `margin`
/// of `time` ([`FINAL_COST_MARGIN`] by default), the cheapest first, up to
/// [`FINAL_COST_CONTENDERS`] with `best`, each costing more than the one
/// before by over [`SAME_COST_SHARE`] of `time` (the others are taken for
/// it). A contender replaces the pick where its final cost is below the
/// pick's by more than [`FINAL_TIE_SHARE`] of `time`: a tie goes to
/// `best`, then to the cheaper.
pub(super) fn fastest_written(
    objective: &dyn Objective,
    margin: f64,
    (time, best): (f64, SmoothedRun),
    mut others: Vec<(f64, SmoothedRun)>,
) -> (f64, SmoothedRun) {
    others.retain(|(t, _)| *t <= time * (1.0 + margin));
    if others.is_empty() {
        return (time, best);
    }
    others.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut last = time;
    others.retain(|&(t, _)| {
        let apart = t - last > time * SAME_COST_SHARE;
        if apart {
            last = t;
        }
        apart
    });
    others.truncate(FINAL_COST_CONTENDERS - 1);
    let mut all = Vec::with_capacity(others.len() + 1);
    all.push((time, best));
    all.extend(others);
    let finals: Vec<f64> = super::candidate_threads::map_candidates(all.len(), |k| {
        objective.final_cost(&all[k].1.pieces, all[k].0)
    });
    let mut pick = 0;
    for k in 1..all.len() {
        if finals[k] < finals[pick] - FINAL_TIE_SHARE * time {
            pick = k;
        }
    }
    all.swap_remove(pick)
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{
        corner_curves, line_candidate as candidate, render_options, result,
    };
    use super::*;
    use crate::feed::limits::MachineLimits;
    use proptest::prelude::*;

    /// Costs and final costs by the first piece's end `x`.
    #[derive(Debug)]
    struct Table {
        costs: Vec<f64>,
        finals: Vec<f64>,
    }

    impl Objective for Table {
        fn cost(&self, pieces: &[Piece]) -> Option<f64> {
            Some(self.costs[result(pieces)])
        }
        fn final_cost(&self, pieces: &[Piece], _cost: f64) -> f64 {
            self.finals[result(pieces)]
        }
    }

    proptest! {
        /// The choice is the least final cost among the best and the
        /// others within the margin (the cheapest of them, up to the
        /// contenders' count), the best on a tie, then the cheaper; it
        /// comes with its own cost.
        #[test]
        fn the_least_final_cost_among_the_near_contenders_wins(
            costs in proptest::collection::vec(1000u32..1150, 12),
            finals in proptest::collection::vec(900u32..1100, 12),
        ) {
            let costs: Vec<f64> = costs.iter().map(|&c| f64::from(c)).collect();
            let finals: Vec<f64> = finals.iter().map(|&c| f64::from(c)).collect();
            let table = Table { costs: costs.clone(), finals: finals.clone() };
            let best = (0..12).min_by(|&a, &b| costs[a].total_cmp(&costs[b])).unwrap();
            let others: Vec<(f64, SmoothedRun)> =
                (0..12).filter(|&r| r != best).map(|r| (costs[r], candidate(r))).collect();
            let (t, chosen) =
                fastest_written(&table, FINAL_COST_MARGIN, (costs[best], candidate(best)), others);
            let r = result(&chosen.pieces);
            prop_assert_eq!(t, costs[r]);
            let mut near: Vec<usize> = (0..12)
                .filter(|&o| o != best && costs[o] <= costs[best] * (1.0 + FINAL_COST_MARGIN))
                .collect();
            near.sort_by(|&a, &b| costs[a].total_cmp(&costs[b]));
            // A cost equal to the one before (the integers' ties) is the
            // same smoothing: judged once.
            let mut last = costs[best];
            near.retain(|&o| {
                let apart = costs[o] > last;
                last = costs[o];
                apart
            });
            near.truncate(FINAL_COST_CONTENDERS - 1);
            let mut want = best;
            for &o in &near {
                if finals[o] < finals[want] - FINAL_TIE_SHARE * costs[best] {
                    want = o;
                }
            }
            prop_assert_eq!(r, want);
        }
    }

    /// `arc-arc-test.ngc` (LinuxCNC, 0.05 mm): the best cost 2.736961 s,
    /// judged 2.736961 s as written; a mix of sections costing 2.837476
    /// s judged 2.736753 s (7.6e-5 of the time less) and written 2.766
    /// s. A lead within [`FINAL_TIE_SHARE`] is a tie, which goes to the
    /// best; a lead beyond it wins.
    #[test]
    fn regression_arc_arc_test_a_lead_within_the_tie_share_keeps_the_best() {
        let costs = alloc::vec![2.736961, 2.780041, 2.837476];
        let table = Table {
            costs: costs.clone(),
            finals: alloc::vec![2.736961, 2.771276, 2.736753],
        };
        let others = (1..3).map(|r| (costs[r], candidate(r))).collect();
        let (t, chosen) =
            fastest_written(&table, FINAL_COST_MARGIN, (costs[0], candidate(0)), others);
        assert_eq!(result(&chosen.pieces), 0);
        assert_eq!(t, costs[0]);
        let table = Table {
            costs: costs.clone(),
            finals: alloc::vec![2.736961, 2.771276, 2.736961 * (1.0 - 2.0 * FINAL_TIE_SHARE)],
        };
        let others = (1..3).map(|r| (costs[r], candidate(r))).collect();
        let (_, chosen) =
            fastest_written(&table, FINAL_COST_MARGIN, (costs[0], candidate(0)), others);
        assert_eq!(result(&chosen.pieces), 2);
    }

    /// `3D_Chips.ngc`: one mix of sections reached twice (costs equal to
    /// 1e-14) took two of the contenders' places, and the candidate the
    /// writer writes fastest, the fourth cheapest, was not judged. Here
    /// the best's cost is reached again by as many others as there are
    /// places: taken for the best, they leave the places to the next.
    #[test]
    fn regression_3d_chips_a_smoothing_reached_twice_is_judged_once() {
        let n = FINAL_COST_CONTENDERS + 2;
        let mut costs = alloc::vec![100.0; n];
        costs[n - 1] = 101.0;
        for c in costs.iter_mut().take(n - 1).skip(1) {
            *c += 100.0 * 1e-14;
        }
        let mut finals = alloc::vec![99.0; n];
        finals[n - 1] = 98.0;
        let table = Table {
            costs: costs.clone(),
            finals,
        };
        let others = (1..n).map(|r| (costs[r], candidate(r))).collect();
        let (t, chosen) =
            fastest_written(&table, FINAL_COST_MARGIN, (costs[0], candidate(0)), others);
        assert_eq!(result(&chosen.pieces), n - 1);
        assert_eq!(t, 101.0);
    }

    /// `r027_engrave.ngc` (`scripts/random-programs.py /tmp/sw 28 9711
    /// raster,pocket,spiral,walk,mixed,circles,engrave`, peer settings):
    /// on one glyph the outer-edge candidate cost 2.3259 s and was written
    /// so; a mix of sections cost 2.4033 s (3.3% more) and the writer's
    /// tries wrote it in 2.2930 s. With a 2% margin the mix was not
    /// judged, and the program wrote 14.767 s where it had written
    /// 14.731 s before that candidate existed; it is judged now.
    #[test]
    fn regression_r027_engrave_a_mix_costed_3_percent_behind_is_judged() {
        let table = Table {
            costs: alloc::vec![2.3259, 2.4033],
            finals: alloc::vec![2.3259, 2.2930],
        };
        let (t, chosen) = fastest_written(
            &table,
            FINAL_COST_MARGIN,
            (2.3259, candidate(0)),
            alloc::vec![(2.4033, candidate(1))],
        );
        assert_eq!(result(&chosen.pieces), 1);
        assert_eq!(t, 2.4033);
    }

    fn written_time(override_feed: bool, tries: Option<WriterTries>) -> WrittenTime {
        let ro = render_options;
        let mut w = WrittenTime::new(
            MachineLimits::thesis(),
            override_feed,
            alloc::vec![ro(CurveForm::Arcs), ro(CurveForm::Lines)],
        );
        w.writer_tries = tries;
        w
    }

    /// Without a finer step, or on a run the writer takes as long, the
    /// final cost is the cost; with one, it is the cost or a time at
    /// least [`FINER_KEEP_MARGIN`] below it: the finer rendering of the form
    /// that won, planned as the writer plans it, where it gains at every
    /// feed.
    #[test]
    fn the_finer_step_is_taken_only_where_the_writer_keeps_it() {
        let finer = WriterTries {
            finer_share: 0.5,
            finer_steps: 1,
            long_pieces: usize::MAX,
            lines_without_arcs: None,
        };
        let line = candidate(30).pieces;
        let mut seen = [false; 2];
        for pieces in [corner_curves(120), line] {
            for override_feed in [true, false] {
                let plain = written_time(override_feed, None);
                let cost = plain.cost(&pieces).unwrap();
                assert_eq!(plain.final_cost(&pieces, cost), cost);
                let long = WriterTries {
                    long_pieces: pieces.len(),
                    ..finer
                };
                let w = written_time(override_feed, Some(long));
                assert_eq!(w.final_cost(&pieces, cost), cost);
                let w = written_time(override_feed, Some(finer));
                let f = w.final_cost(&pieces, cost);
                // The oracle: the arcs at half the step, planned on the plan
                // (and the shape where it differs).
                let speed = w.shaping_speed(&pieces).unwrap();
                let ro = w.renders[0];
                let half = RenderOptions {
                    step_share: ro.step_share * 0.5,
                    ..ro
                };
                let fine = render_run(&pieces, &speed, &half).unwrap();
                let plain_r = render_run(&pieces, &speed, &ro).unwrap();
                let t = |p: &[Piece], on: &crate::feed::plan::PlanOptions| {
                    w.rendered_time_on(p, CurveForm::Arcs, on).unwrap()
                };
                let gains = t(&fine.pieces, &w.plan) * (1.0 + FINER_KEEP_MARGIN)
                    < t(&plain_r.pieces, &w.plan)
                    && t(&fine.pieces, &w.shape) * (1.0 + FINER_KEEP_MARGIN)
                        < t(&plain_r.pieces, &w.shape);
                assert_eq!(t(&plain_r.pieces, &w.plan), cost, "arcs won");
                if gains {
                    assert_eq!(f, t(&fine.pieces, &w.plan));
                } else {
                    assert_eq!(f, cost);
                }
                seen[usize::from(gains)] = true;
            }
        }
        // Both ways taken: the raster gains, the line does not.
        assert_eq!(seen, [true, true]);
    }

    /// With two finer steps the final cost follows the writer down the
    /// halvings: the arcs at a quarter of the step share where they gain
    /// on those at half, which gained on the first (each by
    /// [`FINER_KEEP_MARGIN`] on the plan and the shape); else the last
    /// that gained. Never above the cost with one step.
    #[test]
    fn the_finer_steps_go_on_while_each_gains() {
        let tries = |finer_steps| WriterTries {
            finer_share: 0.5,
            finer_steps,
            long_pieces: usize::MAX,
            lines_without_arcs: None,
        };
        let mut both = false;
        for pieces in [corner_curves(120), candidate(30).pieces] {
            for override_feed in [true, false] {
                let cost = written_time(override_feed, None).cost(&pieces).unwrap();
                let one = written_time(override_feed, Some(tries(1))).final_cost(&pieces, cost);
                let w = written_time(override_feed, Some(tries(2)));
                let two = w.final_cost(&pieces, cost);
                let speed = w.shaping_speed(&pieces).unwrap();
                let ro = w.renders[0];
                let times = |share: f64| {
                    let o = RenderOptions {
                        step_share: ro.step_share * share,
                        ..ro
                    };
                    let r = render_run(&pieces, &speed, &o).unwrap();
                    let t = |on| w.rendered_time_on(&r.pieces, CurveForm::Arcs, on).unwrap();
                    (t(&w.shape), t(&w.plan))
                };
                let gains = |a: (f64, f64), b: (f64, f64)| {
                    a.0 * (1.0 + FINER_KEEP_MARGIN) < b.0 && a.1 * (1.0 + FINER_KEEP_MARGIN) < b.1
                };
                let (t1, t2, t4) = (times(1.0), times(0.5), times(0.25));
                assert_eq!(t1.1, cost, "arcs won");
                let expected = match (gains(t2, t1), gains(t4, t2)) {
                    (false, _) => t1.1,
                    (true, false) => t2.1,
                    (true, true) => {
                        both = true;
                        t4.1
                    }
                };
                assert_eq!(two, expected);
                assert!(two <= one, "{two} s against {one} s");
            }
        }
        // The raster's corners gain at both halvings.
        assert!(both);
    }

    /// Where no programmed feed is below the machine's maximum, the
    /// programmed feeds plan as the maximum does: one plan serves both
    /// feeds, and the final cost is the one the overriding objective
    /// finds; below it, both are planned.
    #[test]
    fn feeds_at_the_maximum_plan_once() {
        let tries = Some(WriterTries {
            finer_share: 0.5,
            finer_steps: 1,
            long_pieces: usize::MAX,
            lines_without_arcs: None,
        });
        let slow = corner_curves(120);
        let max_mm_min = MachineLimits::thesis().max_feed * 60.0;
        let fast: Vec<Piece> = slow
            .iter()
            .map(|p| Piece {
                feed: Some(max_mm_min),
                ..p.clone()
            })
            .collect();
        let (at_feeds, at_max) = (written_time(false, tries), written_time(true, tries));
        assert!(!at_feeds.one_feed(&slow));
        assert!(at_feeds.one_feed(&fast) && at_max.one_feed(&slow));
        let cost = at_max.cost(&fast).unwrap();
        assert_eq!(at_feeds.cost(&fast), Some(cost));
        assert_eq!(
            at_feeds.final_cost(&fast, cost),
            at_max.final_cost(&fast, cost)
        );
    }
}
