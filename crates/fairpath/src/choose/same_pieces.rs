//! Whether two smoothed runs are the same pieces bit for bit, so that
//! `auto` costs a candidate once when several candidates smooth a run to
//! the same pieces (a run without dense sections is the same under every
//! fit as under `bspline-corner`, say).
//!
//! Bit equality, not `==`: the objective is a pure function of the pieces'
//! bits, so equal bits give the same cost to the bit, while `==` would
//! take `0.0` for `-0.0`.

use crate::geom::{Arc, Curve, Line, Nurbs, Vec3};
use crate::path::Piece;

fn f(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits()
}

fn v(a: Vec3, b: Vec3) -> bool {
    f(a.x, b.x) && f(a.y, b.y) && f(a.z, b.z)
}

fn line(a: &Line, b: &Line) -> bool {
    v(a.p0, b.p0) && v(a.p1, b.p1)
}

fn arc(a: &Arc, b: &Arc) -> bool {
    let Arc {
        center,
        normal,
        u,
        r0,
        r1,
        sweep,
        rise,
        p0,
        p1,
    } = *a;
    v(center, b.center)
        && v(normal, b.normal)
        && v(u, b.u)
        && f(r0, b.r0)
        && f(r1, b.r1)
        && f(sweep, b.sweep)
        && f(rise, b.rise)
        && v(p0, b.p0)
        && v(p1, b.p1)
}

fn nurbs(a: &Nurbs, b: &Nurbs) -> bool {
    let floats =
        |x: &[f64], y: &[f64]| x.len() == y.len() && x.iter().zip(y).all(|(p, q)| f(*p, *q));
    a.degree == b.degree
        && floats(&a.knots, &b.knots)
        && a.points.len() == b.points.len()
        && a.points.iter().zip(&b.points).all(|(p, q)| v(*p, *q))
        && match (&a.weights, &b.weights) {
            (None, None) => true,
            (Some(x), Some(y)) => floats(x, y),
            _ => false,
        }
}

fn curve(a: &Curve, b: &Curve) -> bool {
    match (a, b) {
        (Curve::Line(a), Curve::Line(b)) => line(a, b),
        (Curve::Arc(a), Curve::Arc(b)) => arc(a, b),
        (Curve::Nurbs(a), Curve::Nurbs(b)) => nurbs(a, b),
        _ => false,
    }
}

fn piece(a: &Piece, b: &Piece) -> bool {
    let Piece {
        curve: c,
        rapid,
        source_lines,
        feed,
    } = a;
    curve(c, &b.curve)
        && *rapid == b.rapid
        && *source_lines == b.source_lines
        && match (feed, b.feed) {
            (None, None) => true,
            (Some(x), Some(y)) => f(*x, y),
            _ => false,
        }
}

/// Whether `a` and `b` are the same pieces, every number bit for bit.
pub(super) fn same_pieces(a: &[Piece], b: &[Piece]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(p, q)| piece(p, q))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run() -> alloc::vec::Vec<Piece> {
        let p = |x: f64, y: f64| Vec3::new(x, y, 0.0);
        let z = Vec3::new(0.0, 0.0, 1.0);
        let arc = Arc::from_center(p(1.0, 0.0), p(0.0, 1.0), p(0.0, 0.0), z, false, 0, 1e-9);
        let nurbs = Nurbs::new(
            3,
            alloc::vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
            alloc::vec![p(0.0, 1.0), p(-1.0, 1.0), p(-1.0, 2.0), p(-2.0, 2.0)],
            None,
        )
        .unwrap();
        let piece = |curve| Piece {
            curve,
            rapid: false,
            source_lines: (3, 4),
            feed: Some(100.0),
        };
        alloc::vec![
            piece(Curve::Line(Line::new(p(2.0, 0.0), p(1.0, 0.0)))),
            piece(Curve::Arc(arc.unwrap())),
            piece(Curve::Nurbs(nurbs)),
        ]
    }

    #[test]
    fn equal_runs_are_the_same_and_any_change_is_seen() {
        let a = run();
        assert!(same_pieces(&a, &a.clone()));
        assert!(!same_pieces(&a, &a[..2]));
        let mut b = a.clone();
        b[0].feed = None;
        assert!(!same_pieces(&a, &b));
        let mut b = a.clone();
        b[1].source_lines.1 = 5;
        assert!(!same_pieces(&a, &b));
        let mut b = a.clone();
        if let Curve::Nurbs(n) = &mut b[2].curve {
            n.knots[4] = 0.5;
        }
        assert!(!same_pieces(&a, &b));
        let mut b = a.clone();
        if let Curve::Line(l) = &mut b[0].curve {
            l.p0.z = -0.0;
        }
        // `==` takes -0.0 for 0.0; the bits do not.
        assert_eq!(a, b);
        assert!(!same_pieces(&a, &b));
    }
}
