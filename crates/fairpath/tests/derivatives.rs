//! Derivatives of every curve type against finite differences, and exact
//! arc NURBS.

use crate::common;
use common::v;
use fairpath::geom::{arc_length, Arc, Curve, Nurbs, ParamCurve, Vec3};
use proptest::prelude::*;

fn check_fd<C: ParamCurve>(c: &C, scale: f64) {
    let (a, b) = c.domain();
    let h = 1e-5 * (b - a);
    for k in 1..=20 {
        let t = a + (b - a) * (k as f64 - 0.5 + 0.0137) / 20.0;
        let d1 = (c.eval(t + h) - c.eval(t - h)) / (2.0 * h);
        let d2 = (c.deriv1(t + h) - c.deriv1(t - h)) / (2.0 * h);
        assert!(
            (d1 - c.deriv1(t)).norm() <= 1e-5 * scale,
            "d1 at {t}: {:?} vs {:?}",
            d1,
            c.deriv1(t)
        );
        assert!(
            (d2 - c.deriv2(t)).norm() <= 1e-4 * scale,
            "d2 at {t}: {:?} vs {:?}",
            d2,
            c.deriv2(t)
        );
    }
}

fn pt() -> impl Strategy<Value = Vec3> {
    (-50.0..50.0f64, -50.0..50.0f64, -50.0..50.0f64).prop_map(|(x, y, z)| v(x, y, z))
}

proptest! {
    #[test]
    fn bspline_derivatives_match_finite_differences(pts in prop::collection::vec(pt(), 4..9), deg in 1usize..4, rational in any::<bool>(), ws in prop::collection::vec(0.5..2.0f64, 9)) {
        let n = pts.len();
        let mut knots = vec![0.0; deg + 1];
        for i in 1..(n - deg) { knots.push(i as f64 / (n - deg) as f64); }
        knots.extend(std::iter::repeat_n(1.0, deg + 1));
        let weights = if rational { Some(ws[..n].to_vec()) } else { None };
        let c = Nurbs::new(deg, knots, pts, weights).unwrap();
        check_fd(&c, 1000.0);
        prop_assert_eq!(c.eval(0.0), c.points[0]);
        prop_assert_eq!(c.eval(1.0), *c.points.last().unwrap());
    }

    /// `eval_derivs12` (one basis evaluation on a polynomial spline) gives
    /// `eval`'s point and `derivs12`'s derivatives to the bit, for every
    /// degree, rational or not, with double knots, at the domain's ends,
    /// on knots and between them, through `Curve` as through `Nurbs`: the
    /// renderer samples with it and must write what it wrote before.
    #[test]
    fn eval_derivs12_is_eval_and_derivs12_to_the_bit(pts in prop::collection::vec(pt(), 4..10), deg in 1usize..6, rational in any::<bool>(), ws in prop::collection::vec(0.5..2.0f64, 10), double in any::<bool>(), fr in prop::collection::vec(0.0..=1.0f64, 6)) {
        let n = pts.len();
        prop_assume!(n > deg);
        let inner = n - deg - 1;
        let mut knots = vec![0.0; deg + 1];
        for i in 1..=inner {
            // With `double`, the first inner knot repeats the one before it
            // (an empty span inside the domain).
            let k = if double && i == 2 { knots[knots.len() - 1] } else { i as f64 / (inner + 1) as f64 };
            knots.push(k);
        }
        knots.extend(std::iter::repeat_n(1.0, deg + 1));
        let weights = if rational { Some(ws[..n].to_vec()) } else { None };
        let c = Nurbs::new(deg, knots.clone(), pts, weights).unwrap();
        let curve = Curve::from(c.clone());
        let mut ts: Vec<f64> = fr.clone();
        ts.extend(knots.iter().copied());
        ts.extend([-0.5, 1.5]);
        let bits = |p: Vec3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
        for t in ts {
            let (p, d1, d2) = c.eval_derivs12(t);
            let (e1, e2) = c.derivs12(t);
            prop_assert_eq!(bits(p), bits(c.eval(t)), "point at {}", t);
            prop_assert_eq!(bits(d1), bits(e1), "C' at {}", t);
            prop_assert_eq!(bits(d2), bits(e2), "C'' at {}", t);
            prop_assert_eq!(bits(d1), bits(c.deriv1(t)), "C' against deriv1 at {}", t);
            let (q, f1, f2) = curve.eval_derivs12(t);
            prop_assert_eq!((bits(q), bits(f1), bits(f2)), (bits(p), bits(d1), bits(d2)));
        }
    }

    /// The fit's fast evaluations of polynomial cubics (basis values by P&T
    /// A2.2, `C''` from the second-difference control points) against
    /// `cubic_basis` and the general rational evaluation (unit weights), on
    /// clamped cubic knots with random spans and double and triple knots,
    /// at the ends of spans and inside them (and the basis functions'
    /// second derivatives at the span ends).
    #[test]
    fn fit_span_evaluation_matches_the_general_bspline(pts in prop::collection::vec(pt(), 4..12), gaps in prop::collection::vec(prop_oneof![Just(0.0), 0.01..3.0f64], 8), fr in 0.0..=1.0f64) {
        use fairpath::geom::fit::{cubic_basis, cubic_basis_d2_at_ends, cubic_basis_values, eval_in_span};
        let n = pts.len();
        let mut knots = vec![0.0; 4];
        let mut u = 0.0;
        // Simple and double interior knots (a cubic is C1 across a double
        // knot), none at the clamped start.
        let mut zeros = 0;
        for &g in &gaps[..n - 4] {
            let g = if zeros == 2 || u == 0.0 { g.max(0.5) } else { g };
            zeros = if g == 0.0 { zeros + 1 } else { 0 };
            u += g;
            knots.push(u);
        }
        let end = u + 1.0;
        knots.extend([end; 4]);
        let c = Nurbs::new(3, knots.clone(), pts.clone(), None).unwrap();
        // Unit weights: the same curve through the general rational
        // algorithm (P&T A2.3 and eq. 4.8), not the polynomial fast path.
        let general = Nurbs::new(3, knots.clone(), pts.clone(), Some(vec![1.0; n])).unwrap();
        for s in 3..n {
            let (k0, k1) = (knots[s], knots[s + 1]);
            if k1 <= k0 {
                continue;
            }
            let ends = cubic_basis_d2_at_ends(&knots, s);
            let (full0, full1) = (cubic_basis(&knots, s, k0)[2], cubic_basis(&knots, s, k1)[2]);
            for j in 0..4 {
                let scale = 1.0 + full0[j].abs() + full1[j].abs();
                prop_assert!((ends.0[j] - full0[j]).abs() <= 1e-9 * scale, "s {} j {}: {:?} vs {:?}", s, j, ends.0, full0);
                prop_assert!((ends.1[j] - full1[j]).abs() <= 1e-9 * scale, "s {} j {}: {:?} vs {:?}", s, j, ends.1, full1);
            }
            for t in [k0, k0 + fr * (k1 - k0), k1] {
                let full = cubic_basis(&knots, s, t);
                let fast = cubic_basis_values(&knots, s, t);
                for j in 0..4 {
                    prop_assert!((full[0][j] - fast[j]).abs() <= 1e-12, "s {} t {} j {}: {} vs {}", s, t, j, full[0][j], fast[j]);
                }
                let (p, d2) = eval_in_span(&knots, &pts, s, t);
                let d2_full = (0..4).fold(Vec3::ZERO, |a, j| a + pts[s - 3 + j] * full[2][j]);
                let scale = 1.0 + d2_full.norm();
                prop_assert!((d2 - d2_full).norm() <= 1e-9 * scale, "s {} t {}: {:?} vs {:?}", s, t, d2, d2_full);
                if t < k1 {
                    let g = general.derivs(t);
                    prop_assert!(p.dist(g[0]) <= 1e-9, "s {} t {}", s, t);
                    prop_assert!((d2 - g[2]).norm() <= 1e-9 * (1.0 + g[2].norm()), "s {} t {}: {:?} vs {:?}", s, t, d2, g[2]);
                    let f = c.derivs(t);
                    for k in 0..3 {
                        let sc = 1.0 + g[k].norm();
                        prop_assert!((f[k] - g[k]).norm() <= 1e-9 * sc, "derivative {} at s {} t {}", k, s, t);
                    }
                }
            }
        }
    }

    #[test]
    fn arc_derivatives_match_finite_differences(r0 in 0.5..20.0f64, dr in -0.1..0.1f64, rise in -5.0..5.0f64, sweep in 0.1..12.0f64) {
        let mut a = Arc { center: v(1.0, 2.0, 3.0), normal: v(0.0, 0.0, 1.0), u: v(1.0, 0.0, 0.0), r0, r1: r0 + dr, sweep, rise, p0: Vec3::ZERO, p1: Vec3::ZERO };
        a.p0 = a.eval_formula(0.0);
        a.p1 = a.eval_formula(1.0);
        check_fd(&a, 100.0);
    }

    #[test]
    fn circular_arc_nurbs_is_exact(r in 0.1..100.0f64, sweep in 0.01..(2.0 * std::f64::consts::PI), turns_cw in any::<bool>()) {
        let axis = v(0.0, 0.0, 1.0);
        let c = v(3.0, -4.0, 2.0);
        let start = c + v(r, 0.0, 0.0);
        let end = c + v(r * sweep.cos(), r * sweep.sin(), 0.0);
        let arc = Arc::from_center(start, end, c, axis, turns_cw, 1, 1e-9).unwrap();
        let nurbs = Nurbs::from_circular_arc(&arc);
        for k in 0..=50 {
            let p = nurbs.eval(k as f64 / 50.0);
            prop_assert!(((p - c).norm() - r).abs() <= 1e-9 * r.max(1.0));
        }
        prop_assert!(nurbs.eval(0.0).dist(arc.eval(0.0)) <= 1e-12 * r.max(1.0));
        prop_assert!(nurbs.eval(1.0).dist(arc.eval(1.0)) <= 1e-9 * r.max(1.0));
        let len = arc_length(&Curve::from(nurbs), 1e-9);
        prop_assert!((len - r * arc.sweep).abs() <= 1e-6 * r.max(1.0));
    }
}

#[test]
fn g2_arc_full_circle_and_turns() {
    let c = Vec3::ZERO;
    let s = v(5.0, 0.0, 0.0);
    let full = Arc::from_center(s, s, c, v(0.0, 0.0, 1.0), false, 1, 1e-7).unwrap();
    assert!((full.sweep - 2.0 * std::f64::consts::PI).abs() < 1e-15);
    let two = Arc::from_center(s, s, c, v(0.0, 0.0, 1.0), true, 2, 1e-7).unwrap();
    assert!((two.sweep - 4.0 * std::f64::consts::PI).abs() < 1e-12);
    // G2 (clockwise in G17) goes to negative y first.
    assert!(two.eval(0.05).y < 0.0);
    let quarter =
        Arc::from_center(s, v(0.0, 5.0, 1.0), c, v(0.0, 0.0, 1.0), false, 1, 1e-7).unwrap();
    assert!((quarter.sweep - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    assert!(quarter.eval(1.0).dist(v(0.0, 5.0, 1.0)) < 1e-12);
    let rev = quarter.reversed();
    assert!(rev.eval(0.0).dist(quarter.eval(1.0)) < 1e-12);
    assert!(rev.eval(1.0).dist(quarter.eval(0.0)) < 1e-12);
}
