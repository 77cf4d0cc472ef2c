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
    /// Index of the path's piece it is part of.
    piece: usize,
}

/// The path as segments (see the module docs).
fn segments(path: &[Piece], accuracy: f64) -> Vec<Segment> {
    let mut out = Vec::new();
    for (piece, p) in path.iter().enumerate() {
        match &p.curve {
            Curve::Line(l) => out.push(Segment {
                a: l.p0,
                b: l.p1,
                shrink: 0.0,
                piece,
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
                        piece,
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
    entries(&segments(path, accuracy), gates).is_some()
}

/// The segment at which the path enters each gate, taking each as early
/// as possible after the previous one; `None` where some gate is not
/// passed in order.
fn entries(segs: &[Segment], gates: &[(Vec3, f64)]) -> Option<Vec<usize>> {
    let (mut k, mut u) = (0usize, 0.0f64);
    let mut out = Vec::with_capacity(gates.len());
    'gates: for &(q, radius) in gates {
        while k < segs.len() {
            if let Some(t) = entry(&segs[k], q, radius, u) {
                u = t;
                out.push(k);
                continue 'gates;
            }
            k += 1;
            u = 0.0;
        }
        return None;
    }
    Some(out)
}

/// [`follows_in_order`], and every piece of the path runs no faster
/// (`speed_of`, mm/s) than the cap of each stretch between gates it is
/// part of: `caps[i]` from entering gate `i - 1` to entering gate `i`,
/// `caps[0]` from the path's start, the last to its end (the feeds of
/// [`crate::feed::lower_bound::InOrderGates`]). A piece holding a gate's
/// entry counts on both sides of it. The entries are the earliest ones
/// in order, as [`follows_in_order`] takes them: `true` is never wrong
/// (that order of passing has every stretch within its cap), and a path
/// that some later choice of entries would pass may be reported `false`.
pub fn follows_in_order_within(
    path: &[Piece],
    gates: &[(Vec3, f64)],
    caps: &[f64],
    speed_of: impl Fn(&Piece) -> f64,
    accuracy: f64,
) -> bool {
    if caps.len() != gates.len() + 1 || path.is_empty() {
        return false;
    }
    let segs = segments(path, accuracy);
    let Some(at) = entries(&segs, gates) else {
        return false;
    };
    // Piece ranges of each stretch: from the piece holding the previous
    // entry (or the first) to the one holding the next (or the last).
    let piece_at = |k: usize| segs.get(k).map_or(path.len() - 1, |s| s.piece);
    let mut from = 0;
    for (i, &cap) in caps.iter().enumerate() {
        let to = at.get(i).map_or(path.len() - 1, |&k| piece_at(k));
        if path[from..=to.max(from)].iter().any(|p| speed_of(p) > cap) {
            return false;
        }
        from = to;
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
    fn each_stretch_between_entries_keeps_its_cap() {
        // Two lines at 10 and 20 mm/s; gates at x = 5 and x = 15.
        let mut p = [
            line(Vec3::new(0.0, 0.0, 0.0), Vec3::new(10.0, 0.0, 0.0)),
            line(Vec3::new(10.0, 0.0, 0.0), Vec3::new(20.0, 0.0, 0.0)),
        ];
        p[0].feed = Some(600.0);
        p[1].feed = Some(1200.0);
        let speed = |q: &Piece| q.feed.unwrap_or(0.0) / 60.0;
        let gates = [
            (Vec3::new(5.0, 0.0, 0.0), 0.01),
            (Vec3::new(15.0, 0.0, 0.0), 0.01),
        ];
        // Between the gates both pieces count, so the middle cap must
        // allow the faster.
        assert!(follows_in_order_within(
            &p,
            &gates,
            &[10.0, 20.0, 20.0],
            speed,
            1e-4
        ));
        assert!(!follows_in_order_within(
            &p,
            &gates,
            &[10.0, 10.0, 20.0],
            speed,
            1e-4
        ));
        // Before the first gate only the first piece: 10 is enough there;
        // after the last only the second.
        assert!(!follows_in_order_within(
            &p,
            &gates,
            &[10.0, 20.0, 10.0],
            speed,
            1e-4
        ));
        // One cap per stretch, or no answer but `false`.
        assert!(!follows_in_order_within(
            &p,
            &gates,
            &[20.0, 20.0],
            speed,
            1e-4
        ));
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
