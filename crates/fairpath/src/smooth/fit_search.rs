//! `bspline-fit`'s search for the control points of one section at given
//! smoothing weights (module docs of `bspline_fit.rs`, steps 3, 5 and 6):
//! knots by averaging, one linear least-squares attempt with its proven
//! span bounds, the control-point count by doubling and bisection, then
//! knots inserted where the bound fails.

use crate::geom::fit::{
    averaged_knots, span_errors, span_errors_within, EndCondition, FitData, FitError, FitSystem,
};
use crate::geom::{Nurbs, Vec3};
use alloc::vec::Vec;

/// Most data parts a [`DataCache`] keeps.
const CACHED_DATA: usize = 8;

/// The data parts ([`FitData`]) of the latest fits of one section (one set
/// of points, parameters and end conditions), by knot vector: the raises
/// of the weights start on the knots of the fit before, and the weights
/// of the ladder retry the knot counts of the search before, so their data
/// terms are built once. The systems are the same to the bit as built
/// afresh ([`FitData`]).
#[derive(Default)]
pub(super) struct DataCache {
    /// Latest used last.
    entries: Vec<FitData>,
}

impl DataCache {
    /// The system of a fit to data at `params` with `knots`, end
    /// conditions `conds`, end points `ends` and `weights`. Every call on
    /// one cache must pass the same `params`, `conds` and `ends`.
    fn system(
        &mut self,
        params: &[f64],
        knots: &[f64],
        conds: (EndCondition, EndCondition),
        ends: (Vec3, Vec3),
        weights: (f64, f64),
    ) -> Result<FitSystem, FitError> {
        let same = |d: &FitData| {
            let k = d.knots();
            k.len() == knots.len() && k.iter().zip(knots).all(|(a, b)| a.to_bits() == b.to_bits())
        };
        if let Some(i) = self.entries.iter().rposition(same) {
            let d = self.entries.remove(i);
            let system = d.system(weights);
            self.entries.push(d);
            return system;
        }
        let d = FitData::new(params, knots, conds, ends)?;
        let system = d.system(weights);
        if self.entries.len() >= CACHED_DATA {
            self.entries.remove(0);
        }
        self.entries.push(d);
        system
    }
}

/// Rounds of knot insertion from the largest failing count.
const REFINE_ROUNDS: usize = 12;

/// One attempt: the curve and its largest span bound, with the span bounds.
pub(super) struct Attempt {
    pub(super) curve: Nurbs,
    /// The bound of every span; empty where the attempt was only judged
    /// ([`judge`]) and failed.
    pub(super) errs: Vec<f64>,
    /// The largest span bound; for a judged attempt that failed, the first
    /// bound found above the target (the largest is at least that).
    pub(super) max: f64,
}

/// The least-squares fit of one attempt (counted in `fits`), or `None`
/// where its system cannot be built or solved.
fn solve(
    pts: &[Vec3],
    params: &[f64],
    knots: &[f64],
    ends: (EndCondition, EndCondition),
    weights: (f64, f64),
    (fits, cache): (&mut usize, &mut DataCache),
) -> Option<Nurbs> {
    *fits += 1;
    #[cfg(test)]
    tests::MOST_CONTROL_POINTS.with(|m| m.set(m.get().max(knots.len().saturating_sub(4))));
    let (Some(&first), Some(&last)) = (pts.first(), pts.last()) else {
        return None;
    };
    let system = cache
        .system(params, knots, ends, (first, last), weights)
        .ok()?;
    system.solve(pts).ok()
}

pub(super) fn attempt(
    pts: &[Vec3],
    params: &[f64],
    knots: &[f64],
    ends: (EndCondition, EndCondition),
    weights: (f64, f64),
    (fits, cache): (&mut usize, &mut DataCache),
) -> Option<Attempt> {
    let curve = solve(pts, params, knots, ends, weights, (fits, cache))?;
    let errs = span_errors(&curve, pts, params);
    let max = errs.iter().copied().fold(0.0, f64::max);
    max.is_finite().then_some(Attempt { curve, errs, max })
}

/// [`attempt`] where only whether it passes `target` is wanted: a fit that
/// fails is known to fail at the first span whose bound exceeds `target`,
/// and comes without its span bounds (`errs` empty; [`with_bounds`] adds
/// them). The same verdict as [`attempt`]: its control points are finite
/// (else `None`, as [`attempt`], whose bound is then infinite), so every
/// span's bound is finite and the largest exceeds `target` exactly when
/// one does.
fn judge(
    pts: &[Vec3],
    params: &[f64],
    knots: &[f64],
    ends: (EndCondition, EndCondition),
    (weights, target): ((f64, f64), f64),
    (fits, cache): (&mut usize, &mut DataCache),
) -> Option<Attempt> {
    let curve = solve(pts, params, knots, ends, weights, (fits, cache))?;
    if !curve.points.iter().all(|p| p.is_finite()) {
        return None;
    }
    match span_errors_within(&curve, pts, params, target) {
        Ok(errs) => {
            let max = errs.iter().copied().fold(0.0, f64::max);
            max.is_finite().then_some(Attempt { curve, errs, max })
        }
        Err(max) => max.is_finite().then_some(Attempt {
            curve,
            errs: Vec::new(),
            max,
        }),
    }
}

/// `a` with the bound of every span (computed where [`judge`] left them
/// out).
fn with_bounds(mut a: Attempt, pts: &[Vec3], params: &[f64]) -> Attempt {
    if a.errs.is_empty() {
        a.errs = span_errors(&a.curve, pts, params);
        a.max = a.errs.iter().copied().fold(0.0, f64::max);
    }
    a
}

/// Doubling, bisection, then knot insertion where the bound fails (module
/// docs, step 6). Returns the passing curve with fewest control points.
pub(super) fn search(
    pts: &[Vec3],
    params: &[f64],
    start: EndCondition,
    end: EndCondition,
    target: f64,
    weights: (f64, f64),
    (fits, cache): (&mut usize, &mut DataCache),
) -> Option<(Nurbs, f64)> {
    let smoothed = weights.0 > 0.0 || weights.1 > 0.0;
    let n = pts.len() - 1;
    let fixed = |e: EndCondition| match e {
        EndCondition::Free => 1,
        EndCondition::Tangent(_) => 3,
    };
    let h_min = (fixed(start) + fixed(end) + 1).max(4);
    // Without the smoothing term, at most one control point per data point
    // (Schoenberg-Whitney); with it, up to two per segment.
    let h_max = if smoothed { 2 * n + 8 } else { n + 1 }.max(h_min);
    let ends = (start, end);
    // Only judged: the bounds of the last failing count are computed
    // where the knot insertion starts from it.
    let mut try_count = |h: usize, fits: &mut usize| {
        let knots = averaged_knots(params, h);
        judge(
            pts,
            params,
            &knots,
            ends,
            (weights, target),
            (fits, &mut *cache),
        )
    };
    let mut lo: Option<(usize, Attempt)> = None;
    let mut hi: Option<(usize, Attempt)> = None;
    let mut h = h_min;
    loop {
        match try_count(h, fits) {
            Some(a) if a.max <= target => {
                hi = Some((h, a));
                break;
            }
            Some(a) => lo = Some((h, a)),
            None => {}
        }
        if h >= h_max {
            break;
        }
        h = (2 * h).min(h_max);
    }
    // Bisection to within an eighth of the failing count.
    if let (Some((l, _)), Some((u, _))) = (&lo, &hi) {
        let (mut l, mut u) = (*l, *u);
        while u - l > (l / 8).max(1) {
            let mid = l + (u - l) / 2;
            match try_count(mid, fits) {
                Some(a) if a.max <= target => {
                    hi = Some((mid, a));
                    u = mid;
                }
                Some(a) => {
                    lo = Some((mid, a));
                    l = mid;
                }
                None => l = mid,
            }
        }
    }
    // Knot insertion from the largest failing count, to fewer control
    // points than the passing count, or, where none passed, to
    // [`INSERTION_PER_DOUBLING`] times the most the doubling tried.
    let limit = hi
        .as_ref()
        .map_or(INSERTION_PER_DOUBLING * (h_max + 1), |(u, _)| *u);
    let min_span = min_span(params);
    let mut refined: Option<Attempt> = None;
    if let Some((_, a)) = lo {
        let mut a = with_bounds(a, pts, params);
        for _ in 0..REFINE_ROUNDS {
            let knots = refine_knots(&a.curve.knots, &a.errs, target, min_span);
            if knots.len() - 4 >= limit || knots.len() == a.curve.knots.len() {
                break;
            }
            match attempt(pts, params, &knots, ends, weights, (fits, &mut *cache)) {
                Some(b) if b.max <= target => {
                    refined = Some(b);
                    break;
                }
                Some(b) => a = b,
                None => break,
            }
        }
    }
    match (refined, hi) {
        (Some(r), _) => Some((r.curve, r.max)),
        (None, Some((_, a))) => Some((a.curve, a.max)),
        (None, None) => None,
    }
}

/// Where no control-point count of the doubling passes, knot insertion
/// may go on to this many times the most it tried (one control point per
/// data point, two per segment with the smoothing term), so that its work
/// stays linear in the data. Without a bound, a hopeless fit (a spiral of
/// 4.5-degree corners within 1 um, LinuxCNC's `sam-circle_lines.ngc`) ran
/// to 100,000 control points and hundreds of megabytes; with the
/// doubling's own count as the bound (one time), fits that pass only with
/// knots crowded where the data bend failed, and `auto` wrote
/// `3D_Chips.ngc` at 0.05 mm slower. Twice restores that and keeps the
/// spiral bounded (measurements: docs/tuning.md, `INSERTION_PER_DOUBLING`).
pub(super) const INSERTION_PER_DOUBLING: usize = 2;

/// The shortest knot span [`refine_knots`] splits, for data parameters
/// `params`.
pub(super) fn min_span(params: &[f64]) -> f64 {
    MIN_SPAN_PER_SEGMENT
        * params
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min)
}

/// A knot span shorter than this share of the shortest data segment is not
/// split further: knots closer than the data cannot pull the fit nearer to
/// it, and only make the curvature ripple.
const MIN_SPAN_PER_SEGMENT: f64 = 0.25;

/// The knots plus the middle of every span whose bound exceeds `target`
/// and that is at least `min_span` long.
pub(super) fn refine_knots(knots: &[f64], errs: &[f64], target: f64, min_span: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(knots.len() + errs.len());
    out.extend_from_slice(&knots[..4]);
    for (j, &e) in errs.iter().enumerate() {
        let s = 3 + j;
        let (a, b) = (knots[s], knots[s + 1]);
        if e > target && b - a >= min_span {
            let m = 0.5 * (a + b);
            if m > a && m < b {
                out.push(m);
            }
        }
        out.push(b);
    }
    out.extend_from_slice(&knots[knots.len() - 3..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::fit::chord_params;
    use core::cell::Cell;
    use proptest::prelude::*;

    std::thread_local! {
        /// The most control points of a fit this thread solved.
        pub(super) static MOST_CONTROL_POINTS: Cell<usize> = const { Cell::new(0) };
    }

    #[test]
    fn a_fit_that_never_passes_stays_within_the_control_points_its_data_support() {
        // The first 60 moves of the spiral of LinuxCNC's
        // `sam-circle_lines.ngc` (`G91 @-.0025 ^4.5` from (1, 0) in, mm),
        // fitted as `bspline-fit` fits a section, within 1.125 um (what
        // `fair` at 0.005 mm leaves its fit of the lines): no count passes,
        // and the knot insertion from the largest failing one went on
        // down to its shortest span: 37,572 control points for 909 data
        // points here, 1.6 million on moves 100 to 370. It stops at
        // `INSERTION_PER_DOUBLING` times the most the doubling tries, two
        // per data segment.
        let pts = crate::smooth::fit_chain::tests::sam_circle_lines_points(60);
        let target = 0.001125;
        let o = crate::smooth::BsplineFitOptions::default();
        MOST_CONTROL_POINTS.with(|m| m.set(0));
        let fit = crate::smooth::fit_fairing::fit_polyline_faired(
            &pts,
            EndCondition::Free,
            EndCondition::Free,
            target,
            (o.fairness, o.jerk_fairness),
            o.fairness_raises,
            o.relax.as_ref(),
        );
        let most = MOST_CONTROL_POINTS.with(|m| m.get());
        let n = crate::smooth::fit_fill::fill_segments(&pts, target).len() - 1;
        let doubling_most = 2 * n + 8;
        assert!(
            most <= INSERTION_PER_DOUBLING * (doubling_most + 1),
            "{most} control points for {n} segments"
        );
        if let Some(f) = fit {
            assert!(f.bound <= target);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        /// A judged attempt passes or fails (or cannot be made) exactly as
        /// the full attempt, and where it passes it is the full attempt.
        #[test]
        fn a_judged_attempt_has_the_full_attempts_verdict(
            ys in prop::collection::vec(-1.0f64..1.0, 4..40),
            extra in 0usize..40,
            weight in prop_oneof![Just(0.0), 1e-6f64..1.0],
            target in 1e-4f64..0.5,
        ) {
            let pts: Vec<Vec3> = ys
                .iter()
                .enumerate()
                .map(|(i, &y)| Vec3::new(i as f64, y, 0.0))
                .collect();
            let params = chord_params(&pts);
            let h = (4 + extra).min(pts.len()).max(4);
            let knots = averaged_knots(&params, h);
            let free = (EndCondition::Free, EndCondition::Free);
            let w = (weight, 0.0);
            let full = attempt(&pts, &params, &knots, free, w, (&mut 0, &mut DataCache::default()));
            let judged = judge(&pts, &params, &knots, free, (w, target), (&mut 0, &mut DataCache::default()));
            prop_assert_eq!(full.is_some(), judged.is_some());
            if let (Some(f), Some(j)) = (full, judged) {
                prop_assert_eq!(f.max <= target, j.max <= target);
                if f.max <= target {
                    prop_assert_eq!(f.max.to_bits(), j.max.to_bits());
                    prop_assert_eq!(f.errs, j.errs);
                } else {
                    let j = with_bounds(j, &pts, &params);
                    prop_assert_eq!(f.max.to_bits(), j.max.to_bits());
                }
            }
        }
    }
}
