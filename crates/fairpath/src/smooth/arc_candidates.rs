//! `arc-fit`'s candidate arcs from a vertex `P_i` to a vertex `P_j`: the
//! arc tangent to the previous block, and the free arc (through the
//! halfway vertex, else of the bulge that fits the stretch best), each
//! only when it is one that may be written (radius, sweep, chord limits;
//! module docs of `arc_fit.rs`, "The fit" and "Limits").

use super::arc_chain::Fitter;
use super::arc_check::within;
use super::arc_fit::{ARC_MAX_SWEEP, ARC_MIN_RADIUS_MM};
use crate::geom::{Arc, Vec3};
use crate::math;

/// Steps of the golden-section search for a free arc's bulge.
const BULGE_ITERATIONS: usize = 16;

/// A best-bulge arc is looked for only where the three-point arc's
/// estimate ([`Fitter::bulge_error`]) is within this many fit tolerances:
/// choosing the bulge gains less than a factor of two on it (0.14 against
/// 0.25 of the depth of a corner between two segments), so further out
/// the search would be wasted.
const BULGE_GATE: f64 = 2.5;

impl Fitter<'_> {
    /// The helical arc from `P_i` to `P_j` about the XY centre `center`,
    /// clockwise or not, if it is one that may be written.
    fn arc(&self, i: usize, j: usize, center: Vec3, clockwise: bool) -> Option<Arc> {
        let (p, q) = (self.pts[i], self.pts[j]);
        if !within(
            self.lim.min_chord,
            Vec3::new(q.x - p.x, q.y - p.y, 0.0).norm(),
        ) {
            return None;
        }
        let arc =
            Arc::from_center(p, q, center, Vec3::Z, clockwise, 1, self.lim.coincident).ok()?;
        let (rmin, rmax) = (arc.r0.min(arc.r1), arc.r0.max(arc.r1));
        let ok = rmin >= ARC_MIN_RADIUS_MM
            && rmax <= self.lim.max_radius
            && arc.sweep > 0.0
            && arc.sweep <= ARC_MAX_SWEEP
            && arc.rise.is_finite()
            && arc.center.is_finite();
        ok.then_some(arc)
    }

    /// The arc from `P_i` leaving along the unit XY direction `t`, through
    /// `P_j` (module docs).
    pub(super) fn tangent_arc(&self, i: usize, j: usize, t: Vec3) -> Option<Arc> {
        let (p, q) = (self.pts[i], self.pts[j]);
        let d = Vec3::new(q.x - p.x, q.y - p.y, 0.0);
        let n = Vec3::new(-t.y, t.x, 0.0);
        let dn = d.dot(n);
        let rho = d.norm_sq() / (2.0 * dn);
        if !(rho.is_finite() && math::abs(rho) <= self.lim.max_radius) {
            return None;
        }
        self.arc(i, j, p + n * rho, rho < 0.0)
    }

    /// The arc through `P_i`, the vertex halfway along `i..j` by length,
    /// and `P_j`.
    fn three_point_arc(&self, i: usize, j: usize) -> Option<Arc> {
        let half = 0.5 * (self.cum[i] + self.cum[j]);
        let m = (i + self.cum[i..=j].partition_point(|&c| c < half)).clamp(i + 1, j - 1);
        let (p, pm, q) = (self.pts[i], self.pts[m], self.pts[j]);
        let b = Vec3::new(pm.x - p.x, pm.y - p.y, 0.0);
        let c = Vec3::new(q.x - p.x, q.y - p.y, 0.0);
        let dd = 2.0 * (b.x * c.y - b.y * c.x);
        let (bb, cc) = (b.norm_sq(), c.norm_sq());
        let ux = (c.y * bb - b.y * cc) / dd;
        let uy = (b.x * cc - c.x * bb) / dd;
        if !(ux.is_finite() && uy.is_finite()) {
            return None;
        }
        self.arc(i, j, p + Vec3::new(ux, uy, 0.0), dd < 0.0)
    }

    /// The XY circle through `P_i` and `P_j` of bulge `b` (the tangent of a
    /// quarter of the signed sweep, positive counter-clockwise): its centre
    /// and whether it runs clockwise. The centre lies on the chord's
    /// perpendicular bisector, `(c / 4) (1 / b - b)` to the left of the
    /// chord of length `c`.
    fn bulge_center(&self, i: usize, j: usize, b: f64) -> Option<(Vec3, bool)> {
        let (p, q) = (self.pts[i], self.pts[j]);
        let d = Vec3::new(q.x - p.x, q.y - p.y, 0.0);
        let c = d.norm();
        let n = Vec3::new(-d.y, d.x, 0.0) / c;
        let s = 0.25 * c * (1.0 / b - b);
        let center = p + d * 0.5 + n * s;
        (center.is_finite() && b != 0.0).then_some((center, b < 0.0))
    }

    /// The largest XY radial distance of the vertices and segment
    /// midpoints of `i..j` from the circle of bulge `b` through `P_i` and
    /// `P_j` (a cheap estimate of the fit, used to choose `b`).
    fn bulge_error(&self, i: usize, j: usize, b: f64) -> f64 {
        let Some((center, _)) = self.bulge_center(i, j, b) else {
            return f64::INFINITY;
        };
        let radial = |q: Vec3| {
            let (dx, dy) = (q.x - center.x, q.y - center.y);
            math::sqrt(dx * dx + dy * dy)
        };
        let r = radial(self.pts[i]);
        let mut e: f64 = 0.0;
        for k in i..j {
            let (a, bq) = (self.pts[k], self.pts[k + 1]);
            e = e
                .max(math::abs(radial(bq) - r))
                .max(math::abs(radial(a.lerp(bq, 0.5)) - r));
        }
        e
    }

    /// An arc from `P_i` to `P_j` not bound to the vertices between: the
    /// bulge that minimises [`Fitter::bulge_error`], by golden-section
    /// search between half and 1.25 times the bulge of the three-point arc
    /// `arc3` (an arc through a corner of the polyline fits best somewhat
    /// flatter than through the corner).
    fn bulge_arc(&self, i: usize, j: usize, arc3: &Arc) -> Option<Arc> {
        let b0 = math::tan(0.25 * arc3.sweep) * if arc3.normal.z < 0.0 { -1.0 } else { 1.0 };
        if !within(self.bulge_error(i, j, b0), BULGE_GATE * self.lim.tol) {
            return None;
        }
        let (mut lo, mut hi) = (0.5 * b0, 1.25 * b0);
        let g = 0.5 * (math::sqrt(5.0) - 1.0);
        let mut x1 = hi - g * (hi - lo);
        let mut x2 = lo + g * (hi - lo);
        let (mut f1, mut f2) = (self.bulge_error(i, j, x1), self.bulge_error(i, j, x2));
        for _ in 0..BULGE_ITERATIONS {
            if f1 < f2 {
                hi = x2;
                x2 = x1;
                f2 = f1;
                x1 = hi - g * (hi - lo);
                f1 = self.bulge_error(i, j, x1);
            } else {
                lo = x1;
                x1 = x2;
                f1 = f2;
                x2 = lo + g * (hi - lo);
                f2 = self.bulge_error(i, j, x2);
            }
        }
        let (b, e) = if f1 < f2 { (x1, f1) } else { (x2, f2) };
        if !within(e, self.lim.tol) {
            return None;
        }
        let (center, cw) = self.bulge_center(i, j, b)?;
        self.arc(i, j, center, cw)
    }

    /// A free arc over `i..j` that fits: the three-point arc, else the arc
    /// of the best bulge.
    pub(super) fn free_arc(&mut self, i: usize, j: usize) -> Option<Arc> {
        let arc3 = self.three_point_arc(i, j)?;
        if self.arc_fits(&arc3, i, j) {
            return Some(arc3);
        }
        let arc = self.bulge_arc(i, j, &arc3)?;
        self.arc_fits(&arc, i, j).then_some(arc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::ParamCurve;
    use crate::smooth::arc_chain::Limits;
    use alloc::vec::Vec;
    use core::f64::consts::PI;

    #[test]
    fn tangent_arc_leaves_along_the_tangent() {
        let pts = [
            Vec3::ZERO,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ];
        let mut f = Fitter {
            pts: &pts,
            cum: alloc::vec![0.0, 1.0, 2.0],
            lim: Limits {
                tol: 0.01,
                sample: 0.0005,
                max_radius: 1e5,
                min_chord: 1e-4,
                coincident: 1e-5,
            },
            angles: Vec::new(),
        };
        let a = f.tangent_arc(0, 2, Vec3::X).unwrap();
        assert!((a.r0 - 1.0).abs() < 1e-12 && (a.sweep - PI).abs() < 1e-12);
        let t = a.deriv1(0.0);
        assert!(t.y.abs() < 1e-12 && t.x > 0.0);
        let b = f.three_point_arc(0, 2).unwrap();
        assert!((b.center - Vec3::new(0.0, 1.0, 0.0)).norm() < 1e-12);
        let (c, cw) = f.bulge_center(0, 2, 1.0).unwrap();
        assert!((c - b.center).norm() < 1e-12 && !cw);
        // The two segments are chords of 90 degrees: 0.29 mm off the arc.
        assert!(f.free_arc(0, 2).is_none());
        f.lim.tol = 0.3;
        f.lim.sample = 0.015;
        assert!(f.free_arc(0, 2).is_some());
    }
}
