//! What method `fair` measures a run by when it chooses between two
//! smoothings of it: total turning, peak curvature, and the demand of
//! the machine's speed caps on samples of the curves.

use super::fit_sections::SectionOptions;
use crate::geom::tube_fair::guard::{PEAK_ACCURACY, PEAK_SAMPLES};
use crate::geom::tube_fair::PeakPass;
use crate::geom::{sampled_peak, total_curvature, Curve, Extrema, Nurbs, ParamCurve, Vec3};
use crate::path::Piece;
use alloc::vec::Vec;

/// `sections` with every vertex up to its turn dense whatever its
/// segments' lengths and chord error ([`LineFit::ThroughShallowCorners`](super::LineFit::ThroughShallowCorners);
/// the bounds are finite, as the options require, and far beyond any tool
/// path: a segment of 1 km, a chord error of a million tolerances).
pub fn shallow_corner_sections(sections: &SectionOptions) -> SectionOptions {
    SectionOptions {
        max_segment: 1e6,
        chord_error_per_tol: 1e6,
        ..*sections
    }
}

/// Accuracy (rad) of [`run_turning`]'s integrals: far below the turning
/// a fairing changes (a 0.2 mm bump over 30 mm turns 0.03 rad).
pub const TURNING_ACCURACY: f64 = 1e-6;

/// Total turning (rad) of the curves among smoothed pieces, the integral
/// of the curvature over the arc length (to [`TURNING_ACCURACY`] each).
/// Joints are not counted: [`LineFit::Fairer`](super::LineFit::Fairer) compares two fits of one
/// run, whose corners between pieces are the same.
pub fn run_turning(pieces: &[Piece]) -> f64 {
    pieces
        .iter()
        .filter(|p| !matches!(p.curve, Curve::Line(_)))
        .map(|p| total_curvature(&p.curve, TURNING_ACCURACY))
        .sum()
}

/// Peak curvature (1/mm) of smoothed pieces: each NURBS at
/// [`PEAK_SAMPLES`] steps per knot span, ends included (its cubic Bezier
/// spans; other NURBS at as many steps over their domain), refined
/// between the samples to [`PEAK_ACCURACY`] of its span where they show a
/// peak narrower than their step ([`sampled_peak`], [`Extrema::Narrow`]:
/// a near-cusp between samples counts at its height);
/// arcs their own, lines none. A lower bound, exact to that accuracy at
/// every peak the samples bracket.
pub fn run_peak_curvature(pieces: &[Piece]) -> f64 {
    pieces
        .iter()
        .map(|p| match &p.curve {
            Curve::Line(_) => 0.0,
            Curve::Arc(a) => a.curvature(a.domain().0),
            Curve::Nurbs(c) => knot_spans(c)
                .into_iter()
                .map(|(a, b)| {
                    let derivs = |t: f64| c.derivs12(t);
                    let accuracy = PEAK_ACCURACY * (b - a);
                    sampled_peak(derivs, (a, b), PEAK_SAMPLES, accuracy, Extrema::Narrow)
                })
                .fold(0.0, f64::max),
        })
        .fold(0.0, f64::max)
}

/// The non-empty knot spans of a NURBS's domain.
fn knot_spans(c: &Nurbs) -> Vec<(f64, f64)> {
    let (t0, t1) = c.domain();
    let mut knots: Vec<f64> = c.knots.clone();
    knots.dedup();
    knots
        .windows(2)
        .filter(|w| w[0] >= t0 && w[1] <= t1 && w[1] > w[0])
        .map(|w| (w[0], w[1]))
        .collect()
}

/// The parameters [`sampled_demand`] samples a NURBS at: [`PEAK_SAMPLES`]
/// steps over each non-empty knot span of its domain, both ends of each
/// span included.
fn span_samples(c: &Nurbs) -> impl Iterator<Item = f64> {
    knot_spans(c).into_iter().flat_map(|(a, b)| {
        (0..=PEAK_SAMPLES).map(move |j| a + (b - a) * j as f64 / PEAK_SAMPLES as f64)
    })
}

/// Highest demand of `pass` ([`PeakPass::demand`]: for its speed caps,
/// the inverse of the lowest of `sqrt(A / k)`, `cbrt(J / k^2)`,
/// `cbrt(J / |dk/ds|)` and the feed) over the curves among `pieces`, each
/// NURBS sampled at [`PEAK_SAMPLES`] steps per knot span, `dk/ds` from the
/// differences of neighbouring samples' curvature vectors, across joints
/// too (a rational curve has no cubic spans to take it from in closed
/// form); a step `dk` of the curvature vector at a joint demands what the
/// planner's `feed::junction::step_cap` caps it at, `sqrt(J Ts / dk)`
/// ([`PeakPass::jump_demand`]) and, spread over the step after it, a
/// `dk/ds`; arcs and lines at their ends, with their curvature. A sample,
/// not a bound: it
/// compares a run's curves kept as written with the same curves sampled,
/// fitted and faired, like with like ([`OtherCurves::Sampled`](super::OtherCurves::Sampled)).
pub fn sampled_demand(pieces: &[Piece], pass: PeakPass) -> f64 {
    sampled_demands(pieces, pass).0
}

/// [`sampled_demand`], and the integral of the demand over the length
/// sampled: about the time the pieces would take at their caps' speeds
/// (each step at the lower cap of its two ends, a step of the curvature
/// vector at a joint charged over the step after it).
pub fn sampled_demands(pieces: &[Piece], pass: PeakPass) -> (f64, f64) {
    let (mut k_max, mut jerk_max, mut jump_max, mut time) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    // The sample before, across joints too: a step of the curvature
    // vector where two pieces meet (the arcs LinuxCNC runs a G5.2 block
    // as meet G1, as do the spans of a G5.2 quadratic) caps the speed
    // there (`PeakPass::jump_demand`) and shows as a steep `dk/ds` over
    // the next step. A sample at the point of the one before (a joint)
    // does not replace it, so the step is charged over the next one.
    // Vectors, not magnitudes: arcs that turn opposite ways have equal
    // curvatures and the largest step between them.
    let mut prev: Option<(Vec3, Vec3)> = None;
    let mut jump = 0.0f64;
    let mut sample = |q: Vec3, kv: Vec3| {
        let k = kv.norm();
        k_max = k_max.max(k);
        let mut jerk_term = k * k;
        match prev {
            Some((q0, kv0)) => {
                let ds = q.dist(q0);
                if ds > 0.0 {
                    jerk_term = jerk_term.max((kv - kv0).norm() / ds);
                    let step = pass.demand(k.max(kv0.norm()), jerk_term).max(jump);
                    time += ds * step;
                    jump = 0.0;
                    prev = Some((q, kv));
                } else {
                    jump = jump.max(pass.jump_demand((kv - kv0).norm()));
                    jump_max = jump_max.max(jump);
                }
            }
            None => prev = Some((q, kv)),
        }
        jerk_max = jerk_max.max(jerk_term);
    };
    for p in pieces {
        match &p.curve {
            Curve::Line(l) => {
                sample(l.p0, Vec3::ZERO);
                sample(l.p1, Vec3::ZERO);
            }
            Curve::Arc(a) => {
                let (t0, t1) = a.domain();
                sample(a.p0, a.curvature_vector(t0));
                sample(a.p1, a.curvature_vector(t1));
            }
            Curve::Nurbs(c) => {
                for t in span_samples(c) {
                    sample(c.eval(t), c.curvature_vector(t));
                }
            }
        }
    }
    (pass.demand(k_max, jerk_max).max(jump_max), time)
}
