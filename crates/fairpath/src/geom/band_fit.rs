//! Relaxing a fitted cubic B-spline inside its tolerance band: the fairest
//! curve (least bending and jerk energy) whose point at each data
//! parameter stays within a radius of its data point.
//!
//! A least-squares fit is pulled towards every data point, so even with a
//! strong smoothing term it runs along the middle of the band and bends
//! where the data bends. Seed 003 (Naseath 2007, chapter 3) instead moves
//! the control points inside the tolerance tube until the spline "touches
//! the path tolerance", so that a corner is taken the way "a racecar driver
//! would take" it: wide before and after, touching the inside at the apex.
//! Its movement rules (categories, direction vectors, sensitivities) are
//! heuristics; here the same aim is posed as a convex problem and solved:
//!
//! `minimise lambda * integral |C''|^2 + mu * integral |C'''|^2`
//! `subject to |C(t_i) - Q_i| <= r` for every data point `i`,
//!
//! with the end points and end conditions of the fit. Nothing pulls a
//! point that is inside its ball, so the curve flattens until the balls
//! stop it. Balls (rather than the band around the polyline) are the
//! constraint because [`super::fit::span_errors`], the proof every fit
//! passes, asks each data point to lie within the target of the fit too.
//! Between data points the curve is held only by its smoothness, so the
//! data are first made denser (points on the polyline, at most
//! [`RelaxOptions::spacing_per_target`] apart, and one in every knot span)
//! and the radius is a little below the target
//! ([`RelaxOptions::radius_share`]).
//!
//! **Solver**: ADMM (Boyd, Parikh, Chu, Peleato, Eckstein, "Distributed
//! optimization and statistical learning via the alternating direction
//! method of multipliers", 2011, section 5.1, scaled form) with the
//! splitting `z_i = C(t_i)`: the curve step is the banded least-squares fit
//! to the targets `z_i - u_i` ([`super::fit::FitSystem`], factored once per weight, so
//! each step is one back-substitution), the `z` step projects `C(t_i) + u_i`
//! onto the ball of `Q_i`, and `u` accumulates the residuals. ADMM converges
//! for any ratio of the data weight to the energy weights, but slowly when
//! the energy is much stiffer than the data (a sharp corner then stays
//! outside its ball for hundreds of steps); when the largest violation has
//! not shrunk by a fifth in three steps, the energy weights are divided by
//! 4 (the penalty `rho` multiplied by 4, and the scaled duals `u` divided
//! by 4, Boyd et al. section 3.4.1). Every few steps, and when both
//! residuals are below [`RelaxOptions::converged_share`] of the target
//! (then the steps stop), the curve is a candidate; the last candidate
//! that [`span_errors`] proves within the target is kept. Candidates are
//! bounded lazily, from the last backwards (the last usually passes), a
//! few at a time: on the 138,803-segment surface raster that made
//! `bspline-fit`'s smoothing faster, the same curves (measurements:
//! docs/tuning.md, `last_passing`).

use super::fit::{span_errors, with_spans_at_most, EndCondition, FitData, FitError};
use super::{Nurbs, Vec3};
use alloc::vec::Vec;

/// Settings of [`relax_in_band`]. Chosen on the issue-5 survey
/// (`scripts/survey.sh` at 0.05 mm; the measurements are in
/// docs/tuning.md under each field's name). The radius, the
/// steps and the span were chosen first, with the fit's own weights and
/// 100 steps always; the early stop and the weight factor after them, and
/// the early stop's threshold again with the weight factor.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct RelaxOptions {
    /// Radius of the balls around the data, as a share of the target:
    /// the rest is room for the curve between data points. A larger share
    /// lets the fit use more of the band, which planned the survey
    /// programs faster (measurements: docs/tuning.md,
    /// `RelaxOptions::radius_share`).
    pub radius_share: f64,
    /// ADMM steps. More planned no faster and took longer (measurements:
    /// docs/tuning.md, `RelaxOptions::iterations`).
    pub iterations: usize,
    /// Steps between the curves that are candidates for the result (each
    /// bounded by [`span_errors`] unless a later one passes).
    pub check_every: usize,
    /// Longest knot span, in targets: the fit's knots are refined (by
    /// knot insertion, same curve) so that the relaxed curve can bend where
    /// the fit did not need to. Shorter spans planned faster (measurements:
    /// docs/tuning.md, `RelaxOptions::max_span_per_target`).
    pub max_span_per_target: f64,
    /// Longest distance between the constrained points, in targets.
    pub spacing_per_target: f64,
    /// The steps stop early when no point of the curve or of its
    /// projection moved by more than this share of the target in a step
    /// (both ADMM residuals below it, Boyd et al. section 3.3.1). The early
    /// stop smooths the surface raster in a fraction of the time that every
    /// step takes, planning the same. With [`RelaxOptions::weight_factor`]
    /// a larger share stops sooner; 3e-3 planned the issue-5 survey as a
    /// smaller one did, while a larger one planned the surface raster
    /// slower (measurements: docs/tuning.md,
    /// `RelaxOptions::converged_share`).
    pub converged_share: f64,
    /// Factor on the energy weights passed to [`relax_in_band`] at the
    /// first step. The optimum does not depend on a common factor of the
    /// weights, but the steps do: with the fit's own weights (1) a step
    /// moved the curve so little that the early stop took it for converged
    /// after one step on the surface raster; stiffer weights move it
    /// further per step and are lowered by the stall rule where the balls
    /// need it. On the issue-5 survey stiffer weights planned the dense
    /// programs faster, in about the same smoothing time (measurements:
    /// docs/tuning.md, `RelaxOptions::weight_factor`).
    pub weight_factor: f64,
}

impl Default for RelaxOptions {
    fn default() -> Self {
        RelaxOptions {
            radius_share: 0.95,
            iterations: 100,
            check_every: 5,
            max_span_per_target: 4.0,
            spacing_per_target: 2.0,
            converged_share: 3e-3,
            weight_factor: 1000.0,
        }
    }
}

impl RelaxOptions {
    /// Whether the options are usable: the radius share in `(0, 1]`, the
    /// lengths positive and finite, at least one step.
    /// Checks the ranges of the options: the failing option and what it
    /// must be.
    pub fn check(&self) -> Result<(), (&'static str, &'static str)> {
        let positive = |x: f64| x > 0.0 && x.is_finite();
        if !(positive(self.radius_share) && self.radius_share <= 1.0) {
            return Err(("relax.radius_share", "must be in (0, 1]"));
        }
        if !(self.converged_share >= 0.0 && self.converged_share < 1.0) {
            return Err(("relax.converged_share", "must be in [0, 1)"));
        }
        if !positive(self.weight_factor) {
            return Err(("relax.weight_factor", "must be positive and finite"));
        }
        if !positive(self.max_span_per_target) {
            return Err(("relax.max_span_per_target", "must be positive"));
        }
        if !positive(self.spacing_per_target) {
            return Err(("relax.spacing_per_target", "must be positive"));
        }
        if self.iterations == 0 {
            return Err(("relax.iterations", "must be positive"));
        }
        if self.check_every == 0 {
            return Err(("relax.check_every", "must be positive"));
        }
        Ok(())
    }
}

/// Share by which the largest violation must shrink in
/// [`STALL_STEPS`] steps before the energy weights are lowered.
const STALL_SHRINK: f64 = 0.8;
/// Steps over which progress is judged.
const STALL_STEPS: usize = 3;
/// Factor by which the energy weights are lowered on a stall.
const STALL_FACTOR: f64 = 0.25;
/// Violations below this share of the radius do not count as a stall.
const STALL_MIN_SHARE: f64 = 0.05;

/// What [`relax_in_band`] returns: the relaxed curve and its proven bound.
#[derive(Clone, Debug, PartialEq)]
pub struct Relaxed {
    pub curve: Nurbs,
    /// Bound of [`span_errors`] against the (densified) polyline, mm.
    pub bound: f64,
}

/// Relaxes `fit`, a fit of the polyline `pts` at chord-length parameters
/// `params` with end conditions `ends`, towards the fairest curve whose
/// point at every data parameter lies within `radius_share * target` mm
/// of its data point (module documentation), with the energy weights
/// `(lambda, mu)` (times [`RelaxOptions::weight_factor`] at the start)
/// against unit data weights. Returns the last checked
/// curve whose [`span_errors`] bound is within `target` mm, or `None` when
/// none passed (or the weights are both zero: nothing to relax towards).
pub fn relax_in_band(
    fit: &Nurbs,
    pts: &[Vec3],
    params: &[f64],
    ends: (EndCondition, EndCondition),
    target: f64,
    (lambda, mu): (f64, f64),
    opts: &RelaxOptions,
) -> Result<Option<Relaxed>, FitError> {
    let n = pts.len();
    if n < 2 || params.len() != n || target.is_nan() || target <= 0.0 {
        return Err(FitError::BadInput);
    }
    opts.check().map_err(|_| FitError::BadInput)?;
    if !(lambda > 0.0 || mu > 0.0) {
        return Ok(None);
    }
    let radius = opts.radius_share * target;
    // At small tolerances the spans and the spacing are held to a budget of
    // MAX_GROWTH per data point on average.
    let floor = (params[n - 1] - params[0]) / (MAX_GROWTH * n as f64);
    let fit = with_spans_at_most(fit, (opts.max_span_per_target * target).max(floor));
    let spacing = (opts.spacing_per_target * target).max(floor);
    let (pts, params) = densify(pts, params, spacing, &fit.knots);
    let n = pts.len();
    let (first, last) = (pts[0], pts[n - 1]);
    let mut weights = (lambda * opts.weight_factor, mu * opts.weight_factor);
    // The data term is the same at every weight: built once, the weights
    // added to it at the start and after every stall.
    let data = FitData::new(&params, &fit.knots, ends, (first, last))?;
    let mut system = data.system(weights)?;
    // z starts on the fit, u at zero.
    let mut z = system.points_at_data(&fit);
    let mut u = alloc::vec![Vec3::ZERO; n];
    let mut targets = pts.clone();
    let mut history: Vec<f64> = Vec::new();
    // The curves of the checked steps not bounded yet. Only the last one
    // that passes is kept, so they are bounded from the last backwards,
    // stopping at the first that passes (usually the last: one bound
    // instead of one per `check_every` steps), when PENDING_CHECKS of them
    // wait and at the end.
    let mut snapshots: Vec<Nurbs> = Vec::new();
    let mut best = None;
    // Buffers of every step: the right-hand side, the control points and
    // the curve's points at the data.
    let (mut rhs, mut ctrl, mut at) = (Vec::new(), Vec::new(), Vec::new());
    for step in 1..=opts.iterations {
        for i in 1..n - 1 {
            targets[i] = z[i] - u[i];
        }
        system.solve_into(&targets, &mut rhs, &mut ctrl)?;
        system.points_at_data_into(&ctrl, &mut at);
        let mut worst: f64 = 0.0;
        // Largest primal (C - z) and dual (change of z) residuals.
        let mut moved: f64 = 0.0;
        for i in 1..n - 1 {
            let w = at[i] + u[i];
            let d = w - pts[i];
            let len = d.norm();
            let zi = if len > radius {
                pts[i] + d * (radius / len)
            } else {
                w
            };
            moved = moved.max(zi.dist(z[i])).max(zi.dist(at[i]));
            z[i] = zi;
            u[i] = w - zi;
            worst = worst.max(at[i].dist(pts[i]) - radius);
        }
        let converged = moved <= opts.converged_share * target;
        if step % opts.check_every == 0 || step == opts.iterations || converged {
            snapshots.push(system.curve(ctrl.clone()));
            if snapshots.len() >= PENDING_CHECKS {
                best = last_passing(&mut snapshots, &pts, &params, target).or(best);
            }
        }
        if converged {
            break;
        }
        history.push(worst);
        if history.len() > STALL_STEPS {
            let before = history[history.len() - 1 - STALL_STEPS];
            if worst > STALL_MIN_SHARE * radius && worst > STALL_SHRINK * before {
                weights = (weights.0 * STALL_FACTOR, weights.1 * STALL_FACTOR);
                for x in u.iter_mut() {
                    *x = *x * STALL_FACTOR;
                }
                system = data.system(weights)?;
                history.clear();
            }
        }
    }
    Ok(last_passing(&mut snapshots, &pts, &params, target).or(best))
}

/// Most curves of checked steps [`relax_in_band`] holds before bounding
/// them (memory against bounds computed).
const PENDING_CHECKS: usize = 8;

/// The last of `curves` whose [`span_errors`] bound against `pts` at
/// `params` is within `target`, bounding them from the last backwards;
/// `curves` is left empty.
fn last_passing(
    curves: &mut Vec<Nurbs>,
    pts: &[Vec3],
    params: &[f64],
    target: f64,
) -> Option<Relaxed> {
    while let Some(c) = curves.pop() {
        let bound = span_errors(&c, pts, params).into_iter().fold(0.0, f64::max);
        if bound <= target {
            curves.clear();
            return Some(Relaxed { curve: c, bound });
        }
    }
    None
}

/// Most knot spans and constrained points per data point, on average, that
/// the refinement of [`RelaxOptions::max_span_per_target`] and
/// [`RelaxOptions::spacing_per_target`] may make: at 0.05 mm it never
/// binds on the issue-5 survey; at 1 um it keeps a 100 mm fit from
/// growing to 25,000 spans and 50,000 points.
const MAX_GROWTH: f64 = 8.0;

/// Most pieces [`densify`] cuts one segment into (a long lead-in at a
/// small tolerance would otherwise take millions of points).
const MAX_SPLIT: f64 = 256.0;

/// `pts` and `params` with points added on the segments so that none is
/// longer than `spacing` (or cut into [`MAX_SPLIT`] pieces), and one in
/// the middle of every non-empty knot span of `knots` (so that every span
/// holds data: the Schoenberg-Whitney condition, without which the curve
/// step is singular where the energy weights are small), chord-length
/// parameters interpolated.
fn densify(pts: &[Vec3], params: &[f64], spacing: f64, knots: &[f64]) -> (Vec<Vec3>, Vec<f64>) {
    let mids: Vec<f64> = knots
        .windows(2)
        .filter(|w| w[1] > w[0])
        .map(|w| 0.5 * (w[0] + w[1]))
        .collect();
    let mut m = 0;
    let mut p = Vec::with_capacity(2 * pts.len());
    let mut t = Vec::with_capacity(2 * pts.len());
    let mut here: Vec<f64> = Vec::new();
    for i in 0..pts.len() - 1 {
        p.push(pts[i]);
        t.push(params[i]);
        let (a, b) = (params[i], params[i + 1]);
        let k = crate::math::ceil(pts[i].dist(pts[i + 1]) / spacing).min(MAX_SPLIT) as usize;
        here.clear();
        here.extend((1..k).map(|j| a + (b - a) * j as f64 / k as f64));
        while m < mids.len() && mids[m] < b {
            if mids[m] > a {
                here.push(mids[m]);
            }
            m += 1;
        }
        here.sort_by(f64::total_cmp);
        for &x in &here {
            p.push(pts[i].lerp(pts[i + 1], (x - a) / (b - a)));
            t.push(x);
        }
    }
    p.push(pts[pts.len() - 1]);
    t.push(params[params.len() - 1]);
    (p, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cubic along the x axis from 0 to 4 mm, lifted by `dz` mm in the
    /// middle (its two inner control points).
    fn curve(dz: f64) -> Nurbs {
        let p = |x: f64, z: f64| Vec3::new(x, 0.0, z);
        Nurbs::new(
            3,
            alloc::vec![0.0, 0.0, 0.0, 0.0, 4.0, 4.0, 4.0, 4.0],
            alloc::vec![p(0.0, 0.0), p(4.0 / 3.0, dz), p(8.0 / 3.0, dz), p(4.0, 0.0)],
            None,
        )
        .unwrap()
    }

    #[test]
    fn the_last_curve_within_the_target_is_kept_and_the_rest_dropped() {
        let pts = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(4.0, 0.0, 0.0)];
        let params = [0.0, 4.0];
        // The lifted cubics deviate 0.75 dz from the line.
        let (near, far, nearer) = (curve(0.01), curve(1.0), curve(0.001));
        let target = 0.1;
        let mut cs = alloc::vec![near.clone(), far.clone()];
        let r = last_passing(&mut cs, &pts, &params, target).unwrap();
        assert_eq!(r.curve, near);
        assert!(r.bound <= target);
        assert!(cs.is_empty());
        let mut cs = alloc::vec![near, nearer.clone(), far.clone()];
        assert_eq!(
            last_passing(&mut cs, &pts, &params, target).unwrap().curve,
            nearer
        );
        let mut cs = alloc::vec![far.clone(), far];
        assert!(last_passing(&mut cs, &pts, &params, target).is_none());
        assert!(cs.is_empty());
    }
}
