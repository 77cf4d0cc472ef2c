//! A clamped B-spline as its Bezier spans, built one span at a time
//! from the control points and knots the fairing moves (no [`Nurbs`]
//! built per evaluation): the curve, its difference splines (thesis eq.
//! 2-16: `D(t) = sum (P_i - Q_i) N_i(t)`, the same knots) and their
//! samples, bounds and curvature are all read from these.
//!
//! The Bezier control points of span `s` (`u_s < u_{s+1}`) are the blossom
//! (polar form) values `b_j = f(u_s^(3-j), u_(s+1)^j)` (Sederberg, CAGD,
//! ch. 6; the thesis' eq. 2-15), each by de Boor's algorithm with a
//! different argument on each level: O(1) per span, so walking all spans
//! is linear in the number of control points (knot insertion of every
//! breakpoint, as `Nurbs::bezier_spans` does, is quadratic).
//!
//! Cubics, the thesis' curves, take the fast path ([`Span::Cubic`]);
//! other degrees and rational curves ([`Span::General`]) are blossomed in
//! homogeneous coordinates `(w P, w)` (Piegl and Tiller, The NURBS Book,
//! 2nd ed., section 4.2), which the fairing's moves keep the weights of:
//! the difference of two such curves, `sum R_i (P_i - Q_i)` with the
//! rational basis `R_i = w_i N_i / sum w_j N_j`, is the same kind of
//! curve, and positive weights keep each span in the convex hull of its
//! Cartesian Bezier points (ibid., section 4.2, property P4.5), so the
//! sure bound of the tube holds for them too.
//!
//! [`Nurbs`]: crate::geom::Nurbs

use crate::geom::basis::MAX_DEGREE;
use crate::geom::{Nurbs, Vec3};
use alloc::vec::Vec;

/// Degree of the cubics, the thesis' curves.
pub(super) const DEGREE: usize = 3;

/// Bezier coefficients a span of the highest degree has.
const ORDER_MAX: usize = MAX_DEGREE + 1;

/// What the control points of the curve being faired share, and the
/// fairing never changes: knots, degree and weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Basis<'a> {
    /// The clamped knot vector.
    pub knots: &'a [f64],
    /// The degree, 2 to [`MAX_DEGREE`].
    pub degree: usize,
    /// One positive weight per control point, `None` for a polynomial
    /// B-spline.
    pub weights: Option<&'a [f64]>,
}

impl<'a> Basis<'a> {
    /// The basis of a non-rational cubic on `knots`.
    pub fn cubic(knots: &'a [f64]) -> Basis<'a> {
        Basis {
            knots,
            degree: DEGREE,
            weights: None,
        }
    }

    /// The basis of `c` (equal weights are none: the same curve).
    pub fn of(c: &'a Nurbs) -> Basis<'a> {
        let weights = c
            .weights
            .as_deref()
            .filter(|w| w.iter().any(|&x| x != w[0]));
        Basis {
            knots: &c.knots,
            degree: c.degree,
            weights,
        }
    }

    /// Whether this is the thesis' case, a non-rational cubic.
    fn is_cubic(&self) -> bool {
        self.degree == DEGREE && self.weights.is_none()
    }
}

/// Knot indices `s` of the non-empty spans `u_s < u_{s+1}` of a clamped
/// B-spline of `basis` with `count` control points, in order
/// (`p <= s < count`).
pub(super) fn nonempty_spans(basis: &Basis, count: usize) -> Vec<usize> {
    let knots = basis.knots;
    (basis.degree..count)
        .filter(|&s| knots[s] < knots[s + 1])
        .collect()
}

/// A homogeneous point `(w x, w y, w z, w)`.
type Hom = [f64; 4];

fn lerp(a: Hom, b: Hom, t: f64) -> Hom {
    let mut o = [0.0; 4];
    for k in 0..4 {
        o[k] = a[k] * (1.0 - t) + b[k] * t;
    }
    o
}

fn xyz(h: Hom) -> Vec3 {
    Vec3::new(h[0], h[1], h[2])
}

/// One Bezier span of a B-spline, `tau` in `[0, 1]` its parameter.
#[derive(Clone, Copy, Debug)]
pub(super) enum Span {
    /// A non-rational cubic: its four Bezier points.
    Cubic([Vec3; 4]),
    /// Any other degree, or rational: `degree + 1` homogeneous
    /// coefficients.
    General { h: [Hom; ORDER_MAX], degree: usize },
}

impl Span {
    /// The non-empty span `s` of the B-spline (`basis`, `pts`).
    pub(super) fn of(basis: &Basis, pts: &[Vec3], s: usize) -> Span {
        if basis.is_cubic() {
            return Span::Cubic(bezier_of_span(basis.knots, pts, s));
        }
        let (u, p) = (basis.knots, basis.degree);
        let hom = |i: usize| {
            let w = basis.weights.map_or(1.0, |w| w[i]);
            let q = pts[i];
            [q.x * w, q.y * w, q.z * w, w]
        };
        let (a, b) = (u[s], u[s + 1]);
        let mut h = [[0.0; 4]; ORDER_MAX];
        for (j, hj) in h.iter_mut().enumerate().take(p + 1) {
            // The blossom f(a^(p-j), b^j): de Boor's algorithm with those
            // arguments on its p levels.
            let mut d = [[0.0; 4]; ORDER_MAX];
            for (k, dk) in d.iter_mut().enumerate().take(p + 1) {
                *dk = hom(s - p + k);
            }
            for r in 1..=p {
                let t = if r <= p - j { a } else { b };
                for k in (r..=p).rev() {
                    let i = s - p + k;
                    let alpha = (t - u[i]) / (u[i + p + 1 - r] - u[i]);
                    d[k] = lerp(d[k - 1], d[k], alpha);
                }
            }
            *hj = d[p];
        }
        Span::General { h, degree: p }
    }

    /// The point at `tau`.
    pub(super) fn point(&self, tau: f64) -> Vec3 {
        match self {
            Span::Cubic(b) => bezier_point(b, tau),
            Span::General { h, degree } => {
                let mut d = *h;
                for r in 1..=*degree {
                    for k in 0..=degree - r {
                        d[k] = lerp(d[k], d[k + 1], tau);
                    }
                }
                xyz(d[0]) * (1.0 / d[0][3])
            }
        }
    }

    /// First and second derivatives at `tau`.
    pub(super) fn derivs12(&self, tau: f64) -> (Vec3, Vec3) {
        match self {
            Span::Cubic(b) => bezier_derivatives(b, tau),
            Span::General { .. } => {
                let (d1, d2, _) = self.derivs3(tau);
                (d1, d2)
            }
        }
    }

    /// First, second and third derivatives at `tau`: for a rational span
    /// `C = A / W` by the quotient rule, `C' = (A' - W' C) / W`,
    /// `C'' = (A'' - 2 W' C' - W'' C) / W`,
    /// `C''' = (A''' - 3 W' C'' - 3 W'' C' - W''' C) / W` (Piegl and
    /// Tiller eq. 4.8), the derivatives of the numerator and weight those
    /// of Bezier polynomials (`p!/(p-k)!` times the `k`-th differences of
    /// the coefficients, eq. 1.9).
    pub(super) fn derivs3(&self, tau: f64) -> (Vec3, Vec3, Vec3) {
        match self {
            Span::Cubic(b) => {
                let (d1, d2) = bezier_derivatives(b, tau);
                (d1, d2, (b[3] - b[2] * 3.0 + b[1] * 3.0 - b[0]) * 6.0)
            }
            Span::General { h, degree } => {
                let p = *degree;
                // ders[k]: the k-th derivative of (A, W) at tau, k <= 3.
                let mut ders = [[0.0; 4]; 4];
                let mut diff = *h;
                let mut factor = 1.0;
                for (k, dk) in ders.iter_mut().enumerate() {
                    if k > p {
                        break;
                    }
                    // diff[0..=p-k]: the k-th differences; at tau by de
                    // Casteljau on degree p - k.
                    let mut e = diff;
                    for r in 1..=p - k {
                        for i in 0..=p - k - r {
                            e[i] = lerp(e[i], e[i + 1], tau);
                        }
                    }
                    for c in 0..4 {
                        dk[c] = factor * e[0][c];
                    }
                    if k < p {
                        for i in 0..p - k {
                            let next = diff[i + 1];
                            for (x, y) in diff[i].iter_mut().zip(next) {
                                *x = y - *x;
                            }
                        }
                        factor *= (p - k) as f64;
                    }
                }
                let w = ders[0][3];
                let c0 = xyz(ders[0]) * (1.0 / w);
                let (w1, w2, w3) = (ders[1][3], ders[2][3], ders[3][3]);
                let c1 = (xyz(ders[1]) - c0 * w1) * (1.0 / w);
                let c2 = (xyz(ders[2]) - c1 * (2.0 * w1) - c0 * w2) * (1.0 / w);
                let c3 = (xyz(ders[3]) - c2 * (3.0 * w1) - c1 * (3.0 * w2) - c0 * w3) * (1.0 / w);
                (c1, c2, c3)
            }
        }
    }

    /// The two halves split at `tau = 1/2`.
    pub(super) fn split_half(&self) -> (Span, Span) {
        match self {
            Span::Cubic(b) => {
                let (l, r) = split_half(b);
                (Span::Cubic(l), Span::Cubic(r))
            }
            Span::General { h, degree } => {
                let p = *degree;
                let (mut left, mut right) = ([[0.0; 4]; ORDER_MAX], [[0.0; 4]; ORDER_MAX]);
                let mut d = *h;
                for r in 0..=p {
                    left[r] = d[0];
                    right[p - r] = d[p - r];
                    for k in 0..p - r {
                        d[k] = lerp(d[k], d[k + 1], 0.5);
                    }
                }
                (
                    Span::General { h: left, degree: p },
                    Span::General {
                        h: right,
                        degree: p,
                    },
                )
            }
        }
    }

    /// The largest distance of its Cartesian Bezier points from the
    /// origin: a sure bound of the span's (convex hull; positive weights).
    pub(super) fn hull_norm(&self) -> f64 {
        match self {
            Span::Cubic(b) => b.iter().map(|p| p.norm()).fold(0.0, f64::max),
            Span::General { h, degree } => h[..=*degree]
                .iter()
                .map(|c| (xyz(*c) * (1.0 / c[3])).norm())
                .fold(0.0, f64::max),
        }
    }

    /// The first and last points.
    pub(super) fn ends(&self) -> (Vec3, Vec3) {
        match self {
            Span::Cubic(b) => (b[0], b[3]),
            Span::General { h, degree } => (
                xyz(h[0]) * (1.0 / h[0][3]),
                xyz(h[*degree]) * (1.0 / h[*degree][3]),
            ),
        }
    }
}

/// The blossom `f(a, b, c)` of span `s`: de Boor's algorithm with `a`,
/// `b`, `c` on its three levels (symmetric in them).
fn blossom(knots: &[f64], pts: &[Vec3], s: usize, args: [f64; 3]) -> Vec3 {
    let u = knots;
    let mut d = [pts[s - 3], pts[s - 2], pts[s - 1], pts[s]];
    for (r, &t) in (1..=DEGREE).zip(args.iter()) {
        // Level r: d_j = (1 - alpha) d_{j-1} + alpha d_j for j = s-3+r..=s,
        // alpha = (t - u_j) / (u_{j+4-r} - u_j) (de Boor's recurrence; the
        // denominators cover the non-empty span s, so they are positive).
        for k in (r..=DEGREE).rev() {
            let j = s - DEGREE + k;
            let den = u[j + DEGREE + 1 - r] - u[j];
            let alpha = (t - u[j]) / den;
            d[k] = d[k - 1] * (1.0 - alpha) + d[k] * alpha;
        }
    }
    d[DEGREE]
}

/// The Bezier control points of the non-empty span `s` of the cubic
/// B-spline (`knots`, `pts`): the curve on `[u_s, u_{s+1}]` is
/// `sum b_j B_j^3(tau)`, `tau = (t - u_s) / (u_{s+1} - u_s)`.
pub(super) fn bezier_of_span(knots: &[f64], pts: &[Vec3], s: usize) -> [Vec3; 4] {
    let (a, b) = (knots[s], knots[s + 1]);
    [
        blossom(knots, pts, s, [a, a, a]),
        blossom(knots, pts, s, [a, a, b]),
        blossom(knots, pts, s, [a, b, b]),
        blossom(knots, pts, s, [b, b, b]),
    ]
}

/// A cubic Bezier curve at `tau` in `[0, 1]` (de Casteljau).
pub(super) fn bezier_point(b: &[Vec3; 4], tau: f64) -> Vec3 {
    let l = |p: Vec3, q: Vec3| p.lerp(q, tau);
    let (p01, p12, p23) = (l(b[0], b[1]), l(b[1], b[2]), l(b[2], b[3]));
    let (p012, p123) = (l(p01, p12), l(p12, p23));
    l(p012, p123)
}

/// First and second derivatives of a cubic Bezier curve with respect to
/// `tau` (curvature does not depend on the parameterisation, so these
/// give the B-spline's curvature on the span).
pub(super) fn bezier_derivatives(b: &[Vec3; 4], tau: f64) -> (Vec3, Vec3) {
    let d = [b[1] - b[0], b[2] - b[1], b[3] - b[2]];
    let s = 1.0 - tau;
    let d1 = (d[0] * (s * s) + d[1] * (2.0 * s * tau) + d[2] * (tau * tau)) * 3.0;
    let d2 = ((d[1] - d[0]) * s + (d[2] - d[1]) * tau) * 6.0;
    (d1, d2)
}

/// The two halves of a cubic Bezier curve split at `tau = 1/2`.
pub(super) fn split_half(b: &[Vec3; 4]) -> ([Vec3; 4], [Vec3; 4]) {
    let m = |p: Vec3, q: Vec3| (p + q) * 0.5;
    let (p01, p12, p23) = (m(b[0], b[1]), m(b[1], b[2]), m(b[2], b[3]));
    let (p012, p123) = (m(p01, p12), m(p12, p23));
    let mid = m(p012, p123);
    ([b[0], p01, p012, mid], [mid, p123, p23, b[3]])
}

/// The B-spline (`basis`, `pts`) at `t` (in the domain): the Bezier
/// span containing it (the last span at the domain's end).
pub(super) fn eval(basis: &Basis, pts: &[Vec3], t: f64) -> Vec3 {
    let knots = basis.knots;
    let s = if basis.degree == DEGREE {
        crate::geom::cubic_span::span_of(knots, pts.len(), t)
    } else {
        let (p, n) = (basis.degree, pts.len());
        if t >= knots[n] {
            (p..n).rev().find(|&s| knots[s] < knots[n]).unwrap_or(p)
        } else {
            p + knots[p + 1..=n].partition_point(|&k| k <= t)
        }
    };
    let (a, e) = (knots[s], knots[s + 1]);
    Span::of(basis, pts, s).point(((t - a) / (e - a)).clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{Nurbs, ParamCurve};
    use alloc::vec;

    fn curve() -> Nurbs {
        let pts = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 2.0, 0.5),
            Vec3::new(3.0, -1.0, 0.0),
            Vec3::new(4.0, 1.0, 1.0),
            Vec3::new(6.0, 0.5, 0.0),
            Vec3::new(7.0, 3.0, -1.0),
            Vec3::new(9.0, 0.0, 0.0),
        ];
        let knots = vec![0.0, 0.0, 0.0, 0.0, 0.7, 1.0, 1.0, 3.0, 3.0, 3.0, 3.0];
        Nurbs::new(3, knots, pts, None).unwrap()
    }

    #[test]
    fn spans_are_the_curve() {
        let c = curve();
        let spans = nonempty_spans(&Basis::cubic(&c.knots), c.points.len());
        assert_eq!(spans, vec![3, 4, 6]);
        let reference = c.bezier_spans();
        assert_eq!(reference.len(), spans.len());
        for (&s, r) in spans.iter().zip(&reference) {
            let b = bezier_of_span(&c.knots, &c.points, s);
            for (p, q) in b.iter().zip(&r.points) {
                assert!(p.dist(*q) < 1e-12, "{p:?} {q:?}");
            }
        }
        for i in 0..=60 {
            let t = 3.0 * i as f64 / 60.0;
            assert!(eval(&Basis::cubic(&c.knots), &c.points, t).dist(c.eval(t)) < 1e-12);
        }
    }

    #[test]
    fn derivatives_give_the_curvature() {
        let c = curve();
        let s = 6;
        let b = bezier_of_span(&c.knots, &c.points, s);
        let (a, e) = (c.knots[s], c.knots[s + 1]);
        for i in 0..=8 {
            let tau = i as f64 / 8.0;
            let (d1, d2) = bezier_derivatives(&b, tau);
            let k = crate::geom::curvature_from(d1, d2);
            let kr = c.curvature(a + (e - a) * tau);
            assert!((k - kr).abs() <= 1e-9 * kr.max(1.0), "{k} {kr}");
        }
        let (l, r) = split_half(&b);
        assert!(bezier_point(&l, 0.5).dist(bezier_point(&b, 0.25)) < 1e-12);
        assert!(bezier_point(&r, 0.5).dist(bezier_point(&b, 0.75)) < 1e-12);
    }

    /// A quintic and a rational cubic span by span: points, first and
    /// second derivatives as the NURBS evaluates them, the third against a
    /// difference of the second, the halves, and the hull containing the
    /// span.
    #[test]
    fn general_spans_are_the_curve() {
        let pts: Vec<Vec3> = (0..9)
            .map(|i| {
                let x = i as f64;
                Vec3::new(x, (1.3 * x).sin() * 2.0, 0.3 * (0.7 * x).cos())
            })
            .collect();
        let quintic = {
            let mut k = vec![0.0; 6];
            k.extend([0.8, 2.0, 2.0]);
            k.extend(vec![5.0; 6]);
            Nurbs::new(5, k, pts.clone(), None).unwrap()
        };
        let rational = {
            let mut k = vec![0.0; 4];
            k.extend([1.0, 1.7, 3.0, 4.0, 5.5]);
            k.extend(vec![7.0; 4]);
            let w = (0..9).map(|i| [1.0, 0.4, 2.5][i % 3]).collect();
            Nurbs::new(3, k, pts, Some(w)).unwrap()
        };
        for c in [&quintic, &rational] {
            let basis = Basis::of(c);
            for s in nonempty_spans(&basis, c.points.len()) {
                let span = Span::of(&basis, &c.points, s);
                let (a, e) = (c.knots[s], c.knots[s + 1]);
                for i in 0..=10 {
                    let tau = i as f64 / 10.0;
                    let t = a + (e - a) * tau;
                    let d = c.derivs(t);
                    assert!(span.point(tau).dist(d[0]) < 1e-11, "{s} {tau}");
                    assert!(eval(&basis, &c.points, t).dist(d[0]) < 1e-11);
                    let (d1, d2, d3) = span.derivs3(tau);
                    let h = e - a;
                    assert!(d1.dist(d[1] * h) < 1e-9 * (1.0 + d1.norm()), "{s} {tau}");
                    assert!(d2.dist(d[2] * (h * h)) < 1e-8 * (1.0 + d2.norm()));
                    let dt = 1e-5;
                    if (dt..=1.0 - dt).contains(&tau) {
                        let fd =
                            (span.derivs12(tau + dt).1 - span.derivs12(tau - dt).1) * (0.5 / dt);
                        assert!(fd.dist(d3) < 1e-4 * (1.0 + d3.norm()), "{fd:?} {d3:?}");
                    }
                }
                let (l, r) = span.split_half();
                assert!(l.point(0.5).dist(span.point(0.25)) < 1e-12);
                assert!(r.point(0.5).dist(span.point(0.75)) < 1e-12);
                let hull = span.hull_norm();
                assert!((0..=50).all(|i| span.point(i as f64 / 50.0).norm() <= hull + 1e-12));
            }
        }
    }
}
