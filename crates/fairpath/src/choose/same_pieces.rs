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
pub fn same_pieces(a: &[Piece], b: &[Piece]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(p, q)| piece(p, q))
}

/// A 128-bit digest of `pieces`, every number bit for bit (what
/// [`same_pieces`] compares): pieces that differ have different digests
/// but with a chance of about 2^-128, so a cache keyed by it can stand
/// for [`same_pieces`] where holding the pieces themselves would cost.
pub fn pieces_digest(pieces: &[Piece]) -> [u64; 2] {
    let mut d = Digest([0x243f_6a88_85a3_08d3, 0x1319_8a2e_0370_7344]);
    d.word(pieces.len() as u64);
    for p in pieces {
        match &p.curve {
            Curve::Line(l) => {
                d.word(1);
                d.vec(l.p0);
                d.vec(l.p1);
            }
            Curve::Arc(a) => {
                d.word(2);
                for v in [a.center, a.normal, a.u, a.p0, a.p1] {
                    d.vec(v);
                }
                for x in [a.r0, a.r1, a.sweep, a.rise] {
                    d.word(x.to_bits());
                }
            }
            Curve::Nurbs(n) => {
                d.word(3);
                d.word(n.degree as u64);
                d.word(n.knots.len() as u64);
                for k in &n.knots {
                    d.word(k.to_bits());
                }
                d.word(n.points.len() as u64);
                for q in &n.points {
                    d.vec(*q);
                }
                for w in n.weights.iter().flatten() {
                    d.word(w.to_bits());
                }
            }
        }
        d.word(u64::from(p.rapid));
        d.word(p.source_lines.0 as u64);
        d.word(p.source_lines.1 as u64);
        d.word(p.feed.map_or(u64::MAX, f64::to_bits));
    }
    d.0
}

/// Two independent 64-bit mixes (multiply-rotate, as in wyhash and
/// splitmix64) of the words fed to them.
struct Digest([u64; 2]);

impl Digest {
    fn word(&mut self, w: u64) {
        let [a, b] = &mut self.0;
        *a = (*a ^ w).wrapping_mul(0x9e37_79b9_7f4a_7c15).rotate_left(27);
        *b = (b.wrapping_add(w) ^ (*b >> 31)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    }

    fn vec(&mut self, v: Vec3) {
        for x in [v.x, v.y, v.z] {
            self.word(x.to_bits());
        }
    }
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
            piece(Curve::from(arc.unwrap())),
            piece(Curve::from(nurbs)),
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
