//! Gates on the run's gentle curves, for paths in order (module docs,
//! step 1).
//!
//! A path that follows the run in order comes within `e` of every point
//! of it, so a gate of radius `e` may stand anywhere on the run; the
//! straight gates (`gates.rs`) stand only where the run is straight
//! within half a tolerance over the reach, which a curve of radius below
//! about `r^2 / tol` (0.8 mm at 0.05 mm) never is: a glyph's bowl, a
//! small loop, a tight spiral had no gate at all, and their bound fell
//! to the straight-line floor of their length. Where a gate stands is a
//! choice that only matters for which paths the bound applies to
//! ([`crate::verify::follows_in_order`] checks a path passes them): a
//! path that cuts a corner at depth `h` inside the band passes its
//! vertex at `h / cos(theta / 2)` (`theta` the turn), beyond `e` at
//! every sharp corner, as every corner method's transition does. On a
//! curve of radius `R` above the depth, the nearest point of the curve
//! to a point of its normal within `R` is the foot, so a path within `h`
//! of the curve crosses that normal within `h` of it. So a curved gate
//! stands only where the run turns by at most
//! [`super::BoundOptions::curved_turn`] over every stretch of `2e`
//! within the reach (a radius of at least `2e / curved_turn`) and by at
//! most [`super::BoundOptions::curved_vertex_turn`] at each vertex (a
//! coarse polyline's vertex is a corner the corner methods cut: at 0.2
//! rad a cut `h` deep passes it within `1.005 h`, inside `e` wherever
//! the cut is at least 0.4% shallower than the tolerance). The limits
//! only choose which written paths the bound applies to; `compare`
//! checks each (measurements: docs/tuning.md, `BoundOptions::curved_turn`).

use super::gates::{point_at, Gate};
use crate::geom::Vec3;
use alloc::vec::Vec;

/// The turning of a polyline at each vertex and over a window after it.
pub(super) struct Turning {
    /// The turning angle at each vertex (rad; 0 at the ends).
    vertex: Vec<f64>,
    /// The sum of the vertices' turning over arc lengths `[s_v, s_v +
    /// len]` from each vertex `v`.
    windowed: Vec<f64>,
}

/// The [`Turning`] of the polyline `pts` (arc lengths `s`) over windows
/// of `len` mm.
pub(super) fn windowed_turning(pts: &[Vec3], s: &[f64], len: f64) -> Turning {
    let n = pts.len();
    let turn: Vec<f64> = (0..n)
        .map(|v| {
            if v == 0 || v + 1 >= n {
                return 0.0;
            }
            let a = (pts[v] - pts[v - 1]).angle_to(pts[v + 1] - pts[v]);
            if a.is_finite() {
                a
            } else {
                0.0
            }
        })
        .collect();
    let mut out = alloc::vec![0.0f64; n];
    // Two pointers: `acc` sums the turning of vertices `v..j`.
    let (mut j, mut acc) = (0usize, 0.0f64);
    for v in 0..n {
        while j < n && s[j] <= s[v] + len {
            acc += turn[j];
            j += 1;
        }
        out[v] = acc;
        acc -= turn[v];
    }
    Turning {
        vertex: turn,
        windowed: out,
    }
}

/// A gate of radius `e` on the run at arc length `x`, where the run
/// turns by at most `max_turn` (rad) over every stretch of `2e` and by at
/// most `max_vertex` at every vertex within `r` of `x` (`turning`, from
/// [`windowed_turning`] over `2e`); `None` at a sharper turn.
pub(super) fn curved_gate(
    pts: &[Vec3],
    s: &[f64],
    x: f64,
    r: f64,
    e: f64,
    turning: &Turning,
    (max_turn, max_vertex): (f64, f64),
) -> Option<Gate> {
    if max_turn.is_nan() || max_turn <= 0.0 {
        return None;
    }
    // Windows starting up to 2e before the reach cover every stretch of
    // 2e inside it.
    let lo = s.partition_point(|&v| v < x - r - 2.0 * e);
    let hi = s.partition_point(|&v| v <= x + r);
    let at = s.partition_point(|&v| v < x - r);
    if turning.windowed[lo..hi].iter().any(|&t| t > max_turn)
        || turning.vertex[at..hi].iter().any(|&t| t > max_vertex)
    {
        return None;
    }
    Some(Gate {
        at: point_at(pts, s, x),
        radius: e,
        along: x,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arc(r: f64, n: usize, turn: f64) -> (Vec<Vec3>, Vec<f64>) {
        let pts: Vec<Vec3> = (0..=n)
            .map(|k| {
                let a = turn * k as f64 / n as f64;
                Vec3::new(r * a.cos(), r * a.sin(), 0.0)
            })
            .collect();
        let mut s = alloc::vec![0.0];
        for w in pts.windows(2) {
            let last = *s.last().unwrap();
            s.push(last + w[0].dist(w[1]));
        }
        (pts, s)
    }

    #[test]
    fn the_windowed_turning_of_an_arc_is_its_curvature_times_the_window() {
        // A quarter circle of radius 1 mm in 900 chords: 0.1 mm turns by
        // 0.1 rad, give or take one vertex's turn.
        let (pts, s) = arc(1.0, 900, core::f64::consts::FRAC_PI_2);
        let w = windowed_turning(&pts, &s, 0.1);
        let step = core::f64::consts::FRAC_PI_2 / 900.0;
        for &t in &w.vertex[1..900] {
            assert!((t - step).abs() < 1e-9, "{t}");
        }
        for &t in &w.windowed[1..800] {
            assert!((t - 0.1).abs() <= step + 1e-12, "{t}");
        }
    }

    #[test]
    fn a_gentle_arc_holds_a_curved_gate_and_a_corner_does_not() {
        let e = 0.05;
        // Radius 0.3 mm: 2e turns by a third of a radian.
        let (pts, s) = arc(0.3, 300, core::f64::consts::PI);
        let w = windowed_turning(&pts, &s, 2.0 * e);
        let mid = 0.5 * s[s.len() - 1];
        let g = curved_gate(&pts, &s, mid, 0.2, e, &w, (1.0, 0.2)).expect("a gate");
        assert_eq!(g.radius, e);
        assert!(g.at.dist(point_at(&pts, &s, mid)) < 1e-12);
        assert!(curved_gate(&pts, &s, mid, 0.2, e, &w, (0.2, 0.2)).is_none());
        // The same arc in 20 chords: each vertex turns by 0.16 rad.
        let (pts, s) = arc(0.3, 20, core::f64::consts::PI);
        let w = windowed_turning(&pts, &s, 2.0 * e);
        let mid = 0.5 * s[s.len() - 1];
        assert!(curved_gate(&pts, &s, mid, 0.2, e, &w, (1.0, 0.2)).is_some());
        assert!(curved_gate(&pts, &s, mid, 0.2, e, &w, (1.0, 0.1)).is_none());
        // A right angle between two 1 mm legs.
        let pts = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ];
        let s = [0.0, 1.0, 2.0];
        let w = windowed_turning(&pts, &s, 2.0 * e);
        assert!(curved_gate(&pts, &s, 0.9, 0.2, e, &w, (1.0, 0.2)).is_none());
        assert!(curved_gate(&pts, &s, 0.5, 0.2, e, &w, (1.0, 0.2)).is_some());
    }
}
