//! Machine limits and the speed caps they put on a point of a path.
//!
//! Units: mm, s (feeds in mm/s here; G-code feeds in mm/min are divided by
//! 60 by the caller). Each cap is the largest tangential speed `v` that
//! keeps one quantity within its limit, with its source:
//!
//! | cap | constraint | source |
//! |---|---|---|
//! | feed | `v <= F` | programmed feed, machine maximum |
//! | centripetal acceleration | `kappa v^2 <= A_n` | normal acceleration of a point moving on a curve |
//! | centripetal jerk | `kappa^2 v^3 <= J` | `d/dt (kappa v^2 N) = kappa^2 v^3 (-T) + ...`: the tangential part of the jerk at constant speed |
//! | curvature change | `abs(dkappa/ds) v^3 <= J` | the normal jerk `d(kappa v^2)/dt = (dkappa/ds) v^3` at constant speed |
//! | interpolation chord error | `v <= (2/Ts) sqrt(2 rho e - e^2)` | a chord of length `v Ts` on a circle of radius `rho = 1/kappa` deviates by `e` (the usual CNC interpolation limit, e.g. seed 001); none when `2 rho <= e` |
//! | axis velocity | `v abs(T_i) <= V_i` | per-axis drive limits |
//! | axis acceleration | `v^2 kappa abs(N_i) <= A_i` | normal acceleration projected on each axis |
//!
//! The two jerk caps on curves can be switched off
//! ([`MachineLimits::jerk_on_curves`]) for the thesis' own time model.
//!
//! At a joint that is not G2 the speed is capped as in
//! [`super::junction`]: a corner is passed on the circle that deviates by
//! the junction deviation, a curvature jump within one interpolation
//! period.

use crate::geom::Vec3;
use crate::math;

/// The limits of a machine. Every value must be positive and finite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MachineLimits {
    /// Largest feed, mm/s.
    pub max_feed: f64,
    /// Largest tangential acceleration, mm/s^2.
    pub acc: f64,
    /// Largest normal (centripetal) acceleration, mm/s^2.
    pub normal_acc: f64,
    /// Largest jerk, mm/s^3.
    pub jerk: f64,
    /// Per-axis velocity limits (X, Y, Z), mm/s.
    pub axis_vel: [f64; 3],
    /// Per-axis acceleration limits (X, Y, Z), mm/s^2.
    pub axis_acc: [f64; 3],
    /// Interpolation period, s.
    pub period: f64,
    /// Largest chord error of the interpolator, mm.
    pub chord_error: f64,
    /// Junction deviation (mm): how far from a corner of G1 moves the
    /// controller may pass it (grbl's `junction_deviation`, LinuxCNC's
    /// `G64 P`).
    pub junction_deviation: f64,
    /// Whether the jerk limit also caps the speed on curves: centripetal
    /// jerk `kappa^2 v^3 <= J` and curvature change
    /// `abs(dkappa/ds) v^3 <= J` (the default). `false` is the time model
    /// of the thesis (seed 003, section 4.5, eq. 4-1): on curves only the
    /// centripetal acceleration caps the speed, `v = sqrt(A / kappa)`, and
    /// the jerk limit shapes the S-curves between the caps. Corners of G1
    /// moves are capped as in [`super::junction`] either way.
    pub jerk_on_curves: bool,
    /// Least time (s) the control spends on a block, 0 for none: a block
    /// of length `L` is run at no more than `L / block_time`. A control
    /// that reads or prepares at most one block per interpolation period
    /// (LinuxCNC's motion queue takes one per servo cycle, and caps a
    /// block's speed at its length over 1.02 periods, `tp.c`) has about
    /// one period; a control with a stated block processing rate has its
    /// inverse. Each piece of a run is taken as one block.
    pub block_time: f64,
}

/// A limit out of its range: not a positive finite number (the block
/// time: not finite or negative).
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error("machine limit {name} must be {expected}, got {value}")]
pub struct LimitError {
    pub name: &'static str,
    pub value: f64,
    /// What the limit must be, in words.
    pub expected: &'static str,
}

impl MachineLimits {
    /// The machine of the thesis' simulations (seed 003): V 400 mm/s,
    /// A 4000 mm/s^2, J 20000 mm/s^3, Ts 1 ms; axes as fast as the path;
    /// chord error 1 um; junction deviation 0.01 mm (grbl's default).
    pub fn thesis() -> MachineLimits {
        MachineLimits {
            max_feed: 400.0,
            acc: 4000.0,
            normal_acc: 4000.0,
            jerk: 20000.0,
            axis_vel: [400.0; 3],
            axis_acc: [4000.0; 3],
            period: 0.001,
            chord_error: 0.001,
            junction_deviation: 0.01,
            jerk_on_curves: true,
            block_time: 0.0,
        }
    }

    /// Checks every limit, naming the first bad one.
    pub fn validate(&self) -> Result<(), LimitError> {
        let named = [
            ("max feed", self.max_feed),
            ("acceleration", self.acc),
            ("normal acceleration", self.normal_acc),
            ("jerk", self.jerk),
            ("X velocity", self.axis_vel[0]),
            ("Y velocity", self.axis_vel[1]),
            ("Z velocity", self.axis_vel[2]),
            ("X acceleration", self.axis_acc[0]),
            ("Y acceleration", self.axis_acc[1]),
            ("Z acceleration", self.axis_acc[2]),
            ("interpolation period", self.period),
            ("chord error", self.chord_error),
            ("junction deviation", self.junction_deviation),
        ];
        for (name, value) in named {
            if !(value.is_finite() && value > 0.0) {
                return Err(LimitError {
                    name,
                    value,
                    expected: "a positive number",
                });
            }
        }
        if !(self.block_time.is_finite() && self.block_time >= 0.0) {
            return Err(LimitError {
                name: "block time",
                value: self.block_time,
                expected: "0 (none) or a positive number",
            });
        }
        Ok(())
    }
}

/// Which constraint sets a speed cap.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Constraint {
    Feed,
    NormalAcceleration,
    NormalJerk,
    CurvatureChange,
    ChordError,
    AxisVelocity,
    AxisAcceleration,
    Junction,
    /// The block's least time ([`MachineLimits::block_time`]).
    BlockTime,
}

impl Constraint {
    pub fn as_str(self) -> &'static str {
        match self {
            Constraint::Feed => "feed",
            Constraint::NormalAcceleration => "normal acceleration",
            Constraint::NormalJerk => "normal jerk",
            Constraint::CurvatureChange => "curvature change",
            Constraint::ChordError => "chord error",
            Constraint::AxisVelocity => "axis velocity",
            Constraint::AxisAcceleration => "axis acceleration",
            Constraint::Junction => "junction",
            Constraint::BlockTime => "block time",
        }
    }
}

/// The local geometry of a path point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathPoint {
    /// Unit tangent.
    pub tangent: Vec3,
    /// Curvature vector `kappa N` (1/mm).
    pub curvature: Vec3,
    /// `dkappa/ds` (1/mm^2).
    pub dkappa_ds: f64,
}

/// The largest speed (mm/s) at `p` under `m` and the programmed `feed`
/// (mm/s), with the constraint that sets it (the first in
/// [`Constraint`] order on ties).
pub fn speed_cap(m: &MachineLimits, feed: f64, p: &PathPoint) -> (f64, Constraint) {
    let mut best = (feed.min(m.max_feed), Constraint::Feed);
    let take = |best: &mut (f64, Constraint), v: f64, c: Constraint| {
        if v < best.0 {
            *best = (v, c);
        }
    };
    let k = p.curvature.norm();
    if k > 0.0 {
        take(
            &mut best,
            math::sqrt(m.normal_acc / k),
            Constraint::NormalAcceleration,
        );
        if m.jerk_on_curves {
            let x = m.jerk / (k * k);
            if !math::cbrt_at_least(x, best.0) {
                take(&mut best, math::cbrt(x), Constraint::NormalJerk);
            }
        }
        // A circle of diameter within the chord error lies within the
        // chord error of any chord across it: no cap.
        let rho = 1.0 / k;
        let e = m.chord_error;
        if e < 2.0 * rho {
            take(
                &mut best,
                2.0 / m.period * math::sqrt(2.0 * rho * e - e * e),
                Constraint::ChordError,
            );
        }
        let n = p.curvature / k;
        let na = [n.x, n.y, n.z];
        for (i, &ni) in na.iter().enumerate() {
            let a = k * math::abs(ni);
            if a > 0.0 {
                take(
                    &mut best,
                    math::sqrt(m.axis_acc[i] / a),
                    Constraint::AxisAcceleration,
                );
            }
        }
    }
    if p.dkappa_ds != 0.0 && m.jerk_on_curves {
        let x = m.jerk / math::abs(p.dkappa_ds);
        if !math::cbrt_at_least(x, best.0) {
            take(&mut best, math::cbrt(x), Constraint::CurvatureChange);
        }
    }
    let t = [p.tangent.x, p.tangent.y, p.tangent.z];
    for (i, &ti) in t.iter().enumerate() {
        if ti != 0.0 {
            take(
                &mut best,
                m.axis_vel[i] / math::abs(ti),
                Constraint::AxisVelocity,
            );
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::seeded::Rng;

    /// [`speed_cap`] with every cube root taken.
    fn speed_cap_every_root(m: &MachineLimits, feed: f64, p: &PathPoint) -> (f64, Constraint) {
        let mut best = (feed.min(m.max_feed), Constraint::Feed);
        let mut take = |v: f64, c: Constraint| {
            if v < best.0 {
                best = (v, c);
            }
        };
        let k = p.curvature.norm();
        if k > 0.0 {
            take(math::sqrt(m.normal_acc / k), Constraint::NormalAcceleration);
            if m.jerk_on_curves {
                take(math::cbrt(m.jerk / (k * k)), Constraint::NormalJerk);
            }
            let rho = 1.0 / k;
            let e = m.chord_error;
            if e < 2.0 * rho {
                take(
                    2.0 / m.period * math::sqrt(2.0 * rho * e - e * e),
                    Constraint::ChordError,
                );
            }
            let n = p.curvature / k;
            for (i, &ni) in [n.x, n.y, n.z].iter().enumerate() {
                let a = k * math::abs(ni);
                if a > 0.0 {
                    take(math::sqrt(m.axis_acc[i] / a), Constraint::AxisAcceleration);
                }
            }
        }
        if p.dkappa_ds != 0.0 && m.jerk_on_curves {
            take(
                math::cbrt(m.jerk / math::abs(p.dkappa_ds)),
                Constraint::CurvatureChange,
            );
        }
        for (i, &ti) in [p.tangent.x, p.tangent.y, p.tangent.z].iter().enumerate() {
            if ti != 0.0 {
                take(m.axis_vel[i] / math::abs(ti), Constraint::AxisVelocity);
            }
        }
        best
    }

    /// The cube roots skipped change nothing: the same cap and constraint,
    /// bit for bit, over curvatures and curvature changes of many decades,
    /// including those whose root lands on the cap.
    #[test]
    fn seeded_random_points_cap_as_with_every_root() {
        let mut rng = Rng(0xCA95);
        let mut roots_set = 0;
        for i in 0..200_000 {
            let mut m = MachineLimits::thesis();
            m.jerk = rng.decades(2.0, 6.0);
            m.normal_acc = rng.decades(2.0, 5.0);
            m.max_feed = rng.decades(0.0, 3.0);
            let tangent = Vec3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5)
                .normalized(0.0)
                .unwrap_or(Vec3::X);
            let normal = Vec3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5);
            let k = rng.decades(-6.0, 3.0);
            let mut dkds = rng.decades(-6.0, 5.0);
            let feed = rng.decades(0.0, 3.0);
            if i % 4 == 0 {
                // The curvature change's root exactly at the feed cap.
                let v = feed.min(m.max_feed);
                dkds = m.jerk / (v * v * v);
            }
            let p = PathPoint {
                tangent,
                curvature: normal.normalized(0.0).unwrap_or(Vec3::Y) * k,
                dkappa_ds: dkds,
            };
            let want = speed_cap_every_root(&m, feed, &p);
            let got = speed_cap(&m, feed, &p);
            assert_eq!(got.0.to_bits(), want.0.to_bits(), "{m:?} {feed} {p:?}");
            assert_eq!(got.1, want.1, "{m:?} {feed} {p:?}");
            if matches!(want.1, Constraint::NormalJerk | Constraint::CurvatureChange) {
                roots_set += 1;
            }
        }
        assert!(roots_set > 10_000, "{roots_set} caps set by a root");
    }

    #[test]
    fn a_root_just_above_the_cap_is_skipped_only_when_sure() {
        for v in [1e-3f64, 0.7, 1.0, 3.0, 66.666_666_666_666_67, 400.0, 1e6] {
            let v3 = v * v * v;
            // At v^3 itself and a few ulps above, the root may round to
            // v or below: it must be taken.
            for ulps in 0..8 {
                let x = f64::from_bits(v3.to_bits() + ulps);
                assert!(
                    !math::cbrt_at_least(x, v) || math::cbrt(x) >= v,
                    "{v} {ulps}"
                );
            }
            assert!(!math::cbrt_at_least(v3 * 0.999, v));
            assert!(math::cbrt_at_least(v3 * 1.001, v));
            assert!(math::cbrt(v3 * 1.001) >= v);
        }
    }
}
