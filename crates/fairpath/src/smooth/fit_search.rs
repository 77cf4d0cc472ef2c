//! `bspline-fit`'s search for the control points of one section at given
//! smoothing weights (module docs of `bspline_fit.rs`, steps 3, 5 and 6):
//! knots by averaging, one linear least-squares attempt with its proven
//! span bounds, the control-point count by doubling and bisection, then
//! knots inserted where the bound fails.

use crate::geom::fit::{averaged_knots, span_errors, EndCondition, FitData, FitError, FitSystem};
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
    pub(super) errs: Vec<f64>,
    pub(super) max: f64,
}

pub(super) fn attempt(
    pts: &[Vec3],
    params: &[f64],
    knots: &[f64],
    ends: (EndCondition, EndCondition),
    weights: (f64, f64),
    (fits, cache): (&mut usize, &mut DataCache),
) -> Option<Attempt> {
    *fits += 1;
    let (Some(&first), Some(&last)) = (pts.first(), pts.last()) else {
        return None;
    };
    let system = cache
        .system(params, knots, ends, (first, last), weights)
        .ok()?;
    let curve = system.solve(pts).ok()?;
    let errs = span_errors(&curve, pts, params);
    let max = errs.iter().copied().fold(0.0, f64::max);
    max.is_finite().then_some(Attempt { curve, errs, max })
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
    let mut try_count = |h: usize, fits: &mut usize| {
        let knots = averaged_knots(params, h);
        attempt(pts, params, &knots, ends, weights, (fits, &mut *cache))
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
    // points than the passing count (or the most the data support).
    let limit = hi.as_ref().map_or(usize::MAX, |(u, _)| *u);
    let min_span = min_span(params);
    let mut refined: Option<Attempt> = None;
    if let Some((_, mut a)) = lo {
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
