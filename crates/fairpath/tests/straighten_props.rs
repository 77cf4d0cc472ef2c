//! The sliding tube (`geom::tube_fair::slide`) and the straightening
//! (`geom::tube_fair::straighten`), checked without trusting them: the
//! sliding bound against the distance to a dense polyline of the original
//! curve, the straightened curve against the same and against dense
//! samples at equal parameters, its ends, its peaks and its turning; a
//! slide along a line costs nothing; a planar path tilted into 3D gives
//! the planar result; random splines.
use crate::common;

use common::{rotate, v};
use fairpath::geom::tube_fair::slide::{sliding_bound_on, Original};
use fairpath::geom::tube_fair::tube::{deviation_bound, difference};
use fairpath::geom::tube_fair::{
    fair_in_tube, Basis, Faired, PeakPass, TubeFairOptions, TubeMeasure,
};
use fairpath::geom::{Nurbs, ParamCurve, Vec3};
use proptest::prelude::*;

/// Clamped knots with spans of random lengths (0.5 to 1.5) for `m` points.
fn knots(m: usize, rnd: &mut impl FnMut() -> f64) -> Vec<f64> {
    let mut k = vec![0.0; 4];
    let mut t = 0.0;
    for _ in 1..m - 3 {
        t += 1.0 + rnd();
        k.push(t);
    }
    t += 1.0;
    k.extend([t; 4]);
    k
}

/// A xorshift generator of numbers in [-0.5, 0.5) from `seed`.
fn rng(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed | 1;
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

/// A wavy clamped cubic of `m` control points (planar or not).
fn wavy(m: usize, wave: f64, noise: f64, seed: u64, planar: bool) -> Nurbs {
    let mut rnd = rng(seed);
    let pts: Vec<Vec3> = (0..m)
        .map(|i| {
            let x = 2.0 * i as f64;
            let z = if planar { 0.0 } else { noise * rnd() };
            v(x, wave * (0.4 * x).sin() + noise * rnd(), z)
        })
        .collect();
    let k = knots(m, &mut rnd);
    Nurbs::new(3, k, pts, None).unwrap()
}

/// Points of `c` at `n` equal parameter steps per span, ends included.
fn dense(c: &Nurbs, n: usize) -> Vec<Vec3> {
    let mut out = vec![c.eval(c.domain().0)];
    for w in c.breakpoints().windows(2) {
        for i in 1..=n {
            out.push(c.eval(w[0] + (w[1] - w[0]) * i as f64 / n as f64));
        }
    }
    out
}

/// Distance from `p` to the polyline `line` (exact, segment by segment).
fn to_polyline(p: Vec3, line: &[Vec3]) -> f64 {
    line.windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let ab = b - a;
            let l2 = ab.dot(ab);
            let t = if l2 > 0.0 {
                ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            p.dist(a + ab * t)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Largest distance from `c` (sampled at `n` steps per span) to the
/// original `orig`'s dense polyline (`line`, whose chords are within
/// `chord` of the original curve): an independent estimate of the
/// distance to the original curve, within `chord` of it from above.
fn distance_to_path(c: &Nurbs, line: &[Vec3], n: usize) -> f64 {
    dense(c, n)
        .into_iter()
        .map(|p| to_polyline(p, line))
        .fold(0.0, f64::max)
}

/// The largest distance between a curve's dense polyline at `n` steps per
/// span and the curve itself, estimated at the chords' middles (a bound
/// for the small steps used here, where chords are nearly arcs).
fn chord_error(c: &Nurbs, n: usize) -> f64 {
    let mut e: f64 = 0.0;
    for w in c.breakpoints().windows(2) {
        for i in 0..n {
            let (t0, t1) = (
                w[0] + (w[1] - w[0]) * i as f64 / n as f64,
                w[0] + (w[1] - w[0]) * (i + 1) as f64 / n as f64,
            );
            let mid = c.eval(0.5 * (t0 + t1));
            e = e.max(to_polyline(mid, &[c.eval(t0), c.eval(t1)]));
        }
    }
    e
}

/// Highest curvature: the largest of `n` steps per span, refined by
/// ternary search between the neighbours of each span's largest sample.
fn peak(c: &Nurbs, n: usize) -> f64 {
    let mut top: f64 = 0.0;
    for w in c.breakpoints().windows(2) {
        let t = |i: usize| w[0] + (w[1] - w[0]) * i as f64 / n as f64;
        let best = (0..=n).fold(0, |b, i| {
            if c.curvature(t(i)) > c.curvature(t(b)) {
                i
            } else {
                b
            }
        });
        let (mut lo, mut hi) = (t(best.saturating_sub(1)), t((best + 1).min(n)));
        for _ in 0..100 {
            let (a, b) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
            if c.curvature(a) < c.curvature(b) {
                lo = a;
            } else {
                hi = b;
            }
        }
        top = top
            .max(c.curvature(t(best)))
            .max(c.curvature(0.5 * (lo + hi)));
    }
    top
}

/// A straight line's interior control points moved along it by 0.3 mm:
/// at equal parameters that is 0.3 mm away, but every point is still on
/// the line, and the sliding bound says so.
#[test]
fn a_slide_along_a_line_is_free() {
    let m = 12;
    let mut rnd = rng(7);
    let orig: Vec<Vec3> = (0..m).map(|i| v(3.0 * i as f64, 0.0, 0.0)).collect();
    let k = knots(m, &mut rnd);
    let mut cur = orig.clone();
    for p in &mut cur[1..m - 1] {
        p.x += 0.3;
    }
    let basis = Basis::cubic(&k);
    let diff = difference(&cur, &orig);
    let equal = deviation_bound(&diff, &basis, 1e-6);
    let o = Original::new(&basis, &orig).unwrap();
    let spans: Vec<usize> = (3..m).filter(|&s| k[s] < k[s + 1]).collect();
    let slid = sliding_bound_on(&cur, Some(&o), &diff, &basis, &spans, 1e-6);
    assert!(equal > 0.25, "equal {equal}");
    assert!(slid <= 1e-5, "sliding {slid}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// The sliding bound is sure: never below the distance from the curve
    /// to a dense polyline of the original less that polyline's chord
    /// error, and never above the bound at equal parameters.
    #[test]
    fn the_sliding_bound_is_sure(
        m in 6usize..24,
        seed in any::<u64>(),
        wave in 0.0f64..3.0,
        shift in 0.0f64..0.5,
        wiggle in 0.0f64..0.2,
        planar in any::<bool>(),
    ) {
        let c = wavy(m, wave, 0.3, seed, planar);
        let mut rnd = rng(seed ^ 0x9e37);
        // The interior points slide along their polygon legs and wiggle.
        let mut moved = c.points.clone();
        for (j, w) in c.points.windows(3).enumerate() {
            let along = (w[2] - w[0]).normalized(0.0).unwrap_or(Vec3::X);
            moved[j + 1] = w[1]
                + along * (shift * (1.0 + rnd()))
                + v(rnd(), rnd(), if planar { 0.0 } else { rnd() }) * wiggle;
        }
        let cur = Nurbs { points: moved.clone(), ..c.clone() };
        let basis = Basis::cubic(&c.knots);
        let diff = difference(&moved, &c.points);
        let tol = 1e-4;
        let o = Original::new(&basis, &c.points).unwrap();
        let spans: Vec<usize> = (3..m).filter(|&s| c.knots[s] < c.knots[s + 1]).collect();
        let slid = sliding_bound_on(&moved, Some(&o), &diff, &basis, &spans, tol);
        let equal = deviation_bound(&diff, &basis, tol);
        prop_assert!(slid <= equal + 1e-15, "sliding {slid} > equal {equal}");
        let line = dense(&c, 400);
        let chord = chord_error(&c, 400);
        let seen = distance_to_path(&cur, &line, 100);
        prop_assert!(seen - chord <= slid, "seen {seen} (chords {chord}) > bound {slid}");
    }
}

/// The options of the straightening on the sliding tube, the pass on
/// speed caps.
fn straighten(r: f64, tube: TubeMeasure) -> TubeFairOptions {
    TubeFairOptions {
        tube,
        straighten: true,
        ..TubeFairOptions::new(r)
    }
}

/// Checks a straightened curve without trusting the fairing: within `r`
/// of the original path (dense polyline; at equal parameters too when the
/// tube is measured so), ends exact, same knots, peak not above the
/// original's, and the straightening's turning not above its start's.
fn check(orig: &Nurbs, f: &Faired, r: f64, tube: TubeMeasure) -> Result<(), TestCaseError> {
    let c = &f.curve;
    prop_assert_eq!(&c.knots, &orig.knots);
    prop_assert_eq!(c.points[0], orig.points[0]);
    prop_assert_eq!(c.points.last(), orig.points.last());
    prop_assert!(f.deviation_bound <= r, "bound {}", f.deviation_bound);
    let line = dense(orig, 400);
    let chord = chord_error(orig, 400);
    let seen = distance_to_path(c, &line, 100);
    prop_assert!(
        seen - chord <= r,
        "path distance {seen} (chords {chord}) > {r}"
    );
    if tube == TubeMeasure::EqualParameter {
        let equal = deviation_bound(&difference(&c.points, &orig.points), &Basis::of(orig), 1e-9);
        prop_assert!(equal <= r, "equal-parameter bound {equal} > {r}");
    }
    let (before, after) = (peak(orig, 200), peak(c, 200));
    prop_assert!(after <= before * (1.0 + 1e-6), "peak {before} -> {after}");
    let s = f.straightened;
    prop_assert!(s.turning_after <= s.turning_before, "{s:?}");
    prop_assert!((0.0..=1.0).contains(&s.kept), "{s:?}");
    for p in &c.points {
        prop_assert!(p.is_finite());
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Random splines, radii and both tubes: the straightened curve stays
    /// in the tube, keeps its ends, raises no peak over the original's
    /// highest, and does not turn more than where it started.
    #[test]
    fn random_splines_straightened_stay_in_the_tube(
        m in 6usize..30,
        seed in any::<u64>(),
        wave in 0.0f64..3.0,
        noise in 0.0f64..0.5,
        planar in any::<bool>(),
        r in prop_oneof![Just(0.025), Just(0.125), Just(0.25)],
        sliding in any::<bool>(),
    ) {
        let c = wavy(m, wave, noise, seed, planar);
        let tube = if sliding { TubeMeasure::Sliding } else { TubeMeasure::EqualParameter };
        // The straightening alone: the peak pass after it has its own
        // guard, on the guard's samples.
        let opts = TubeFairOptions { peak_pass: PeakPass::Off, ..straighten(r, tube) };
        let f = fair_in_tube(&c, &opts).unwrap();
        check(&c, &f, r, tube)?;
    }
}

/// A square-like ripple run: a saw-tooth line of 24 control points, where
/// both tubes have room to straighten; the turning falls.
#[test]
fn a_saw_tooth_is_straightened_in_both_tubes() {
    let pts: Vec<Vec3> = (0..24)
        .map(|i| v(2.0 * i as f64, if i % 2 == 0 { 0.0 } else { 0.3 }, 0.0))
        .collect();
    let k = knots(24, &mut rng(3));
    let c = Nurbs::new(3, k, pts, None).unwrap();
    for tube in [TubeMeasure::EqualParameter, TubeMeasure::Sliding] {
        for r in [0.025, 0.125] {
            let plain = TubeFairOptions {
                tube,
                peak_pass: PeakPass::Off,
                ..TubeFairOptions::new(r)
            };
            let opts = TubeFairOptions {
                straighten: true,
                ..plain
            };
            let f = fair_in_tube(&c, &opts).unwrap();
            check(&c, &f, r, tube).unwrap();
            let s = f.straightened;
            assert!(s.kept > 0.0, "{tube:?} {r}: {s:?}");
            assert!(
                s.turning_after < 0.99 * s.turning_before,
                "{tube:?} {r}: {s:?}"
            );
        }
    }
}

/// A planar path tilted into 3D is straightened as in its plane. With the
/// thesis' tube the turning it reaches agrees to 0.1% and its curve,
/// rotated, lies within a fifth of the radius of the other at equal
/// parameters. Not to the bit: the optimiser's arithmetic rounds
/// differently in another frame, its iterations part ways, and it stops
/// when progress stalls, not at an exact optimum. With the sliding tube
/// points slide along the curve at almost no cost to the turning and the
/// caps on each stretch's curvature follow the parameter, so the end
/// point is less sharply defined: measured 2% apart in turning here; both
/// frames must straighten by at least 2% and agree to 5%.
#[test]
fn a_tilted_planar_path_is_straightened_as_in_its_plane() {
    let c = wavy(20, 2.0, 0.3, 11, true);
    let tilted = Nurbs {
        points: c.points.iter().map(|&p| rotate(p)).collect(),
        ..c.clone()
    };
    let r = 0.125;
    for tube in [TubeMeasure::EqualParameter, TubeMeasure::Sliding] {
        let opts = straighten(r, tube);
        let a = fair_in_tube(&c, &opts).unwrap();
        let b = fair_in_tube(&tilted, &opts).unwrap();
        let (sa, sb) = (a.straightened, b.straightened);
        for s in [sa, sb] {
            assert!(s.kept > 0.0, "{tube:?}: {s:?}");
            assert!(
                s.turning_after <= 0.98 * s.turning_before,
                "{tube:?}: {s:?}"
            );
        }
        let agree = match tube {
            TubeMeasure::EqualParameter => 1e-3,
            TubeMeasure::Sliding => 0.05,
        };
        assert!(
            (sa.turning_after - sb.turning_after).abs() <= agree * sa.turning_after,
            "{tube:?}: {sa:?} {sb:?}"
        );
        if tube == TubeMeasure::EqualParameter {
            let turned = Nurbs {
                points: a.curve.points.iter().map(|&p| rotate(p)).collect(),
                ..a.curve.clone()
            };
            let apart = dense(&turned, 100)
                .into_iter()
                .zip(dense(&b.curve, 100))
                .map(|(p, q)| p.dist(q))
                .fold(0.0, f64::max);
            assert!(apart < 0.2 * r, "{tube:?}: {apart}");
        }
    }
}

/// Regression: seed 17415750764187490486 of
/// `random_splines_straightened_stay_in_the_tube` (10 points, wave 1.762,
/// noise 0.346, planar, r 0.25, sliding tube): the straightening folded
/// the last span into a cusp between its samples, which its sampled
/// turning did not see (a peak of 8.5e27 1/mm where the original's is
/// 0.258). Its peaks now refine the speed's minima as well.
#[test]
fn seed_17415750764187490486_straightened_without_a_cusp() {
    let c = wavy(
        10,
        1.762330447509743,
        0.34563472443295673,
        17415750764187490486,
        true,
    );
    let r = 0.25;
    let tube = TubeMeasure::Sliding;
    let opts = TubeFairOptions {
        peak_pass: PeakPass::Off,
        ..straighten(r, tube)
    };
    let f = fair_in_tube(&c, &opts).unwrap();
    check(&c, &f, r, tube).unwrap();
    // Still straightened: all of the move kept, the turning 2.059 ->
    // 2.022 rad when this test was written.
    let s = f.straightened;
    assert!(s.kept > 0.0, "{s:?}");
    assert!(s.turning_after < 0.99 * s.turning_before, "{s:?}");
}
