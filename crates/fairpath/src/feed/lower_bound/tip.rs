//! The slow point at a reversal's tip (module docs of [`super`], step
//! 12): a path in order that runs up a leg to the tip and back down must
//! turn round inside the band's thin sleeve around the legs, and its
//! speed there is capped near that of a U-turn of the sleeve's width.

use super::chain::SlowWindow;
use super::gates::Gate;
use crate::geom::Vec3;
use alloc::vec::Vec;

/// Bisection steps of [`sagitta_curvature`].
const SAGITTA_STEPS: usize = 48;

/// The height `H` of gate `b` over gates `a` and `c` along the unit `n`
/// from their midpoint towards `q_b`, less the radii, `n . q_b - rho_b -
/// max(n . q_a + rho_a, n . q_c + rho_c)`, and the most the path's
/// positions at `a` and `c` can be apart, `D = |q_c - q_a| + rho_a +
/// rho_c`; `None` where `H <= 0`.
fn sagitta_terms(a: &Gate, b: &Gate, c: &Gate) -> Option<(f64, f64)> {
    let n = (b.at - (a.at + c.at) * 0.5).normalized(0.0)?;
    let h = n.dot(b.at) - b.radius - (n.dot(a.at) + a.radius).max(n.dot(c.at) + c.radius);
    let d = a.at.dist(c.at) + a.radius + c.radius;
    (h > 0.0 && d > 0.0).then_some((h, d))
}

/// The least curvature (1/mm) a path reaches between passing gates `a`
/// and `c` while passing gate `b` between them, in order, unless its
/// length `L` there exceeds `pi / K` (`K` its largest curvature there).
///
/// With `n`, `H` and `D` of [`sagitta_terms`] and `h = n . x` along the
/// path by arc length: `|h''| = |n . T'| <= K`, so `h` less its chord
/// between the path's ends is at most `K x (L - x) / 2 <= K L^2 / 8` (a
/// function that vanishes at both ends of an interval with `|g''| <= K`);
/// `h` is at most `n . q_a + rho_a` at the path's start and `n . q_c +
/// rho_c` at its end, and at least `n . q_b - rho_b` where it passes `b`,
/// so `K L^2 >= 8 H`. If `L <= pi / K`,
/// Schur's comparison (step 8) puts the ends at least `(2 / K) sin(K L /
/// 2)` apart, and at most `D`: `K L / 2 <= asin(K D / 2)` where `K D <
/// 2`. Together `f(K) = asin(K D / 2)^2 - 2 H K >= 0` or `K D >= 2`; `f`
/// is convex (`asin` is convex and positive on `[0, 1]`) with `f(0) = 0`
/// and `f'(0) = -2 H < 0`, so `K` is at least its positive root, or `2 /
/// D` where there is none below it (bisection, the lower end kept).
fn sagitta_curvature(a: &Gate, b: &Gate, c: &Gate) -> f64 {
    let Some((h, d)) = sagitta_terms(a, b, c) else {
        return 0.0;
    };
    let f = |k: f64| {
        let a = super::asin((0.5 * k * d).min(1.0));
        a * a - 2.0 * h * k
    };
    // `asin x >= x` makes `f >= 0` at `8 H / D^2`: the root is below it.
    let (mut lo, mut hi) = (0.0, (8.0 * h / (d * d)).min(2.0 / d));
    if f(hi) < 0.0 {
        // Then `hi = 2 / D`, and `f < 0` on all of `(0, 2 / D]`.
        return hi;
    }
    for _ in 0..SAGITTA_STEPS {
        let k = 0.5 * (lo + hi);
        if f(k) < 0.0 {
            lo = k;
        } else {
            hi = k;
        }
    }
    lo
}

/// The least curvature (1/mm) a path in order reaches while it passes
/// gates `a < b < c` where gate `b` stands on a reversal's tip, within
/// `e` of the run's polyline `pts` (arc lengths `s`) between gates `a`
/// and `c`; 0 where the gates do not stand so (module docs, step 12).
///
/// Let `u` be the unit from the midpoint of `q_a` and `q_c` towards `q_b`.
/// If `u . (q_b - q_a) > rho_a + rho_b` and likewise for `c`, the path's
/// mean direction between passing `a` and `b` has `u . T > 0` and between
/// `b` and `c` `u . T < 0`, so `u . T(s0) = 0` somewhere between passing
/// `a` and `c`. If that stretch is no longer than `pi / K`,
/// [`sagitta_curvature`] holds. Otherwise one side of `s0` holds an arc
/// of length `pi / (2 K)`, along which `T` stays within the angle `K x` of
/// `T(s0)` (`|T'| <= K`): it advances at least `int_0^{pi / 2K} cos(K x)
/// dx = 1 / K` along `T(s0)`, a direction across `u`. The path stays within
/// `e` of the run between `a` and `c`, whose width across `u` is at most
/// `W = 2 (e + r)` with `r` the farthest polyline point there from the
/// line through `q_b` along `u`; so `K >= 1 / W`. On an exact reversal of
/// straight legs `W = 2e`: the tip caps the curvature below at `1 / (2e)`,
/// where the tightest U-turn inside the sleeve has `1 / e`.
pub(super) fn tip_curvature(
    gates: &[Gate],
    (a, b, c): (usize, usize, usize),
    pts: &[Vec3],
    s: &[f64],
    e: f64,
) -> f64 {
    let (ga, gb, gc) = (&gates[a], &gates[b], &gates[c]);
    let Some(u) = (gb.at - (ga.at + gc.at) * 0.5).normalized(0.0) else {
        return 0.0;
    };
    if u.dot(gb.at - ga.at) <= ga.radius + gb.radius
        || u.dot(gb.at - gc.at) <= gc.radius + gb.radius
    {
        return 0.0;
    }
    // The polyline between the gates: its points, and the gates' own (on
    // it, between two of its points).
    let lo = s.partition_point(|&x| x < ga.along);
    let hi = s.partition_point(|&x| x <= gc.along);
    let off_axis = |p: Vec3| {
        let d = p - gb.at;
        (d - u * d.dot(u)).norm()
    };
    let r = pts[lo..hi]
        .iter()
        .chain([&ga.at, &gc.at])
        .map(|&p| off_axis(p))
        .fold(0.0, f64::max);
    let width = 2.0 * (e + r);
    sagitta_curvature(ga, gb, gc).min(1.0 / width)
}

/// Step 12's slow windows: for each gate on a reversal's tip (arc lengths
/// `tips`), the gates next to it either side and the speed `speed_of` the
/// curvature [`tip_curvature`] proves there.
pub(super) fn tip_windows(
    gates: &[Gate],
    tips: &[(f64, Vec3)],
    pts: &[Vec3],
    s: &[f64],
    e: f64,
    speed_of: impl Fn(f64) -> f64,
) -> Vec<SlowWindow> {
    let mut out = Vec::new();
    for &(x, _) in tips {
        let b = gates.partition_point(|g| g.along < x);
        if b == 0 || b + 1 >= gates.len() || gates[b].along != x {
            continue;
        }
        let k = tip_curvature(gates, (b - 1, b, b + 1), pts, s, e);
        if k > 0.0 {
            out.push(SlowWindow {
                first: b - 1,
                last: b + 1,
                cap: speed_of(k),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const E: f64 = 0.05;

    fn gate(x: f64, y: f64, z: f64, along: f64) -> Gate {
        Gate {
            at: Vec3::new(x, y, z),
            radius: E,
            along,
        }
    }

    #[test]
    fn an_exact_reversal_on_straight_legs_caps_at_half_the_sleeve() {
        // Gates 0.3 mm down each leg of a spike up the Z axis: the sagitta
        // alone asks `2 / D = 1 / e` (the ends within `e` of one point),
        // the sleeve's width `2e` gives `1 / (2e)` in the long case.
        let pts = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 0.0, 0.0),
        ];
        let s = [0.0, 1.0, 2.0];
        let gates = [
            gate(0.0, 0.0, 0.7, 0.7),
            gate(0.0, 0.0, 1.0, 1.0),
            gate(0.0, 0.0, 0.7, 1.3),
        ];
        assert_eq!(sagitta_curvature(&gates[0], &gates[1], &gates[2]), 1.0 / E);
        let k = tip_curvature(&gates, (0, 1, 2), &pts, &s, E);
        assert!((k - 0.5 / E).abs() < 1e-12, "{k}");
    }

    #[test]
    fn a_spike_with_splayed_legs_caps_lower_and_a_short_one_not_at_all() {
        // Legs 0.2 mm apart at their feet: the sleeve is wider where the
        // gates stand.
        let pts = [
            Vec3::new(-0.1, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.1, 0.0, 0.0),
        ];
        let s = [0.0, 1.005, 2.01];
        let gates = [
            gate(-0.03, 0.0, 0.7, 0.7035),
            gate(0.0, 0.0, 1.0, 1.005),
            gate(0.03, 0.0, 0.7, 1.3065),
        ];
        let k = tip_curvature(&gates, (0, 1, 2), &pts, &s, E);
        assert!(k > 0.0 && k < 0.5 / E, "{k}");
        // Gates within `2e` of the tip along the legs prove no turn.
        let near = [
            gate(0.0, 0.0, 0.95, 0.95),
            gate(0.0, 0.0, 1.0, 1.0),
            gate(0.0, 0.0, 0.95, 1.05),
        ];
        let straight = [pts[1] - Vec3::new(0.0, 0.0, 1.0), pts[1], pts[1]];
        assert_eq!(tip_curvature(&near, (0, 1, 2), &straight, &s, E), 0.0);
    }

    #[test]
    fn the_sagitta_of_an_arc_comes_near_its_curvature_from_below() {
        // Gates at -phi, 0 and +phi on a circle of radius 2 mm: the bound
        // rises towards `1 / R` as the sagitta grows against the radii.
        let r = 2.0;
        let on = |a: f64| gate(r * a.sin(), r * a.cos(), 0.0, r * a);
        let mut last = 0.0;
        for phi in [0.4, 0.6, 0.8, 1.0, 1.2] {
            let k = sagitta_curvature(&on(-phi), &on(0.0), &on(phi));
            assert!(k > last && k < 1.0 / r, "phi {phi}: {k}");
            last = k;
        }
        assert!(last > 0.8 / r, "{last}");
    }
}
