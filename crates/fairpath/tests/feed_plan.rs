//! The look-ahead planner: limits never exceeded on random paths (raw and
//! smoothed), and convergence to the acceleration-limited time-optimal
//! traversal as the jerk limit grows.

use crate::common;

use common::Rng;

use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{plan_run, plan_run_shaped, plan_time_shaped, Corners, PlanOptions};
use fairpath::feed::shaping::Shaping;
use fairpath::geom::{Curve, Line, Vec3};
use fairpath::path::{Piece, Run};
use fairpath::smooth::{BsplineCorner, Smoother};

fn run_of(pts: &[Vec3], feeds: &[f64]) -> Run {
    common::polyline_run_with_feeds(pts, feeds)
}

/// Samples every segment profile: speed within its cap, |a| <= A, |j| <= J,
/// speeds continuous across segments, at rest at both ends.
fn check_limits(pieces: &[Piece], m: &MachineLimits) -> f64 {
    check_limits_window(pieces, m, None)
}

fn check_limits_window(pieces: &[Piece], m: &MachineLimits, window: Option<usize>) -> f64 {
    let plan = plan_run(
        pieces,
        &PlanOptions {
            limits: *m,
            override_feed: false,
            window,
            ends: Default::default(),
        },
    )
    .unwrap_or_else(|e| panic!("window {window:?}: {e}"));
    let slack = 1e-9;
    let mut last_v = 0.0;
    for s in &plan.segments {
        let p = &s.profile;
        assert!(
            (p.v0() - last_v).abs() <= 1e-9 * (1.0 + last_v),
            "speed jumps at a boundary"
        );
        let n = 200;
        for k in 0..=n {
            let st = p.eval(p.duration() * k as f64 / n as f64);
            assert!(st.v.is_finite() && st.a.is_finite() && st.j.is_finite());
            let cap = s.cap_at(st.q);
            assert!(
                st.v <= cap * (1.0 + slack) + 1e-12,
                "v {} > cap {} at {} of {}",
                st.v,
                cap,
                st.q,
                s.length
            );
            assert!(st.v >= -1e-12);
            assert!(st.a.abs() <= m.acc * (1.0 + slack));
            assert!(st.j.abs() <= m.jerk * (1.0 + slack));
        }
        // At every joint inside the segment the speed is within the joint's
        // cap (bisection on time for the joint's position).
        let mut q = 0.0;
        for part in &s.parts {
            if q > 0.0 && part.entry_cap.is_finite() {
                let (mut lo, mut hi) = (0.0, p.duration());
                for _ in 0..100 {
                    let mid = 0.5 * (lo + hi);
                    if p.eval(mid).q < q {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let v = p.eval(hi).v;
                assert!(
                    v <= part.entry_cap * (1.0 + 1e-6) + 1e-9,
                    "v {v} > joint cap {} at {q}",
                    part.entry_cap
                );
            }
            q += part.length;
        }
        // The profile's own speed limit is the highest cap inside.
        assert!(p.vlim() <= s.cap * (1.0 + slack));
        assert!((p.length() - s.length).abs() <= 1e-9 * s.length.max(1.0));
        last_v = p.v1();
    }
    assert!(last_v.abs() <= 1e-12);
    assert!(plan.max_acc <= m.acc * (1.0 + slack));
    plan.time
}

/// A random polyline of 2 to 31 points at one of three scales (0.05, 1
/// and 20 mm, by `case`), flat in Z to a fifth, and its two feeds.
fn random_polyline(rng: &mut Rng, case: usize) -> (Vec<Vec3>, [f64; 2]) {
    let n = 2 + (rng.unit() * 30.0) as usize;
    let scale = [0.05, 1.0, 20.0][case % 3];
    let pts: Vec<Vec3> = (0..n)
        .map(|_| {
            Vec3::new(
                rng.unit() * scale,
                rng.unit() * scale,
                rng.unit() * scale * 0.2,
            )
        })
        .collect();
    (pts, [600.0 + rng.unit() * 24000.0, 1000.0])
}

#[test]
fn seeded_random_paths_never_exceed_limits() {
    let mut rng = Rng(42);
    for case in 0..1200 {
        let (pts, feeds) = random_polyline(&mut rng, case);
        let m = MachineLimits {
            max_feed: 50.0 + rng.unit() * 500.0,
            acc: 100.0 + rng.unit() * 10000.0,
            normal_acc: 100.0 + rng.unit() * 10000.0,
            jerk: 1000.0 + rng.unit() * 100000.0,
            ..MachineLimits::thesis()
        };
        let run = run_of(&pts, &feeds);
        let t_raw = check_limits(&run.pieces, &m);
        assert!(t_raw.is_finite() && t_raw > 0.0);
        let smoothed = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
        let t_smooth = check_limits(&smoothed.pieces, &m);
        assert!(t_smooth.is_finite() && t_smooth > 0.0);
    }
}

/// With a block time `T` every piece of a run takes at least `T`, the
/// limits still hold, and the plan is never faster than without it (the
/// block time only lowers caps). Seeded random chords of gentle circles
/// and random polylines: without a block time the machine runs the chords
/// faster than one per `T`.
#[test]
fn seeded_random_paths_take_at_least_the_block_time_per_piece() {
    let mut rng = Rng(11);
    let mut floored = 0;
    for case in 0..200 {
        let pts: Vec<Vec3> = if case % 4 == 3 {
            random_polyline(&mut rng, case).0
        } else {
            let r = 5.0 + rng.unit() * 50.0;
            let step = (0.01 + rng.unit() * 0.3) / r;
            let n = 50 + (rng.unit() * 250.0) as usize;
            (0..=n)
                .map(|i| {
                    let a = step * i as f64;
                    Vec3::new(r * a.cos(), r * a.sin(), 0.0)
                })
                .collect()
        };
        let run = run_of(&pts, &[24000.0, 24000.0]);
        let free = MachineLimits::thesis();
        let m = MachineLimits {
            block_time: 1e-4 + rng.unit() * 2e-3,
            ..free
        };
        let t_free = check_limits(&run.pieces, &free);
        let t = check_limits(&run.pieces, &m);
        let blocks = run.pieces.len() as f64;
        assert!(
            t >= blocks * m.block_time * (1.0 - 1e-9),
            "case {case}: {t} s for {blocks} blocks of at least {} s",
            m.block_time
        );
        assert!(
            t >= t_free * (1.0 - 1e-9),
            "case {case}: {t} s < {t_free} s"
        );
        if t_free < blocks * m.block_time {
            floored += 1;
        }
    }
    assert!(
        floored >= 20,
        "{floored} runs faster than one block per T without it"
    );
}

/// A plan for its time alone (no segments kept, so no stretch located on
/// the run) is the plan with its segments, to the bit, on random paths raw
/// and smoothed, at the programmed feeds and overridden, with each way of
/// passing corners.
#[test]
fn seeded_random_paths_plan_the_same_time_with_or_without_segments() {
    let mut rng = Rng(7);
    for case in 0..300 {
        let (pts, feeds) = random_polyline(&mut rng, case);
        let run = run_of(&pts, &feeds);
        let smoothed = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
        let corners = [Corners::Blended, Corners::Followed, Corners::BlockCapped][case % 3];
        for pieces in [&run.pieces, &smoothed.pieces] {
            for override_feed in [false, true] {
                let po = PlanOptions {
                    limits: MachineLimits::thesis(),
                    override_feed,
                    window: None,
                    ends: Default::default(),
                };
                let whole = plan_run_shaped(pieces, &po, &Shaping::none(), corners).unwrap();
                let time = plan_time_shaped(pieces, &po, &Shaping::none(), corners).unwrap();
                assert_eq!(whole.time.to_bits(), time.to_bits(), "case {case}");
                // The segments' parts are located in order along the run:
                // each starts where the one before ends (on its piece, or
                // at the start of a later one), their lengths add up to
                // the segment's, and each cap is within the segment's.
                let parts: Vec<_> = whole.segments.iter().flat_map(|s| &s.parts).collect();
                assert!(!parts.is_empty(), "case {case}");
                for w in parts.windows(2) {
                    let (a, b) = (w[0], w[1]);
                    assert!(
                        (a.piece == b.piece && a.t1 == b.t0) || (b.piece > a.piece && b.t0 == 0.0),
                        "case {case}: {a:?} then {b:?}"
                    );
                }
                for sg in &whole.segments {
                    let sum: f64 = sg.parts.iter().map(|p| p.length).sum();
                    assert!(
                        (sum - sg.length).abs() <= 1e-9 * sg.length.max(1.0),
                        "case {case}"
                    );
                    assert!(sg.parts.iter().all(|p| p.cap <= sg.cap), "case {case}");
                }
            }
        }
    }
}

/// Acceleration-limited (infinite jerk) time-optimal traversal of segments
/// with speed caps, starting and ending at rest: an independent model.
fn trapezoid_time(lengths: &[f64], caps: &[f64], acc: f64) -> f64 {
    let n = lengths.len();
    let mut v = vec![0.0f64; n + 1];
    for i in 1..n {
        v[i] = caps[i - 1].min(caps[i]);
    }
    for i in (0..n).rev() {
        v[i] = v[i].min((v[i + 1] * v[i + 1] + 2.0 * acc * lengths[i]).sqrt());
    }
    for i in 0..n {
        v[i + 1] = v[i + 1].min((v[i] * v[i] + 2.0 * acc * lengths[i]).sqrt());
    }
    let mut t = 0.0;
    for i in 0..n {
        let (a, b, c, l) = (v[i], v[i + 1], caps[i], lengths[i]);
        // Peak speed of the triangle, limited by the cap.
        let peak = ((2.0 * acc * l + a * a + b * b) / 2.0).sqrt().min(c);
        let da = (peak * peak - a * a) / (2.0 * acc);
        let db = (peak * peak - b * b) / (2.0 * acc);
        t += (peak - a) / acc + (peak - b) / acc + (l - da - db).max(0.0) / peak;
    }
    t
}

#[test]
fn converges_to_the_acceleration_limited_time_as_jerk_grows() {
    // Collinear segments with different feeds: caps are the feeds, joints
    // are G2 (no junction caps), so the independent model has the same caps.
    let pts: Vec<Vec3> = [0.0, 3.0, 10.0, 11.0, 30.0, 31.5, 60.0]
        .iter()
        .map(|&x| Vec3::new(x, 0.0, 0.0))
        .collect();
    let feeds = [6000.0, 18000.0, 3000.0, 24000.0, 1200.0, 12000.0];
    let run = run_of(&pts, &feeds);
    let lengths: Vec<f64> = pts.windows(2).map(|w| w[1].x - w[0].x).collect();
    let caps: Vec<f64> = feeds.iter().map(|f| (f / 60.0f64).min(400.0)).collect();
    let want = trapezoid_time(&lengths, &caps, 4000.0);
    let mut last_gap = f64::INFINITY;
    for jerk in [2e4, 2e5, 2e6, 2e7, 2e8, 2e9] {
        let m = MachineLimits {
            jerk,
            ..MachineLimits::thesis()
        };
        let plan = plan_run(
            &run.pieces,
            &PlanOptions {
                limits: m,
                override_feed: false,
                window: None,
                ends: Default::default(),
            },
        )
        .unwrap();
        let gap = plan.time - want;
        assert!(
            gap >= -1e-9,
            "faster than the acceleration-limited optimum: {} < {want}",
            plan.time
        );
        assert!(gap <= last_gap + 1e-12);
        last_gap = gap;
    }
    assert!(last_gap / want < 1e-3, "gap {last_gap} of {want}");
}

#[test]
fn bounded_lookahead_is_feasible_slower_and_converges_to_the_full_scan() {
    let mut rng = Rng(7);
    for _ in 0..100 {
        let n = 3 + (rng.unit() * 40.0) as usize;
        let pts: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new(i as f64 * (0.2 + rng.unit()), rng.unit() * 0.5, 0.0))
            .collect();
        let run = run_of(&pts, &[24000.0]);
        let smoothed = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
        let m = MachineLimits::thesis();
        let full = check_limits_window(&smoothed.pieces, &m, None);
        let mut last = f64::INFINITY;
        for w in [1, 2, 4, 8, 16, 64, 1 << 20] {
            let t = check_limits_window(&smoothed.pieces, &m, Some(w));
            assert!(t >= full * (1.0 - 1e-12), "window {w}: {t} < full {full}");
            assert!(
                t <= last * (1.0 + 1e-12),
                "window {w}: {t} > smaller window {last}"
            );
            last = t;
        }
        assert!(
            (last - full).abs() <= 1e-9 * full,
            "an unbounded window is the full scan"
        );
    }
}

#[test]
fn interpolation_tracks_the_path_with_small_feed_fluctuation() {
    use fairpath::feed::interpolate::interpolate;
    use fairpath::geom::{distance_to_polyline, Arc};
    // A half circle of radius 20 as one G3, then a line.
    let arc = Arc::from_center(
        Vec3::new(20.0, 0.0, 0.0),
        Vec3::new(-20.0, 0.0, 0.0),
        Vec3::ZERO,
        Vec3::Z,
        false,
        1,
        1e-9,
    )
    .unwrap();
    let pieces = vec![
        Piece {
            curve: Curve::from(arc),
            rapid: false,
            source_lines: (1, 1),
            feed: Some(6000.0),
        },
        Piece {
            curve: Curve::Line(Line::new(
                Vec3::new(-20.0, 0.0, 0.0),
                Vec3::new(-20.0, -30.0, 0.0),
            )),
            rapid: false,
            source_lines: (2, 2),
            feed: Some(6000.0),
        },
    ];
    let m = MachineLimits::thesis();
    let plan = plan_run(
        &pieces,
        &PlanOptions {
            limits: m,
            override_feed: false,
            window: None,
            ends: Default::default(),
        },
    )
    .unwrap();
    let it = interpolate(&pieces, &plan, m.period, 0.0);
    assert!((it.samples.len() as f64 - plan.time / m.period).abs() <= 2.0);
    for s in &it.samples {
        // On the circle while s is within the arc, on the line after.
        let on_arc = (s.p.norm() - 20.0).abs();
        let on_line = distance_to_polyline(
            s.p,
            &[Vec3::new(-20.0, 0.0, 0.0), Vec3::new(-20.0, -30.0, 0.0)],
        )
        .unwrap()
        .0;
        assert!(on_arc.min(on_line) < 1e-6, "{:?}", s.p);
        // Arc length agrees with the position on the arc.
        if s.s < 20.0 * std::f64::consts::PI - 1e-3 {
            let angle = s.p.y.atan2(s.p.x);
            assert!(
                (angle * 20.0 - s.s).abs() < 1e-3,
                "s {} angle {}",
                s.s,
                angle
            );
        }
    }
    let last = it.samples.last().unwrap().p;
    assert!(last.dist(Vec3::new(-20.0, -30.0, 0.0)) < 1e-3);
    assert!(it.max_fluctuation < 0.01, "{}", it.max_fluctuation);
    // Sample by sample (what `simulate` does, keeping none): the same
    // samples in order and the same fluctuation, to the bit.
    let mut seen = Vec::new();
    let f = fairpath::feed::interpolate::interpolate_each(&pieces, &plan, m.period, 0.0, |s| {
        seen.push(s)
    });
    assert_eq!(seen, it.samples);
    assert_eq!(f.samples, it.samples.len());
    assert_eq!(f.max.to_bits(), it.max_fluctuation.to_bits());
    assert_eq!(f.mean.to_bits(), it.mean_fluctuation.to_bits());
}

/// Acceleration-limited (infinite jerk) time-optimal traversal of a curve,
/// independent of the planner: the speed cap sampled every `ds` of arc
/// length, backward and forward passes `v'^2 <= v^2 + 2 A ds`, time
/// `sum 2 ds / (v_i + v_i+1)`.
fn phase_plane_time(c: &Curve, m: &MachineLimits, feed: f64, samples: usize) -> f64 {
    use fairpath::feed::limits::{speed_cap, PathPoint};
    use fairpath::geom::{curvature_vector_from, ParamCurve};
    let (t0, t1) = c.domain();
    let mut s = vec![0.0f64];
    let mut caps = Vec::with_capacity(samples + 1);
    let mut prev = c.eval(t0);
    let mut kappa = Vec::with_capacity(samples + 1);
    let mut geo = Vec::with_capacity(samples + 1);
    for i in 0..=samples {
        let t = t0 + (t1 - t0) * i as f64 / samples as f64;
        let p = c.eval(t);
        if i > 0 {
            // Chord sums converge to the arc length as samples grow.
            s.push(s[i - 1] + p.dist(prev));
        }
        prev = p;
        let (d1, d2) = (c.deriv1(t), c.deriv2(t));
        let k = curvature_vector_from(d1, d2);
        kappa.push(k.norm());
        geo.push((d1.normalized(0.0).unwrap(), k));
    }
    for (i, &(tangent, curvature)) in geo.iter().enumerate() {
        let (a, b) = (i.saturating_sub(1), (i + 1).min(samples));
        let dk = (kappa[b] - kappa[a]) / (s[b] - s[a]);
        let p = PathPoint {
            tangent,
            curvature,
            dkappa_ds: dk.abs(),
        };
        caps.push(speed_cap(m, feed, &p).0);
    }
    let n = samples;
    let mut v = caps.clone();
    v[0] = 0.0;
    v[n] = 0.0;
    for i in (0..n).rev() {
        v[i] = v[i].min((v[i + 1] * v[i + 1] + 2.0 * m.acc * (s[i + 1] - s[i])).sqrt());
    }
    for i in 0..n {
        v[i + 1] = v[i + 1].min((v[i] * v[i] + 2.0 * m.acc * (s[i + 1] - s[i])).sqrt());
    }
    (0..n)
        .map(|i| 2.0 * (s[i + 1] - s[i]) / (v[i] + v[i + 1]).max(1e-300))
        .sum()
}

#[test]
fn on_a_curve_of_varying_curvature_the_plan_converges_to_the_phase_plane_optimum() {
    use fairpath::geom::Nurbs;
    // A wavy cubic B-spline, 2D then lifted in z: curvature varies
    // continuously, so the speed cap has many minima and maxima.
    let pts: Vec<Vec3> = (0..12)
        .map(|i| {
            let x = i as f64 * 8.0;
            Vec3::new(x, if i % 2 == 0 { 0.0 } else { 6.0 }, 0.3 * x)
        })
        .collect();
    let n = pts.len();
    let mut knots = vec![0.0; 4];
    for i in 1..n - 3 {
        knots.push(i as f64 / (n - 3) as f64);
    }
    knots.extend([1.0; 4]);
    let c = Curve::from(Nurbs::new(3, knots, pts, None).unwrap());
    let pieces = vec![Piece {
        curve: c.clone(),
        rapid: false,
        source_lines: (1, 1),
        feed: Some(24000.0),
    }];
    for jerk in [2e4, 2e9] {
        let m = MachineLimits {
            jerk,
            ..MachineLimits::thesis()
        };
        let want = phase_plane_time(&c, &m, 400.0, 200_000);
        let got = check_limits(&pieces, &m);
        assert!(
            got >= want * (1.0 - 1e-3),
            "J {jerk}: faster than the acceleration-limited optimum: {got} < {want}"
        );
        if jerk > 1e9 {
            // With jerk out of the way only the caps and A remain: the
            // segments from one cap minimum to the next lose little.
            assert!(
                got <= want * 1.03,
                "J {jerk}: {got} s, phase-plane optimum {want} s"
            );
        }
        println!("J {jerk}: plan {got:.4} s, phase-plane optimum {want:.4} s");
    }
}

#[test]
fn regression_line_contouring_xz_near_reversal_is_not_crawled() {
    // Down and back up almost the same line: the transition's radius is
    // below a micrometre. Its stretches are cut until the cap is uniform
    // within each (or the stretch is shorter than a period of travel), so
    // it costs about what the corner of the raw program costs, not the
    // seconds a stretch capped at its peak curvature took. (The program's
    // own return rose 0.004 mm over 10 mm; held to the corner reach
    // (`CORNER_REACH_SHARE`) its transition would be narrower than the
    // zero-length threshold, and the corner is kept as a reversal: 0.05
    // mm keeps a transition, of radius 0.7 um.)
    let pts = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(10.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 0.05),
    ];
    let run = run_of(&pts, &[24000.0]);
    let m = MachineLimits::thesis();
    let raw = check_limits(&run.pieces, &m);
    let smoothed = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
    assert!(smoothed.transitions == 1, "{smoothed:?}");
    let t = check_limits(&smoothed.pieces, &m);
    assert!(t < raw * 1.2, "smoothed {t} s, raw {raw} s");
}

#[test]
fn regression_arc_to_line_tangent_joint_is_a_curvature_jump_not_a_corner() {
    // A filleted corner: line, 2 mm arc, line, all tangent. The tangents at
    // the arc's end and the next line's start differ by rounding only; the
    // joint was taken for a corner of a microradian (no cap) instead of a
    // curvature jump of 1/2 mm (cap sqrt(J Ts / 0.5)).
    use fairpath::geom::Arc;
    let r = 2.0;
    let arc = Arc::from_center(
        Vec3::new(38.0, 0.0, 0.0),
        Vec3::new(40.0, 2.0, 0.0),
        Vec3::new(38.0, 2.0, 0.0),
        Vec3::Z,
        false,
        0,
        1e-9,
    )
    .unwrap();
    let pieces: Vec<Piece> = [
        Curve::Line(Line::new(Vec3::ZERO, Vec3::new(38.0, 0.0, 0.0))),
        Curve::from(arc),
        Curve::Line(Line::new(
            Vec3::new(40.0, 2.0, 0.0),
            Vec3::new(40.0, 30.0, 0.0),
        )),
    ]
    .into_iter()
    .enumerate()
    .map(|(i, curve)| Piece {
        curve,
        rapid: false,
        source_lines: (i + 1, i + 1),
        feed: Some(24000.0),
    })
    .collect();
    let m = MachineLimits::thesis();
    let plan = plan_run(
        &pieces,
        &PlanOptions {
            limits: m,
            override_feed: false,
            window: None,
            ends: Default::default(),
        },
    )
    .unwrap();
    let cap = (m.jerk * m.period * r).sqrt();
    let mut s = 0.0;
    for seg in &plan.segments {
        s += seg.length;
        // Both ends of the arc are joints with the same curvature jump.
        if (s - 38.0).abs() < 1e-6 || (s - (38.0 + r * std::f64::consts::FRAC_PI_2)).abs() < 1e-6 {
            assert!(
                seg.profile.v1() <= cap * (1.0 + 1e-9),
                "{} > {cap} at s = {s}",
                seg.profile.v1()
            );
        }
    }
    check_limits(&pieces, &m);
}

#[test]
fn a_corner_is_passed_on_its_circle_at_the_circle_cap() {
    // Two 20 mm lines at 90 degrees: the planner replaces the last and
    // first T = R tan(45 deg) of them by the junction circle of radius
    // R = e sin45 / (1 - sin45), traversed over its arc length R pi / 2 at
    // its own cap (centripetal jerk (J R^2)^(1/3)), with the curvature
    // jump sqrt(J Ts R) where it leaves the first line and joins the second.
    use fairpath::feed::junction::{blend_cap, corner_blend};
    let pts = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(20.0, 0.0, 0.0),
        Vec3::new(20.0, 20.0, 0.0),
    ];
    let run = run_of(&pts, &[24000.0]);
    let m = MachineLimits::thesis();
    let bl = corner_blend(&m, Vec3::X, Vec3::new(0.0, 1.0, 0.0), 10.0).unwrap();
    let plan = plan_run(
        &run.pieces,
        &PlanOptions {
            limits: m,
            override_feed: false,
            window: None,
            ends: Default::default(),
        },
    )
    .unwrap();
    let total: f64 = plan.segments.iter().map(|s| s.length).sum();
    let want = 40.0 - 2.0 * bl.tangent_length + bl.arc_length;
    assert!((total - want).abs() < 1e-9, "{total} vs {want}");
    let on_circle = blend_cap(&m, &bl, 0.0);
    assert!((on_circle - (m.jerk * bl.radius * bl.radius).cbrt()).abs() < 1e-9);
    let jump = (m.jerk * m.period * bl.radius).sqrt();
    let parts: Vec<_> = plan.segments.iter().flat_map(|s| s.parts.iter()).collect();
    let blended: Vec<usize> = (0..parts.len())
        .filter(|&i| (parts[i].length - 0.5 * bl.arc_length).abs() < 1e-12)
        .collect();
    assert_eq!(blended.len(), 2);
    for &i in &blended {
        assert!((parts[i].cap - on_circle).abs() <= 1e-9 * on_circle);
    }
    // Entering the circle, and leaving it onto the second line.
    assert!((parts[blended[0]].entry_cap - jump).abs() <= 1e-9 * jump);
    assert!((parts[blended[1] + 1].entry_cap - jump).abs() <= 1e-9 * jump);
    check_limits(&run.pieces, &m);
}

#[test]
fn regression_130207l_reversal_next_to_a_gentle_corner() {
    // linuxcnc/wz-tests/130207L.ngc, lines 914-917: a gentle corner whose
    // circle meets the circle of a near-reversal. The reversal's curvature
    // jump capped the whole gentle circle at ~1e-7 mm/s (688,408 s of
    // planned time, and an interpolation that ran out of memory); the jump
    // belongs where the circles meet, the circles keep their own caps.
    let pts = [
        Vec3::new(10.2937, 3.7729, -0.035),
        Vec3::new(10.2673, 3.7992, -0.0122),
        Vec3::new(10.2551, 3.8114, 0.0),
        Vec3::new(10.2669, 3.7996, -0.0118),
        Vec3::new(10.30, 3.70, -0.0118),
    ];
    let run = run_of(&pts, &[80.0]);
    let m = MachineLimits::thesis();
    let t = check_limits(&run.pieces, &m);
    assert!(t < 1.0, "{t} s");
}

/// Regression, LinuxCNC `performance/tort.ngc` run 1: a 270-degree helical
/// arc of radius 7 mm (rise 3 mm), then a line at a corner of about 40
/// degrees. Sampled and fitted, as `auto` does, the curve's cap ripples by
/// fractions of a percent, and a segment boundary at every ripple stopped
/// the acceleration at each one: the machine crept up to speed over the
/// arc (planned 1.064 s against 0.724 s for the G-code as it is). Every
/// limit is still checked along the profile.
#[test]
fn regression_tort_ripples_of_a_fitted_arc_do_not_stop_the_acceleration() {
    use fairpath::choose::Auto;
    use fairpath::geom::Arc;
    let arc = Arc::from_center(
        Vec3::new(2.0, -1.0, 16.0),
        Vec3::new(9.0, 6.0, 13.0),
        Vec3::new(2.0, 6.0, 16.0),
        Vec3::new(0.0, 0.0, -1.0),
        false,
        0,
        1e-9,
    )
    .unwrap();
    let piece = |curve: Curve, line: usize| Piece {
        curve,
        rapid: false,
        source_lines: (line, line),
        feed: Some(24000.0),
    };
    let run = Run::new(vec![
        piece(Curve::from(arc), 1),
        piece(
            Curve::Line(Line::new(
                Vec3::new(9.0, 6.0, 13.0),
                Vec3::new(10.5, 10.5, 15.5),
            )),
            2,
        ),
    ]);
    let mut m = MachineLimits::thesis();
    m.junction_deviation = 0.05;
    let raw = check_limits(&run.pieces, &m);
    let smoothed = Auto::default().smooth_run(&run, 0.05).unwrap();
    let t = check_limits(&smoothed.pieces, &m);
    println!("as programmed {raw:.4} s, auto {t:.4} s");
    assert!(t <= raw * 1.2, "auto {t} s, as programmed {raw} s");
}

/// `RunEnds::AtCap` (the thesis' simulation, seed 003 section 4.5): a
/// straight run at the maximum feed takes exactly `L / V`; at rest it
/// takes longer by the time to reach and leave the feed; with a curve in
/// the middle, both plans slow down there and stay within the limits.
#[test]
fn runs_that_start_and_end_at_their_cap() {
    use fairpath::feed::plan::RunEnds;
    let m = MachineLimits::thesis();
    let opts = |ends| PlanOptions {
        limits: m,
        override_feed: true,
        window: None,
        ends,
    };
    let line = [Piece {
        curve: Curve::Line(Line::new(Vec3::ZERO, Vec3::new(100.0, 0.0, 0.0))),
        rapid: false,
        source_lines: (1, 1),
        feed: None,
    }];
    let at_cap = plan_run(&line, &opts(RunEnds::AtCap)).unwrap();
    assert!(
        (at_cap.time - 100.0 / m.max_feed).abs() < 1e-9,
        "{}",
        at_cap.time
    );
    let at_rest = plan_run(&line, &opts(RunEnds::AtRest)).unwrap();
    assert!(
        at_rest.time > at_cap.time + 0.05,
        "{} {}",
        at_rest.time,
        at_cap.time
    );
    // A run with a corner transition: slower than L / V, faster than from
    // rest, the profile starts and ends at the feed (the lines are long
    // enough to brake from it to the corner's cap and back: where they are
    // not, the start speed is lowered as the thesis lowers its maxima).
    let run = run_of(
        &[
            Vec3::ZERO,
            Vec3::new(200.0, 0.0, 0.0),
            Vec3::new(400.0, 80.0, 0.0),
        ],
        &[6000.0],
    );
    let pieces = BsplineCorner::default()
        .smooth_run(&run, 0.05)
        .unwrap()
        .pieces;
    let capped = plan_run(&pieces, &opts(RunEnds::AtCap)).unwrap();
    let rest = plan_run(&pieces, &opts(RunEnds::AtRest)).unwrap();
    let length: f64 = capped.segments.iter().map(|s| s.length).sum();
    assert!(capped.time > length / m.max_feed && capped.time < rest.time);
    let first = &capped.segments[0].profile;
    let last = &capped.segments[capped.segments.len() - 1].profile;
    assert!((first.eval(0.0).v - m.max_feed).abs() < 1e-9);
    assert!((last.eval(last.duration()).v - m.max_feed).abs() < 1e-6);
}

/// The planned times of the arc of `at` from 0 to `sweep` (centre on the
/// Z axis at its start's height, at `feed` mm/min) as one piece and cut
/// into `cuts` arcs meeting end to end.
fn whole_and_cut(at: impl Fn(f64) -> Vec3, sweep: f64, cuts: usize, feed: f64) -> (f64, f64) {
    use fairpath::geom::Arc;
    let arc = |a: f64, b: f64, line: usize| Piece {
        curve: Curve::from(
            Arc::from_center(
                at(a),
                at(b),
                Vec3::new(0.0, 0.0, at(a).z),
                Vec3::Z,
                false,
                1,
                1e-9,
            )
            .unwrap(),
        ),
        rapid: false,
        source_lines: (line, line),
        feed: Some(feed),
    };
    let opts = PlanOptions {
        limits: MachineLimits::thesis(),
        override_feed: false,
        window: None,
        ends: Default::default(),
    };
    let whole = vec![arc(0.0, sweep, 1)];
    check_limits(&whole, &opts.limits);
    let parts: Vec<Piece> = (0..cuts)
        .map(|i| {
            arc(
                sweep * i as f64 / cuts as f64,
                sweep * (i + 1) as f64 / cuts as f64,
                i + 1,
            )
        })
        .collect();
    (
        plan_run(&whole, &opts).unwrap().time,
        plan_run(&parts, &opts).unwrap().time,
    )
}

/// An arc planned as one piece and cut into many arcs meeting at G2
/// joints plans the same: the planner takes an arc's caps once for the
/// whole arc (they are the same all along it), not per flattened span.
#[test]
fn an_arc_plans_as_the_arcs_it_is_cut_into() {
    let mut rng = Rng(0x5eed_a4c5);
    for case in 0..40 {
        let r = 0.5 + 50.0 * rng.unit();
        let sweep = 0.2 + 5.0 * rng.unit();
        let rise = if case % 2 == 0 {
            0.0
        } else {
            10.0 * (rng.unit() - 0.5)
        };
        let feed = 600.0 + 24000.0 * rng.unit();
        let at = |th: f64| Vec3::new(r * th.cos(), r * th.sin(), rise * th / sweep);
        let cuts = 2 + (10.0 * rng.unit()) as usize;
        let (a, b) = whole_and_cut(at, sweep, cuts, feed);
        assert!(
            (a - b).abs() <= 1e-6 * a,
            "case {case}: r {r} sweep {sweep} rise {rise}: {a} vs {b}"
        );
    }
}

/// A spiral whose radius changes by a tenth (far more than an arc read
/// back from rounded coordinates) plans as the spirals it is cut into:
/// the planner samples it as a curve. Taken as one stretch (the least of
/// its caps all along it) the first one planned 0.239 s against 0.244 s
/// cut: the planner's profile depends on where its stretches end
/// (docs/planning.md), so the two ways must be the same way.
#[test]
fn a_spiral_plans_as_the_spirals_it_is_cut_into() {
    for (r0, r1, sweep) in [(2.0, 2.2, 3.0), (5.0, 4.5, 2.0), (0.8, 0.88, 4.0)] {
        let rad = |th: f64| r0 + (r1 - r0) * th / sweep;
        let at = |th: f64| Vec3::new(rad(th) * th.cos(), rad(th) * th.sin(), 0.0);
        let (whole, cut) = whole_and_cut(at, sweep, 8, 24000.0);
        assert!(
            (whole - cut).abs() <= 5e-3 * cut,
            "r {r0} -> {r1}: whole {whole} vs cut {cut}"
        );
    }
}

/// A feed move along `c` at the default machine's maximum feed.
fn piece(c: Curve) -> Piece {
    Piece {
        curve: c,
        rapid: false,
        source_lines: (1, 1),
        feed: Some(24000.0),
    }
}

/// Regression: a cubic B-spline with a control point repeated three times
/// (the way some CAM systems put a sharp corner into one spline block, and
/// the shape a JSON path or a G6.2 block can carry) has a corner at the
/// knot where it passes that point, and straight stretches either side:
/// its sampled curvature is zero everywhere the planner looked, so it ran
/// through the corner at the feed (20 mm of path with a right angle in
/// the middle planned as fast as 20 mm of straight line, 0.3175 s). The
/// corner is now passed as a corner followed exactly: the plan takes as
/// long as the same path as two lines with [`Corners::Followed`].
#[test]
fn regression_a_triple_control_point_is_a_corner_not_a_straight() {
    use fairpath::geom::Nurbs;
    let q = Vec3::new(10.0, 0.0, 0.0);
    let ctrl = vec![
        Vec3::new(9.8, 0.0, 0.0),
        Vec3::new(9.9, 0.0, 0.0),
        q,
        q,
        q,
        Vec3::new(10.0, 0.1, 0.0),
        Vec3::new(10.0, 0.2, 0.0),
    ];
    let knots = vec![0.0, 0.0, 0.0, 0.0, 0.25, 0.5, 0.75, 1.0, 1.0, 1.0, 1.0];
    let curve = Curve::from(Nurbs::new(3, knots, ctrl, None).unwrap());
    let with_spline = vec![
        piece(Curve::Line(Line::new(Vec3::ZERO, Vec3::new(9.8, 0.0, 0.0)))),
        piece(curve),
        piece(Curve::Line(Line::new(
            Vec3::new(10.0, 0.2, 0.0),
            Vec3::new(10.0, 10.0, 0.0),
        ))),
    ];
    let as_lines = run_of(&[Vec3::ZERO, q, Vec3::new(10.0, 10.0, 0.0)], &[24000.0]);
    let straight = run_of(&[Vec3::ZERO, Vec3::new(20.0, 0.0, 0.0)], &[24000.0]);
    let m = MachineLimits::thesis();
    let opts = PlanOptions {
        limits: m,
        override_feed: false,
        window: None,
        ends: Default::default(),
    };
    let time =
        |p: &[Piece], corners| plan_time_shaped(p, &opts, &Shaping::none(), corners).unwrap();
    let spline = time(&with_spline, Corners::Blended);
    let lines = time(&as_lines.pieces, Corners::Followed);
    let line = time(&straight.pieces, Corners::Blended);
    assert!(
        (spline - lines).abs() <= 1e-3 * lines,
        "spline {spline} s, two lines through the corner {lines} s"
    );
    assert!(spline > 1.4 * line, "spline {spline} s, straight {line} s");
    check_limits(&with_spline, &m);
}

/// Regression: a cubic span whose derivative vanishes inside it (control
/// points (0,0), (1,1), (0,1), (1,0): it stops at its middle and turns
/// back, as a least-squares fit through a reversal of a program does)
/// between two lines. The samples either side of the cusp saw a curvature
/// that let the plan through it at 1.1 mm/s, where turning back within a
/// period needs the speed of a reversal followed exactly (about 0.05
/// mm/s on this machine): the motion streamed at the servo period broke
/// the jerk limit there, and streaming LinuxCNC's `130207L.ngc` as the
/// exact curves `auto` fits to it (a V-carving, fits through the tips of
/// its strokes) took 249 s where the plan said 128 s. The cusp is now a
/// cut of the plan with the cap of a corner followed exactly.
#[test]
fn regression_a_cusp_inside_a_span_is_passed_as_a_reversal() {
    use fairpath::geom::Nurbs;
    let v = |x: f64, y: f64| Vec3::new(x, y, 0.0);
    let knots = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let cusp = Nurbs::new(
        3,
        knots,
        vec![v(0.0, 0.0), v(1.0, 1.0), v(0.0, 1.0), v(1.0, 0.0)],
        None,
    )
    .unwrap();
    let pieces = vec![
        piece(Curve::Line(Line::new(v(-5.0, -5.0), v(0.0, 0.0)))),
        piece(Curve::from(cusp)),
        piece(Curve::Line(Line::new(v(1.0, 0.0), v(6.0, -5.0)))),
    ];
    let m = MachineLimits::thesis();
    let plan = plan_run(
        &pieces,
        &PlanOptions {
            limits: m,
            override_feed: false,
            window: None,
            ends: Default::default(),
        },
    )
    .unwrap();
    // `Corners::Followed`: `min(A Ts, 5 J Ts^2) / (2 sin(phi / 2))`, phi = pi.
    let reversal = (m.acc * m.period).min(5.0 * m.jerk * m.period * m.period) / 2.0;
    let at_cusp: Vec<_> = plan
        .segments
        .iter()
        .flat_map(|s| s.parts.iter())
        .filter(|p| p.piece == 1 && (p.t0 - 0.5).abs() < 1e-6)
        .collect();
    // The turn is taken between the tangents a 32nd of the span either
    // side of the cusp: 179.4 degrees here.
    let slowest = at_cusp
        .iter()
        .map(|p| p.entry_cap)
        .fold(f64::INFINITY, f64::min);
    assert!(
        slowest <= reversal * 1.01,
        "{slowest} mm/s at the cusp, a reversal {reversal}"
    );
    check_limits(&pieces, &m);
}

/// A circle of radius 5 mm, a quarter of it as an arc and the next
/// quarter as chords of 0.02 mm (arcs that give way to G1 where a curve
/// leaves their plane, as on LinuxCNC's `blur_torus.ngc`): the chords'
/// blends fill them and go on at the circle's curvature, so the joint
/// between the arc and the first chord is no curvature jump. Taken as a
/// jump from the arc's curvature to a line's (and the first blend's on
/// top) it capped the joint at `sqrt(J Ts / 1.5 k)`, 8 mm/s, where the
/// circle runs at 100.
#[test]
fn regression_blur_torus_an_arc_going_on_as_short_moves_keeps_its_curvature() {
    use fairpath::geom::Arc;
    let r = 5.0;
    let at = |th: f64| Vec3::new(r * th.cos(), r * th.sin(), 0.0);
    let quarter = std::f64::consts::FRAC_PI_2;
    let arc = |a: f64, b: f64| {
        Curve::from(Arc::from_center(at(a), at(b), Vec3::ZERO, Vec3::Z, false, 0, 1e-9).unwrap())
    };
    let n = (r * quarter / 0.02).round() as usize;
    let chords = |from: f64| -> Vec<Curve> {
        (0..n)
            .map(|i| {
                let th = |i: usize| from + quarter * i as f64 / n as f64;
                Curve::Line(Line::new(at(th(i)), at(th(i + 1))))
            })
            .collect()
    };
    let opts = PlanOptions {
        limits: MachineLimits::thesis(),
        override_feed: false,
        window: None,
        ends: Default::default(),
    };
    let time = |curves: Vec<Curve>| {
        let pieces: Vec<Piece> = curves.into_iter().map(piece).collect();
        check_limits(&pieces, &opts.limits);
        plan_run(&pieces, &opts).unwrap().time
    };
    let arcs = time(vec![arc(0.0, quarter), arc(quarter, 2.0 * quarter)]);
    let lines = time([chords(0.0), chords(quarter)].concat());
    let mixed = time([vec![arc(0.0, quarter)], chords(quarter)].concat());
    let mixed_back = time([chords(0.0), vec![arc(quarter, 2.0 * quarter)]].concat());
    for (name, t) in [("arc then chords", mixed), ("chords then arc", mixed_back)] {
        assert!(
            t <= arcs.max(lines) * 1.005,
            "{name}: {t} s, all arcs {arcs} s, all chords {lines} s"
        );
    }
}
