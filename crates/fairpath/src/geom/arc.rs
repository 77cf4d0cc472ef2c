//! Circular, helical and spiral arcs as G2/G3 describe them.

use super::{ParamCurve, Vec3};
use crate::math;
use alloc::vec::Vec;
use core::f64::consts::PI;

/// An arc turning counter-clockwise about the unit `normal` through `sweep`
/// radians (more than 2 pi for several turns), with radius varying linearly
/// from `r0` to `r1` (a G2/G3 whose end radius differs slightly from its start
/// radius, as LinuxCNC runs it) and a helical rise `rise` along `normal`:
///
/// `C(t) = center + r(t) (cos(t sweep) u + sin(t sweep) v) + t rise normal`,
/// `r(t) = r0 + t (r1 - r0)`, `t` in `[0, 1]`, `v = normal x u`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arc {
    /// Centre, in the plane of the start point.
    pub center: Vec3,
    /// Unit normal; the arc turns counter-clockwise about it.
    pub normal: Vec3,
    /// Unit vector from the centre towards the start point.
    pub u: Vec3,
    pub r0: f64,
    pub r1: f64,
    /// Total turning angle in radians, > 0.
    pub sweep: f64,
    /// Displacement along `normal` from start to end, mm.
    pub rise: f64,
    /// The programmed start and end points: `C(0)` and `C(1)` return them
    /// exactly, so pieces join without rounding gaps.
    pub p0: Vec3,
    pub p1: Vec3,
}

/// Why an arc could not be built from G2/G3 data.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ArcError {
    /// Start or end coincides with the centre.
    #[error("the start or end point is at the centre")]
    ZeroRadius,
    /// A coordinate is NaN or infinite.
    #[error("a coordinate is not a finite number")]
    NotFinite,
}

impl Arc {
    /// The arc from `start` to `end` about the axis through `center` along
    /// `axis` (the plane normal: +Z for G17, +Y for G18, +X for G19),
    /// clockwise about `axis` for G2, counter-clockwise for G3, making
    /// `turns >= 1` turns (G-code `P`). `coincident` (mm) is the distance
    /// below which start and end are the same point in the plane, which makes
    /// a full circle.
    pub fn from_center(
        start: Vec3,
        end: Vec3,
        center: Vec3,
        axis: Vec3,
        clockwise: bool,
        turns: u32,
        coincident: f64,
    ) -> Result<Arc, ArcError> {
        if !(start.is_finite() && end.is_finite() && center.is_finite() && axis.is_finite()) {
            return Err(ArcError::NotFinite);
        }
        let normal = if clockwise { -axis } else { axis };
        let c = center + normal * (start - center).dot(normal);
        let a = start - c;
        let r0 = a.norm();
        let rise = (end - start).dot(normal);
        let e_in_plane = end - normal * rise;
        let b = e_in_plane - c;
        let r1 = b.norm();
        // Finite points can still be too far apart for f64 (1e308 and
        // -1e308).
        if !(r0.is_finite() && r1.is_finite() && rise.is_finite()) {
            return Err(ArcError::NotFinite);
        }
        if r0 <= coincident || r1 <= coincident {
            return Err(ArcError::ZeroRadius);
        }
        let u = a / r0;
        let mut phi = math::atan2(a.cross(b).dot(normal), a.dot(b));
        if (e_in_plane - start).norm() <= coincident {
            phi = 2.0 * PI;
        } else if phi <= 0.0 {
            phi += 2.0 * PI;
        }
        let sweep = phi + 2.0 * PI * (turns.max(1) - 1) as f64;
        Ok(Arc {
            center: c,
            normal,
            u,
            r0,
            r1,
            sweep,
            rise,
            p0: start,
            p1: end,
        })
    }

    fn v(&self) -> Vec3 {
        self.normal.cross(self.u)
    }

    /// True when the radius is constant and there is no rise: the arc is
    /// exactly a rational quadratic NURBS.
    pub fn is_circular(&self, tol: f64) -> bool {
        math::abs(self.r1 - self.r0) <= tol && math::abs(self.rise) <= tol
    }

    /// Exact length of a circular or helical arc; for a spiral (r0 != r1),
    /// the length of the circular arc of the mean radius, which is within
    /// `|r1 - r0| * sweep` of it; use [`super::arc_length`] for more.
    pub fn approx_length(&self) -> f64 {
        let r = 0.5 * (self.r0 + self.r1);
        math::sqrt((r * self.sweep) * (r * self.sweep) + self.rise * self.rise)
    }

    /// Radius at `t`.
    pub fn radius(&self, t: f64) -> f64 {
        self.r0 + t * (self.r1 - self.r0)
    }

    /// An upper bound of `|C''(t)|` over the arc: `r_max sweep^2 + 2 |r1 -
    /// r0| sweep`, from `C'' = 2 (r1 - r0) sweep T - r(t) sweep^2 R` (unit
    /// tangential `T` and radial `R`; the rise is linear in `t` and adds
    /// nothing).
    pub fn second_derivative_bound(&self) -> f64 {
        let r = self.r0.max(self.r1);
        r * self.sweep * self.sweep + 2.0 * math::abs(self.r1 - self.r0) * self.sweep
    }

    /// Parameters `0 = t_0 < ... < t_n = 1`, evenly spaced, whose chords are
    /// within `chord` (mm) of the arc both ways (every point of the arc
    /// within `chord` of a chord and every point of a chord within `chord`
    /// of the arc), in closed form: linear interpolation between parameters
    /// `h` apart is within `h^2 M / 8` of a C2 curve with `|C''| <= M`
    /// ([`Arc::second_derivative_bound`]; the remainder of linear
    /// interpolation, de Boor, *A Practical Guide to Splines*, ch. II), and
    /// the snapped ends ([`Arc::p0`], [`Arc::p1`]) move the end chords by at
    /// most their distance from the formula's ends. `None` where that
    /// distance leaves no room under `chord`, or more than `max_spans`
    /// chords would be needed.
    pub fn chord_params(&self, chord: f64, max_spans: usize) -> Option<Vec<f64>> {
        let gap = self
            .p0
            .dist(self.eval_formula(0.0))
            .max(self.p1.dist(self.eval_formula(1.0)));
        let room = chord - gap;
        // (NaN: not finite coordinates, no room either.)
        if room.is_nan() || room <= 0.0 {
            return None;
        }
        let spans = math::ceil(math::sqrt(self.second_derivative_bound() / (8.0 * room))).max(1.0);
        if spans.is_nan() || spans > max_spans as f64 {
            return None;
        }
        let n = spans as usize;
        Some((0..=n).map(|i| i as f64 / n as f64).collect())
    }

    /// The part of the arc over `[t0, t1]` (`0 <= t0 < t1 <= 1`), as an arc
    /// of its own: the same centre line, radius law and pitch, its ends the
    /// points [`ParamCurve::eval`] gives at `t0` and `t1` (the programmed
    /// end where `t0 = 0` or `t1 = 1`), so that a piece cut from an arc
    /// meets what is joined to it there exactly.
    pub fn between(&self, t0: f64, t1: f64) -> Arc {
        let (radial, _) = self.frame(t0);
        Arc {
            center: self.center + self.normal * (t0 * self.rise),
            normal: self.normal,
            u: radial,
            r0: self.radius(t0),
            r1: self.radius(t1),
            sweep: (t1 - t0) * self.sweep,
            rise: (t1 - t0) * self.rise,
            p0: self.eval(t0),
            p1: self.eval(t1),
        }
    }

    /// The arc reversed (same points, opposite direction).
    pub fn reversed(&self) -> Arc {
        let end = self.eval_formula(1.0);
        let e_in = end - self.normal * self.rise;
        let b = e_in - self.center;
        let r1 = b.norm();
        Arc {
            center: self.center + self.normal * self.rise,
            normal: -self.normal,
            u: b / r1,
            r0: self.r1,
            r1: self.r0,
            sweep: self.sweep,
            rise: self.rise,
            p0: self.p1,
            p1: self.p0,
        }
    }
}

impl Arc {
    /// Unit radial and tangential directions at `t`.
    fn frame(&self, t: f64) -> (Vec3, Vec3) {
        let a = t * self.sweep;
        let (s, c) = (math::sin(a), math::cos(a));
        let v = self.v();
        (self.u * c + v * s, v * c - self.u * s)
    }

    /// `C(t)` from the formula, without snapping the ends.
    pub fn eval_formula(&self, t: f64) -> Vec3 {
        let (radial, _) = self.frame(t);
        self.center + radial * self.radius(t) + self.normal * (t * self.rise)
    }
}

impl ParamCurve for Arc {
    fn domain(&self) -> (f64, f64) {
        (0.0, 1.0)
    }
    fn eval(&self, t: f64) -> Vec3 {
        if t <= 0.0 {
            return self.p0;
        }
        if t >= 1.0 {
            return self.p1;
        }
        self.eval_formula(t)
    }
    fn deriv1(&self, t: f64) -> Vec3 {
        let (radial, tang) = self.frame(t);
        radial * (self.r1 - self.r0)
            + tang * (self.radius(t) * self.sweep)
            + self.normal * self.rise
    }
    fn deriv2(&self, t: f64) -> Vec3 {
        let (radial, tang) = self.frame(t);
        tang * (2.0 * (self.r1 - self.r0) * self.sweep)
            - radial * (self.radius(t) * self.sweep * self.sweep)
    }
    /// The midpoint rule on the speed `g(t) = |C'(t)| = sqrt(K + (s r(t))^2)`
    /// (`s` the sweep, `K = (r1 - r0)^2 + rise^2`): exact for a circular or
    /// helical arc, where `g` is constant; on a spiral (as an arc read back
    /// from rounded coordinates, whose end radius differs from its start
    /// radius by the rounding) within `(b - a)^3 / 24 max g''`, with
    /// `g'' = (s (r1 - r0))^2 K / g^3` and `g >= max(sqrt(K), s r_min)`.
    /// `None` where that bound exceeds `accuracy`.
    fn closed_length(&self, a: f64, b: f64, accuracy: f64) -> Option<f64> {
        let dr = self.r1 - self.r0;
        let s = self.sweep;
        let k = dr * dr + self.rise * self.rise;
        let g = |t: f64| math::sqrt(k + (s * self.radius(t)) * (s * self.radius(t)));
        let h = b - a;
        if dr != 0.0 {
            let r_min = self.radius(a).min(self.radius(b)).max(0.0);
            let g_min = math::sqrt(k).max(s * r_min);
            let bound = h * h * h / 24.0 * (s * dr) * (s * dr) * k / (g_min * g_min * g_min);
            // A NaN bound (a degenerate spiral) integrates too.
            if bound.is_nan() || bound > accuracy {
                return None;
            }
        }
        Some(g(0.5 * (a + b)) * h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A part of a spiral helix is the same curve over its interval: the
    /// same points, tangents and curvature vectors, its ends exactly the
    /// whole arc's points there (and its programmed ends at 0 and 1).
    #[test]
    fn a_part_of_a_spiral_helix_is_the_same_curve() {
        let a = Arc::from_center(
            Vec3::new(3.0, 0.0, 1.0),
            Vec3::new(-0.5, 3.2, 1.7),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 0.0, 1.0),
            false,
            2,
            1e-9,
        )
        .unwrap();
        for (t0, t1) in [(0.0, 0.3), (0.25, 0.8), (0.6, 1.0), (0.0, 1.0)] {
            let b = a.between(t0, t1);
            assert_eq!(b.p0, a.eval(t0));
            assert_eq!(b.p1, a.eval(t1));
            for i in 0..=10 {
                let s = i as f64 / 10.0;
                let t = t0 + s * (t1 - t0);
                assert!(b.eval(s).dist(a.eval(t)) < 1e-12, "{t0} {t1} {s}");
                let (ta, tb) = (a.unit_tangent(t).unwrap(), b.unit_tangent(s).unwrap());
                assert!(ta.dist(tb) < 1e-12);
                assert!(a.curvature_vector(t).dist(b.curvature_vector(s)) < 1e-12);
            }
        }
    }
}
