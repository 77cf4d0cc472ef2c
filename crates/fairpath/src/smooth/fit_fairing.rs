//! `bspline-fit`'s fit of one section and its smoothing weights (module
//! docs of `bspline_fit.rs`, step 4): the weights from the input's
//! sampling, the ladder tried when no fit passes (`lambda`, `lambda / 16`,
//! 0), the raises by [`FAIRNESS_RAISE`] while the fit still passes (seed
//! 003's aim), and the relaxation towards the fairest curve in the band.
//! The search for the control points at given weights is `fit_search.rs`.

use super::fit_fill::fill_segments;
use super::fit_search::{attempt, min_span, refine_knots, search, DataCache};
use crate::geom::band_fit::{relax_in_band, RelaxOptions};
use crate::geom::fit::{chord_params, EndCondition};
use crate::geom::{Nurbs, Vec3};
use core::f64::consts::PI;

/// A fit of one section.
#[derive(Clone, Debug, PartialEq)]
pub struct SectionFit {
    /// The fitted clamped cubic B-spline, parameterised by chord length (mm).
    pub curve: Nurbs,
    /// Proven bound of its distance from the polyline (and of the data
    /// points' distance from it), mm.
    pub bound: f64,
    /// Fairness weight used (mm^3).
    pub lambda: f64,
    /// Number of least-squares fits solved in the search.
    pub fits: usize,
}

/// Fits a cubic B-spline to the polyline `pts` (at least 2 points, no
/// zero-length segment) that starts at `pts[0]` and ends at the last point
/// exactly with the given end conditions, and whose every point lies within
/// `target` mm of the polyline (and every vertex within `target` of it).
/// `fairness` scales the smoothing term (module docs, step 4). `None` when
/// no fit passes.
pub fn fit_polyline(
    pts: &[Vec3],
    start: EndCondition,
    end: EndCondition,
    target: f64,
    fairness: f64,
) -> Option<SectionFit> {
    fit_polyline_weighted(pts, start, end, target, fairness, 0.0)
}

/// [`fit_polyline`] with the jerk term of
/// [`BsplineFitOptions::jerk_fairness`] as well.
///
/// [`BsplineFitOptions::jerk_fairness`]: super::BsplineFitOptions::jerk_fairness
pub fn fit_polyline_weighted(
    pts: &[Vec3],
    start: EndCondition,
    end: EndCondition,
    target: f64,
    fairness: f64,
    jerk_fairness: f64,
) -> Option<SectionFit> {
    fit_polyline_faired(pts, start, end, target, (fairness, jerk_fairness), 0, None)
}

/// Factor by which [`fit_polyline_faired`] raises the smoothing weights
/// at each step.
pub const FAIRNESS_RAISE: f64 = 4.0;

/// Default [`BsplineFitOptions::fairness_raises`]: up to `4^6 = 4096`
/// times the default weights.
///
/// [`BsplineFitOptions::fairness_raises`]: super::BsplineFitOptions::fairness_raises
pub const FAIRNESS_RAISES: usize = 6;

/// Least-squares solves per raise: the knots of the fit before, then
/// knots inserted where the raised fit misses.
const RAISE_SOLVES: usize = 3;

/// [`fit_polyline_weighted`] (weights `(fairness, jerk_fairness)`), then,
/// up to `raises` times, the same fit with both weights multiplied by
/// [`FAIRNESS_RAISE`], as long as it still passes: the fairest fit within
/// `target` that this ladder finds. Each raise solves on the knots of the
/// fit before it and, where it misses, inserts knots (at most
/// `RAISE_SOLVES` linear solves; a full control-point search per raise
/// planned the same but cost several times the fit on a long row;
/// measurements: docs/tuning.md, `fit_polyline_faired`).
///
/// Seed 003 (Naseath 2007, chapter 3) lowers the curvature of a B-spline
/// tool path by moving its control points inside the tolerance tube,
/// iterating "until the spline touches the path tolerance". The weight of
/// a smoothing term plays that role here: raising it flattens the fit, and
/// the search (with its proven bound) keeps it within the band. The
/// seed's movement rules (categories, direction vectors, sensitivities)
/// are not used. On the issue-5 survey, 6 raises of 4 planned the dense
/// programs faster than fewer, larger raises or more, smaller ones
/// (measurements: docs/tuning.md, `fit_polyline_faired`).
pub fn fit_polyline_faired(
    pts: &[Vec3],
    start: EndCondition,
    end: EndCondition,
    target: f64,
    (fairness, jerk_fairness): (f64, f64),
    raises: usize,
    relax: Option<&RelaxOptions>,
) -> Option<SectionFit> {
    let n = pts.len().checked_sub(1)?;
    if n == 0 || target.is_nan() || target <= 0.0 {
        return None;
    }
    let mean = chord_params(pts)[n] / n as f64;
    if !(mean > 0.0 && mean.is_finite()) {
        return None;
    }
    // The smoothing weight follows the input's sampling, not the points
    // added on long segments.
    let lambda0 = fairness * mean * mean * mean / (PI * PI * PI * PI);
    let mu0 = jerk_fairness * mean * mean * mean * mean * mean / (PI * PI * PI * PI);
    let dense = fill_segments(pts, target);
    let pts = &dense[..];
    let params = chord_params(pts);
    let mut fits = 0;
    let mut cache = DataCache::default();
    let ladder: &[(f64, f64)] = if lambda0 > 0.0 || mu0 > 0.0 {
        &[(lambda0, mu0), (lambda0 / 16.0, mu0 / 16.0), (0.0, 0.0)]
    } else {
        &[(0.0, 0.0)]
    };
    for (step, &(lambda, mu)) in ladder.iter().enumerate() {
        let Some((mut curve, mut bound)) = search(
            pts,
            &params,
            start,
            end,
            target,
            (lambda, mu),
            (&mut fits, &mut cache),
        ) else {
            continue;
        };
        let mut lambda = lambda;
        // Raise the weights while the fit stays within the target (only
        // from the full weights: a section that needed less keeps it).
        if step == 0 {
            let mut mu = mu;
            for _ in 0..raises {
                let w = (lambda * FAIRNESS_RAISE, mu * FAIRNESS_RAISE);
                // The knots of the fit before, with knots inserted where
                // the raised fit misses (at most RAISE_SOLVES solves).
                let mut knots = curve.knots.clone();
                let mut passed = None;
                for _ in 0..RAISE_SOLVES {
                    let Some(a) = attempt(
                        pts,
                        &params,
                        &knots,
                        (start, end),
                        w,
                        (&mut fits, &mut cache),
                    ) else {
                        break;
                    };
                    if a.max <= target {
                        passed = Some((a.curve, a.max));
                        break;
                    }
                    let next = refine_knots(&a.curve.knots, &a.errs, target, min_span(&params));
                    if next.len() == knots.len() {
                        break;
                    }
                    knots = next;
                }
                let Some((c, b)) = passed else {
                    break;
                };
                (curve, bound, lambda, mu) = (c, b, w.0, w.1);
            }
        }
        // Relax towards the fairest curve the band allows, from the
        // default weights (the raised ones are what a least-squares fit
        // needed to flatten; the relaxation needs none of that).
        if let Some(opts) = relax {
            if let Ok(Some(r)) = relax_in_band(
                &curve,
                pts,
                &params,
                (start, end),
                target,
                (lambda0, mu0),
                opts,
            ) {
                (curve, bound) = (r.curve, r.bound);
            }
        }
        return Some(SectionFit {
            curve,
            bound,
            lambda,
            fits,
        });
    }
    None
}
