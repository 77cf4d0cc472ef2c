//! How a controller passes a joint between pieces that is not G2, from the
//! same limits as every curve.
//!
//! * A **corner** (the tangent turns by `phi`) is passed on the circle
//!   tangent to both moves that stays within the junction deviation `e` of
//!   the corner (the model of grbl and its successors): radius
//!   `R = e sin(a) / (1 - sin(a))` with `a = (pi - phi) / 2`. The circle must
//!   also fit in the moves: its tangent length `R tan(phi / 2)` is at most
//!   `room`, half the shorter adjacent move (LinuxCNC's blends are limited
//!   to half a segment the same way), so `R <= room / tan(phi / 2)`.
//!   Without this a chain of short moves with small turns would be passed
//!   on circles far longer than the moves, faster than any path through
//!   them. On the circle the caps of any curve apply ([`speed_cap`]:
//!   `kappa v^2 <= A_n`, `kappa^2 v^3 <= J`, chord error, axes), all along
//!   it: the planner (`caps.rs`) replaces the `tangent_length` of each line
//!   next to a corner by half the circle's arc, at the circle's cap, so a
//!   corner costs the time of its circle (a sharp corner's circle is tiny
//!   and cheap; grbl-style planners cap the speed at the corner point
//!   only). Next to arcs and curves the blend also keeps the mean of their
//!   curvature vectors ([`follow_neighbours`]), and the joint is capped as
//!   one jump of their difference plus the circle's own curvature
//!   ([`corner_jump`]): a kink of rounding size between two arcs costs
//!   about what their own curvature jump costs, not the jump from their
//!   curvature to a nearly straight circle. Where the neighbour is a short
//!   line that this circle and the next one fill, the jump is to the next
//!   circle's curvature, not to the line's (`caps.rs`): an arc that goes on
//!   as short moves along the same curve keeps its curvature.
//! * Where the circle meets what comes before and after it the curvature
//!   vector jumps by `dk`, and the normal acceleration steps by `v^2 dk`
//!   within one interpolation period `Ts`: `v <= sqrt(J Ts / dk)`, at
//!   those two points. On an
//!   isolated corner `dk = 1/R` (grbl stops at the caps above, so without
//!   this a polyline corner would escape the jerk limit that every curve is
//!   held to). On a dense chain of short moves the circles fill the moves
//!   and meet each other, and `dk` is the difference of their curvature
//!   vectors: a finely sampled smooth curve is passed as the curve it
//!   samples, as a blending controller passes it.
//! * A **tangent joint** (G1, or G2 within the class thresholds) whose
//!   curvature vector jumps by `dk` has the same cap `sqrt(J Ts / dk)`.
//! * Jumps closer than a period of travel add up: a chain of arcs, or of
//!   meeting circles, `L` mm long each steps the normal acceleration by
//!   `v^2 dk` every `L / v` s, so such a joint (and a meeting circle's
//!   ends) is also capped at `cbrt(J L / dk)`, the `|dkappa/ds| v^3 <= J`
//!   of the curve the chain follows ([`step_cap`]).

use super::limits::{speed_cap, MachineLimits, PathPoint};
use crate::geom::Vec3;
use crate::math;

/// Relative length below which two blends on one move count as meeting
/// (rounding of `room`, which makes them meet exactly).
pub const MEET_REL: f64 = 1e-9;

/// The circle on which a corner is passed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blend {
    /// Radius, mm.
    pub radius: f64,
    /// Length taken from each move, mm.
    pub tangent_length: f64,
    /// Length of the circle's arc, mm (`R phi`: shorter than the
    /// `2 tangent_length` of the moves it replaces).
    pub arc_length: f64,
    /// Curvature vector (1/mm), towards the inside of the corner.
    pub curvature: Vec3,
    /// Unit tangent in the middle of the circle.
    pub tangent: Vec3,
}

/// The blend circle of a corner between unit tangents `tangent_in` and
/// `tangent_out`, taking at most `room` mm from each move
/// (`f64::INFINITY`: unlimited); `None` when the path runs straight on or
/// reverses.
pub fn corner_blend(
    m: &MachineLimits,
    tangent_in: Vec3,
    tangent_out: Vec3,
    room: f64,
) -> Option<Blend> {
    let phi = tangent_in.angle_to(tangent_out);
    let sa = math::cos(0.5 * phi); // sin((pi - phi) / 2)
    if !(phi > 0.0 && sa < 1.0 && sa > 0.0) {
        return None;
    }
    let half_tan = math::tan(0.5 * phi);
    let radius = (m.junction_deviation * sa / (1.0 - sa)).min(room / half_tan);
    let normal = (tangent_out - tangent_in).normalized(0.0)?;
    let tangent = (tangent_in + tangent_out).normalized(0.0)?;
    Some(Blend {
        radius,
        tangent_length: radius * half_tan,
        arc_length: radius * phi,
        curvature: normal / radius,
        tangent,
    })
}

/// The blend of a corner between pieces whose curvature vectors at the
/// joint are `k_in` and `k_out`: the circle's own turn added to the mean of
/// the neighbours' curvature. Between lines this is the circle itself. Next
/// to arcs and curves the blend keeps bending with them: a kink of a few
/// microradians between two arcs of radius 100 mm (what rounding of written
/// coordinates leaves) is passed at the curvature the arcs already have,
/// not on a nearly straight circle whose curvature would jump by the arcs'
/// own `1/100` at both ends (a cap of 45 mm/s for nothing).
pub fn follow_neighbours(b: Blend, k_in: Vec3, k_out: Vec3) -> Blend {
    Blend {
        curvature: b.curvature + (k_in + k_out) * 0.5,
        ..b
    }
}

/// The curvature jump (1/mm) of passing a corner whose circle alone has
/// curvature vector `circle`, between neighbours with curvature vectors
/// `k_in` and `k_out`: `|k_out - k_in| + |circle|`. A blend between arcs
/// is as short as the kink is small, far shorter than a period of travel,
/// so the curvature changes from `k_in` to `k_out` and the circle's turn
/// comes on top, within one period (between lines: the circle's own
/// curvature, as before).
pub fn corner_jump(circle: Vec3, k_in: Vec3, k_out: Vec3) -> f64 {
    (k_out - k_in).norm() + circle.norm()
}

/// The largest speed (mm/s) on `blend`, whose curvature vector jumps by
/// `jump` (1/mm) where it meets its neighbours.
pub fn blend_cap(m: &MachineLimits, blend: &Blend, jump: f64) -> f64 {
    let p = PathPoint {
        tangent: blend.tangent,
        curvature: blend.curvature,
        dkappa_ds: 0.0,
    };
    speed_cap(m, m.max_feed, &p).0.min(jump_cap(m, jump))
}

/// The largest speed (mm/s) across jumps `dk` (1/mm) of the curvature
/// vector that follow each other every `spacing` mm: one jump per period
/// raises the normal acceleration by `v^2 dk` within it, `v^2 dk <= J Ts`;
/// jumps closer than a period of travel (`spacing < v Ts`) raise it by
/// `v^2 dk` every `spacing / v` s, `v^3 dk / spacing <= J` (the
/// `|dkappa/ds| v^3 <= J` of the curve a chain of short arcs follows). So
/// `min(sqrt(J Ts / dk), cbrt(J spacing / dk))`.
pub fn step_cap(m: &MachineLimits, dk: f64, spacing: f64) -> f64 {
    if dk > 0.0 {
        let jump = jump_cap(m, dk);
        let x = m.jerk * spacing.max(0.0) / dk;
        if math::cbrt_at_least(x, jump) {
            jump
        } else {
            jump.min(math::cbrt(x))
        }
    } else {
        f64::INFINITY
    }
}

/// The largest speed (mm/s) across a jump `dk` (1/mm) of the curvature
/// vector: `sqrt(J Ts / dk)`.
pub fn jump_cap(m: &MachineLimits, dk: f64) -> f64 {
    if dk > 0.0 {
        math::sqrt(m.jerk * m.period / dk)
    } else {
        f64::INFINITY
    }
}

/// The largest speed (mm/s) through an isolated joint: a corner passed on
/// its blend (neighbours with curvature vectors `k_in`, `k_out`), or a
/// tangent joint whose curvature vector jumps from `k_in` to `k_out`.
/// `room` as in [`corner_blend`].
pub fn junction_cap(
    m: &MachineLimits,
    tangent_in: Vec3,
    tangent_out: Vec3,
    k_in: Vec3,
    k_out: Vec3,
    room: f64,
) -> f64 {
    if tangent_in.angle_to(tangent_out) > 0.0 {
        return match corner_blend(m, tangent_in, tangent_out, room) {
            Some(b) => {
                let jump = corner_jump(b.curvature, k_in, k_out);
                blend_cap(m, &follow_neighbours(b, k_in, k_out), jump)
            }
            // Straight on within rounding: the curvature jump alone; a
            // reversal: stop.
            None if tangent_in.dot(tangent_out) > 0.0 => jump_cap(m, (k_out - k_in).norm()),
            None => 0.0,
        };
    }
    jump_cap(m, (k_out - k_in).norm())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::seeded::Rng;

    /// [`step_cap`] with the cube root always taken gives the same bits.
    #[test]
    fn seeded_random_step_caps_as_with_the_root() {
        let mut rng = Rng(0x57E9);
        let mut roots = 0;
        for _ in 0..100_000 {
            let mut m = MachineLimits::thesis();
            m.jerk = rng.decades(2.0, 6.0);
            m.period = rng.decades(-4.0, -2.0);
            let (dk, spacing) = (rng.decades(-8.0, 3.0), rng.decades(-6.0, 2.0));
            let jump = jump_cap(&m, dk);
            let root = math::cbrt(m.jerk * spacing / dk);
            let want = jump.min(root);
            assert_eq!(step_cap(&m, dk, spacing).to_bits(), want.to_bits());
            roots += usize::from(root < jump);
        }
        assert!(roots > 10_000, "{roots} caps set by the root");
    }
}
