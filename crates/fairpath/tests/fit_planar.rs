//! A fit of data that share a coordinate keeps it to the bit: the fit
//! solves relative to its start point (`geom::fit::FitData`), so that
//! coordinate is 0 in every sum. Solved in absolute coordinates, a pass
//! at `Y = 36.449` mm (LinuxCNC's `blur_torus.ngc`, `Y1.4350` in inches)
//! came out up to 4e-8 mm off its plane, and its arcs were written as
//! helices.

use crate::common;
use fairpath::geom::fit::{averaged_knots, chord_params, fit_cubic_weighted, EndCondition};
use fairpath::geom::Vec3;
use proptest::prelude::*;

/// A wavy polyline of `n` points in the plane where coordinate `axis` is
/// `level`, from `seed`.
fn planar(n: usize, axis: usize, level: f64, step: f64, seed: u64) -> Vec<Vec3> {
    let mut rng = common::Rng(seed);
    let mut rnd = move || rng.unit() - 0.5;
    (0..n)
        .map(|i| {
            let u = 3.7 + i as f64 * step;
            let w = 0.4 * (0.9 * u).sin() + 0.01 * rnd();
            let mut c = [u, w, 0.0];
            c.rotate_right(axis);
            c[axis] = level;
            Vec3::new(c[0], c[1], c[2])
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn a_fit_of_planar_data_stays_in_its_plane(
        n in 8usize..120,
        axis in 0usize..3,
        level in prop_oneof![Just(36.449), Just(1.435 * 25.4), -500.0f64..500.0],
        step in 0.05f64..2.0,
        seed in any::<u64>(),
        extra in 0usize..60,
        tangents in any::<bool>(),
        lambda in prop_oneof![Just(0.0), 1e-6f64..10.0],
        mu in prop_oneof![Just(0.0), 1e-6f64..10.0],
    ) {
        let pts = planar(n, axis, level, step, seed);
        let params = chord_params(&pts);
        let knots = averaged_knots(&params, (4 + extra).min(n + 2).max(4));
        let dir = |a: Vec3, b: Vec3| (b - a).normalized(0.0).unwrap();
        let (start, end) = if tangents {
            (
                EndCondition::Tangent(dir(pts[0], pts[1])),
                EndCondition::Tangent(dir(pts[n - 2], pts[n - 1])),
            )
        } else {
            (EndCondition::Free, EndCondition::Free)
        };
        let Ok(c) = fit_cubic_weighted(&pts, &params, &knots, start, end, lambda, mu) else {
            return Ok(());
        };
        for p in &c.points {
            let got = [p.x, p.y, p.z][axis];
            prop_assert_eq!(got.to_bits(), level.to_bits(), "{} against {}", got, level);
        }
    }
}
