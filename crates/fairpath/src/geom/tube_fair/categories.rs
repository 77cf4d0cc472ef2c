//! Categories of the control points (thesis section 3.5, "3.3" in the
//! checklist): ends, ripple points and smooth points, recomputed every
//! iteration from the shape of the control polygon.
//!
//! * **Ends**: the first and last point (the seam of a closed path).
//! * **The four-point case**: with only four control points (one Bezier
//!   curve) the two middle points are ripples.
//! * **Line test 1** (eqs. 3-7 to 3-10): the line through `P(i-1)` and
//!   `P(i)`; if `P(i-2)` and `P(i+1)` lie on opposite sides, `P(i)` is a
//!   ripple point. **Line test 2** (eqs. 3-11 to 3-13): else the line
//!   through `P(i)` and `P(i+1)` with `P(i-1)` and `P(i+2)`. If both find
//!   the two points on the same side, `P(i)` is a **primary smooth** point
//!   and its two neighbours **secondary smooth** points (smooth overrides
//!   ripple; ends stay ends). The second and second-to-last points cannot
//!   be tested (no `P(i-2)` or `P(i+2)`): they are ripples unless next to
//!   a primary smooth point.
//! * **Smooth groups**: maximal runs of adjacent smooth points, with a
//!   beginning (first), an ending (last), one apex (odd count `n_s`:
//!   `i_b + (n_s - 1) / 2`, eq. 3-14) or two (even: `i_b + n_s/2 - 1` and
//!   `i_b + n_s/2`, eqs. 3-15, 3-16), and middle points.
//!
//! Choices where the thesis is silent, as a CNC engineer would make them:
//! * **A zero sign** (a point on the line, or a leg too short to define
//!   one): "on the line" counts as *not on the same side*, so the point is
//!   a ripple. A polygon running straight is no arc to flatten; a ripple
//!   point on the line through its neighbours gets a zero direction (the
//!   thesis' collinear rule, [`super::directions`]). "On the line" means
//!   within `flat` mm (the caller passes `accuracy * R`: moving such a
//!   point onto the line moves the curve by less than the accuracy asked
//!   for).
//! * **Adjacent smooth groups** with no ripple between them (the thesis'
//!   Figure 3-9, two arcs meeting): a run of smooth points is cut where the
//!   polygon's turning direction changes sign (the turn vectors
//!   `(P_i - P_(i-1)) x (P_(i+1) - P_i)` of two neighbours point into
//!   opposite half-spaces), so an S-bend makes two groups, each with its
//!   own apex, instead of one whose apex would sit on the inflection.
//! * **3D** (the thesis is 2D; its 5.1.2 sketches two orthogonal planes per
//!   line): "the same side of the line" is the sign of the dot product of
//!   the two points' offsets perpendicular to the line. In a plane the
//!   offsets are parallel to the plane's normal of the line, and the dot
//!   product's sign is the product of the thesis' signed distances
//!   (eq. 3-8), so a planar path gives exactly the thesis' categories in
//!   any orientation; a twisted polygon counts as turning one way while
//!   its offsets make an acute angle. Only dot products and lengths are
//!   used: the categories do not change when the path is rotated.
//! * **Closed paths**: indices wrap ([`Polygon`]); the seam is an end (it
//!   is pinned), so groups never run across it.

use super::polygon::Polygon;
use crate::geom::Vec3;
use alloc::vec;
use alloc::vec::Vec;

/// Where two points lie relative to a line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Both off the line, on the same side.
    Same,
    /// Both off the line, on opposite sides.
    Opposite,
    /// One of them on the line (within `flat`), or no line (a leg
    /// shorter than `flat`): the thesis' zero sign.
    On,
}

/// The thesis' line test (eqs. 3-7 to 3-13) in 3D: the line through `a`
/// and `b`; on which sides do `p` and `q` lie? Offsets of `flat` mm or
/// less from the line count as on it.
pub fn line_test(a: Vec3, b: Vec3, p: Vec3, q: Vec3, flat: f64) -> Side {
    let Some(e) = (b - a).normalized(flat) else {
        return Side::On;
    };
    let off = |x: Vec3| {
        let d = x - a;
        d - e * d.dot(e)
    };
    let (u, v) = (off(p), off(q));
    if u.norm() <= flat || v.norm() <= flat {
        Side::On
    } else if u.dot(v) > 0.0 {
        Side::Same
    } else {
        Side::Opposite
    }
}

/// A point's place in its smooth group.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    Beginning,
    Middle,
    /// One of the one or two median points.
    Apex,
    Ending,
}

/// The category of one control point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Category {
    /// An end of the polygon (the seam of a closed one).
    End,
    /// A ripple point.
    Ripple,
    /// A smooth point of group `group` (an index into
    /// [`Categories::groups`]), primary or secondary.
    Smooth {
        group: usize,
        role: Role,
        primary: bool,
    },
}

/// A smooth group: ring points `first..=last` (never across the seam).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SmoothGroup {
    pub first: usize,
    pub last: usize,
    /// The apex (eq. 3-14), or the first of a double apex (eq. 3-15).
    pub apex: usize,
    /// The second apex of a double apex (eq. 3-16).
    pub apex2: Option<usize>,
}

impl SmoothGroup {
    fn new(first: usize, last: usize) -> SmoothGroup {
        let ns = last - first + 1;
        if ns % 2 == 1 {
            SmoothGroup {
                first,
                last,
                apex: first + (ns - 1) / 2,
                apex2: None,
            }
        } else {
            SmoothGroup {
                first,
                last,
                apex: first + ns / 2 - 1,
                apex2: Some(first + ns / 2),
            }
        }
    }
}

/// The categories of all ring points and the smooth groups.
#[derive(Clone, Debug, PartialEq)]
pub struct Categories {
    pub of: Vec<Category>,
    pub groups: Vec<SmoothGroup>,
}

/// Categorises the ring points `pts` (see the module documentation);
/// `flat` (mm) is how close to a line counts as on it.
pub fn categorize(pts: &[Vec3], poly: &Polygon, flat: f64) -> Categories {
    let n = poly.n;
    let mut primary = vec![false; n];
    // The four-point case (one Bezier curve): both middle points are
    // ripples, so nothing is tested.
    let four_point = !poly.closed && n == 4;
    if !four_point {
        for (i, prim) in primary.iter_mut().enumerate() {
            if poly.is_end(i) {
                continue;
            }
            let at = |k: isize| poly.at(i, k);
            let (Some(m2), Some(m1), Some(p1), Some(p2)) = (at(-2), at(-1), at(1), at(2)) else {
                continue; // second or second-to-last point: not tested
            };
            let test1 = line_test(pts[m1], pts[i], pts[m2], pts[p1], flat);
            *prim = test1 == Side::Same
                && line_test(pts[i], pts[p1], pts[m1], pts[p2], flat) == Side::Same;
        }
    }
    let smooth: Vec<bool> = (0..n)
        .map(|i| {
            !poly.is_end(i)
                && (primary[i]
                    || [-1, 1]
                        .iter()
                        .any(|&k| poly.at(i, k).is_some_and(|j| primary[j])))
        })
        .collect();
    let turn = |i: usize| -> Option<Vec3> {
        let (a, b) = (poly.at(i, -1)?, poly.at(i, 1)?);
        Some((pts[i] - pts[a]).cross(pts[b] - pts[i]))
    };
    let mut groups = Vec::new();
    let mut i = 0;
    while i < n {
        if !smooth[i] {
            i += 1;
            continue;
        }
        let first = i;
        while i + 1 < n && smooth[i + 1] {
            // A change of turning direction ends the group (adjacent groups).
            let flips = matches!((turn(i), turn(i + 1)), (Some(a), Some(b)) if a.dot(b) < 0.0);
            if flips {
                break;
            }
            i += 1;
        }
        groups.push(SmoothGroup::new(first, i));
        i += 1;
    }
    let mut of: Vec<Category> = (0..n)
        .map(|i| {
            if poly.is_end(i) {
                Category::End
            } else {
                Category::Ripple
            }
        })
        .collect();
    for (g, grp) in groups.iter().enumerate() {
        for (j, cat) in of.iter_mut().enumerate().take(grp.last + 1).skip(grp.first) {
            let role = if j == grp.apex || Some(j) == grp.apex2 {
                Role::Apex
            } else if j == grp.first {
                Role::Beginning
            } else if j == grp.last {
                Role::Ending
            } else {
                Role::Middle
            };
            *cat = Category::Smooth {
                group: g,
                role,
                primary: primary[j],
            };
        }
    }
    Categories { of, groups }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn xy(pts: &[(f64, f64)]) -> Vec<Vec3> {
        pts.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect()
    }

    #[test]
    fn line_tests_in_the_plane_and_tilted() {
        let (a, b) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
        let up = Vec3::new(-1.0, 1.0, 0.0);
        let up2 = Vec3::new(2.0, 0.5, 0.0);
        let down = Vec3::new(2.0, -0.5, 0.0);
        assert_eq!(line_test(a, b, up, up2, 1e-9), Side::Same);
        assert_eq!(line_test(a, b, up, down, 1e-9), Side::Opposite);
        assert_eq!(
            line_test(a, b, up, Vec3::new(3.0, 0.0, 0.0), 1e-9),
            Side::On
        );
        assert_eq!(line_test(a, a, up, down, 1e-9), Side::On);
        // Rotated about any axis: the same answers.
        let rot = |p: Vec3| Vec3::new(p.x, 0.6 * p.y - 0.8 * p.z, 0.8 * p.y + 0.6 * p.z);
        assert_eq!(
            line_test(rot(a), rot(b), rot(up), rot(up2), 1e-9),
            Side::Same
        );
        assert_eq!(
            line_test(rot(a), rot(b), rot(up), rot(down), 1e-9),
            Side::Opposite
        );
    }

    /// A saw-tooth is all ripples; an arc is one smooth group with the
    /// thesis' roles (its Figure 3-15: beginning, middle, two apexes).
    #[test]
    fn saw_tooth_ripples_and_arc_groups() {
        let saw = xy(&[
            (0., 0.),
            (1., 1.),
            (2., 0.),
            (3., 1.),
            (4., 0.),
            (5., 1.),
            (6., 0.),
        ]);
        let c = categorize(&saw, &Polygon::new(7, false), 1e-9);
        assert!(c.groups.is_empty());
        assert_eq!(c.of[0], Category::End);
        assert!(c.of[1..6].iter().all(|&k| k == Category::Ripple));
        // Eight points on a circle: points 2..=5 are primary, 1..=6 smooth.
        let arc: Vec<Vec3> = (0..8)
            .map(|i| {
                let a = core::f64::consts::PI * i as f64 / 7.0;
                Vec3::new(-libm::cos(a), libm::sin(a), 0.0)
            })
            .collect();
        let c = categorize(&arc, &Polygon::new(8, false), 1e-9);
        assert_eq!(c.groups.len(), 1);
        let g = c.groups[0];
        assert_eq!((g.first, g.last, g.apex, g.apex2), (1, 6, 3, Some(4)));
        let roles: Vec<Role> = c.of[1..7]
            .iter()
            .map(|k| match k {
                Category::Smooth { role, .. } => *role,
                _ => panic!("{k:?}"),
            })
            .collect();
        use Role::*;
        assert_eq!(roles, [Beginning, Middle, Apex, Apex, Middle, Ending]);
    }

    /// The four-point case: both middle points are ripples.
    #[test]
    fn four_points_are_two_ripples() {
        let p = xy(&[(0., 0.), (1., 1.), (2., 1.), (3., 0.)]);
        let c = categorize(&p, &Polygon::new(4, false), 1e-9);
        assert_eq!(
            c.of,
            [
                Category::End,
                Category::Ripple,
                Category::Ripple,
                Category::End
            ]
        );
    }

    /// An S-bend: two arcs turning opposite ways with no ripple between
    /// make two groups, cut where the turning direction changes.
    #[test]
    fn an_s_bend_is_two_groups() {
        let mut pts = Vec::new();
        for i in 0..7 {
            let a = core::f64::consts::PI * i as f64 / 6.0;
            pts.push(Vec3::new(-libm::cos(a), libm::sin(a), 0.0));
        }
        for i in 1..7 {
            let a = core::f64::consts::PI * i as f64 / 6.0;
            pts.push(Vec3::new(2.0 - libm::cos(a), -libm::sin(a), 0.0));
        }
        let c = categorize(&pts, &Polygon::new(pts.len(), false), 1e-9);
        assert_eq!(c.groups.len(), 2, "{:?}", c.groups);
        assert!(c.groups[0].last < c.groups[1].first);
    }

    /// Points on a straight line are ripples (the zero sign).
    #[test]
    fn straight_points_are_ripples() {
        let p = xy(&[(0., 0.), (1., 0.), (2., 0.), (3., 0.), (4., 0.), (5., 0.)]);
        let c = categorize(&p, &Polygon::new(6, false), 1e-9);
        assert!(c.groups.is_empty());
    }
}
