//! Continuity class of a joint between two pieces: position, tangent and
//! curvature-vector continuity (C0/G1/G2), with thresholds scaled from the
//! user's tolerance and f64 rounding of the coordinates. Shared by the
//! methods (which joints still need work), the planner (which joints are
//! corners) and the verifier: it is geometry, not a judgement of any of them.

use crate::geom::{curvature_vector_from, Curve, ParamCurve};

/// Continuity class of a joint between two pieces.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Continuity {
    /// The pieces do not meet.
    Gap,
    /// Position only: a corner.
    G0,
    /// Common unit tangent, curvature jumps.
    G1,
    /// Common unit tangent and curvature vector.
    G2,
}

impl Continuity {
    pub fn as_str(self) -> &'static str {
        match self {
            Continuity::Gap => "gap",
            Continuity::G0 => "G0",
            Continuity::G1 => "G1",
            Continuity::G2 => "G2",
        }
    }
}

/// The largest angle (rad) between unit tangents that
/// [`JointTolerances::from_tolerance`] counts as tangent: 1 microradian.
pub const TANGENT_ANGLE: f64 = 1e-6;

/// Thresholds for classing joints.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointTolerances {
    /// Largest gap (mm) that still counts as meeting.
    pub position: f64,
    /// Largest angle (rad) between unit tangents that counts as tangent.
    pub angle: f64,
    /// Largest difference of curvature vectors (1/mm) that counts as G2,
    /// relative part: times the larger curvature...
    pub curvature_rel: f64,
    /// ...plus this absolute part (1/mm).
    pub curvature_abs: f64,
}

impl JointTolerances {
    /// From the user's tolerance: gaps up to a millionth of it, tangents
    /// within 1 microradian, curvature vectors equal to 1e-6 relative plus
    /// `1e-6 / tolerance` absolute (for 0.05 mm: radius differences beyond
    /// 50 km count as jumps).
    pub fn from_tolerance(tol: f64) -> Self {
        JointTolerances {
            position: tol * 1e-6,
            angle: TANGENT_ANGLE,
            curvature_rel: 1e-6,
            curvature_abs: 1e-6 / tol,
        }
    }
}

/// Continuity of the joint where `a` ends and `b` starts.
///
/// Besides the thresholds of `jt`, differences that f64 rounding of the
/// control points alone can cause are ignored: coordinates of magnitude `X`
/// carry errors of about `X * 2^-52`, which tilt a tangent of a piece of
/// length `l` by `~X eps / l` and bend it by `~X eps / l^2`; a thousand
/// times those amounts is allowed on top.
pub fn classify_joint(a: &Curve, b: &Curve, jt: &JointTolerances) -> Continuity {
    let (_, ta) = a.domain();
    let (tb, _) = b.domain();
    let at = a.end();
    if at.dist(b.start()) > jt.position {
        return Continuity::Gap;
    }
    let (da1, da2) = a.derivs12(ta);
    let (db1, db2) = b.derivs12(tb);
    let (Some(ua), Some(ub)) = (da1.normalized(0.0), db1.normalized(0.0)) else {
        return Continuity::G0;
    };
    let scale = 1.0 + at.x.abs().max(at.y.abs()).max(at.z.abs());
    // Length scale at the joint: speed times the parameter range of the
    // knot span that ends or starts there (the whole domain for lines and
    // arcs; a chord would be 0 for a full circle). Rounding of control
    // points at spacing `l` bends the curve by about `X eps / l^2`.
    let (a0, b1) = (end_span_start(a), start_span_end(b));
    let l = (da1.norm() * (ta - a0))
        .min(db1.norm() * (b1 - tb))
        .max(jt.position);
    let round = 1e3 * f64::EPSILON * scale;
    if ua.angle_to(ub) > jt.angle + round / l {
        return Continuity::G0;
    }
    let ka = curvature_vector_from(da1, da2);
    let kb = curvature_vector_from(db1, db2);
    let lim = jt.curvature_rel * ka.norm().max(kb.norm()) + jt.curvature_abs + round / (l * l);
    if (ka - kb).norm() <= lim {
        Continuity::G2
    } else {
        Continuity::G1
    }
}

/// Start of the last knot span of `c` (its domain's start if it has one span).
fn end_span_start(c: &Curve) -> f64 {
    let (t0, t1) = c.domain();
    match c {
        Curve::Nurbs(n) => n
            .knots
            .iter()
            .rev()
            .find(|&&k| k < t1)
            .map_or(t0, |&k| k.max(t0)),
        _ => t0,
    }
}

/// End of the first knot span of `c`.
fn start_span_end(c: &Curve) -> f64 {
    let (t0, t1) = c.domain();
    match c {
        Curve::Nurbs(n) => n.knots.iter().find(|&&k| k > t0).map_or(t1, |&k| k.min(t1)),
        _ => t1,
    }
}
