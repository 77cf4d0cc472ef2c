//! Feed planning: jerk-limited velocity profiles along the smoothed path.
//!
//! Seeds 001 and 003. What is here:
//!
//! * [`double_s`]: the seven-phase double-S (jerk-limited) profile of
//!   Biagiotti and Melchiorri, *Trajectory Planning for Automatic Machines
//!   and Robots* (Springer 2008), section 3.4, for one segment of length `h`
//!   between given start and end velocities, with evaluation of position,
//!   velocity, acceleration and jerk at any time (eqs. 3.30a-3.30g). Two
//!   methods: [`Method::Fastest`] (default; solves the peak velocity exactly)
//!   and [`Method::Book`] (the book's algorithm, with its iterative reduction
//!   of the acceleration replaced by its exact limit).
//! * [`reach`]: jerk-limited reachability along a segment: the largest
//!   velocity reachable from `v0` within a length (and, by time reversal, the
//!   largest entry velocity from which an exit velocity can be reached), and
//!   the shortest distance of a velocity change. These are the building
//!   blocks of the look-ahead.
//!
//! * [`limits`]: machine limits (feed, acceleration, jerk, per-axis limits,
//!   interpolation period, chord error) and the speed caps they put on a
//!   point of the path (curvature, curvature change, chord error, axes) and
//!   on joints that are not G2, each with its source.
//!
//! * [`junction`]: how joints that are not G2 are passed (blend circles
//!   within the junction deviation and half the adjacent moves).
//! * [`plan`]: the look-ahead planner (full scan or bounded window), with
//!   its parts in private files: `caps.rs` (the speed caps of a run's
//!   stretches and joints), `lookahead.rs` (the backward and forward
//!   passes) and `cap_check.rs` (a profile checked against the caps inside
//!   its segment).
//! * [`windowed`]: a long run's planned time, planned window by window
//!   and stitched where consecutive windows' plans agree, so that its
//!   memory grows with a window, not with the run.
//! * [`interpolate`]: positions every interpolation period by the
//!   second-order Taylor parameter update, and the feed fluctuation.
//! * [`program`]: whole-program planning: the motions of a program (runs
//!   of feed moves and rapids, in order) planned one by one, with the
//!   times, and the motion sampled every period.
//!
//! Not built: acceleration carried across segment boundaries. Segments
//! run from one local minimum of the speed cap to the next and start and
//! end at zero tangential acceleration, which is safe and close to optimal
//! where the speed touches the cap.
//!
//! Units: mm, s, mm/s, mm/s², mm/s³. f64 everywhere. Bad input (NaN,
//! infinite, zero or negative limits, negative lengths or velocities) is an
//! error naming the offending quantity, never a panic.

pub mod double_s;
pub mod interpolate;
pub mod junction;
pub mod limits;
pub mod lower_bound;
pub mod plan;
pub mod program;
pub mod reach;
pub mod sampled;
pub mod shaping;
pub mod stream;
pub mod windowed;

// The planner's parts; `plan` re-exports what they make public.
mod cap_check;
mod caps;
mod lookahead;

pub use double_s::{DoubleS, Method, Phases, State};
pub use reach::{max_entry_velocity, max_reachable_velocity, velocity_change, VelocityChange};

/// Kinematic limits along the path: velocity (mm/s), acceleration (mm/s²)
/// and jerk (mm/s³), each a positive finite number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Largest velocity, mm/s.
    pub vmax: f64,
    /// Largest acceleration magnitude, mm/s².
    pub amax: f64,
    /// Largest jerk magnitude, mm/s³.
    pub jmax: f64,
}

impl Limits {
    /// The limits, checked: each must be positive and finite.
    pub fn new(vmax: f64, amax: f64, jmax: f64) -> Result<Self, FeedError> {
        let limits = Limits { vmax, amax, jmax };
        limits.check()?;
        Ok(limits)
    }

    /// Rejects NaN, infinite, zero or negative limits, naming the limit.
    pub fn check(&self) -> Result<(), FeedError> {
        check_limit("vmax", self.vmax)?;
        check_limit("amax", self.amax)?;
        check_limit("jmax", self.jmax)
    }
}

/// Why a feed plan could not be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FeedError {
    /// A limit (vmax, amax, jmax) is NaN, infinite, zero or negative.
    #[error("{name} must be a positive finite number, got {value}")]
    BadLimit {
        /// Which limit.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A length or velocity is NaN, infinite or negative.
    #[error("{name} must be a finite number >= 0, got {value}")]
    BadValue {
        /// Which quantity (`h`, `v0`, `v1`, `length`).
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A boundary velocity is above the velocity limit.
    #[error("{name} = {value} mm/s is above vmax = {vmax} mm/s")]
    AboveVmax {
        /// Which velocity (`v0` or `v1`).
        name: &'static str,
        /// The value given.
        value: f64,
        /// The velocity limit.
        vmax: f64,
    },
    /// `v1` cannot be reached from `v0` within `h` under the acceleration and
    /// jerk limits: the shortest velocity change needs `needed` mm.
    #[error(
        "v1 = {v1} mm/s cannot be reached from v0 = {v0} mm/s within {h} mm (needs {needed} mm)"
    )]
    Infeasible {
        /// Segment length, mm.
        h: f64,
        /// Start velocity, mm/s.
        v0: f64,
        /// End velocity, mm/s.
        v1: f64,
        /// Shortest distance of the velocity change, mm.
        needed: f64,
    },
}

pub(crate) fn check_limit(name: &'static str, value: f64) -> Result<(), FeedError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(FeedError::BadLimit { name, value })
    }
}

pub(crate) fn check_value(name: &'static str, value: f64) -> Result<(), FeedError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(FeedError::BadValue { name, value })
    }
}
