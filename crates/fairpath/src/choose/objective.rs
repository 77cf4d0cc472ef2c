//! What `auto` minimises, injected by the caller: the user's machine.
//!
//! `auto` smooths each run several ways and keeps the cheapest; what
//! "cheapest" means is not the method's business. A CAM system ranks by
//! the planned time on the machine that will cut the part, a researcher
//! perhaps by peak curvature. The method only asks an [`Objective`].

use crate::feed::limits::MachineLimits;
use crate::feed::plan::{plan_run, PlanOptions};
use crate::path::Piece;

/// A cost of running a smoothed run (lower is better).
pub trait Objective: core::fmt::Debug + Send + Sync {
    /// The cost of `pieces` (one continuous run), or `None` when it cannot
    /// be run at all (the planner rejects it); such candidates are kept only
    /// when no other can be run.
    fn cost(&self, pieces: &[Piece]) -> Option<f64>;
}

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

impl Objective for PlannedTime {
    fn cost(&self, pieces: &[Piece]) -> Option<f64> {
        plan_run(pieces, &self.plan).ok().map(|p| p.time)
    }
}
