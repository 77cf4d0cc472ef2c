//! `fair` as the registry builds it: its two smoothings of a run with arcs
//! or curves it cannot fair itself (the curves kept, or sampled as chords
//! and faired: [`FairAlternatives`]) judged by the objective, the planner
//! on the user's machine, instead of by the demand of the fairing's speed
//! caps ([`FairAlternatives::sampled_demands_less`]), which only
//! estimates the time: a corner transition the sampled run gains in place
//! of a corner its curves kept is left out of that estimate, and can cost
//! more than the corner (`Ruota_dentata_p1.ngc` at 0.125 mm: sampled and
//! faired it planned slower than the program at the maximum feed and was
//! kept as written; the curves faired themselves plan faster at both
//! feeds). With [`Straighten::Judged`] (the default) each run that holds
//! a B-spline is also smoothed with the straightening in the sliding tube,
//! and the objective keeps the faster of the two.

use super::candidates::has_splines;
use super::objective::Objective;
use crate::path::Run;
use crate::smooth::{
    Fair, FairAlternatives, RunMemo, SmoothError, SmoothedRun, Smoother, Straighten,
};
use alloc::sync::Arc;

/// [`Fair`] choosing between its smoothings of a run by `objective`
/// ([`Objective::prefers`]): the sampled one where the objective prefers
/// it to the curves kept.
#[derive(Debug)]
pub struct JudgedFair {
    pub fair: Fair,
    pub objective: Arc<dyn Objective>,
}

impl Smoother for JudgedFair {
    fn name(&self) -> &'static str {
        self.fair.name()
    }

    fn smooth_run(&self, run: &Run, tolerance: f64) -> Result<SmoothedRun, SmoothError> {
        // One memo for both: the fits of the run's lines are shared.
        let memo = RunMemo::default();
        let best = self.judged(&self.fair, run, tolerance, &memo)?;
        if self.fair.options.straighten != Straighten::Judged || !has_splines(run) {
            return Ok(best);
        }
        let straight = Fair {
            options: self.fair.options.straightened(),
        };
        let other = self.judged(&straight, run, tolerance, &memo)?;
        Ok(if self.objective.prefers(&other.pieces, &best.pieces) {
            other
        } else {
            best
        })
    }
}

impl JudgedFair {
    /// `fair`'s smoothings of `run`, the faster by the objective.
    fn judged(
        &self,
        fair: &Fair,
        run: &Run,
        tolerance: f64,
        memo: &RunMemo,
    ) -> Result<SmoothedRun, SmoothError> {
        let FairAlternatives { kept, sampled, .. } =
            fair.alternatives_with(run, tolerance, memo)?;
        Ok(match sampled {
            Some(s) if self.objective.prefers(&s.pieces, &kept.pieces) => s,
            _ => kept,
        })
    }
}
