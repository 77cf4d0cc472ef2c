//! Whether a path follows a run in order: it passes within its radius of
//! each of a sequence of gates on the run, one after the other.
//!
//! The one-sided deviation of [`super::verify_run`] lets a path cut
//! across where the run comes back near itself (on a closed contour, a
//! path that never leaves the start point is within any tolerance). A
//! lower bound of the time of paths that follow the run in order
//! ([`crate::feed::lower_bound::BandPaths::InOrder`]) holds for a path
//! only if it passes that bound's gates in order: this checks it.
//!
//! Method: the path is cut into segments (lines as they are; arcs and
//! curves flattened within `accuracy`, their segments held to the radius
//! less `accuracy`, so a segment point inside counts only if a point of
//! the curve is inside too), and each gate is taken at the earliest point
//! after the previous gate's where a segment enters its ball. Taking each
//! gate as early as possible leaves the most path for the ones after it,
//! so the greedy scan finds an order whenever one exists on the segments.

use crate::geom::{flatten_params, Curve, ParamCurve, Vec3};
use crate::math;
use crate::path::Piece;
use alloc::vec::Vec;

/// One segment of the path and how much a gate's radius shrinks on it.
struct Segment {
    a: Vec3,
    b: Vec3,
    shrink: f64,
}

/// The path as segments (see the module docs).
fn segments(path: &[Piece], accuracy: f64) -> Vec<Segment> {
    let mut out = Vec::new();
    for p in path {
        match &p.curve {
            Curve::Line(l) => out.push(Segment {
                a: l.p0,
                b: l.p1,
                shrink: 0.0,
            }),
            c => {
                let pts: Vec<Vec3> = flatten_params(c, accuracy)
                    .into_iter()
                    .map(|t| c.eval(t))
                    .collect();
                for w in pts.windows(2) {
                    out.push(Segment {
                        a: w[0],
                        b: w[1],
                        shrink: accuracy,
                    });
                }
            }
        }
    }
    out
}

/// The earliest parameter in `[u0, 1]` at which the segment `s` is within
/// `radius` (less its shrink) of `q`, if any.
fn entry(s: &Segment, q: Vec3, radius: f64, u0: f64) -> Option<f64> {
    let radius = radius - s.shrink;
    if radius < 0.0 {
        return None;
    }
    let d = s.b - s.a;
    let f = s.a - q;
    let r2 = radius * radius;
    let at = |t: f64| (f + d * t).norm_sq();
    if at(u0) <= r2 {
        return Some(u0);
    }
    // |f + d t|^2 = r^2: the smaller root is where the segment enters.
    let (a, b, c) = (d.norm_sq(), f.dot(d), f.norm_sq() - r2);
    let disc = b * b - a * c;
    if a <= 0.0 || disc < 0.0 {
        return None;
    }
    let t = (-b - math::sqrt(disc)) / a;
    (t >= u0 && t <= 1.0).then_some(t)
}

/// Whether `path` passes within its radius of every gate (a point and a
/// radius) of `gates`, in their order; `accuracy` (mm) bounds the
/// flattening of its arcs and curves, and a gate counts only where the
/// flattened path is within the radius less `accuracy` of it on them (so
/// `true` is never wrong; a path that passes a gate closer than `accuracy`
/// to its radius may be reported `false`).
pub fn follows_in_order(path: &[Piece], gates: &[(Vec3, f64)], accuracy: f64) -> bool {
    let segs = segments(path, accuracy);
    let (mut k, mut u) = (0usize, 0.0f64);
    'gates: for &(q, radius) in gates {
        while k < segs.len() {
            if let Some(t) = entry(&segs[k], q, radius, u) {
                u = t;
                continue 'gates;
            }
            k += 1;
            u = 0.0;
        }
        return false;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Line;

    fn line(a: Vec3, b: Vec3) -> Piece {
        Piece {
            curve: Curve::Line(Line::new(a, b)),
            rapid: false,
            source_lines: (1, 1),
            feed: None,
        }
    }

    #[test]
    fn a_line_passes_its_own_points_in_order_and_not_reversed() {
        let p = [line(Vec3::new(0.0, 0.0, 0.0), Vec3::new(10.0, 0.0, 0.0))];
        let gates: Vec<(Vec3, f64)> = (1..10)
            .map(|i| (Vec3::new(i as f64, 0.0, 0.0), 0.01))
            .collect();
        assert!(follows_in_order(&p, &gates, 1e-4));
        let back: Vec<(Vec3, f64)> = gates.iter().rev().copied().collect();
        assert!(!follows_in_order(&p, &back, 1e-4));
    }

    #[test]
    fn the_earliest_entry_is_taken() {
        // A gate reached at the start of a segment and another further on
        // the same segment: both in order.
        let p = [line(Vec3::new(0.0, 0.0, 0.0), Vec3::new(10.0, 0.0, 0.0))];
        let gates = |r: f64| {
            [
                (Vec3::new(0.0, 0.05, 0.0), r),
                (Vec3::new(5.0, 0.05, 0.0), r),
            ]
        };
        assert!(follows_in_order(&p, &gates(0.1), 1e-4));
        assert!(!follows_in_order(&p, &gates(0.04), 1e-4));
    }
}
