//! A B-spline or NURBS curve written again, exactly, as a clamped curve of
//! a higher (or the same) degree: degree elevation and clamping by
//! blossoming (polar forms; Ramshaw 1989, Sederberg, CAGD ch. 6; the same
//! result as Piegl and Tiller's A5.9 DegreeElevateCurve and their
//! clamping by knot insertion, section 5.2, computed point by point).
//!
//! A curve of degree `p` on knots `u` is, on each non-empty span, a
//! polynomial whose blossom `f(v_1, ..., v_p)` is symmetric and affine in
//! each argument; its control points are `P_i = f(u_(i+1), ..., u_(i+p))`
//! on any span that the `p` knots reach. The same polynomial as a curve of
//! degree `q > p` has the blossom
//! `F(v_1, ..., v_q) = average over the p-subsets S of {1..q} of f(v_S)`,
//! and the control points `Q_i = F(w_(i+1), ..., w_(i+q))` on the knot
//! vector `w` whose interior knots have the multiplicity they had plus
//! `q - p` (so the curve keeps its continuity at each knot) and whose ends
//! are the domain's ends `q + 1` times (clamped: knots outside the domain
//! are dropped, with the control points they carried). Rational curves are
//! done in homogeneous coordinates.
//!
//! Exact up to rounding: the result evaluates to the same points at the
//! same parameters; its end control points are set to the curve's end
//! points as [`ParamCurve::start`] and [`ParamCurve::end`] give them, bit
//! for bit.

use super::{Nurbs, NurbsError, ParamCurve};
use alloc::vec;
use alloc::vec::Vec;

/// Homogeneous control point `(w x, w y, w z, w)`.
type Hom = [f64; 4];

/// Why a curve cannot be written exactly at a degree.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum ElevateError {
    /// The curve is not a valid NURBS.
    #[error("invalid curve: {0}")]
    Invalid(#[from] NurbsError),
    /// The target degree is below the curve's (not exact in general) or
    /// above [`Nurbs::MAX_DEGREE`].
    #[error("degree {from} cannot be written exactly as degree {to}")]
    Degree { from: usize, to: usize },
    /// An interior knot repeated more than the degree: the curve jumps
    /// there.
    #[error("the curve is not continuous at knot {0}")]
    Discontinuous(f64),
}

/// Whether the knot vector of `c` starts and ends with `degree + 1` equal
/// knots.
pub fn is_clamped(c: &Nurbs) -> bool {
    let (u, p) = (&c.knots, c.degree);
    let k = u.len();
    k > 2 * p + 1
        && u[..=p].iter().all(|&x| x == u[0])
        && u[k - p - 1..].iter().all(|&x| x == u[k - 1])
}

/// `c` as a clamped curve of degree `degree` (at least `c.degree`), the
/// same curve at the same parameters over `c`'s domain (see the module
/// documentation). A curve that jumps at an interior knot (multiplicity
/// above its degree) or at an end of its domain (above the degree plus
/// one) is refused.
pub fn clamped_with_degree(c: &Nurbs, degree: usize) -> Result<Nurbs, ElevateError> {
    c.validate()?;
    let p = c.degree;
    let q = degree;
    if q < p || q > Nurbs::MAX_DEGREE {
        return Err(ElevateError::Degree { from: p, to: q });
    }
    let (a, b) = c.domain();
    for end in [a, b] {
        if c.knots.iter().filter(|&&t| t == end).count() > p + 1 {
            return Err(ElevateError::Discontinuous(end));
        }
    }
    // The knot vector of the result: the domain's ends q + 1 times, each
    // interior break with its multiplicity raised by q - p.
    let mut w = vec![a; q + 1];
    let interior: Vec<f64> = c
        .knots
        .iter()
        .copied()
        .filter(|&t| t > a && t < b)
        .collect();
    let mut i = 0;
    while i < interior.len() {
        let t = interior[i];
        let mult = interior[i..].iter().take_while(|&&x| x == t).count();
        if mult > p {
            return Err(ElevateError::Discontinuous(t));
        }
        w.extend(core::iter::repeat_n(t, mult + q - p));
        i += mult;
    }
    w.extend(core::iter::repeat_n(b, q + 1));
    let count = w.len() - q - 1;
    let hom = homogeneous(c);
    let mut out = Vec::with_capacity(count);
    let mut args = vec![0.0; q];
    for i in 0..count {
        args.copy_from_slice(&w[i + 1..=i + q]);
        // A non-empty span of the result that the q knots reach: among
        // w[i..=i+q+1] (q + 1 intervals, at most q of them empty).
        let k = (i..=i + q).find(|&k| w[k] < w[k + 1]).unwrap_or(q);
        let span = c.find_span(0.5 * (w[k] + w[k + 1]));
        out.push(elevated_blossom(c, &hom, span, &args));
    }
    let rational = c.weights.is_some();
    let mut points: Vec<_> = out
        .iter()
        .map(|h| {
            if rational {
                super::Vec3::new(h[0] / h[3], h[1] / h[3], h[2] / h[3])
            } else {
                super::Vec3::new(h[0], h[1], h[2])
            }
        })
        .collect();
    points[0] = c.start();
    points[count - 1] = c.end();
    let weights = rational.then(|| out.iter().map(|h| h[3]).collect());
    let r = Nurbs::new(q, w, points, weights)?;
    Ok(r)
}

fn homogeneous(c: &Nurbs) -> Vec<Hom> {
    c.points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let w = c.weights.as_ref().map_or(1.0, |w| w[i]);
            [p.x * w, p.y * w, p.z * w, w]
        })
        .collect()
}

/// The blossom of degree `args.len()` of the polynomial of `c` on its
/// span `span`: the average of `c`'s own blossom over every choice of
/// `c.degree` of the arguments.
fn elevated_blossom(c: &Nurbs, hom: &[Hom], span: usize, args: &[f64]) -> Hom {
    let (p, q) = (c.degree, args.len());
    let mut sum = [0.0; 4];
    let mut n = 0usize;
    let mut chosen = Vec::with_capacity(p);
    for mask in 0u32..(1 << q) {
        if mask.count_ones() as usize != p {
            continue;
        }
        chosen.clear();
        chosen.extend((0..q).filter(|&j| mask & (1 << j) != 0).map(|j| args[j]));
        let v = blossom(c, hom, span, &chosen);
        for k in 0..4 {
            sum[k] += v[k];
        }
        n += 1;
    }
    let inv = 1.0 / n as f64;
    sum.map(|x| x * inv)
}

/// The blossom `f(args)` of `c`'s polynomial on span `span` (`knots[span] <
/// knots[span + 1]`): de Boor's algorithm with `args[r - 1]` on level `r`.
fn blossom(c: &Nurbs, hom: &[Hom], span: usize, args: &[f64]) -> Hom {
    let (u, p) = (&c.knots, c.degree);
    let mut d: Vec<Hom> = hom[span - p..=span].to_vec();
    for (r, &t) in (1..=p).zip(args) {
        for k in (r..=p).rev() {
            let j = span - p + k;
            let alpha = (t - u[j]) / (u[j + p + 1 - r] - u[j]);
            let prev = d[k - 1];
            for (x, q) in d[k].iter_mut().zip(prev) {
                *x = q * (1.0 - alpha) + *x * alpha;
            }
        }
    }
    d[p]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Vec3;

    fn max_gap(a: &Nurbs, b: &Nurbs) -> f64 {
        let (t0, t1) = a.domain();
        (0..=400)
            .map(|i| {
                let t = t0 + (t1 - t0) * i as f64 / 400.0;
                a.eval(t).dist(b.eval(t))
            })
            .fold(0.0, f64::max)
    }

    fn quadratic() -> Nurbs {
        let pts = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 2.0, 0.5),
            Vec3::new(3.0, -1.0, 0.0),
            Vec3::new(4.0, 1.0, 1.0),
            Vec3::new(6.0, 0.5, 0.0),
            Vec3::new(7.0, 3.0, -1.0),
        ];
        let knots = vec![0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 2.5, 2.5, 2.5];
        Nurbs::new(2, knots, pts, None).unwrap()
    }

    #[test]
    fn a_quadratic_as_a_cubic_is_the_same_curve() {
        let c = quadratic();
        let e = clamped_with_degree(&c, 3).unwrap();
        assert_eq!(e.degree, 3);
        // Simple knot 0.5 -> double, double knot 1.0 -> triple.
        assert_eq!(
            e.knots,
            vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0, 2.5, 2.5, 2.5, 2.5]
        );
        assert!(max_gap(&c, &e) < 1e-12, "{}", max_gap(&c, &e));
        assert_eq!((e.start(), e.end()), (c.start(), c.end()));
        // Derivatives agree too (the same polynomial on each span).
        for t in [0.1, 0.7, 1.8] {
            let (d, f) = (c.derivs(t), e.derivs(t));
            assert!(d[1].dist(f[1]) < 1e-9 && d[2].dist(f[2]) < 1e-9);
        }
    }

    #[test]
    fn an_unclamped_cubic_is_clamped() {
        let pts: Vec<Vec3> = (0..7)
            .map(|i| Vec3::new(i as f64, if i % 2 == 0 { 0.0 } else { 1.0 }, 0.0))
            .collect();
        let knots: Vec<f64> = (0..11).map(|i| i as f64).collect();
        let c = Nurbs::new(3, knots, pts, None).unwrap();
        assert!(!is_clamped(&c));
        let e = clamped_with_degree(&c, 3).unwrap();
        assert!(is_clamped(&e));
        assert_eq!(e.domain(), c.domain());
        assert!(max_gap(&c, &e) < 1e-12);
        assert_eq!(e.points.len(), 4 + 3); // interior knots 4, 5, 6
    }

    #[test]
    fn a_rational_arc_keeps_its_weights_in_homogeneous_form() {
        let arc = crate::geom::Arc::from_center(
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::ZERO,
            Vec3::Z,
            false,
            1,
            0.0,
        );
        let c = Nurbs::from_circular_arc(&arc.unwrap());
        let e = clamped_with_degree(&c, 3).unwrap();
        assert!(e.weights.is_some());
        assert!(max_gap(&c, &e) < 1e-12);
        for i in 0..=50 {
            let t = i as f64 / 50.0;
            assert!((e.eval(t).norm() - 1.0).abs() < 1e-12);
        }
    }

    /// Seeded random curves of degree 1 to 4, clamped or not, rational or
    /// not, with repeated knots: every elevation up to degree 5 is the same
    /// curve, clamped, with the curve's end points bit for bit.
    #[test]
    fn random_curves_elevate_exactly() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut tried = 0;
        for case in 0..200 {
            let p = 1 + case % 4;
            let m = p + 1 + (rnd() * 8.0) as usize;
            let pts: Vec<Vec3> = (0..m)
                .map(|_| Vec3::new(10.0 * rnd(), 10.0 * rnd(), rnd()))
                .collect();
            let mut knots: Vec<f64> = (0..m + p + 1).map(|_| (4.0 * rnd()).floor()).collect();
            knots.sort_by(f64::total_cmp);
            if case % 3 == 0 {
                for k in 0..=p {
                    knots[k] = knots[0];
                    let l = knots.len() - 1 - k;
                    knots[l] = knots[knots.len() - 1];
                }
            }
            let weights = (case % 5 == 0).then(|| (0..m).map(|_| 0.5 + rnd()).collect());
            let Ok(c) = Nurbs::new(p, knots, pts, weights) else {
                continue;
            };
            if let Err(ElevateError::Discontinuous(_)) = clamped_with_degree(&c, p) {
                continue;
            }
            tried += 1;
            for q in p.max(2)..=5 {
                let e = clamped_with_degree(&c, q).unwrap();
                assert!(is_clamped(&e));
                let gap = max_gap(&c, &e);
                assert!(gap < 1e-9, "case {case}, {p} -> {q}: {gap}");
                assert_eq!((e.start(), e.end()), (c.start(), c.end()));
            }
        }
        assert!(tried > 50, "{tried}");
    }

    #[test]
    fn lowering_the_degree_and_jumps_are_refused() {
        let mut c = quadratic();
        c.knots = vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.5, 2.5, 2.5];
        assert_eq!(
            clamped_with_degree(&c, 3),
            Err(ElevateError::Discontinuous(1.0))
        );
        assert_eq!(
            clamped_with_degree(&quadratic(), 1),
            Err(ElevateError::Degree { from: 2, to: 1 })
        );
    }
}
