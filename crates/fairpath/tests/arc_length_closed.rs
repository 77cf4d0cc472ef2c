//! The arc's closed-form length (`ParamCurve::closed_length`: exact for
//! circular and helical arcs, the midpoint rule within its bound for the
//! spirals that rounded coordinates make) against quadrature of `|C'|`
//! on the same interval.

use fairpath::geom::{arc_length_between, Arc, ParamCurve, Vec3};
use proptest::prelude::*;

/// `|C'|` integrated by the composite Simpson rule on `n` intervals: an
/// oracle independent of the library's quadrature.
fn simpson(arc: &Arc, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let f = |t: f64| arc.deriv1(t).norm();
    let mut s = f(a) + f(b);
    for i in 1..n {
        let w = if i % 2 == 1 { 4.0 } else { 2.0 };
        s += w * f(a + i as f64 * h);
    }
    s * h / 3.0
}

fn arc(r: f64, sweep: f64, rise: f64, dr: f64) -> Arc {
    let start = Vec3::new(r, 0.0, 0.0);
    let end_r = r + dr;
    let end = Vec3::new(end_r * sweep.cos(), end_r * sweep.sin(), rise);
    Arc::from_center(
        start,
        end,
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, 1.0),
        false,
        1,
        1e-12,
    )
    .expect("a valid arc")
}

proptest! {
    #[test]
    fn closed_length_matches_quadrature(
        r in 0.01f64..500.0,
        sweep in 0.01f64..6.2,
        rise_share in -2.0f64..2.0,
        dr_share in prop_oneof![Just(0.0), -1e-3f64..1e-3, -0.5f64..0.5],
        a in 0.0f64..0.9,
        span in 0.01f64..1.0,
    ) {
        let c = arc(r, sweep, rise_share * r, dr_share * r);
        let b = (a + span).min(1.0);
        let want = simpson(&c, a, b, 4000);
        let accuracy = 1e-9 * (1.0 + want);
        match c.closed_length(a, b, accuracy) {
            Some(l) => prop_assert!(
                (l - want).abs() <= accuracy + 1e-12 * want,
                "closed {l} vs Simpson {want}"
            ),
            // Beyond the midpoint rule's bound: a strong spiral.
            None => prop_assert!(dr_share.abs() > 0.0),
        }
        let l = arc_length_between(&c, a, b, accuracy);
        prop_assert!((l - want).abs() <= 2.0 * accuracy + 1e-12 * want);
    }
}

#[test]
fn a_circular_arc_is_exact_and_a_strong_spiral_is_integrated() {
    let c = arc(2.0, 1.5, 0.0, 0.0);
    assert_eq!(c.closed_length(0.0, 1.0, 0.0), Some(2.0 * 1.5));
    let spiral = arc(2.0, 3.0, 0.0, 1.0);
    assert_eq!(spiral.closed_length(0.0, 1.0, 1e-9), None);
}
