//! Interpolation at the controller period: the planned arc length `s(t)`
//! is turned into curve parameters by the second-order Taylor update used
//! by NURBS interpolators (seed 001; e.g. Yeh and Hsu 1999):
//!
//! `du = ds / |C'| - (C' . C'') ds^2 / (2 |C'|^4)`
//!
//! with `ds = s(t_k+1) - s(t_k)`, from where the previous step actually
//! arrived. The feed fluctuation `(|P_k+1 - P_k| / Ts - ds / Ts) / (ds / Ts)`
//! compares the achieved chord feed with the commanded one; it is the
//! interpolator's error (parameter drift and chord versus arc).

use super::plan::RunPlan;
use crate::geom::{ParamCurve, Vec3};
use crate::math;
use crate::path::Piece;
use alloc::vec::Vec;

/// Accuracy (mm) of the remaining length of a piece where a step passes
/// onto the next: the fluctuation compares steps of a period's travel
/// (micrometres and up), so a nanometre's error in where the next piece
/// starts is below what it measures.
const REST_LENGTH_ACCURACY: f64 = 1e-9;

/// Shortest commanded step (mm) whose fluctuation is counted: a step of
/// less than a micrometre (the machine at rest, or nearly) makes the
/// relative error of its chord the rounding of its coordinates.
const MIN_MEASURED_STEP: f64 = 1e-3;

/// One interpolation period.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Time from the start of the run, s.
    pub t: f64,
    /// Planned arc length, mm.
    pub s: f64,
    /// Planned speed (mm/s), tangential acceleration (mm/s^2) and jerk (mm/s^3).
    pub v: f64,
    pub a: f64,
    pub j: f64,
    /// Interpolated position.
    pub p: Vec3,
}

/// Samples of a planned run and the feed fluctuation of the interpolator.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Interpolation {
    pub samples: Vec<Sample>,
    /// Largest `|achieved - commanded| / commanded` over periods that moved
    /// at least a micrometre.
    pub max_fluctuation: f64,
    /// Mean of the same.
    pub mean_fluctuation: f64,
}

/// The feed fluctuation of an interpolation and how many samples it took.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Fluctuation {
    /// Largest `|achieved - commanded| / commanded` over periods that moved
    /// at least a micrometre.
    pub max: f64,
    /// Mean of the same.
    pub mean: f64,
    /// Samples taken.
    pub samples: usize,
}

/// Interpolates `plan` (made for `pieces`) every `period` s, starting at
/// time `t0` (for sample times that continue across runs).
pub fn interpolate(pieces: &[Piece], plan: &RunPlan, period: f64, t0: f64) -> Interpolation {
    let mut samples = Vec::new();
    let f = interpolate_each(pieces, plan, period, t0, |s| samples.push(s));
    Interpolation {
        samples,
        max_fluctuation: f.max,
        mean_fluctuation: f.mean,
    }
}

/// [`interpolate`], each sample given to `each` in order instead of kept
/// (the fluctuation of a long run without its samples held: a million
/// periods are 64 MB).
pub fn interpolate_each(
    pieces: &[Piece],
    plan: &RunPlan,
    period: f64,
    t0: f64,
    mut each: impl FnMut(Sample),
) -> Fluctuation {
    let mut out = Fluctuation::default();
    if plan.segments.is_empty() || period.is_nan() || period <= 0.0 {
        return out;
    }
    // Walker along the pieces: current piece and parameter.
    let first = plan.segments[0].parts[0].piece;
    let (mut pi, mut u) = (first, pieces[first].curve.domain().0);
    let mut p_prev = pieces[pi].curve.eval(u);
    let mut s_prev = 0.0;
    let (mut sum, mut count) = (0.0, 0usize);
    let mut seg_start_t = 0.0;
    let mut seg_start_s = 0.0;
    let mut k = 0usize;
    for seg in &plan.segments {
        let d = seg.profile.duration();
        loop {
            let t = k as f64 * period;
            if t > seg_start_t + d {
                break;
            }
            let st = seg.profile.eval(t - seg_start_t);
            let s = seg_start_s + st.q;
            // Advance the parameter by ds with the Taylor update, moving on
            // to the next piece when this one ends.
            let mut ds = s - s_prev;
            while ds > 0.0 {
                let c = &pieces[pi].curve;
                let (_, u1) = c.domain();
                let (d1, d2) = c.derivs12(u);
                let speed = d1.norm();
                if speed == 0.0 {
                    break;
                }
                let du = ds / speed - d1.dot(d2) * ds * ds / (2.0 * speed * speed * speed * speed);
                if u + du < u1 {
                    u += du.max(0.0);
                    ds = 0.0;
                } else {
                    // Remaining length on this piece, then the next piece.
                    let rest = crate::geom::arc_length_between(c, u, u1, REST_LENGTH_ACCURACY);
                    ds -= rest;
                    if pi + 1 < pieces.len() {
                        pi += 1;
                        u = pieces[pi].curve.domain().0;
                    } else {
                        u = u1;
                        ds = 0.0;
                    }
                }
            }
            let p = pieces[pi].curve.eval(u);
            let commanded = s - s_prev;
            if k > 0 && commanded > MIN_MEASURED_STEP {
                let achieved = p.dist(p_prev);
                let f = math::abs(achieved - commanded) / commanded;
                out.max = out.max.max(f);
                sum += f;
                count += 1;
            }
            each(Sample {
                t: t0 + t,
                s,
                v: st.v,
                a: st.a,
                j: st.j,
                p,
            });
            out.samples += 1;
            p_prev = p;
            s_prev = s;
            k += 1;
        }
        seg_start_t += d;
        seg_start_s += seg.profile.length();
    }
    if count > 0 {
        out.mean = sum / count as f64;
    }
    out
}
