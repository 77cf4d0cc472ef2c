//! Method `lotm`: the locally optimal transition method of seed 001 ("A
//! locally optimal transition method ...", Proc. IMechE Part B,
//! DOI 10.1177/0954405417697351), on the Bezier corner transitions of
//! `bezier_corner.rs` (notation there: half corner angle `theta`,
//! transition length `l`, proportional coefficient `c`).
//!
//! **Step 1, the coefficient** (seed section "Cubic Bezier curve with
//! minimum CVE"). The curvature variation energy
//! `CVE = int (d kappa / ds)^2 ds` (seed eq. 6) of a transition of length `l`
//! is `(1 + c)^3 / l^3` times a function of `c` and `theta` alone
//! ([`curvature_variation_energy`]: derived from the curvature of
//! `bezier_corner.rs`, integrated by graded Gauss-Legendre quadrature), so
//! the best `c` for a given transition length depends on the angle only.
//! The seed fits it with MATLAB's `lsqcurvefit`, but the fitted formula
//! (eq. 9) was lost in extraction; here the optimum is found by
//! golden-section search ([`optimal_coefficient`]) and fitted by least
//! squares with a quintic in `x = 2 theta / pi` (the corner angle over pi)
//! over corner angles 15 to 179.5 degrees ([`lotm_coefficient_fit`],
//! [`LOTM_COEFFICIENT_FIT`]). The fit is within 2e-4 of the direct optimum
//! (the tests check it at many angles); the optimum grows from 0 at a
//! reversal through 0.075 at 45 degrees and 0.214 at 90 degrees to 0.387 at
//! a straight line.
//!
//! **Step 2, the lengths** (seed section "Locally optimal transition
//! method", eqs. 10-17, Theorem 1). The peak curvature of a transition is
//! `K / l` with `K = 4 (1 + c) cos(theta) / (3 sin^2(theta))`; for the two
//! transitions that share a segment of length `L` the seed minimises
//! `K1 / l1 + K2 / l2` subject to the error bounds `l_i <= lmax_i =
//! 4 (1 + c_i) delta / sin(2 theta_i)` and `l1 + l2 <= L`
//! ([`split_shared_segment`]):
//!
//! * long segment, `lmax1 + lmax2 <= L`: both at their error bounds;
//! * short segment: the objective falls as either length grows, so the
//!   optimum has `l1 + l2 = L`; `f(l1) = K1 / l1 + K2 / (L - l1)` is convex
//!   and `f' = 0` is the quadratic `(K1 - K2) l1^2 - 2 K1 L l1 + K1 L^2 = 0`
//!   (the seed's eq. 16), whose only root in `(0, L)` (Theorem 1) is
//!   `l1 = L sqrt(K1) / (sqrt(K1) + sqrt(K2))` (the other,
//!   `L sqrt(K1) / (sqrt(K1) - sqrt(K2))`, lies outside `[0, L]`); clamped to
//!   `[L - lmax2, lmax1]` it is the constrained optimum.
//!
//! Each corner takes the smaller of the two lengths its two segments give
//! it, so no pair of neighbours ever overlaps.
//!
//! Gaps in the seed, and what is done here (besides those listed in
//! `bezier_corner.rs`):
//!
//! * *Fixed length or fixed `d`?* The CVE is minimised at fixed transition
//!   length `l` (the seed: "c, in addition to the transition length l, has
//!   an effect on the geometry"): the length is what step 2 allocates.
//! * *Sharp corners.* Towards a reversal the optimal `c` tends to 0, which
//!   would make `P0 P1` vanish; `c` is kept at least
//!   [`LOTM_MIN_COEFFICIENT`] (corner angles below about 20 degrees), which
//!   costs at most 6% of CVE there.
//! * *The seed's Table 1 and algorithm `LoOpTran`* lost their conditions in
//!   extraction; they are rebuilt above: one segment at a time, each corner
//!   the smaller of its two values; a segment with a transition at one end
//!   only is that transition's whole (error-bounded) room.

use super::bezier_corner::{
    bezier_corner_peak_curvature, bezier_length_for_deviation, check_min_half_angle,
    smooth_run_by_corners, Planned,
};
use super::corner_engine::ChainCorners;
use super::corner_engine::Reach;
use super::{SmoothError, SmoothedRun, Smoother};
use crate::geom::golden_max;
use crate::math;
use crate::path::Run;
use crate::smooth::OptionError;
use alloc::vec;
use alloc::vec::Vec;
use core::f64::consts::PI;

/// Smallest coefficient `lotm` uses (corners sharper than about 20
/// degrees, where the optimum tends to 0; module docs).
pub const LOTM_MIN_COEFFICIENT: f64 = 0.02;

/// Coefficients `a0..a5` of the fitted optimum
/// `c(x) = a0 + a1 x + ... + a5 x^5`, `x = 2 theta / pi`: least squares over
/// the direct optimum at corner angles 15, 15.5, ..., 179.5 degrees.
pub const LOTM_COEFFICIENT_FIT: [f64; 6] = [
    -0.0026884, 0.1196243, 0.8287409, -0.0412886, -0.9433597, 0.4259161,
];

/// The fitted CVE-optimal coefficient at half-angle `theta` (no floor).
pub fn lotm_coefficient_fit(theta: f64) -> f64 {
    let x = 2.0 * theta / PI;
    LOTM_COEFFICIENT_FIT
        .iter()
        .rev()
        .fold(0.0, |acc, &a| acc * x + a)
}

/// The coefficient `lotm` uses at half-angle `theta`: the fit, at least
/// [`LOTM_MIN_COEFFICIENT`].
pub fn lotm_coefficient(theta: f64) -> f64 {
    lotm_coefficient_fit(theta).clamp(LOTM_MIN_COEFFICIENT, 1.0)
}

// 10-point Gauss-Legendre nodes and weights on [-1, 1].
const GL10_X: [f64; 5] = [
    0.148_874_338_981_631_2,
    0.433_395_394_129_247_2,
    0.679_409_568_299_024_4,
    0.865_063_366_688_984_5,
    0.973_906_528_517_171_7,
];
const GL10_W: [f64; 5] = [
    0.295_524_224_714_752_9,
    0.269_266_719_309_996_4,
    0.219_086_362_515_982,
    0.149_451_349_150_580_6,
    0.066_671_344_308_688_1,
];

/// The quadrature mesh is graded geometrically, by this ratio, towards
/// both ends of a Bezier half: near `t = 0` the curvature rises within
/// `t ~ c`, near the joint the speed drops to `~ sin(theta)`.
const CVE_GRADING_RATIO: f64 = 1.3;
/// First mesh step at each end, as a share of that scale.
const CVE_FIRST_STEP: f64 = 1.0 / 64.0;

/// Integrand `(d kappa / dt)^2 / (ds / dt)` of the left Bezier half with
/// `d = 1` (module docs of `bezier_corner.rs` for `u`, `v`, `N`).
fn cve_integrand(t: f64, c: f64, cos_a: f64, sin_a: f64) -> f64 {
    let s = 1.0 - t;
    let u = -c * s * s - t * s - 0.25 * t * t;
    let v = 0.25 * t * t;
    let du = 2.0 * c * s - (1.0 - 2.0 * t) - 0.5 * t;
    let dv = 0.5 * t;
    let sp = u * u + v * v + 2.0 * u * v * cos_a;
    let dsp = 2.0 * (u * du + v * dv + cos_a * (du * v + u * dv));
    let nn = t * (c * s + 0.5 * t);
    let dn = c - 2.0 * c * t + t;
    let g = dn * sp - 1.5 * nn * dsp;
    let sp2 = sp * sp;
    sin_a * sin_a * g * g / (108.0 * sp2 * sp2 * sp * math::sqrt(sp))
}

/// Curvature variation energy `int (d kappa / ds)^2 ds` (1/mm^3) of the
/// whole transition of length `l`, coefficient `c`, half-angle `theta`
/// (seed eq. 6): `(1 + c)^3 / l^3` times twice the integral over the left
/// Bezier half at `d = 1`, by 10-point Gauss-Legendre on a mesh graded
/// towards both ends (converged to a relative 1e-12 for `c >= 1e-5`).
pub fn curvature_variation_energy(l: f64, c: f64, theta: f64) -> f64 {
    let alpha = 2.0 * theta;
    let (cos_a, sin_a) = (math::cos(alpha), math::sin(alpha));
    let mut mesh: Vec<f64> = vec![0.0];
    let mut h = c.min(0.5) * CVE_FIRST_STEP;
    while h < 0.5 {
        mesh.push(h);
        h *= CVE_GRADING_RATIO;
    }
    mesh.push(0.5);
    let mut tail = Vec::new();
    let mut h = math::sin(theta).min(0.5) * CVE_FIRST_STEP;
    while h < 0.5 {
        tail.push(1.0 - h);
        h *= CVE_GRADING_RATIO;
    }
    mesh.extend(tail.iter().rev());
    mesh.push(1.0);
    let mut sum = 0.0;
    for w in mesh.windows(2) {
        let (m, r) = (0.5 * (w[0] + w[1]), 0.5 * (w[1] - w[0]));
        for (x, wt) in GL10_X.iter().zip(GL10_W.iter()) {
            sum += r
                * wt
                * (cve_integrand(m - r * x, c, cos_a, sin_a)
                    + cve_integrand(m + r * x, c, cos_a, sin_a));
        }
    }
    let k = (1.0 + c) / l;
    2.0 * sum * k * k * k
}

/// Range searched by [`optimal_coefficient`] (the optimum lies in
/// `(0, 0.39)` at every angle).
const OPTIMUM_SEARCH: (f64, f64) = (1e-5, 1.0);
/// Width of the final bracket of the golden-section search.
const OPTIMUM_BRACKET: f64 = 1e-9;

/// The coefficient that minimises the CVE of a transition of fixed length
/// at half-angle `theta`, by golden-section search (the direct optimisation
/// that [`lotm_coefficient_fit`] approximates).
pub fn optimal_coefficient(theta: f64) -> f64 {
    let f = |c: f64| -curvature_variation_energy(1.0, c, theta);
    let (a, b) = OPTIMUM_SEARCH;
    golden_max(f, a, b, OPTIMUM_BRACKET).1
}

/// Seed eqs. 14-17 and Theorem 1: the lengths `(l1, l2)` of the two
/// transitions sharing a segment of length `len` that minimise
/// `k1 / l1 + k2 / l2` (the sum of their peak curvatures, `k_i` the peak
/// curvature at unit length) with `l_i <= lmax_i` (error bounds) and
/// `l1 + l2 <= len` (module docs).
pub fn split_shared_segment(len: f64, k1: f64, lmax1: f64, k2: f64, lmax2: f64) -> (f64, f64) {
    if lmax1 + lmax2 <= len {
        return (lmax1, lmax2);
    }
    let (r1, r2) = (math::sqrt(k1), math::sqrt(k2));
    let l1 = (len * r1 / (r1 + r2))
        .clamp(len - lmax2, lmax1)
        .clamp(0.0, len);
    (l1, len - l1)
}

/// LOTM lengths for one chain (module docs).
pub(crate) fn lotm_plan(cc: &ChainCorners) -> Vec<Planned> {
    let n = cc.seg_len.len();
    let mut plan = vec![Planned::default(); n + 1];
    let mut k_unit = vec![0.0; n + 1];
    let mut lmax = vec![0.0; n + 1];
    for k in 0..=n {
        if cc.blend[k] {
            let c = lotm_coefficient(cc.theta[k]);
            plan[k] = Planned {
                c,
                l: f64::INFINITY,
            };
            k_unit[k] = bezier_corner_peak_curvature(1.0, c, cc.theta[k]);
            lmax[k] = bezier_length_for_deviation(cc.delta[k], c, cc.theta[k]);
        }
    }
    for j in 0..n {
        let len = cc.seg_len[j];
        if cc.shared(j) {
            let (l1, l2) =
                split_shared_segment(len, k_unit[j], lmax[j], k_unit[j + 1], lmax[j + 1]);
            plan[j].l = plan[j].l.min(l1);
            plan[j + 1].l = plan[j + 1].l.min(l2);
        } else {
            if cc.blend[j] {
                plan[j].l = plan[j].l.min(len.min(lmax[j]));
            }
            if cc.blend[j + 1] {
                plan[j + 1].l = plan[j + 1].l.min(len.min(lmax[j + 1]));
            }
        }
    }
    plan
}

/// Options of [`Lotm`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct LotmOptions {
    /// Corners whose half-angle `theta` (radians) is below this are
    /// reversals and kept.
    pub min_half_angle: f64,
    /// What to do at the joints next to arcs that are not G2: keep them
    /// (the seed's method, the default) or blend them G2
    /// ([`super::ArcJoints`]).
    pub arc_joints: super::ArcJoints,
}

impl LotmOptions {
    /// Checks the ranges of the options.
    pub fn validate(&self) -> Result<(), OptionError> {
        check_min_half_angle("lotm", self.min_half_angle)
    }
}

impl Default for LotmOptions {
    fn default() -> Self {
        LotmOptions {
            min_half_angle: 1e-6,
            arc_joints: super::ArcJoints::Kept,
        }
    }
}

/// The `lotm` method (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Lotm {
    pub options: LotmOptions,
}

impl Smoother for Lotm {
    fn name(&self) -> &'static str {
        "lotm"
    }

    fn smooth_run(&self, run: &Run, tolerance: f64) -> Result<SmoothedRun, SmoothError> {
        self.smooth_run_reaching(run, tolerance, None)
    }
}

impl Lotm {
    /// [`Smoother::smooth_run`] with every transition's apex held to
    /// `reach` instead of the band's own.
    pub(crate) fn smooth_run_reaching(
        &self,
        run: &Run,
        tolerance: f64,
        reach: Option<Reach>,
    ) -> Result<SmoothedRun, SmoothError> {
        let m = self.options.min_half_angle;
        self.options.validate()?;
        let mut out = smooth_run_by_corners(run, tolerance, m, reach, &lotm_plan)?;
        self.options.arc_joints.apply(&mut out, tolerance);
        Ok(out)
    }
}
