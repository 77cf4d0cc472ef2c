//! The peak of a curvature along a curve, found by samples and refined
//! between them.
//!
//! Why: equal steps alone miss narrow peaks. Where a curve nearly stops
//! (a near-cusp: its parametric speed dips to a small `s0` at `t0`), its
//! curvature is about `c / (s0^2 + a^2 (t - t0)^2)^(3/2)`, a spike
//! narrower than any fixed step: LinuxCNC's `homer_p1.ngc` (a G6.2
//! program) has a peak of 955 1/mm where 16 steps per knot span see 73,
//! and a fairing judged by those samples raised it to 8,021 unseen. The
//! speed `|C'|` near such a point is `sqrt(s0^2 + a^2 (t - t0)^2)`,
//! unimodal over the two steps around the sample nearest to it, which is
//! then a local minimum of the sampled speeds: golden-section search over
//! that bracket finds `t0` (Kiefer 1953; Press et al., *Numerical
//! Recipes*, 3rd ed., section 10.2). Each sampled local maximum of the
//! curvature is refined the same way, for the peaks that are no
//! near-cusp.

use super::{curvature_from, Vec3};
use crate::math;

/// Golden-section iterations at most (each narrows the bracket by 0.618:
/// 80 take any bracket of a finite domain below a double's resolution).
const MAX_ITERATIONS: usize = 80;

/// Which sampled extrema [`curvature_candidates`] refines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Extrema {
    /// Every local maximum of the sampled curvature and minimum of the
    /// sampled speed.
    All,
    /// Only those the samples show narrower than their step, where the
    /// samples may miss most of a peak: a speed minimum below
    /// `1 / NARROW` times its greater neighbour (a near-cusp's speed,
    /// `sqrt(s0^2 + a^2 (t - t0)^2)`, is at least three times smaller at
    /// the sample nearest to `t0` than at the farther of its neighbours),
    /// and a curvature maximum above [`NARROW`] times both neighbours (on
    /// a polynomial span `C' x C''` is smooth, so a narrow peak of its
    /// curvature comes with a dip of its speed; not the lesser neighbour:
    /// next to an inflection every maximum would count). A wide peak is
    /// then taken as sampled: a few percent low at most where the samples
    /// are as dense as the verifier's, for far less work.
    Narrow,
}

/// How much a sampled extremum must stand out from its neighbours to be
/// [`Extrema::Narrow`].
pub const NARROW: f64 = 2.0;

/// Parameters between the samples `ts` of a curve (`derivs(t) = (C'(t),
/// C''(t))`; `ks[j]` and `speeds[j]` its curvature and `|C'|` at
/// `ts[j]`) where its curvature may peak unseen by them: for each local
/// maximum of the sampled curvature, and for each local minimum of the
/// sampled speed (a near-cusp), that `which` selects, the point
/// golden-section search finds over the bracket of the neighbouring
/// samples, to `accuracy` in the parameter. With the samples, their
/// curvatures give a lower bound of the peak that is the peak, to that
/// accuracy, where the curvature (or the speed) is unimodal over each
/// bracket refined.
pub fn curvature_candidates(
    derivs: impl Fn(f64) -> (Vec3, Vec3),
    ts: &[f64],
    (ks, speeds): (&[f64], &[f64]),
    accuracy: f64,
    which: Extrema,
) -> alloc::vec::Vec<f64> {
    let n = ts.len().saturating_sub(1);
    let mut out = alloc::vec::Vec::new();
    if ts.len() < 2 || ks.len() != ts.len() || speeds.len() != ts.len() {
        return out;
    }
    if which == Extrema::Narrow && !any_narrow(ks, speeds) {
        // (No allocation: most spans have no narrow extremum.)
        return out;
    }
    let bracket = |j: usize| (j.saturating_sub(1), (j + 1).min(n));
    for j in local_maxima(ks) {
        let (lo, hi) = bracket(j);
        if which == Extrema::Narrow && ks[j] <= NARROW * ks[lo].max(ks[hi]) {
            continue;
        }
        let k = |t: f64| {
            let (d1, d2) = derivs(t);
            curvature_from(d1, d2)
        };
        out.push(golden_max(k, ts[lo], ts[hi], accuracy).1);
    }
    // Speeds below the largest, turned into heights above it, so that a
    // least speed is a local maximum.
    let top = speeds.iter().copied().fold(0.0, f64::max);
    let depth: alloc::vec::Vec<f64> = speeds.iter().map(|&v| top - v).collect();
    for j in local_maxima(&depth) {
        let (lo, hi) = bracket(j);
        if which == Extrema::Narrow && NARROW * speeds[j] >= speeds[lo].max(speeds[hi]) {
            continue;
        }
        let speed = |t: f64| top - derivs(t).0.norm();
        out.push(golden_max(speed, ts[lo], ts[hi], accuracy).1);
    }
    out
}

/// Whether the sampled curvatures `ks` and speeds `speeds` have an
/// extremum that [`Extrema::Narrow`] refines (one pass, no allocation).
fn any_narrow(ks: &[f64], speeds: &[f64]) -> bool {
    let n = ks.len();
    (0..n).any(|j| {
        let (lo, hi) = (j.saturating_sub(1), (j + 1).min(n - 1));
        let (s, slo, shi) = (speeds[j], speeds[lo], speeds[hi]);
        let speed_dip = s <= slo && s <= shi && NARROW * s < slo.max(shi);
        let curvature_spike = ks[j] > 0.0 && ks[j] > NARROW * ks[lo].max(ks[hi]);
        speed_dip || curvature_spike
    })
}

/// The peak curvature of a curve (`derivs` as [`curvature_candidates`])
/// on `[a, b]`: `samples` equal steps, ends included, and the candidates
/// `which` selects between them. A lower bound of the peak, exact to
/// `accuracy` in the parameter wherever the curvature, or the speed at a
/// near-cusp, is unimodal between neighbouring samples and the extremum
/// is refined.
pub fn sampled_peak(
    derivs: impl Fn(f64) -> (Vec3, Vec3),
    (a, b): (f64, f64),
    samples: usize,
    accuracy: f64,
    which: Extrema,
) -> f64 {
    let n = samples.max(1);
    let ts: alloc::vec::Vec<f64> = (0..=n)
        .map(|j| {
            if j == n {
                b
            } else {
                a + (b - a) * j as f64 / n as f64
            }
        })
        .collect();
    let curvature = |(d1, d2): (Vec3, Vec3)| curvature_from(d1, d2);
    let at: alloc::vec::Vec<(Vec3, Vec3)> = ts.iter().map(|&t| derivs(t)).collect();
    let ks: alloc::vec::Vec<f64> = at.iter().map(|&d| curvature(d)).collect();
    let speeds: alloc::vec::Vec<f64> = at.iter().map(|(d1, _)| d1.norm()).collect();
    let found = curvature_candidates(&derivs, &ts, (&ks, &speeds), accuracy, which)
        .into_iter()
        .map(|t| curvature(derivs(t)))
        .fold(0.0, f64::max);
    ks.into_iter().fold(found, f64::max)
}

/// The largest value of a function `f` from samples already taken,
/// `values[j] = f(ts[j])` at increasing parameters `ts`, each local
/// maximum of the values refined over `[ts[j - 1], ts[j + 1]]` (ends: the
/// one neighbour) by golden-section search to `accuracy` where
/// `refine(j)` allows (for a peak pass's jerk term, which has no speed to
/// find a near-cusp by). A lower bound of the supremum of `f` over
/// `[ts[0], ts[last]]`, exact to that accuracy where `f` is unimodal over
/// each bracket. NaN counts as 0.
pub fn refined_peak(
    f: impl Fn(f64) -> f64,
    ts: &[f64],
    values: &[f64],
    accuracy: f64,
    refine: impl Fn(usize) -> bool,
) -> f64 {
    let ks: alloc::vec::Vec<f64> = values
        .iter()
        .map(|&v| if v.is_nan() { 0.0 } else { v })
        .collect();
    let n = ks.len().saturating_sub(1);
    let mut best = ks.iter().copied().fold(0.0, f64::max);
    for j in local_maxima(&ks) {
        if refine(j) {
            let (lo, hi) = (ts[j.saturating_sub(1)], ts[(j + 1).min(n)]);
            best = best.max(golden_max(&f, lo, hi, accuracy).0);
        }
    }
    best
}

/// The largest value golden-section search finds of `f` on `[lo, hi]`,
/// and where, narrowing the bracket to `accuracy` (or by at most 80
/// golden steps, each to 0.618 of it): the maximum, to that accuracy,
/// where `f` is unimodal there; a value `f` takes, in any case. NaN
/// counts as 0. (A minimum is the maximum of `-f`.)
pub fn golden_max(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64, accuracy: f64) -> (f64, f64) {
    let f = |t: f64| {
        let v = f(t);
        if v.is_nan() {
            0.0
        } else {
            v
        }
    };
    let g = 0.5 * (math::sqrt(5.0) - 1.0);
    let mut x1 = hi - g * (hi - lo);
    let mut x2 = lo + g * (hi - lo);
    let (mut f1, mut f2) = (f(x1), f(x2));
    let mut best = if f1 >= f2 { (f1, x1) } else { (f2, x2) };
    for _ in 0..MAX_ITERATIONS {
        if hi - lo <= accuracy {
            break;
        }
        if f1 > f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - g * (hi - lo);
            f1 = f(x1);
            if f1 > best.0 {
                best = (f1, x1);
            }
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + g * (hi - lo);
            f2 = f(x2);
            if f2 > best.0 {
                best = (f2, x2);
            }
        }
    }
    best
}

/// The indices of the local maxima of `values` (strict on one side at
/// least, so that a plateau is not one; positive values only) that
/// [`refined_peak`] refines: each is refined over `[ts[j - 1], ts[j + 1]]`.
fn local_maxima(values: &[f64]) -> impl Iterator<Item = usize> + '_ {
    let n = values.len().saturating_sub(1);
    (0..values.len()).filter(move |&j| {
        let v = values[j];
        let left = if j > 0 {
            values[j - 1]
        } else {
            f64::NEG_INFINITY
        };
        let right = if j < n {
            values[j + 1]
        } else {
            f64::NEG_INFINITY
        };
        values.len() >= 2 && v > 0.0 && v >= left && v >= right && (v > left || v > right)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `(C', C'')` of the cubic Bezier `b` at `t`.
    fn bezier(b: [Vec3; 4]) -> impl Fn(f64) -> (Vec3, Vec3) {
        move |t: f64| {
            let d = [b[1] - b[0], b[2] - b[1], b[3] - b[2]];
            let s = 1.0 - t;
            let d1 = (d[0] * (s * s) + d[1] * (2.0 * s * t) + d[2] * (t * t)) * 3.0;
            let d2 = ((d[1] - d[0]) * s + (d[2] - d[1]) * t) * 6.0;
            (d1, d2)
        }
    }

    /// Curvatures and speeds of `d` at `ts`.
    fn sampled(
        d: &impl Fn(f64) -> (Vec3, Vec3),
        ts: &[f64],
    ) -> (alloc::vec::Vec<f64>, alloc::vec::Vec<f64>) {
        let at: alloc::vec::Vec<(Vec3, Vec3)> = ts.iter().map(|&t| d(t)).collect();
        (
            at.iter().map(|&(d1, d2)| curvature_from(d1, d2)).collect(),
            at.iter().map(|(d1, _)| d1.norm()).collect(),
        )
    }

    /// A cubic whose polygon nearly folds back turns near `t = 0.5` on a
    /// spike of curvature far narrower than 8 steps: they see a few 1/mm,
    /// the search the spike (against a dense scan around it).
    #[test]
    fn a_near_cusp_between_samples_is_found() {
        let v = |x: f64, y: f64| Vec3::new(x, y, 0.0);
        let d = bezier([v(0.0, 0.0), v(1.0, 1.0), v(0.0, 1.001), v(1.0, 0.0)]);
        let k = |t: f64| {
            let (d1, d2) = d(t);
            curvature_from(d1, d2)
        };
        let dense = (0..=400_000)
            .map(|j| k(0.4999 + 4e-4 * j as f64 / 400_000.0))
            .fold(0.0, f64::max);
        assert!(dense > 1e6, "{dense}");
        let coarse = (0..=8).map(|j| k(j as f64 / 8.0)).fold(0.0, f64::max);
        assert!(coarse < 1e-4 * dense, "{coarse} vs {dense}");
        let found = sampled_peak(&d, (0.0, 1.0), 8, 1e-12, Extrema::All);
        assert!(found >= 0.99 * dense, "{found} vs {dense}");
        // The samples show it narrow: `Extrema::Narrow` refines it too.
        let ts: alloc::vec::Vec<f64> = (0..=8).map(|j| j as f64 / 8.0).collect();
        let (ks, speeds) = sampled(&d, &ts);
        let narrow = curvature_candidates(&d, &ts, (&ks, &speeds), 1e-12, Extrema::Narrow)
            .into_iter()
            .map(k)
            .fold(0.0, f64::max);
        assert!(narrow >= 0.99 * dense, "{narrow} vs {dense}");
    }

    /// A curve without a near-cusp: the refined peak of an arch is its
    /// vertex's curvature (2/3), between samples (5 steps see 0.6286).
    #[test]
    fn an_ordinary_peak_between_samples_is_found() {
        let v = |x: f64, y: f64| Vec3::new(x, y, 0.0);
        let d = bezier([v(0.0, 0.0), v(1.0, 1.0), v(2.0, 1.0), v(3.0, 0.0)]);
        let top = 2.0 / 3.0;
        let found = sampled_peak(&d, (0.0, 1.0), 5, 1e-12, Extrema::All);
        assert!((found - top).abs() <= 1e-9 * top, "{found} vs {top}");
        // A peak as wide as the steps is left as sampled by `Narrow`.
        let ts: alloc::vec::Vec<f64> = (0..=5).map(|j| j as f64 / 5.0).collect();
        let (ks, speeds) = sampled(&d, &ts);
        let samples = (ks.as_slice(), speeds.as_slice());
        assert!(curvature_candidates(&d, &ts, samples, 1e-12, Extrema::Narrow).is_empty());
        assert!(!curvature_candidates(&d, &ts, samples, 1e-12, Extrema::All).is_empty());
    }

    /// `refined_peak` on functions: peaks at the ends, a plateau, two
    /// maxima, NaN samples, and `refine` obeyed.
    #[test]
    fn refined_peak_on_ends_plateaus_and_several_maxima() {
        let at = |f: &dyn Fn(f64) -> f64, n: usize| {
            let ts: alloc::vec::Vec<f64> = (0..=n).map(|j| j as f64 / n as f64).collect();
            let vs: alloc::vec::Vec<f64> = ts.iter().map(|&t| f(t)).collect();
            (ts, vs)
        };
        let inc = |t: f64| t;
        let (ts, vs) = at(&inc, 8);
        assert_eq!(refined_peak(inc, &ts, &vs, 1e-9, |_| true), 1.0);
        let flat = |_: f64| 3.0;
        let (ts, vs) = at(&flat, 8);
        assert_eq!(refined_peak(flat, &ts, &vs, 1e-9, |_| true), 3.0);
        let two = |t: f64| math::abs(math::sin(7.0 * t)) * (1.0 + t);
        let dense = (0..=100_000)
            .map(|j| two(j as f64 / 100_000.0))
            .fold(0.0, f64::max);
        let (ts, vs) = at(&two, 8);
        let found = refined_peak(two, &ts, &vs, 1e-12, |_| true);
        assert!((found - dense).abs() <= 1e-6, "{found} vs {dense}");
        assert!(refined_peak(two, &ts, &vs, 1e-12, |_| false) < found - 1e-3);
        let nan = |t: f64| if t < 0.5 { f64::NAN } else { 1.0 - t };
        let (ts, vs) = at(&nan, 4);
        assert_eq!(refined_peak(nan, &ts, &vs, 1e-9, |_| true), 0.5);
    }
}
