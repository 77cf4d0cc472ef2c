//! The seven-phase double-S (jerk-limited) velocity profile.
//!
//! Source: L. Biagiotti, C. Melchiorri, *Trajectory Planning for Automatic
//! Machines and Robots*, Springer 2008, section 3.4 (3.4.1-3.4.3). Equation
//! numbers below are the book's.
//!
//! A segment of length `h = q1 - q0 >= 0` is travelled from velocity `v0` to
//! `v1` (both `>= 0`), the acceleration zero at both ends, with
//! `|v| <= vmax`, `|a| <= amax`, `|j| <= jmax`. The profile has up to seven
//! phases: acceleration (`Ta`: jerk `+jmax` for `Tj1`, constant acceleration
//! `alim_a`, jerk `-jmax` for `Tj1`), constant velocity `vlim` (`Tv`), and
//! deceleration (`Td`: jerk `-jmax` for `Tj2`, constant `alim_d < 0`, jerk
//! `+jmax` for `Tj2`). Total duration `T = Ta + Tv + Td`.
//!
//! **Feasibility (eqs. 3.17, 3.18).** The profile exists iff `h` is at least
//! the distance of the fastest velocity change from `v0` to `v1`
//! ([`super::velocity_change`]). Otherwise [`DoubleS::plan`] returns
//! [`FeedError::Infeasible`] with that distance. Lengths short of it by no
//! more than [`FEASIBILITY_SLACK`] (relative), or by what [`VELOCITY_ULPS`]
//! ulps of the velocities account for, are accepted as rounding and planned
//! as the bare velocity change (which then overshoots `h` by that rounding;
//! [`DoubleS::eval`] still ends exactly at `h`). `v0` and `v1` above `vmax` are
//! rejected ([`FeedError::AboveVmax`]).
//!
//! **Case 1, `vlim = vmax` (eqs. 3.19-3.21).** Each of acceleration and
//! deceleration is the fastest change to or from `vmax` (saturating `amax` or
//! not, separately), and `Tv = h/vmax - Ta/2 (1 + v0/vmax) - Td/2 (1 +
//! v1/vmax)`. If `Tv >= 0` this is the profile.
//!
//! **Case 2, `vlim < vmax`, `Tv = 0`.** Two methods ([`Method`]):
//!
//! * [`Method::Fastest`] (default): `vlim` is the largest peak velocity with
//!   `D(v0 -> vlim) + D(vlim -> v1) = h`, where `D` is the distance of the
//!   fastest velocity change; acceleration and deceleration each saturate
//!   `amax` or not on their own. `D` is continuous and strictly increasing in
//!   `vlim` on `[max(v0, v1), vmax]`, so the root is found by bisection to the
//!   last bit of f64 (the lower end of the final bracket, so `D <= h`); the
//!   tiny remainder `h - D` goes into `Tv`, so the profile covers exactly
//!   `h`. When both phases saturate this is the book's eq. 3.23 exactly. In
//!   the seeded random tests it is never slower than the book's method, and
//!   it is much faster when `v0` and `v1` differ a lot (the book's Example
//!   3.12: 1.76 s instead of 2.67 s; Example 3.11: 1.78 s instead of 1.94 s).
//!   It is the fastest profile of this seven-phase shape; it is not claimed
//!   time-optimal among all jerk-limited motions.
//! * [`Method::Book`]: the book's algorithm. `amax` is assumed reached in both
//!   phases, `Tj1 = Tj2 = a/jmax` and (eq. 3.23)
//!   `Delta = a^4/jmax^2 + 2 (v0^2 + v1^2) + a (4 h - 2 a/jmax (v0 + v1))`,
//!   `Ta = (a^2/jmax - 2 v0 + sqrt(Delta)) / (2 a)`,
//!   `Td = (a^2/jmax - 2 v1 + sqrt(Delta)) / (2 a)`. The book reduces `a`
//!   by a factor `gamma` (e.g. 0.99) until `Ta >= 2 Tj` and `Td >= 2 Tj`, or
//!   `Ta < 0` or `Td < 0`. We compute the limit of that iteration as
//!   `gamma -> 1`: a scan by factors of 0.99 brackets the first `a` (from
//!   `amax` down) where the stopping test holds, and bisection narrows the
//!   bracket to f64 resolution. Book values printed with `gamma = 0.99`
//!   therefore differ from ours by up to about 1 %. If `Ta < 0`, only
//!   deceleration remains (eq. 3.26a): `Ta = 0`, `Td = 2 h/(v0 + v1)`,
//!   `Tj2 = (jmax h - sqrt(jmax (jmax h^2 + (v1 + v0)^2 (v1 - v0)))) /
//!   (jmax (v1 + v0))`; if `Td < 0`, only acceleration (eq. 3.26b) with the
//!   signs of `v1 - v0` reversed.
//!
//! The reached values are (eq. 3.24) `alim_a = jmax Tj1`, `alim_d = -jmax
//! Tj2`, `vlim = v0 + (Ta - Tj1) alim_a = v1 - (Td - Tj2) alim_d`.
//!
//! Positions are measured from `q0`: the profile runs from 0 to `h`.

use super::reach::{change_by, change_unchecked, reach_gain};
use super::{check_value, FeedError, Limits};
use crate::math::{abs, sqrt};

/// Lengths short of the fastest velocity change by at most this fraction of
/// it are treated as f64 rounding (e.g. an end velocity computed by
/// [`super::max_reachable_velocity`] for exactly this length) and accepted.
pub const FEASIBILITY_SLACK: f64 = 1e-12;

/// The end velocity may also be off by this many ulps (of the larger
/// boundary velocity): `v1 = v0 + dv` rounds `dv` to an ulp of `v1`, which is
/// a large relative error of `dv`, hence of the distance, when `dv << v1`.
pub const VELOCITY_ULPS: f64 = 8.0;

/// Largest number of 0.99 steps of the book's reduction of `amax` (0.99^5000
/// is about 1.5e-22: far below any acceleration that matters).
const BOOK_SCAN_STEPS: usize = 5000;

/// Most Newton steps, and most widening steps, of the search for the peak
/// velocity ([`DoubleS::fastest_case2`]); the bisection that follows ends
/// it whatever they reached.
const NEWTON_STEPS: usize = 12;
/// The reduction factor of the book's scan (section 3.4.2, `gamma`).
const BOOK_GAMMA: f64 = 0.99;

/// How Case 2 (maximum velocity not reached) is solved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Method {
    /// Highest peak velocity, acceleration and deceleration saturating
    /// independently; exact to f64 (see the module documentation).
    #[default]
    Fastest,
    /// Biagiotti and Melchiorri's algorithm (common reduced acceleration,
    /// only-acceleration and only-deceleration cases of eqs. 3.26a, 3.26b),
    /// with the limit of the `gamma` iteration computed exactly.
    Book,
}

/// The phase durations of a double-S profile, s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phases {
    /// Jerk phase of the acceleration (each of two).
    pub tj1: f64,
    /// Acceleration, total.
    pub ta: f64,
    /// Constant velocity.
    pub tv: f64,
    /// Jerk phase of the deceleration (each of two).
    pub tj2: f64,
    /// Deceleration, total.
    pub td: f64,
}

/// Position (mm from `q0`), velocity, acceleration and jerk at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct State {
    /// Position, mm from the start of the segment.
    pub q: f64,
    /// Velocity, mm/s.
    pub v: f64,
    /// Acceleration, mm/s².
    pub a: f64,
    /// Jerk, mm/s³.
    pub j: f64,
}

/// A planned double-S profile for one segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DoubleS {
    h: f64,
    v0: f64,
    v1: f64,
    jmax: f64,
    phases: Phases,
    vlim: f64,
    alim_a: f64,
    alim_d: f64,
}

impl DoubleS {
    /// Plans the profile over `h` mm from `v0` to `v1` with [`Method::Fastest`].
    pub fn plan(h: f64, v0: f64, v1: f64, limits: &Limits) -> Result<Self, FeedError> {
        Self::plan_with(h, v0, v1, limits, Method::Fastest)
    }

    /// Plans the profile over `h` mm from `v0` to `v1` with the given method.
    ///
    /// Errors: a limit not positive and finite ([`FeedError::BadLimit`]),
    /// `h`, `v0` or `v1` negative or not finite ([`FeedError::BadValue`]),
    /// `v0` or `v1` above `vmax` ([`FeedError::AboveVmax`]), or `v1` not
    /// reachable from `v0` within `h` ([`FeedError::Infeasible`]).
    pub fn plan_with(
        h: f64,
        v0: f64,
        v1: f64,
        limits: &Limits,
        method: Method,
    ) -> Result<Self, FeedError> {
        limits.check()?;
        check_value("h", h)?;
        check_value("v0", v0)?;
        check_value("v1", v1)?;
        let Limits { vmax, amax, jmax } = *limits;
        for (name, value) in [("v0", v0), ("v1", v1)] {
            if value > vmax {
                return Err(FeedError::AboveVmax { name, value, vmax });
            }
        }
        // Feasibility (eqs. 3.17, 3.18), up to rounding: the velocity change
        // shortened by VELOCITY_ULPS ulps must fit within h (1 - slack).
        let direct = change_unchecked(v0, v1, amax, jmax);
        let shrink = VELOCITY_ULPS * f64::EPSILON * v0.max(v1);
        let v1_near = if v1 > v0 {
            (v1 - shrink).max(v0)
        } else {
            (v1 + shrink).min(v0)
        };
        let lenient = change_unchecked(v0, v1_near, amax, jmax).distance;
        if h < lenient * (1.0 - FEASIBILITY_SLACK) {
            return Err(FeedError::Infeasible {
                h,
                v0,
                v1,
                needed: direct.distance,
            });
        }
        let base = DoubleS {
            h,
            v0,
            v1,
            jmax,
            phases: Phases {
                tj1: 0.0,
                ta: 0.0,
                tv: 0.0,
                tj2: 0.0,
                td: 0.0,
            },
            vlim: v0,
            alim_a: 0.0,
            alim_d: 0.0,
        };
        if h <= direct.distance {
            return Ok(base.bare_change(amax));
        }
        // Case 1 (eqs. 3.19-3.21): is vmax reached?
        let (acc, dec) = (
            change_unchecked(v0, vmax, amax, jmax),
            change_unchecked(vmax, v1, amax, jmax),
        );
        let rest = h - acc.distance - dec.distance;
        if rest >= 0.0 {
            return Ok(base.with_peak(vmax, rest / vmax, amax));
        }
        Ok(match method {
            Method::Fastest => base.fastest_case2(vmax, amax),
            Method::Book => base.book_case2(amax),
        })
    }

    /// The profile with peak velocity `vlim`, cruise `tv` and each of
    /// acceleration and deceleration the fastest change under `amax`.
    fn with_peak(mut self, vlim: f64, tv: f64, amax: f64) -> Self {
        let acc = change_unchecked(self.v0, vlim, amax, self.jmax);
        let dec = change_unchecked(vlim, self.v1, amax, self.jmax);
        self.phases = Phases {
            tj1: acc.tj,
            ta: acc.duration,
            tv,
            tj2: dec.tj,
            td: dec.duration,
        };
        self.vlim = vlim;
        self.alim_a = acc.peak_acceleration;
        self.alim_d = -dec.peak_acceleration;
        self
    }

    /// The bare velocity change from `v0` to `v1` when `h` is (to rounding)
    /// its distance. The durations come from the exact velocity gain that
    /// covers `h` ([`super::reach`]), not from `v1 - v0`: when the change is
    /// tiny against the velocities, one ulp of `v1` is a large relative error
    /// of `v1 - v0`, and the distance grows like its square root. So the
    /// profile ends exactly at `h`, with its velocity within a few ulps of `v1`.
    fn bare_change(mut self, amax: f64) -> Self {
        let (v0, v1, jmax) = (self.v0, self.v1, self.jmax);
        let dv = abs(v1 - v0);
        let gain = reach_gain(v0.min(v1), self.h, amax, jmax).clamp(0.0, dv);
        let (tj, t, peak) = change_by(gain, amax, jmax);
        self.vlim = v0.max(v1);
        if v1 > v0 {
            self.phases.tj1 = tj;
            self.phases.ta = t;
            self.alim_a = peak;
        } else {
            self.phases.tj2 = tj;
            self.phases.td = t;
            self.alim_d = -peak;
        }
        self
    }

    /// Case 2 of [`Method::Fastest`]: the largest peak velocity whose
    /// distance fits `h`.
    ///
    /// The distance `D(v)` of the peak `v` is nondecreasing in `v` as
    /// computed in f64 too (each of its operations rounds monotonically), so
    /// the largest f64 `v` with `D(v) <= h` is one number, which bisection
    /// of the bracket `[max(v0, v1), vmax]` down to two adjacent floats
    /// finds. The bracket is first narrowed ([`narrow_peak`]) and the
    /// bisection ends the search from there: the same number, with about a
    /// third of the distance evaluations.
    fn fastest_case2(self, vmax: f64, amax: f64) -> Self {
        let (v0, v1, h, jmax) = (self.v0, self.v1, self.h, self.jmax);
        let dist = |v: f64| {
            change_unchecked(v0, v, amax, jmax).distance
                + change_unchecked(v, v1, amax, jmax).distance
        };
        // dD/dv: of `(v_a + v_b) T(|v_b - v_a|) / 2` with `T(dv)` the
        // change's duration, `2 sqrt(dv / J)` below `amax`, `amax / J + dv /
        // amax` at it (eqs. 3.19, 3.20).
        let slope = |v: f64| {
            let part = |from: f64| {
                let dv = v - from;
                let (_, t, _) = change_by(dv, amax, jmax);
                let dt = if dv * jmax >= amax * amax {
                    1.0 / amax
                } else if dv > 0.0 {
                    1.0 / sqrt(dv * jmax)
                } else {
                    f64::INFINITY
                };
                0.5 * t + 0.5 * (v + from) * dt
            };
            part(v0) + part(v1)
        };
        // dist(lo) <= h (feasibility, and h > direct distance), dist(hi) > h.
        let (mut lo, mut hi) = (v0.max(v1), vmax);
        narrow_peak(&dist, &slope, h, &mut lo, &mut hi);
        let lo = bisect_peak(&dist, h, lo, hi);
        let rest = h - dist(lo);
        let tv = if lo > 0.0 && rest > 0.0 {
            rest / lo
        } else {
            0.0
        };
        self.with_peak(lo, tv, amax)
    }

    /// Case 2 of [`Method::Book`] (eqs. 3.23, 3.26a, 3.26b).
    fn book_case2(mut self, amax: f64) -> Self {
        let (v0, v1, h, jmax) = (self.v0, self.v1, self.h, self.jmax);
        // (Ta, Td, Tj) of eq. 3.23 for the acceleration `a`.
        let case2 = |a: f64| {
            let tj = a / jmax;
            let delta = a * a * a * a / (jmax * jmax)
                + 2.0 * (v0 * v0 + v1 * v1)
                + a * (4.0 * h - 2.0 * a / jmax * (v0 + v1));
            let root = sqrt(delta.max(0.0));
            let ta = (a * a / jmax - 2.0 * v0 + root) / (2.0 * a);
            let td = (a * a / jmax - 2.0 * v1 + root) / (2.0 * a);
            (ta, td, tj)
        };
        let stops = |a: f64| {
            let (ta, td, tj) = case2(a);
            ta < 0.0 || td < 0.0 || (ta >= 2.0 * tj && td >= 2.0 * tj)
        };
        // Find the first a (from amax down) where the book's loop stops.
        let mut a = amax;
        if !stops(a) {
            let mut above = a;
            for _ in 0..BOOK_SCAN_STEPS {
                a = above * BOOK_GAMMA;
                if stops(a) {
                    break;
                }
                above = a;
            }
            // Bisect (above: runs on, a: stops) down to f64 resolution.
            for _ in 0..2100 {
                let mid = 0.5 * (a + above);
                if mid <= a || mid >= above {
                    break;
                }
                if stops(mid) {
                    a = mid;
                } else {
                    above = mid;
                }
            }
        }
        let (ta, td, tj) = case2(a);
        let sum = v0 + v1;
        if ta < 0.0 && sum > 0.0 {
            // Only deceleration (eq. 3.26a).
            let td = 2.0 * h / sum;
            let tj2 = (jmax * h - sqrt((jmax * (jmax * h * h + sum * sum * (v1 - v0))).max(0.0)))
                / (jmax * sum);
            self.phases = Phases {
                tj1: 0.0,
                ta: 0.0,
                tv: 0.0,
                tj2,
                td,
            };
            self.alim_a = 0.0;
            self.alim_d = -jmax * tj2;
            self.vlim = v0;
        } else if td < 0.0 && sum > 0.0 {
            // Only acceleration (eq. 3.26b).
            let ta = 2.0 * h / sum;
            let tj1 = (jmax * h - sqrt((jmax * (jmax * h * h - sum * sum * (v1 - v0))).max(0.0)))
                / (jmax * sum);
            self.phases = Phases {
                tj1,
                ta,
                tv: 0.0,
                tj2: 0.0,
                td: 0.0,
            };
            self.alim_a = jmax * tj1;
            self.alim_d = 0.0;
            self.vlim = v1;
        } else {
            let (ta, td) = (ta.max(2.0 * tj), td.max(2.0 * tj));
            self.phases = Phases {
                tj1: tj,
                ta,
                tv: 0.0,
                tj2: tj,
                td,
            };
            self.alim_a = a;
            self.alim_d = -a;
            self.vlim = v0 + (ta - tj) * a;
        }
        self
    }

    /// The phase durations, s.
    pub fn phases(&self) -> Phases {
        self.phases
    }
    /// Total duration `T = Ta + Tv + Td`, s.
    pub fn duration(&self) -> f64 {
        self.phases.ta + self.phases.tv + self.phases.td
    }
    /// Segment length `h`, mm.
    pub fn length(&self) -> f64 {
        self.h
    }
    /// Start velocity, mm/s.
    pub fn v0(&self) -> f64 {
        self.v0
    }
    /// End velocity, mm/s.
    pub fn v1(&self) -> f64 {
        self.v1
    }
    /// Largest velocity reached, mm/s.
    pub fn vlim(&self) -> f64 {
        self.vlim
    }
    /// Largest acceleration reached during the acceleration phase, mm/s² (>= 0).
    pub fn alim_a(&self) -> f64 {
        self.alim_a
    }
    /// Largest deceleration reached, mm/s² (<= 0).
    pub fn alim_d(&self) -> f64 {
        self.alim_d
    }

    /// The state at time `t` s (eqs. 3.30a-3.30g, positions from `q0 = 0`).
    /// Before 0 (or NaN) the start state, after `T` the end state (`q = h`,
    /// `v = v1`), both with zero acceleration and jerk.
    pub fn eval(&self, t: f64) -> State {
        let Phases {
            tj1,
            ta,
            tv,
            tj2,
            td,
        } = self.phases;
        let (h, v0, v1, vlim, jm) = (self.h, self.v0, self.v1, self.vlim, self.jmax);
        let (aa, ad) = (self.alim_a, self.alim_d);
        let total = ta + tv + td;
        if t.is_nan() || t <= 0.0 {
            return State {
                q: 0.0,
                v: v0,
                a: 0.0,
                j: 0.0,
            };
        }
        if t >= total {
            return State {
                q: h,
                v: v1,
                a: 0.0,
                j: 0.0,
            };
        }
        if t < ta {
            if t < tj1 {
                // (3.30a)
                return State {
                    q: v0 * t + jm * t * t * t / 6.0,
                    v: v0 + 0.5 * jm * t * t,
                    a: jm * t,
                    j: jm,
                };
            }
            if t < ta - tj1 {
                // (3.30b)
                return State {
                    q: v0 * t + aa / 6.0 * (3.0 * t * t - 3.0 * tj1 * t + tj1 * tj1),
                    v: v0 + aa * (t - 0.5 * tj1),
                    a: aa,
                    j: 0.0,
                };
            }
            // (3.30c)
            let r = ta - t;
            return State {
                q: (vlim + v0) * ta / 2.0 - vlim * r + jm * r * r * r / 6.0,
                v: vlim - 0.5 * jm * r * r,
                a: jm * r,
                j: -jm,
            };
        }
        if t < ta + tv {
            // (3.30d)
            return State {
                q: (vlim + v0) * ta / 2.0 + vlim * (t - ta),
                v: vlim,
                a: 0.0,
                j: 0.0,
            };
        }
        let s = t - total + td;
        let q_dec = h - (vlim + v1) * td / 2.0;
        if s < tj2 {
            // (3.30e)
            return State {
                q: q_dec + vlim * s - jm * s * s * s / 6.0,
                v: vlim - 0.5 * jm * s * s,
                a: -jm * s,
                j: -jm,
            };
        }
        if s < td - tj2 {
            // (3.30f)
            return State {
                q: q_dec + vlim * s + ad / 6.0 * (3.0 * s * s - 3.0 * tj2 * s + tj2 * tj2),
                v: vlim + ad * (s - 0.5 * tj2),
                a: ad,
                j: 0.0,
            };
        }
        // (3.30g)
        let r = total - t;
        State {
            q: h - v1 * r - jm * r * r * r / 6.0,
            v: v1 + 0.5 * jm * r * r,
            a: -jm * r,
            j: jm,
        }
    }
}

impl DoubleS {
    /// The time (s) at which the speed first reaches `c` on the rising side
    /// (`rising`: from `v0` up to the peak) or last leaves it on the
    /// falling side (from the peak down to `v1`), in closed form: the
    /// inverse of the speed of eqs. 3.30a-c (rising) or 3.30e-g (falling).
    /// On the rising side 0 where `c <= v0` and the end of the
    /// acceleration where `c >= vlim`; on the falling side the end of the
    /// profile where `c <= v1` and the start of the deceleration where
    /// `c >= vlim`. Exact up to rounding: the speed at the time returned
    /// is `c` to a few ulps.
    pub fn time_at_speed(&self, c: f64, rising: bool) -> f64 {
        let Phases {
            tj1,
            ta,
            tv,
            tj2,
            td,
        } = self.phases;
        let jm = self.jmax;
        let vlim = self.vlim;
        if rising {
            let v0 = self.v0;
            if c <= v0 || ta <= 0.0 {
                return 0.0;
            }
            if c >= vlim {
                return ta;
            }
            // (3.30a) up to the end of the first jerk phase.
            let v_j = v0 + 0.5 * jm * tj1 * tj1;
            let t = if c <= v_j {
                crate::math::sqrt(2.0 * (c - v0) / jm)
            } else if ta - tj1 > tj1 && c <= v0 + self.alim_a * (ta - 1.5 * tj1) {
                // (3.30b): constant acceleration.
                (c - v0) / self.alim_a + 0.5 * tj1
            } else {
                // (3.30c): the jerk phase into the peak.
                ta - crate::math::sqrt(2.0 * (vlim - c) / jm)
            };
            t.clamp(0.0, ta)
        } else {
            let (v1, ad) = (self.v1, self.alim_d);
            let total = ta + tv + td;
            let start = ta + tv;
            if c <= v1 || td <= 0.0 {
                return total;
            }
            if c >= vlim {
                return start;
            }
            // (3.30g) backwards from the end over the last jerk phase.
            let v_j = v1 + 0.5 * jm * tj2 * tj2;
            let t = if c <= v_j {
                total - crate::math::sqrt(2.0 * (c - v1) / jm)
            } else if td - tj2 > tj2 && c <= vlim + 0.5 * ad * tj2 {
                // (3.30f): constant deceleration (`ad` < 0).
                start + (c - vlim) / ad + 0.5 * tj2
            } else {
                // (3.30e): the jerk phase out of the peak.
                start + crate::math::sqrt(2.0 * (vlim - c) / jm)
            };
            t.clamp(start, total)
        }
    }
}

/// The largest `v` in `[lo, hi]` with `dist(v) <= h` found by bisection
/// down to adjacent floats, given `dist(lo) <= h < dist(hi)` (`dist`
/// increasing): the peak velocity of a case-2 profile.
fn bisect_peak(dist: &impl Fn(f64) -> f64, h: f64, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..2100 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if dist(mid) <= h {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Narrows `[lo, hi]`, with `dist(lo) <= h < dist(hi)` and `dist`
/// nondecreasing (of slope `slope`), about the largest `v` with
/// `dist(v) <= h`, keeping that property ([`DoubleS::fastest_case2`]).
///
/// Often `h` barely exceeds the direct change and the answer is `lo`
/// itself, where `dist` rises like a square root and no Newton step gets
/// close: a few ulps above `lo` settle that first. Otherwise Newton steps
/// safeguarded by bisection (`rtsafe`: Press et al., *Numerical Recipes*,
/// 3rd ed., 2007, section 9.4; a bisection step where the Newton step
/// leaves the bracket or halves it no faster) move one end near the root,
/// and steps growing from a few ulps of the last iterate close the other.
fn narrow_peak(
    dist: &dyn Fn(f64) -> f64,
    slope: &dyn Fn(f64) -> f64,
    h: f64,
    lo: &mut f64,
    hi: &mut f64,
) {
    let ulps = |v: f64| 4.0 * f64::EPSILON * v.max(f64::MIN_POSITIVE);
    let near = *lo + ulps(*lo);
    if near < *hi && dist(near) > h {
        *hi = near;
        return;
    }
    let mut v = 0.5 * (*lo + *hi);
    let (mut dx, mut dx_old) = (*hi - *lo, *hi - *lo);
    for _ in 0..NEWTON_STEPS {
        let d = dist(v) - h;
        if d <= 0.0 {
            *lo = v;
        } else {
            *hi = v;
        }
        let s = slope(v);
        let (next, step) =
            if ((v - *hi) * s - d) * ((v - *lo) * s - d) > 0.0 || abs(2.0 * d) > abs(dx_old * s) {
                let half = 0.5 * (*hi - *lo);
                (*lo + half, half)
            } else {
                (v - d / s, d / s)
            };
        dx_old = dx;
        dx = step;
        if !(next > *lo && next < *hi) || abs(dx) <= ulps(v) {
            break;
        }
        v = next;
    }
    // The end the iterates did not reach, closed with steps growing from a
    // few ulps of the last iterate (`v` is `lo` or `hi` now).
    let mut step = ulps(v);
    for _ in 0..NEWTON_STEPS {
        if v == *lo {
            let w = v + step;
            if w >= *hi {
                return;
            }
            if dist(w) > h {
                *hi = w;
                return;
            }
            *lo = w;
        } else {
            let w = v - step;
            if w <= *lo {
                return;
            }
            if dist(w) <= h {
                *lo = w;
                return;
            }
            *hi = w;
        }
        step *= 16.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The peak velocity by plain bisection of the whole bracket: what
    /// [`DoubleS::fastest_case2`] found before [`narrow_peak`].
    fn bisected_peak(v0: f64, v1: f64, h: f64, l: &Limits) -> f64 {
        let dist = |v: f64| {
            change_unchecked(v0, v, l.amax, l.jmax).distance
                + change_unchecked(v, v1, l.amax, l.jmax).distance
        };
        bisect_peak(&dist, h, v0.max(v1), l.vmax)
    }

    proptest! {
        /// The narrowed search finds the bisection's peak to the bit, on
        /// segments from barely longer than the direct change to long ones.
        #[test]
        fn the_narrowed_search_finds_the_bisections_peak(
            v0 in 0.0f64..300.0,
            v1 in 0.0f64..300.0,
            frac in prop_oneof![1e-15f64..1e-9, 1e-9f64..1e-3, 1e-3f64..0.999],
            amax in 100.0f64..10000.0,
            jmax in 1000.0f64..100000.0,
        ) {
            let l = Limits { vmax: 400.0, amax, jmax };
            // Case 2: longer than the direct change, shorter than the
            // changes to and from vmax.
            let direct = change_unchecked(v0, v1, amax, jmax).distance;
            let full = change_unchecked(v0, 400.0, amax, jmax).distance
                + change_unchecked(400.0, v1, amax, jmax).distance;
            let h = direct + frac * (full - direct);
            prop_assume!(h > direct);
            let p = DoubleS::plan(h, v0, v1, &l).unwrap();
            prop_assert_eq!(p.vlim.to_bits(), bisected_peak(v0, v1, h, &l).to_bits());
        }

        /// `time_at_speed` inverts the speed on each side: the speed at the
        /// time it returns is the speed asked for (to rounding), and the
        /// speed before it (rising) or after it (falling) is below it.
        #[test]
        fn the_time_at_a_speed_inverts_the_speed(
            v0 in 0.0f64..300.0,
            v1 in 0.0f64..300.0,
            h in 0.01f64..200.0,
            amax in 100.0f64..10000.0,
            jmax in 1000.0f64..100000.0,
            share in 0.0f64..1.0,
        ) {
            let l = Limits { vmax: 400.0, amax, jmax };
            let Ok(p) = DoubleS::plan(h, v0, v1, &l) else {
                return Ok(());
            };
            let ph = p.phases();
            let tol = 1e-9 * p.vlim();
            for rising in [true, false] {
                let (lo, hi) = if rising { (p.v0(), p.vlim()) } else { (p.v1(), p.vlim()) };
                let c = lo + share * (hi - lo);
                let t = p.time_at_speed(c, rising);
                if rising {
                    prop_assert!(t >= 0.0 && t <= ph.ta);
                } else {
                    prop_assert!(t >= ph.ta + ph.tv && t <= p.duration());
                }
                if hi - lo > tol {
                    prop_assert!((p.eval(t).v - c).abs() <= tol, "{} != {c}", p.eval(t).v);
                    let before = if rising { 0.5 * t } else { 0.5 * (t + p.duration()) };
                    prop_assert!(p.eval(before).v <= c + tol);
                }
            }
        }
    }
}
