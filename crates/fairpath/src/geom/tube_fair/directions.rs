//! Direction vectors of the control points (thesis section 3.6, "3.4" in
//! the checklist), and how far along them a point may go this iteration.
//!
//! * **Ripple points** (eqs. 3-23 to 3-25): `DV = normalize(A + B)`, `A`
//!   and `B` the unit vectors from the point to its two neighbours: the
//!   bisector of the angle, towards the chord of the neighbours. A point on
//!   the straight segment between its neighbours (within `still` mm, the
//!   caller's [`STILL_SHARE`] of the radius) gets the zero vector (the
//!   thesis' collinear case).
//! * **Single apex** of a smooth group: the ripple formula.
//! * **Double apex** (eqs. 3-26 to 3-28): both apexes get the unit normal
//!   of the line through them, turned towards the point after the second
//!   apex (the thesis' sign test, eq. 3-27). In 3D: the part of
//!   `P(a2+1) - P(a2)` perpendicular to the apex line, normalised (in a
//!   plane exactly the thesis' vector).
//! * **Other smooth points** (eqs. 3-29 to 3-31):
//!   `DV = normalize(-normalize(A + B) + 9.0 DV_apex)`
//!   ([`APEX_WEIGHT`]): outwards, widening the arc, but mostly along the
//!   apex, so the group moves to the inside of the tube as a whole.
//! * **Ends** never move (the project's non-negotiable: run endpoints are
//!   kept exactly; the thesis lets them slide across the tube, eqs. 3-17 to
//!   3-22, which we do not). With [`EndRule::SlideAlongTangent`] the second
//!   point (the seam's neighbours on a closed path) keeps only the part of
//!   its direction along its leg, so the end tangent keeps its direction;
//!   it may not come closer to the end than [`MIN_END_LEG_SHARE`] of the
//!   leg's original length. With [`EndRule::Pinned`] the second point
//!   moves as its category says.
//!
//! Choices where the thesis is silent:
//! * **Reach**: a ripple point or single apex moves at most
//!   [`RIPPLE_REACH_SHARE`] of the way to the segment between its
//!   neighbours (where the angle bisector meets it,
//!   `A + (B - A) |PA| / (|PA| + |PB|)`), the target of its direction.
//!   The thesis does not stop it: a point that overshoots the chord
//!   becomes a ripple the other way and swings back next iteration. And
//!   as all points move at once, a full step to the chord swaps a
//!   saw-tooth's phase (the teeth move down as the gaps move up) instead
//!   of flattening it: half a step flattens it at once (damped Jacobi
//!   relaxation with weight 1/2, whose factor on the saw-tooth mode is 0
//!   and on every smoother mode between 0 and 1).
//! * A double apex moves at most [`RIPPLE_REACH_SHARE`] of the way from
//!   the middle of the two apexes to the chord of their outer neighbours,
//!   and the group's other points at most as far as their apex: the group
//!   moves together (eq. 3-30: "so that the curve stays intact as it
//!   flattens"), never further in one iteration than flattening its apex
//!   needs. The thesis bounds them by the tube's allowance only, and a
//!   whole group jumping by `D_allow` at once turns a gentle bend into a
//!   kink.
//! * A zero apex vector (the apex on its chord) gives the group's other
//!   points the zero vector too: the group is straight there and is
//!   categorised again next iteration.
//!
//! Only sums, dot products and lengths of differences: the directions
//! rotate with the path.
//!
//! [`EndRule::SlideAlongTangent`]: super::EndRule::SlideAlongTangent
//! [`EndRule::Pinned`]: super::EndRule::Pinned

use super::categories::{Categories, Category, Role};
use super::polygon::Polygon;
use super::EndRule;
use crate::geom::{point_segment_distance, Vec3};
use alloc::vec;
use alloc::vec::Vec;

/// The thesis' weight of the apex direction in the direction of the other
/// smooth points (eq. 3-30: "The value of 9.0 was chosen through trial and
/// error. It produces the best overall results.").
pub const APEX_WEIGHT: f64 = 9.0;

/// Share of the radius within which a ripple point counts as on the chord
/// of its neighbours (the thesis' collinear case: the zero vector), and a
/// double apex's next point as on the apex line (ours: 25 nm in a tube of
/// 0.25 mm, below any machine's resolution). Much finer than the line
/// tests' `accuracy * R`: a ripple point moves half way to its chord per
/// iteration, and stopping it at a coarser offset leaves that much ripple.
pub const STILL_SHARE: f64 = 1e-4;

/// Share of the way to the chord of its neighbours a ripple point (or
/// single apex) may move in one iteration (ours, not the thesis'; see the
/// module documentation).
pub const RIPPLE_REACH_SHARE: f64 = 0.5;

/// The least share of its original length an end leg keeps when its inner
/// point slides along it ([`EndRule::SlideAlongTangent`]; ours, not the
/// thesis'): the end tangent keeps its direction and the curve cannot fold
/// back at the end.
///
/// [`EndRule::SlideAlongTangent`]: super::EndRule::SlideAlongTangent
pub const MIN_END_LEG_SHARE: f64 = 0.5;

/// Where one control point goes this iteration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Direction {
    /// The direction vector (unit, or zero; shorter than unit only for a
    /// point sliding along its end leg).
    pub dv: Vec3,
    /// The largest move distance (the multiplier of `dv`) it may take this
    /// iteration; infinite when only the tube limits it.
    pub reach: f64,
}

impl Direction {
    const STILL: Direction = Direction {
        dv: Vec3::ZERO,
        reach: 0.0,
    };

    /// Whether the point moves at all.
    pub fn moves(&self) -> bool {
        self.reach > 0.0 && self.dv != Vec3::ZERO
    }
}

/// `normalize(A + B)` at ring point `i` (eqs. 3-23 to 3-25) and its reach,
/// [`RIPPLE_REACH_SHARE`] of the distance along it to the segment between
/// the neighbours; `None` on
/// that segment (within `still`), at an end, or with a zero-length leg.
fn bisector(pts: &[Vec3], poly: &Polygon, i: usize, still: f64) -> Option<(Vec3, f64)> {
    let (pa, pb) = (pts[poly.at(i, -1)?], pts[poly.at(i, 1)?]);
    let p = pts[i];
    if point_segment_distance(p, pa, pb) <= still {
        return None;
    }
    let (la, lb) = ((pa - p).norm(), (pb - p).norm());
    let a = (pa - p).normalized(0.0)?;
    let b = (pb - p).normalized(0.0)?;
    let dv = (a + b).normalized(0.0)?;
    // Angle bisector theorem: the bisector meets segment A B at
    // A + (B - A) |PA| / (|PA| + |PB|).
    let q = pa + (pb - pa) * (la / (la + lb));
    Some((dv, RIPPLE_REACH_SHARE * (q - p).norm()))
}

/// The direction of each ring point (see the module documentation).
/// `pinned[i]`: ring point `i` never moves. `legs`: the original lengths
/// of the two end legs ([`Polygon::end_legs`]).
pub fn directions(
    pts: &[Vec3],
    poly: &Polygon,
    cats: &Categories,
    pinned: &[bool],
    ends: EndRule,
    legs: [f64; 2],
    still: f64,
) -> Vec<Direction> {
    let n = poly.n;
    let mut out = vec![Direction::STILL; n];
    let ripple = |i: usize| -> Direction {
        bisector(pts, poly, i, still)
            .map_or(Direction::STILL, |(dv, reach)| Direction { dv, reach })
    };
    // Apex directions first: the other smooth points use them.
    let mut apex = vec![Direction::STILL; cats.groups.len()];
    for (g, grp) in cats.groups.iter().enumerate() {
        match grp.apex2 {
            None => {
                apex[g] = ripple(grp.apex);
                out[grp.apex] = apex[g];
            }
            Some(a2) => {
                let a1 = grp.apex;
                let (before, after) = (poly.at(a1, -1), poly.at(a2, 1));
                let dv = match ((pts[a2] - pts[a1]).normalized(still), after) {
                    (Some(e), Some(q)) => {
                        let d = pts[q] - pts[a2];
                        (d - e * d.dot(e)).normalized(still).unwrap_or(Vec3::ZERO)
                    }
                    _ => Vec3::ZERO,
                };
                // Reach: half the way from the apexes' middle to the chord
                // of their outer neighbours.
                let reach = match (before, after) {
                    (Some(b), Some(a)) => {
                        let mid = (pts[a1] + pts[a2]) * 0.5;
                        RIPPLE_REACH_SHARE * point_segment_distance(mid, pts[b], pts[a])
                    }
                    _ => 0.0,
                };
                apex[g] = Direction { dv, reach };
                out[a1] = apex[g];
                out[a2] = apex[g];
            }
        }
    }
    for i in 0..n {
        out[i] = match cats.of[i] {
            Category::End => Direction::STILL,
            Category::Ripple => ripple(i),
            Category::Smooth {
                role: Role::Apex, ..
            } => out[i],
            Category::Smooth { group, .. } => {
                let apex = apex[group];
                if !apex.moves() {
                    Direction::STILL
                } else {
                    let outward = match bisector(pts, poly, i, 0.0) {
                        Some((dv, _)) => -dv,
                        None => Vec3::ZERO,
                    };
                    match (outward + apex.dv * APEX_WEIGHT).normalized(0.0) {
                        Some(dv) => Direction {
                            dv,
                            reach: apex.reach,
                        },
                        None => Direction::STILL,
                    }
                }
            }
        };
        if pinned[i] {
            out[i] = Direction::STILL;
        }
    }
    if ends == EndRule::SlideAlongTangent {
        for (k, &(e, s)) in poly.end_legs().iter().enumerate() {
            if pinned[s] || !out[s].moves() {
                continue;
            }
            let Some(t) = (pts[s] - pts[e]).normalized(0.0) else {
                out[s] = Direction::STILL;
                continue;
            };
            let along = out[s].dv.dot(t);
            let dv = t * along;
            // Towards the end: stop at MIN_END_LEG_SHARE of the leg.
            let room = (pts[s] - pts[e]).norm() - MIN_END_LEG_SHARE * legs[k];
            let reach = if along < 0.0 {
                (room.max(0.0) / -along).min(out[s].reach)
            } else {
                out[s].reach
            };
            out[s] = Direction { dv, reach };
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::categories::categorize;
    use super::*;

    fn xy(pts: &[(f64, f64)]) -> Vec<Vec3> {
        pts.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect()
    }

    #[test]
    fn ripple_points_aim_at_the_chord_of_their_neighbours() {
        let p = xy(&[(0., 0.), (1., 0.), (2., 1.), (3., 0.), (4., 0.), (5., 0.)]);
        let poly = Polygon::new(6, false);
        let (dv, reach) = bisector(&p, &poly, 2, 1e-9).unwrap();
        assert!(dv.dist(Vec3::new(0.0, -1.0, 0.0)) < 1e-12);
        assert!((reach - RIPPLE_REACH_SHARE).abs() < 1e-12);
        // On the chord: no direction.
        assert!(bisector(&p, &poly, 4, 1e-9).is_none());
    }

    /// Non-apex smooth points move mostly along the apex (9 to 1).
    #[test]
    fn smooth_points_follow_the_apex() {
        let arc: Vec<Vec3> = (0..9)
            .map(|i| {
                let a = core::f64::consts::PI * i as f64 / 8.0;
                Vec3::new(-libm::cos(a), libm::sin(a), 0.0)
            })
            .collect();
        let poly = Polygon::new(9, false);
        let cats = categorize(&arc, &poly, 1e-9);
        assert_eq!(cats.groups[0].apex, 4);
        let pinned = [false; 9];
        let d = directions(&arc, &poly, &cats, &pinned, EndRule::Pinned, [1.0; 2], 1e-9);
        // Apex (0, 1): towards the centre.
        assert!(d[4].dv.dist(Vec3::new(0.0, -1.0, 0.0)) < 1e-12);
        // Point 2: outward bisector plus 9 apex.
        let out = -bisector(&arc, &poly, 2, 0.0).unwrap().0;
        let want = (out + Vec3::new(0.0, -9.0, 0.0)).normalized(0.0).unwrap();
        assert!(d[2].dv.dist(want) < 1e-12);
        assert!(d[0].dv == Vec3::ZERO && d[8].dv == Vec3::ZERO);
    }

    #[test]
    fn sliding_keeps_the_end_tangent() {
        let p = xy(&[(0., 0.), (1., 0.5), (2., -1.), (3., 0.), (4., 0.)]);
        let poly = Polygon::new(5, false);
        let cats = categorize(&p, &poly, 1e-9);
        let d = directions(
            &p,
            &poly,
            &cats,
            &[false; 5],
            EndRule::SlideAlongTangent,
            [p[1].norm(), 1.0],
            1e-9,
        );
        let t = p[1].normalized(0.0).unwrap();
        assert!(d[1].dv.cross(t).norm() < 1e-12);
    }
}
