//! Geometry kernel: points, lines, arcs, B-spline/NURBS curves, curvature,
//! arc length, distances to polylines, principal planes and biarcs.

use alloc::boxed::Box;

mod arc;
pub mod band_fit;
pub mod basis;
mod bezier_spans;
mod bezier_spline;
pub mod biarc;
pub mod continuity;
mod cubic_bezier;
mod cubic_span;
mod curve;
pub mod elevate;
mod fairness;
pub mod fit;
mod fit_bound;
mod fit_knots;
mod g2_quintic;
mod inner_corners;
mod knot_insertion;
pub mod least_squares;
mod line;
mod nurbs;
mod nurbs_bounds;
mod plane;
mod polyline;
mod sampled_peak;
pub mod tube_fair;
mod turn_bound;
mod vec3;

pub use arc::{Arc, ArcError};
pub use bezier_spline::BezierSpline;
pub use continuity::{classify_joint, Continuity, JointTolerances};
pub use cubic_bezier::CubicBezier;
pub use curve::{
    arc_length, arc_length_between, curvature_from, curvature_vector_from, flatten_params,
    flatten_params_between, total_curvature, ParamCurve,
};
pub use fairness::curvature_variation_energy;
pub use g2_quintic::{bezier_nurbs, g2_quintic_points, EndState};
pub use inner_corners::{corners_between_spans, inner_corners, sharp_turns_in_span, InnerCorner};
pub use line::Line;
pub use nurbs::{Nurbs, NurbsError};
pub use plane::Plane;
pub use polyline::{
    distance_to_polyline, point_segment_distance, point_segment_distance_t, SegmentGrid,
};
pub use sampled_peak::{
    curvature_candidates, golden_max, refined_peak, sampled_peak, Extrema, NARROW,
};
pub use turn_bound::turn_curvature;
pub use vec3::Vec3;

/// One piece of a tool path: a line, a G2/G3 arc, or a NURBS curve.
///
/// Arcs and NURBS curves are boxed: a program is mostly lines, and a
/// piece is held once per copy of a run (as read, smoothed, read back),
/// so a line's piece takes 96 bytes instead of 200 (an arc would make
/// every line as large as itself: 152 bytes). `Curve::from(arc)` builds
/// one.
#[derive(Clone, Debug, PartialEq)]
pub enum Curve {
    Line(Line),
    Arc(Box<Arc>),
    Nurbs(Box<Nurbs>),
}

impl From<Line> for Curve {
    fn from(l: Line) -> Curve {
        Curve::Line(l)
    }
}

impl From<Arc> for Curve {
    fn from(a: Arc) -> Curve {
        Curve::Arc(Box::new(a))
    }
}

impl From<Nurbs> for Curve {
    fn from(n: Nurbs) -> Curve {
        Curve::Nurbs(Box::new(n))
    }
}

impl Curve {
    /// Length accurate to `accuracy` mm (exact for lines, circular and
    /// helical arcs).
    pub fn length(&self, accuracy: f64) -> f64 {
        match self {
            Curve::Line(l) => l.length(),
            Curve::Arc(a) if a.r0 == a.r1 => a.approx_length(),
            c => arc_length(c, accuracy),
        }
    }
}

impl ParamCurve for Curve {
    fn domain(&self) -> (f64, f64) {
        match self {
            Curve::Line(c) => c.domain(),
            Curve::Arc(c) => c.domain(),
            Curve::Nurbs(c) => c.domain(),
        }
    }
    fn eval(&self, t: f64) -> Vec3 {
        match self {
            Curve::Line(c) => c.eval(t),
            Curve::Arc(c) => c.eval(t),
            Curve::Nurbs(c) => c.eval(t),
        }
    }
    fn deriv1(&self, t: f64) -> Vec3 {
        match self {
            Curve::Line(c) => c.deriv1(t),
            Curve::Arc(c) => c.deriv1(t),
            Curve::Nurbs(c) => c.deriv1(t),
        }
    }
    fn deriv2(&self, t: f64) -> Vec3 {
        match self {
            Curve::Line(c) => c.deriv2(t),
            Curve::Arc(c) => c.deriv2(t),
            Curve::Nurbs(c) => c.deriv2(t),
        }
    }
    fn derivs12(&self, t: f64) -> (Vec3, Vec3) {
        match self {
            Curve::Line(c) => c.derivs12(t),
            Curve::Arc(c) => c.derivs12(t),
            Curve::Nurbs(c) => c.derivs12(t),
        }
    }
    fn eval_derivs12(&self, t: f64) -> (Vec3, Vec3, Vec3) {
        match self {
            Curve::Line(c) => c.eval_derivs12(t),
            Curve::Arc(c) => c.eval_derivs12(t),
            Curve::Nurbs(c) => c.eval_derivs12(t),
        }
    }
    fn breaks(&self) -> alloc::vec::Vec<f64> {
        match self {
            Curve::Nurbs(c) => c.breaks(),
            c => {
                let (a, b) = c.domain();
                alloc::vec![a, b]
            }
        }
    }
    fn breaks_within(&self, a: f64, b: f64) -> alloc::vec::Vec<f64> {
        match self {
            Curve::Nurbs(c) => c.breaks_within(a, b),
            _ => alloc::vec::Vec::new(),
        }
    }
    fn closed_length(&self, a: f64, b: f64, accuracy: f64) -> Option<f64> {
        match self {
            Curve::Line(c) => c.closed_length(a, b, accuracy),
            Curve::Arc(c) => c.closed_length(a, b, accuracy),
            Curve::Nurbs(_) => None,
        }
    }
    fn quadratic_deriv1(&self) -> bool {
        match self {
            Curve::Nurbs(c) => c.quadratic_deriv1(),
            _ => false,
        }
    }
    fn curvature(&self, t: f64) -> f64 {
        match self {
            Curve::Line(_) => 0.0,
            Curve::Arc(c) => c.curvature(t),
            Curve::Nurbs(c) => c.curvature(t),
        }
    }
    fn start(&self) -> Vec3 {
        match self {
            Curve::Line(c) => c.p0,
            c => c.eval(c.domain().0),
        }
    }
    fn end(&self) -> Vec3 {
        match self {
            Curve::Line(c) => c.p1,
            c => c.eval(c.domain().1),
        }
    }
}
