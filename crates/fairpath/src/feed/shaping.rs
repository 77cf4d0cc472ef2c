//! Local reductions of a run's plan: where the motion as sampled by the
//! controller would exceed a limit that the planner's caps do not model
//! exactly, the speed cap and the tangential acceleration and jerk are
//! lowered over a stretch of arc length, and the run is planned again.
//!
//! The planner bounds the tangential acceleration and jerk of its
//! profiles and caps the speed by the curvature terms one at a time. The
//! 3D vectors combine them: with arc length `s`, speed `v`, tangential
//! acceleration `a_t`, tangential jerk `j_t`, curvature `k` and torsion
//! `tau` (Frenet-Serret; e.g. Biagiotti and Melchiorri 2008, section 8.3),
//!
//! `a = a_t T + k v^2 N`,
//! `j = (j_t - k^2 v^3) T + (dk/ds v^3 + 3 k v a_t) N + k tau v^3 B`.
//!
//! The cross term `3 k v a_t` is in no single cap: speeding up or braking
//! on a curve at the full tangential acceleration gives a normal jerk of
//! several times the limit (a 10 mm radius at 100 mm/s and 4000 mm/s^2:
//! 120,000 mm/s^3). A [`Shaping`] lowers the speed cap where the `v^3`
//! terms are too large and the tangential limits where the terms in
//! `a_t` and `j_t` are, each only where the sampled motion needs it
//! (see [`super::stream`]).

use alloc::vec::Vec;

/// Factors (each in (0, 1]) on the speed cap and on the tangential
/// acceleration and jerk, piecewise constant over the arc length of a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Shaping {
    /// Breakpoints `(s, cap, tangential)` sorted by `s`: the factors hold
    /// from `s` to the next breakpoint. Before the first, and with none,
    /// both factors are 1.
    steps: Vec<(f64, f64, f64)>,
}

/// One reduction: over `[s0, s1]` (mm of run arc length) multiply the speed
/// cap by `cap` and the tangential acceleration and jerk by `tangential`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reduction {
    pub s0: f64,
    pub s1: f64,
    pub cap: f64,
    pub tangential: f64,
}

impl Shaping {
    /// No reduction anywhere.
    pub fn none() -> Shaping {
        Shaping::default()
    }

    /// The same factors over the whole run.
    pub fn uniform(cap: f64, tangential: f64) -> Shaping {
        Shaping {
            steps: alloc::vec![(f64::NEG_INFINITY, cap, tangential)],
        }
    }

    /// Whether nothing is reduced.
    pub fn is_none(&self) -> bool {
        self.steps.is_empty()
    }

    /// The smallest factors `(cap, tangential)` over `[s0, s1]`.
    pub fn factors(&self, s0: f64, s1: f64) -> (f64, f64) {
        if self.steps.is_empty() {
            return (1.0, 1.0);
        }
        // The step in force at s0: the last breakpoint at or before it.
        let first = self.steps.partition_point(|st| st.0 <= s0);
        let (mut c, mut t) = if first == 0 {
            (1.0, 1.0)
        } else {
            (self.steps[first - 1].1, self.steps[first - 1].2)
        };
        for st in &self.steps[first..] {
            if st.0 >= s1 {
                break;
            }
            c = c.min(st.1);
            t = t.min(st.2);
        }
        (c, t)
    }

    /// Applies one round of reductions: where several overlap, the
    /// strongest of them; the result multiplies what was already there (a
    /// round's reductions are measured on the motion planned with the
    /// factors in force).
    pub fn apply(&mut self, round: &[Reduction]) {
        if round.is_empty() {
            return;
        }
        // Every boundary of the old steps and of the new reductions.
        let mut cuts: Vec<f64> = self.steps.iter().map(|st| st.0).collect();
        for r in round {
            cuts.push(r.s0);
            cuts.push(r.s1);
        }
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        let mut steps = Vec::with_capacity(cuts.len());
        for (i, &s) in cuts.iter().enumerate() {
            let next = cuts.get(i + 1).copied().unwrap_or(f64::INFINITY);
            let (mut c, mut t) = self.at(s);
            let (mut rc, mut rt) = (1.0f64, 1.0f64);
            for r in round {
                if r.s0 <= s && next <= r.s1 && r.s0 < r.s1 {
                    rc = rc.min(r.cap);
                    rt = rt.min(r.tangential);
                }
            }
            c *= rc;
            t *= rt;
            // Equal neighbours are one step.
            if let Some(&(_, pc, pt)) = steps.last() {
                if pc == c && pt == t {
                    continue;
                }
            } else if c == 1.0 && t == 1.0 {
                continue;
            }
            steps.push((s, c, t));
        }
        self.steps = steps;
    }

    /// The factors in force at `s`.
    fn at(&self, s: f64) -> (f64, f64) {
        let i = self.steps.partition_point(|st| st.0 <= s);
        if i == 0 {
            (1.0, 1.0)
        } else {
            (self.steps[i - 1].1, self.steps[i - 1].2)
        }
    }

    /// Multiplies every factor by `f` over the whole run (a last resort
    /// when local reductions do not converge).
    pub fn scale_all(&mut self, f: f64) {
        if self.steps.is_empty() || self.steps[0].0 > 0.0 {
            self.steps.insert(0, (f64::NEG_INFINITY, 1.0, 1.0));
        }
        for st in &mut self.steps {
            st.1 *= f;
            st.2 *= f;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn red(s0: f64, s1: f64, cap: f64, tangential: f64) -> Reduction {
        Reduction {
            s0,
            s1,
            cap,
            tangential,
        }
    }

    #[test]
    fn no_reduction_is_one_everywhere() {
        let s = Shaping::none();
        assert_eq!(s.factors(0.0, 100.0), (1.0, 1.0));
    }

    #[test]
    fn overlapping_reductions_of_one_round_take_the_strongest() {
        let mut s = Shaping::none();
        s.apply(&[red(1.0, 3.0, 0.8, 1.0), red(2.0, 4.0, 0.9, 0.5)]);
        assert_eq!(s.factors(0.0, 0.5), (1.0, 1.0));
        assert_eq!(s.factors(1.0, 1.5), (0.8, 1.0));
        assert_eq!(s.factors(2.2, 2.8), (0.8, 0.5));
        assert_eq!(s.factors(3.2, 3.8), (0.9, 0.5));
        assert_eq!(s.factors(4.0, 9.0), (1.0, 1.0));
        assert_eq!(s.factors(0.0, 9.0), (0.8, 0.5));
    }

    #[test]
    fn rounds_multiply() {
        let mut s = Shaping::none();
        s.apply(&[red(1.0, 3.0, 0.5, 0.5)]);
        s.apply(&[red(2.0, 5.0, 0.5, 1.0)]);
        assert_eq!(s.factors(1.0, 1.9), (0.5, 0.5));
        assert_eq!(s.factors(2.1, 2.9), (0.25, 0.5));
        assert_eq!(s.factors(3.1, 4.9), (0.5, 1.0));
        s.scale_all(0.5);
        assert_eq!(s.factors(10.0, 11.0), (0.5, 0.5));
        assert_eq!(s.factors(2.1, 2.9), (0.125, 0.25));
    }
}
