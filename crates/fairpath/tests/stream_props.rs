//! The servo-rate stream: on seeded random paths (raw polylines with
//! corners, and the same smoothed), every sample is within every limit as a
//! controller measures it (by an independent finite-difference check
//! here), the stream starts and ends exactly at the path's ends, every
//! sample lies on the path, and its length in periods is the planned time.

use crate::common;

use common::Rng;

use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::PlanOptions;
use fairpath::feed::stream::{stream, Motion, StreamError, StreamOptions, StreamedKind};
use fairpath::geom::{Curve, Line, Vec3};
use fairpath::path::Piece;
use fairpath::smooth::{BsplineCorner, Smoother};

fn opts(m: MachineLimits) -> StreamOptions {
    StreamOptions::new(PlanOptions {
        limits: m,
        override_feed: true,
        window: None,
        ends: Default::default(),
    })
}

/// Peaks measured here, independently of the library: speed, 3D
/// acceleration, 3D jerk averaged over 5 periods, and per-axis jerk
/// averaged over 5 periods.
fn peaks(p: &[Vec3], t: f64) -> (f64, f64, f64, [f64; 3]) {
    let mut v: f64 = 0.0;
    for w in p.windows(2) {
        v = v.max(w[0].dist(w[1]) / t);
    }
    let a: Vec<Vec3> = (0..p.len())
        .map(|k| {
            if k == 0 || k + 1 == p.len() {
                Vec3::ZERO
            } else {
                (p[k + 1] - p[k] * 2.0 + p[k - 1]) / (t * t)
            }
        })
        .collect();
    let amax = a.iter().map(|x| x.norm()).fold(0.0, f64::max);
    let mut j5: f64 = 0.0;
    let mut ja = [0.0f64; 3];
    for k in 0..a.len().saturating_sub(5) {
        let j = (a[k + 5] - a[k]) / (5.0 * t);
        j5 = j5.max(j.norm());
        ja[0] = ja[0].max(j.x.abs());
        ja[1] = ja[1].max(j.y.abs());
        ja[2] = ja[2].max(j.z.abs());
    }
    (v, amax, j5, ja)
}

/// Distance from `q` to the nearest of `pieces`, sampled finely.
fn dist_to_path(q: Vec3, pieces: &[Piece]) -> f64 {
    use fairpath::geom::ParamCurve;
    let mut best = f64::INFINITY;
    for p in pieces {
        let (u0, u1) = p.curve.domain();
        match &p.curve {
            Curve::Line(l) => {
                let d = l.p1 - l.p0;
                let f = ((q - l.p0).dot(d) / d.norm_sq()).clamp(0.0, 1.0);
                best = best.min(q.dist(l.p0 + d * f));
            }
            c => {
                // Coarse samples, then a golden-section search around the
                // nearest.
                let n = 400;
                let at = |k: usize| u0 + (u1 - u0) * k as f64 / n as f64;
                let mut ks: Vec<usize> = (0..=n).collect();
                ks.sort_by(|&a, &b| q.dist(c.eval(at(a))).total_cmp(&q.dist(c.eval(at(b)))));
                // Around the three nearest (a closed curve has two ends).
                for &k in &ks[..3] {
                    let (mut lo, mut hi) = (at(k.saturating_sub(1)), at((k + 1).min(n)));
                    for _ in 0..60 {
                        let m1 = lo + (hi - lo) * 0.382;
                        let m2 = lo + (hi - lo) * 0.618;
                        if q.dist(c.eval(m1)) < q.dist(c.eval(m2)) {
                            hi = m2;
                        } else {
                            lo = m1;
                        }
                    }
                    best = best.min(q.dist(c.eval(0.5 * (lo + hi))));
                }
            }
        }
    }
    best
}

fn random_polyline(rng: &mut Rng, n: usize, three_d: bool) -> Vec<Vec3> {
    let mut p = vec![Vec3::ZERO];
    for _ in 0..n {
        let last = *p.last().unwrap();
        let z = if three_d { rng.unit() * 2.0 - 1.0 } else { 0.0 };
        p.push(last + Vec3::new(rng.unit() * 8.0 - 4.0, rng.unit() * 8.0 - 4.0, z));
    }
    p
}

fn check_stream(pieces: &[Piece], m: MachineLimits, what: &str) -> f64 {
    let o = opts(m);
    let s = stream(&[Motion::Run(pieces)], &o).unwrap_or_else(|e| panic!("{what}: {e}"));
    let p = &s.positions;
    assert_eq!(
        p[0],
        pieces[0].start(),
        "{what}: starts at the path's start"
    );
    assert!(
        p.last().unwrap().dist(pieces.last().unwrap().end()) < 1e-9,
        "{what}: ends at the path's end"
    );
    // One sample per period from time 0 to the first period at or after the end.
    let periods = (s.time / m.period).ceil() as usize;
    assert!(
        p.len() == periods + 1 || p.len() == periods + 2,
        "{what}: {} samples for {} s",
        p.len(),
        s.time
    );
    let (v, a, j5, ja) = peaks(p, m.period);
    let slack = 1.0 + 2e-3;
    assert!(v <= m.max_feed * slack, "{what}: speed {v}");
    assert!(a <= m.acc * slack, "{what}: acceleration {a}");
    assert!(j5 <= m.jerk * slack, "{what}: jerk {j5}");
    for (i, x) in ja.iter().enumerate() {
        assert!(*x <= o.axis_jerk[i] * slack, "{what}: axis {i} jerk {x}");
    }
    assert_eq!(s.excess, 0, "{what}");
    for q in p.iter().step_by(7) {
        let d = dist_to_path(*q, pieces);
        assert!(d < 1e-6, "{what}: sample {q:?} is {d} mm off the path");
    }
    s.time
}

#[test]
fn seeded_random_polylines_and_their_smoothing_stream_within_every_limit() {
    let m = MachineLimits::thesis();
    for seed in 0..6u64 {
        let mut rng = Rng(0x5eed_0018 + seed);
        let pts = random_polyline(&mut rng, 8, seed % 2 == 1);
        let run = common::polyline_run(&pts);
        check_stream(&run.pieces, m, &format!("seed {seed} raw"));
        let smoothed = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
        check_stream(&smoothed.pieces, m, &format!("seed {seed} smoothed"));
    }
}

#[test]
fn a_tight_circle_is_slowed_for_the_cross_term_of_the_jerk() {
    // A full circle of radius 2 mm from rest: speeding up on it at the full
    // tangential acceleration gives a normal jerk 3 k v a_t far above J.
    let m = MachineLimits::thesis();
    let arc = fairpath::geom::Arc::from_center(
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::ZERO,
        Vec3::Z,
        false,
        1,
        1e-9,
    )
    .unwrap();
    let pieces = vec![Piece {
        curve: Curve::from(arc),
        ..common::polyline_run(&[Vec3::ZERO, Vec3::X]).pieces[0].clone()
    }];
    check_stream(&pieces, m, "circle r = 2");
}

#[test]
fn per_axis_jerk_and_velocity_limits_hold_on_rapids_and_runs() {
    let mut m = MachineLimits::thesis();
    m.axis_vel = [100.0, 400.0, 400.0];
    let mut o = opts(m);
    o.axis_jerk = [5000.0, 20000.0, 20000.0];
    let rapid = Piece {
        rapid: true,
        ..common::polyline_run(&[Vec3::ZERO, Vec3::new(30.0, 30.0, 0.0)]).pieces[0].clone()
    };
    let run = common::polyline_run(&[
        Vec3::new(30.0, 30.0, 0.0),
        Vec3::new(60.0, 35.0, 0.0),
        Vec3::new(60.0, 60.0, 0.0),
    ]);
    let s = stream(&[Motion::Rapid(&rapid), Motion::Run(&run.pieces)], &o).unwrap();
    assert_eq!(s.excess, 0);
    let p = &s.positions;
    let t = m.period;
    let vx = p
        .windows(2)
        .map(|w| (w[1].x - w[0].x).abs() / t)
        .fold(0.0, f64::max);
    assert!(vx <= 100.0 * (1.0 + 1e-3), "X speed {vx}");
    let (_, _, _, ja) = peaks(p, t);
    assert!(ja[0] <= 5000.0 * 1.002, "X jerk {}", ja[0]);
    assert!(s.peaks.axis_jerk_avg[0] <= 5000.0 * 1.002);
    assert_eq!(s.motions[0].kind, StreamedKind::Rapid);
}

#[test]
fn a_dwell_holds_the_position_for_its_time() {
    let m = MachineLimits::thesis();
    let a = common::polyline_run(&[Vec3::ZERO, Vec3::new(10.0, 0.0, 0.0)]);
    let b = common::polyline_run(&[Vec3::new(10.0, 0.0, 0.0), Vec3::new(10.0, 10.0, 0.0)]);
    let s = stream(
        &[
            Motion::Run(&a.pieces),
            Motion::Dwell(0.25),
            Motion::Run(&b.pieces),
        ],
        &opts(m),
    )
    .unwrap();
    let held = s
        .positions
        .iter()
        .filter(|q| q.dist(Vec3::new(10.0, 0.0, 0.0)) == 0.0)
        .count();
    assert!((250..=252).contains(&held), "held {held} periods");
    assert_eq!(s.motions[1].kind, StreamedKind::Dwell);
    assert!((s.time - s.motions.iter().map(|x| x.duration).sum::<f64>()).abs() < 1e-12);
}

#[test]
fn a_jump_between_motions_is_an_error() {
    let m = MachineLimits::thesis();
    let a = common::polyline_run(&[Vec3::ZERO, Vec3::new(10.0, 0.0, 0.0)]);
    let b = common::polyline_run(&[Vec3::new(11.0, 0.0, 0.0), Vec3::new(20.0, 0.0, 0.0)]);
    let e = stream(&[Motion::Run(&a.pieces), Motion::Run(&b.pieces)], &opts(m)).unwrap_err();
    assert!(matches!(e, StreamError::Gap { index: 1, .. }), "{e}");
}

#[test]
fn a_straight_line_streams_in_its_planned_time_without_replanning() {
    let m = MachineLimits::thesis();
    let run = common::polyline_run(&[Vec3::ZERO, Vec3::new(100.0, 0.0, 0.0)]);
    let s = stream(&[Motion::Run(&run.pieces)], &opts(m)).unwrap();
    assert_eq!(s.motions[0].plans, 1);
    // Rest to rest over 100 mm at V 400, A 4000, J 20000: the double-S time.
    let ds = fairpath::feed::DoubleS::plan(
        100.0,
        0.0,
        0.0,
        &fairpath::feed::Limits::new(400.0, 4000.0, 20000.0).unwrap(),
    )
    .unwrap();
    assert!((s.time - ds.duration()).abs() < 1e-9);
    let _ = Line::new(Vec3::ZERO, Vec3::X);
}
