//! `auto`'s candidates for one run (or section) ranked by its
//! [`Objective`]: each distinct result costed at most once, and, where the
//! objective has a cheap lower bound ([`Objective::bound`]), only the
//! candidates that bound leaves in the race.
//!
//! With a bound, a choice among some candidates costs them in the order
//! of their bounds (branch and bound), and stops at the first whose bound
//! exceeds the least cost found so far: neither it nor any after it can
//! be cheaper while the bound holds. Which candidates are costed depends
//! only on the bounds and costs (not on threads or timing), so the choice
//! is deterministic. One after the other, not side by side (the costs of
//! a batch would be computed before knowing whether the first of them
//! ends the race, and the runs of a program are smoothed side by side
//! already), but for the candidates whose bounds lie within the
//! objective's [`Objective::bound_slack`] of the least bound in the race:
//! a bound that lies that far below the cost by design leaves them all in
//! the race but where the first costs less than its bound says, so they
//! are costed side by side (on a program of one long run, the cores
//! would otherwise wait: `surface-raster-large.ngc`'s two fits).

use super::candidate_threads::map_candidates;
use super::objective::Objective;
use super::same_pieces::same_pieces;
use crate::smooth::SmoothedRun;
use alloc::vec::Vec;

/// Smoothed candidates and what is known of their costs.
pub(super) struct Ranking<'o> {
    objective: &'o dyn Objective,
    /// The candidates, in the table's order (a tie goes to the earlier).
    pub(super) cands: Vec<SmoothedRun>,
    /// For each candidate, the first with the same pieces: only that one
    /// is bounded and costed.
    first_same: Vec<usize>,
    /// The bound of each first-of-its-pieces candidate, once computed
    /// (`Some(None)`: the objective has none for it).
    bounds: Vec<Option<Option<f64>>>,
    /// The cost of each first-of-its-pieces candidate, once computed
    /// (`Some(None)`: the objective could not cost it).
    costs: Vec<Option<Option<f64>>>,
}

impl<'o> Ranking<'o> {
    /// `cands` to be ranked by `objective` (nothing is costed yet).
    pub(super) fn new(objective: &'o dyn Objective, cands: Vec<SmoothedRun>) -> Self {
        let n = cands.len();
        let first_same: Vec<usize> = (0..n)
            .map(|i| {
                (0..i)
                    .find(|&j| same_pieces(&cands[j].pieces, &cands[i].pieces))
                    .unwrap_or(i)
            })
            .collect();
        Ranking {
            objective,
            cands,
            first_same,
            bounds: alloc::vec![None; n],
            costs: alloc::vec![None; n],
        }
    }

    /// Bounds the candidates `which` (first of their pieces) not bounded
    /// yet, side by side.
    fn bound(&mut self, which: &[usize]) {
        let objective = self.objective;
        fill(&mut self.bounds, &self.cands, which, |p| objective.bound(p));
    }

    /// Costs the candidates `which` (first of their pieces) not costed yet,
    /// side by side.
    fn cost(&mut self, which: &[usize]) {
        let objective = self.objective;
        fill(&mut self.costs, &self.cands, which, |p| objective.cost(p));
    }

    /// The cost of candidate `i` where it was computed (`Some(None)`: the
    /// objective could not cost it).
    pub(super) fn cost_of(&self, i: usize) -> Option<Option<f64>> {
        self.costs[self.first_same[i]]
    }

    /// The cheapest of all the candidates that `keep` accepts with their
    /// cost, by index, with its cost (a tie goes to the earlier): every
    /// candidate is costed (no bound prunes them), for a choice whose
    /// rule needs the cost.
    pub(super) fn cheapest_kept(
        &mut self,
        keep: impl Fn(&SmoothedRun, f64) -> bool,
    ) -> Option<(f64, usize)> {
        let all: Vec<usize> = (0..self.cands.len()).map(|i| self.first_same[i]).collect();
        self.cost(&all);
        // Cheapest first, so that `keep` (which may render and plan) is
        // asked only until it accepts one.
        let mut costed: Vec<(f64, usize)> = (0..self.cands.len())
            .filter_map(|i| self.costs[self.first_same[i]].flatten().map(|c| (c, i)))
            .collect();
        costed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        costed.into_iter().find(|&(c, i)| keep(&self.cands[i], c))
    }

    /// [`Ranking::cheapest_kept`], with the costs it computes forgotten
    /// after: what is costed later (the candidates [`Ranking::near`] the
    /// best) stays what the bounds left in the race.
    pub(super) fn cheapest_kept_aside(
        &mut self,
        keep: impl Fn(&SmoothedRun, f64) -> bool,
    ) -> Option<(f64, usize)> {
        let known = self.costs.clone();
        let found = self.cheapest_kept(keep);
        self.costs = known;
        found
    }

    /// The candidates costed at most `limit`, but `best` and those with
    /// its pieces, each result once (the first of its pieces), taken out
    /// with their costs.
    pub(super) fn near(&mut self, best: usize, limit: f64) -> Vec<(f64, SmoothedRun)> {
        let same = self.first_same[best];
        (0..self.cands.len())
            .filter(|&i| self.first_same[i] == i && i != same)
            .filter_map(|i| match self.costs[i] {
                Some(Some(c)) if c <= limit => Some((c, core::mem::take(&mut self.cands[i]))),
                _ => None,
            })
            .collect()
    }

    /// [`Ranking::fastest`], by index only: where `eligible` accepts
    /// candidates of one result only, the first of them, costed by nothing.
    pub(super) fn cheapest(&mut self, eligible: impl Fn(&SmoothedRun) -> bool) -> Option<usize> {
        let accepted: Vec<usize> = (0..self.cands.len())
            .filter(|&i| eligible(&self.cands[i]))
            .collect();
        let first = *accepted.first()?;
        if accepted
            .iter()
            .all(|&i| self.first_same[i] == self.first_same[first])
        {
            return Some(first);
        }
        self.fastest(|c| eligible(c)).map(|(_, i)| i)
    }

    /// The cheapest of the candidates that `eligible` accepts, by index,
    /// with its cost (a tie goes to the earlier); failing any that could be
    /// costed, the first accepted that could not (cost `None`). Costs only
    /// what the bounds leave in the race (see the module documentation).
    pub(super) fn fastest(
        &mut self,
        eligible: impl Fn(&SmoothedRun) -> bool,
    ) -> Option<(Option<f64>, usize)> {
        let accepted: Vec<usize> = (0..self.cands.len())
            .filter(|&i| eligible(&self.cands[i]))
            .collect();
        let mut reps: Vec<usize> = accepted.iter().map(|&i| self.first_same[i]).collect();
        reps.sort_unstable();
        reps.dedup();
        // In the order of the bounds (then of the table) while the bound is
        // at most the least cost found so far; those without a bound are
        // all costed.
        self.bound(&reps);
        let mut bounded: Vec<(f64, usize)> = reps
            .iter()
            .filter_map(|&i| self.bounds[i].flatten().map(|b| (b, i)))
            .collect();
        bounded.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let slack = self.objective.bound_slack().clamp(0.0, 0.5);
        let mut least = f64::INFINITY;
        let mut k = 0;
        while let Some(&(b, _)) = bounded.get(k) {
            if b > least {
                break;
            }
            // The batch: this one and the bounds after it within the slack
            // of it (and at most the least cost).
            let widened = if b > 0.0 { b / (1.0 - slack) } else { b };
            let limit = widened.min(least).max(b);
            let batch: Vec<usize> = core::iter::once(&bounded[k])
                .chain(bounded[k + 1..].iter().take_while(|&&(bb, _)| bb <= limit))
                .map(|&(_, i)| i)
                .collect();
            self.cost(&batch);
            for &i in &batch {
                if let Some(Some(c)) = self.costs[i] {
                    least = least.min(c);
                }
            }
            k += batch.len();
        }
        reps.retain(|&i| self.bounds[i].flatten().is_none());
        self.cost(&reps);
        let mut best: Option<(f64, usize)> = None;
        let mut fallback = None;
        for i in accepted {
            match self.costs[self.first_same[i]] {
                Some(Some(t)) if best.is_none_or(|(b, _)| t < b) => best = Some((t, i)),
                Some(None) if fallback.is_none() => fallback = Some(i),
                _ => {}
            }
        }
        best.map(|(t, i)| (Some(t), i))
            .or(fallback.map(|i| (None, i)))
    }
}

/// Fills the slots `which` of `slots` still empty with `f` of their
/// candidates' pieces, side by side.
fn fill(
    slots: &mut [Option<Option<f64>>],
    cands: &[SmoothedRun],
    which: &[usize],
    f: impl Fn(&[crate::path::Piece]) -> Option<f64> + Sync,
) {
    let todo: Vec<usize> = which
        .iter()
        .copied()
        .filter(|&i| slots[i].is_none())
        .collect();
    let found = map_candidates(todo.len(), |k| f(&cands[todo[k]].pieces));
    for (i, v) in todo.into_iter().zip(found) {
        slots[i] = Some(v);
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{line_candidate as candidate, result};
    use super::*;
    use crate::path::Piece;
    use proptest::prelude::*;

    /// Costs and bounds by result: a candidate's result is the end x of
    /// its one line.
    #[derive(Debug)]
    struct Table {
        costs: Vec<Option<f64>>,
        bounds: Vec<Option<f64>>,
        slack: f64,
    }

    impl Objective for Table {
        fn cost(&self, pieces: &[Piece]) -> Option<f64> {
            self.costs[result(pieces)]
        }
        fn bound(&self, pieces: &[Piece]) -> Option<f64> {
            self.bounds[result(pieces)]
        }
        fn bound_slack(&self) -> f64 {
            self.slack
        }
    }

    proptest! {
        /// Where the bounds hold (each at most its cost), branch and bound
        /// keeps what costing every candidate keeps: the cheapest accepted
        /// (the earlier on a tie), else the first accepted that cannot be
        /// costed; whatever the objective's slack (which candidates are
        /// costed side by side).
        #[test]
        fn with_bounds_that_hold_the_choice_is_the_cheapest(
            bound_slack in prop_oneof![Just(0.0), 0.0f64..0.5],
            results in proptest::collection::vec(0usize..6, 1..10),
            costs in proptest::collection::vec(proptest::option::weighted(0.9, 0u32..8), 6),
            slack in proptest::collection::vec(proptest::option::weighted(0.8, 0u32..4), 6),
            accepted in proptest::collection::vec(any::<bool>(), 10),
        ) {
            let costs: Vec<Option<f64>> = costs.iter().map(|c| c.map(f64::from)).collect();
            let bounds = costs
                .iter()
                .zip(&slack)
                .map(|(c, s)| match (c, s) {
                    (Some(c), Some(s)) => Some(c - f64::from(*s)),
                    // A candidate that cannot be costed has no bound.
                    _ => None,
                })
                .collect();
            let table = Table { costs: costs.clone(), bounds, slack: bound_slack };
            let cands: Vec<SmoothedRun> = results.iter().map(|&r| candidate(r)).collect();
            let eligible = |c: &SmoothedRun| accepted[result(&c.pieces) % accepted.len()];
            let mut want: Option<(f64, usize)> = None;
            let mut fallback = None;
            for (i, c) in cands.iter().enumerate() {
                if !eligible(c) {
                    continue;
                }
                match costs[result(&c.pieces)] {
                    Some(t) if want.is_none_or(|(b, _)| t < b) => want = Some((t, i)),
                    None if fallback.is_none() => fallback = Some(i),
                    _ => {}
                }
            }
            let want = want.map(|(t, i)| (Some(t), i)).or(fallback.map(|i| (None, i)));
            let mut ranking = Ranking::new(&table, cands);
            prop_assert_eq!(ranking.fastest(eligible), want);
        }

        /// `cheapest_kept` keeps the cheapest candidate `keep` accepts
        /// (the earlier on a tie), whatever the bounds (here none holds:
        /// each lies above its cost, so the bounds alone would cost one),
        /// and asks `keep` only of candidates no dearer than it;
        /// `cheapest_kept_aside` keeps the same and forgets the costs it
        /// computed.
        #[test]
        fn the_cheapest_kept_is_found_whatever_the_bounds(
            results in proptest::collection::vec(0usize..6, 1..10),
            costs in proptest::collection::vec(proptest::option::weighted(0.9, 0u32..8), 6),
            accepted in proptest::collection::vec(any::<bool>(), 6),
            aside in any::<bool>(),
        ) {
            let costs: Vec<Option<f64>> = costs.iter().map(|c| c.map(f64::from)).collect();
            let bounds = costs.iter().map(|c| c.map(|c| c + 100.0)).collect();
            let table = Table { costs: costs.clone(), bounds, slack: 0.0 };
            let cands: Vec<SmoothedRun> = results.iter().map(|&r| candidate(r)).collect();
            let want = results
                .iter()
                .enumerate()
                .filter_map(|(i, &r)| costs[r].filter(|_| accepted[r]).map(|c| (c, i)))
                .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let mut ranking = Ranking::new(&table, cands);
            let before: Vec<Option<Option<f64>>> =
                (0..results.len()).map(|i| ranking.cost_of(i)).collect();
            let asked = std::sync::Mutex::new(Vec::new());
            let keep = |c: &SmoothedRun, t: f64| {
                asked.lock().unwrap().push(t);
                accepted[result(&c.pieces)]
            };
            let got = if aside {
                ranking.cheapest_kept_aside(keep)
            } else {
                ranking.cheapest_kept(keep)
            };
            prop_assert_eq!(got, want);
            if let Some((t, _)) = got {
                prop_assert!(asked.lock().unwrap().iter().all(|&a| a <= t));
            }
            for (i, b) in before.iter().enumerate() {
                if aside {
                    prop_assert_eq!(ranking.cost_of(i), *b);
                } else {
                    prop_assert_eq!(ranking.cost_of(i), Some(costs[results[i]]));
                }
            }
        }
    }
}
