//! Invariants of `bspline-fit`: on smooth curves (circles, sines, helices)
//! sampled as CAM does (chord error, noise, coordinates rounded to 1 um),
//! on random and degenerate polylines, and on mixes of dense sections with
//! long lines and corners: within tolerance (checked by the independent
//! verifier), endpoints exact, G2 at every joint but kept corners. Also:
//! control-point count against tolerance, and peak curvature against the
//! true curve and against `bspline-corner`.

use crate::common;
use common::{check_guarantees, polyline_run, v};
use fairpath::geom::fit::{chord_params, span_errors, EndCondition};
use fairpath::geom::{Curve, ParamCurve, Vec3};
use fairpath::path::Run;
use fairpath::smooth::{
    dense_sections, fit_polyline, BsplineCorner, BsplineFit, BsplineFitOptions, SectionOptions,
    SmoothedRun, Smoother, BAND_USE, TRANSITION_KNOTS,
};
use fairpath::verify::{verify_run, Continuity, RunReport, VerifyOptions};
use proptest::prelude::*;
use std::f64::consts::PI;

/// Samples `f` on `[0, 1]` as a CAM system does: chords whose sagitta
/// (checked at 1/4, 1/2, 3/4) stays below `chord`, no longer than
/// `max_len`; then adds uniform noise up to `noise` mm (from `seed`) and
/// rounds to 1 um. The end points are rounded too, not noised.
fn cam_sample(
    f: &dyn Fn(f64) -> Vec3,
    chord: f64,
    max_len: f64,
    noise: f64,
    seed: u64,
) -> Vec<Vec3> {
    cam_sample_at(f, chord, max_len, noise, seed, 1e-3)
}

/// [`cam_sample`] rounding to `resolution` mm (0: no rounding).
fn cam_sample_at(
    f: &dyn Fn(f64) -> Vec3,
    chord: f64,
    max_len: f64,
    noise: f64,
    seed: u64,
    resolution: f64,
) -> Vec<Vec3> {
    let mut pts = vec![f(0.0)];
    let (mut t, mut dt) = (0.0f64, 1e-3);
    while t < 1.0 {
        let mut t1 = (t + dt).min(1.0);
        loop {
            let (a, b) = (f(t), f(t1));
            let sag = [0.25, 0.5, 0.75]
                .iter()
                .map(|&s| {
                    let p = f(t + (t1 - t) * s);
                    fairpath::geom::point_segment_distance(p, a, b)
                })
                .fold(0.0, f64::max);
            if (sag <= chord && a.dist(b) <= max_len) || t1 - t < 1e-9 {
                break;
            }
            t1 = t + 0.6 * (t1 - t);
        }
        dt = (t1 - t) * 1.5;
        t = t1;
        pts.push(f(t));
    }
    let mut state = seed | 1;
    let mut rnd = || {
        // xorshift64*
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let n = pts.len();
    let mut out: Vec<Vec3> = pts
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let q = if i == 0 || i == n - 1 {
                *p
            } else {
                *p + v(rnd(), rnd(), rnd()) * noise
            };
            if resolution > 0.0 {
                let r = |x: f64| (x / resolution).round() * resolution;
                v(r(q.x), r(q.y), r(q.z))
            } else {
                q
            }
        })
        .collect();
    out.dedup();
    out
}

fn round_v(p: Vec3) -> Vec3 {
    let r = |x: f64| (x * 1000.0).round() / 1000.0;
    v(r(p.x), r(p.y), r(p.z))
}

#[derive(Clone, Copy, Debug)]
enum Shape {
    Circle { r: f64, sweep: f64 },
    Sine { amp: f64, wave: f64, len: f64 },
    Helix { r: f64, pitch: f64, turns: f64 },
}

impl Shape {
    fn eval(self, t: f64) -> Vec3 {
        match self {
            Shape::Circle { r, sweep } => v(r * (t * sweep).cos(), r * (t * sweep).sin(), 0.0),
            Shape::Sine { amp, wave, len } => {
                let x = t * len;
                v(
                    x,
                    amp * (2.0 * PI * x / wave).sin(),
                    0.3 * amp * (PI * x / wave).cos(),
                )
            }
            Shape::Helix { r, pitch, turns } => {
                let a = t * turns * 2.0 * PI;
                v(r * a.cos(), r * a.sin(), -pitch * turns * t)
            }
        }
    }
}

fn shape() -> impl Strategy<Value = Shape> {
    prop_oneof![
        (2.0..60.0f64, 0.5..6.0f64).prop_map(|(r, sweep)| Shape::Circle { r, sweep }),
        (0.5..8.0f64, 10.0..60.0f64, 20.0..120.0f64).prop_map(|(amp, wave, len)| Shape::Sine {
            amp,
            wave,
            len
        }),
        (3.0..30.0f64, 0.5..5.0f64, 0.5..3.0f64).prop_map(|(r, pitch, turns)| Shape::Helix {
            r,
            pitch,
            turns
        }),
    ]
}

fn smooth_and_verify(run: &Run, tol: f64, s: &dyn Smoother) -> (SmoothedRun, RunReport) {
    let out = s.smooth_run(run, tol).unwrap();
    let rep = verify_run(&run.pieces, &out.pieces, &VerifyOptions::new(tol));
    (out, rep)
}

/// Fitted pieces: cubic B-splines other than corner transitions.
fn fitted_pieces(out: &SmoothedRun) -> usize {
    out.pieces
        .iter()
        .filter(|p| matches!(&p.curve, Curve::Nurbs(n) if n.knots != TRANSITION_KNOTS))
        .count()
}

fn tol() -> impl Strategy<Value = f64> {
    prop_oneof![Just(0.005), Just(0.01), Just(0.05), Just(0.2)]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Smooth curves sampled at CAM-like chords with noise and 1 um
    /// rounding: the whole curve is one dense section, fitted.
    #[test]
    fn smooth_curves_fit_within_tolerance(
        shape in shape(),
        chord_rel in 0.02..0.5f64,
        noise_rel in 0.0..0.1f64,
        tol in tol(),
        seed in any::<u64>(),
    ) {
        let pts = cam_sample(&|t| shape.eval(t), chord_rel * tol, 4.0, noise_rel * tol, seed);
        let run = polyline_run(&pts);
        let (out, rep) = smooth_and_verify(&run, tol, &BsplineFit::default());
        check_guarantees(&out, &rep, tol)?;
        prop_assert!(rep.peak_curvature.is_finite());
        prop_assert!(fitted_pieces(&out) >= 1, "nothing fitted on {:?}", shape);
    }

    /// The same with the jerk term (`auto`'s jerk-faired candidate) at
    /// weights up to three times `auto`'s: the guarantees do not depend on
    /// the weights.
    #[test]
    fn jerk_faired_fits_stay_within_tolerance(
        shape in shape(),
        chord_rel in 0.02..0.5f64,
        tol in tol(),
        jerk in 0.0..1e5f64,
        seed in any::<u64>(),
    ) {
        let pts = cam_sample(&|t| shape.eval(t), chord_rel * tol, 4.0, 0.05 * tol, seed);
        let run = polyline_run(&pts);
        let s = BsplineFit {
            options: BsplineFitOptions {
                jerk_fairness: jerk,
                ..Default::default()
            },
        };
        let (out, rep) = smooth_and_verify(&run, tol, &s);
        check_guarantees(&out, &rep, tol)?;
        prop_assert!(rep.peak_curvature.is_finite());
    }
}

fn pt2(scale: f64) -> impl Strategy<Value = Vec3> {
    (-scale..scale, -scale..scale).prop_map(|(x, y)| v(x, y, 0.0))
}
fn pt3(scale: f64) -> impl Strategy<Value = Vec3> {
    (-scale..scale, -scale..scale, -scale..scale).prop_map(|(x, y, z)| v(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Random polylines: mostly sparse, some dense random walks; the
    /// guarantees hold whatever the detection decides.
    #[test]
    fn random_polylines(pts in prop::collection::vec(pt2(20.0), 2..40), tol in tol()) {
        let run = polyline_run(&pts);
        let (out, rep) = smooth_and_verify(&run, tol, &BsplineFit::default());
        check_guarantees(&out, &rep, tol)?;
    }

    #[test]
    fn dense_random_walks(start in pt3(1.0), steps in prop::collection::vec(pt3(0.05), 2..300), tol in tol()) {
        let mut pts = vec![start];
        for s in steps { let p = *pts.last().unwrap() + s; pts.push(p); }
        let run = polyline_run(&pts);
        let (out, rep) = smooth_and_verify(&run, tol, &BsplineFit::default());
        check_guarantees(&out, &rep, tol)?;
    }

    /// Gentle random walks (small turns): long dense sections with noise.
    #[test]
    fn gentle_walks_with_duplicates(
        turns in prop::collection::vec(-0.2..0.2f64, 10..300),
        lens in prop::collection::vec(0.05..2.0f64, 10..300),
        dup in prop::collection::vec(any::<u8>(), 300),
        tol in tol(),
    ) {
        let mut pts = vec![v(0.0, 0.0, 0.0)];
        let mut heading = 0.0f64;
        for (i, (t, l)) in turns.iter().zip(&lens).enumerate() {
            heading += t;
            let p = *pts.last().unwrap() + v(heading.cos(), heading.sin(), 0.1 * t) * *l;
            pts.push(round_v(p));
            if dup[i] % 17 == 0 { pts.push(round_v(p)); }
        }
        let run = polyline_run(&pts);
        let (out, rep) = smooth_and_verify(&run, tol, &BsplineFit::default());
        check_guarantees(&out, &rep, tol)?;
    }

    /// Dense sections between long lines and sharp corners, and tangent
    /// entries into sampled arcs: joins with the corner method.
    #[test]
    fn mixed_dense_and_sparse(
        r in 3.0..30.0f64,
        sweep in 0.5..3.0f64,
        lead in 1.0..40.0f64,
        kink in -1.5..1.5f64,
        chord_rel in 0.05..0.5f64,
        tol in tol(),
        seed in any::<u64>(),
    ) {
        // Lead-in line, an arc entered at an angle `kink`, lead-out line
        // along the arc's end tangent, then a sharp corner and a sine.
        let arc = cam_sample(&|t| {
            let a = t * sweep;
            v(r * a.sin(), r * (1.0 - a.cos()), 0.0)
        }, chord_rel * tol, 4.0, 0.05 * tol, seed);
        let mut pts = vec![round_v(v(-lead * kink.cos(), lead * kink.sin(), 0.0))];
        pts.extend(arc.iter().copied());
        let end = *arc.last().unwrap();
        let tan = v(sweep.cos(), sweep.sin(), 0.0);
        let p = round_v(end + tan * lead);
        pts.push(p);
        let normal = v(-tan.y, tan.x, 0.0);
        let sine = cam_sample(&|t| p + normal * (t * 30.0) + tan * (2.0 * (t * 6.0).sin()), chord_rel * tol, 4.0, 0.0, seed);
        pts.extend(sine.iter().skip(1).copied());
        let run = polyline_run(&pts);
        let (out, rep) = smooth_and_verify(&run, tol, &BsplineFit::default());
        check_guarantees(&out, &rep, tol)?;
    }
}

#[test]
fn tangent_entry_into_a_sampled_arc_is_g2_everywhere() {
    let tol = 0.05;
    let arc = cam_sample(
        &|t| {
            let a = t * 2.0;
            v(10.0 * a.sin(), 10.0 * (1.0 - a.cos()), 0.0)
        },
        0.005,
        4.0,
        0.0,
        7,
    );
    let mut pts = vec![v(-20.0, 0.0, 0.0)];
    pts.extend(arc.iter().copied());
    let end = *arc.last().unwrap();
    pts.push(round_v(end + v(2f64.cos(), 2f64.sin(), 0.0) * 20.0));
    let run = polyline_run(&pts);
    let (out, rep) = smooth_and_verify(&run, tol, &BsplineFit::default());
    assert!(rep.within(tol), "{rep:?}");
    assert!(out.kept_corners.is_empty());
    assert!(rep.joints.iter().all(|j| j.class == Continuity::G2));
    assert!(fitted_pieces(&out) >= 1);
}

/// The pass ends of LinuxCNC `performance/test_12mmflat.ngc`: a long line
/// meets a sampled arc (radius 4.3 mm, chords of about 0.29 mm) at a corner
/// of 15 degrees. Regression: the fit started at that vertex along the
/// line, so it had to make the whole turn there on the arc's first chords;
/// it now leads in along the line (0.4 of its 20 mm, below the cap of 200
/// tolerances) and rounds the corner inside the band, which the machine
/// runs faster.
#[test]
fn a_fit_leads_in_along_the_line_before_a_corner() {
    let tol = 0.05;
    let r = 4.3;
    let turn = 15f64.to_radians();
    // The arc leaves the origin at 15 degrees to the line, turning left.
    let centre = v(-r * turn.sin(), r * turn.cos(), 0.0);
    let n = 40; // 0.29 mm chords over 155 degrees
    let sweep = 155f64.to_radians();
    let mut pts = vec![v(-20.0, 0.0, 0.0)];
    for i in 0..=n {
        let a = -PI / 2.0 + turn + sweep * i as f64 / n as f64;
        pts.push(centre + v(r * a.cos(), r * a.sin(), 0.0));
    }
    let run = polyline_run(&pts);
    let (out, rep) = smooth_and_verify(&run, tol, &BsplineFit::default());
    assert!(rep.within(tol), "{rep:?}");
    assert!(out.kept_corners.is_empty());
    assert!(rep.joints.iter().all(|j| j.class == Continuity::G2));
    // The fit starts on the line, 8 mm (0.4 of it) before the vertex, and
    // the path no longer passes through the vertex.
    let fit = out
        .pieces
        .iter()
        .find(|p| matches!(&p.curve, Curve::Nurbs(n) if n.knots != TRANSITION_KNOTS))
        .expect("a fitted piece");
    assert!(
        fit.curve.start().dist(v(-8.0, 0.0, 0.0)) < 1e-9,
        "{:?}",
        fit.curve.start()
    );
    // `f` at 401 parameters of every piece.
    let sampled = |f: &dyn Fn(&Curve, f64) -> f64| -> Vec<f64> {
        out.pieces
            .iter()
            .flat_map(|p| {
                let (a, b) = p.curve.domain();
                (0..=400).map(move |i| (p, a + (b - a) * i as f64 / 400.0))
            })
            .map(|(p, t)| f(&p.curve, t))
            .collect()
    };
    let vertex_gap = sampled(&|c, t| c.eval(t).dist(Vec3::ZERO))
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    assert!(vertex_gap > 0.1 * tol, "{vertex_gap}");
    // The corner is taken on a radius the band allows, not on a chord:
    // a 15-degree turn within 0.05 mm needs no curvature above 1/0.5 mm.
    let peak = sampled(&|c, t| c.curvature(t))
        .into_iter()
        .fold(0.0, f64::max);
    assert!(peak < 2.0, "peak curvature {peak} 1/mm");
}

#[test]
fn long_fits_are_cut_into_pieces_that_join_g2() {
    let tol = 0.01;
    let shape = Shape::Helix {
        r: 8.0,
        pitch: 1.0,
        turns: 5.0,
    };
    let pts = cam_sample(&|t| shape.eval(t), 0.002, 4.0, 0.0005, 3);
    let run = polyline_run(&pts);
    let s = BsplineFit {
        options: BsplineFitOptions {
            max_piece_spans: 4,
            ..Default::default()
        },
    };
    let (out, rep) = smooth_and_verify(&run, tol, &s);
    assert!(rep.within(tol), "{rep:?}");
    assert!(out.pieces.len() > 3, "{} pieces", out.pieces.len());
    assert!(
        rep.joints.iter().all(|j| j.class == Continuity::G2),
        "{:?}",
        rep.joint_counts()
    );
    // Source lines cover the run in order.
    assert_eq!(out.pieces[0].source_lines.0, 1);
    assert_eq!(out.pieces.last().unwrap().source_lines.1, pts.len() - 1);
}

#[test]
fn detection_rule_on_a_raster_row_and_its_corners() {
    // Two rows of 1 mm segments joined by a 90-degree step-over.
    let mut pts: Vec<Vec3> = (0..=20)
        .map(|i| v(i as f64, 0.0, 0.01 * (i as f64 * 0.3).sin()))
        .collect();
    pts.extend((0..=20).map(|i| v(20.0 - i as f64, 2.0, 0.0)));
    let secs = dense_sections(&pts, 0.05, &SectionOptions::default());
    assert_eq!(secs, vec![(0, 19), (22, 41)]);
    // A 5-degree turn between 3 mm moves: a sample at 0.05 mm, a corner at
    // 0.005 mm (rule 3).
    let a = 5f64.to_radians();
    let mut zig = vec![v(0.0, 0.0, 0.0)];
    for i in 1..12 {
        let h = a * i as f64;
        let p = *zig.last().unwrap() + v(h.cos(), h.sin(), 0.0) * 3.0;
        zig.push(p);
    }
    let o = SectionOptions::default();
    assert_eq!(dense_sections(&zig, 0.05, &o), vec![(0, 11)]);
    assert!(dense_sections(&zig, 0.005, &o).is_empty());
    // Too few points.
    assert!(dense_sections(&zig[..3], 0.05, &o).is_empty());
    assert_eq!(dense_sections(&zig[..4], 0.05, &o), vec![(0, 3)]);
    // LinuxCNC `performance/spiral_lines.ngc`, outer turns: 4.9 mm moves
    // turning by 5.7 degrees, a circle sampled at a chord error of 0.061 mm.
    // Regression: with a factor of 1 on the implied chord error these were
    // corners at 0.05 mm; the circle moved inwards by half the sagitta is
    // within 0.031 mm of vertices and chords, so they are dense and the fit
    // passes within the band.
    let a = 5.7f64.to_radians();
    let mut spiral = vec![v(0.0, 0.0, 0.0)];
    for i in 1..40 {
        let h = a * i as f64;
        let p = *spiral.last().unwrap() + v(h.cos(), h.sin(), 0.0) * 4.9;
        spiral.push(round_v(p));
    }
    assert_eq!(dense_sections(&spiral, 0.05, &o), vec![(0, 39)]);
    let strict = SectionOptions {
        chord_error_per_tol: 1.0,
        ..o
    };
    assert!(dense_sections(&spiral, 0.05, &strict).is_empty());
    let band = 0.05 * BAND_USE;
    let fit = fit_polyline(&spiral, EndCondition::Free, EndCondition::Free, band, 1.0)
        .expect("the spiral fits within the band");
    assert_within_with_exact_ends(&fit.curve, &spiral, band);
}

#[test]
fn bad_options_and_tolerances_are_rejected() {
    let run = polyline_run(&[v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(1.0, 1.0, 0.0)]);
    for t in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-12, 1e9] {
        assert!(BsplineFit::default().smooth_run(&run, t).is_err(), "{t}");
    }
    let bad = [
        BsplineFitOptions {
            fairness: -1.0,
            ..Default::default()
        },
        BsplineFitOptions {
            band_use: 1.5,
            ..Default::default()
        },
        BsplineFitOptions {
            max_piece_spans: 0,
            ..Default::default()
        },
        BsplineFitOptions {
            relax: Some(fairpath::geom::band_fit::RelaxOptions {
                radius_share: 1.5,
                ..Default::default()
            }),
            ..Default::default()
        },
        BsplineFitOptions {
            relax: Some(fairpath::geom::band_fit::RelaxOptions {
                spacing_per_target: f64::NAN,
                ..Default::default()
            }),
            ..Default::default()
        },
        BsplineFitOptions {
            sections: SectionOptions {
                min_points: 1,
                ..Default::default()
            },
            ..Default::default()
        },
    ];
    for o in bad {
        assert!(BsplineFit { options: o }.smooth_run(&run, 0.05).is_err());
    }
}

#[test]
fn run_of_zero_length_moves_and_single_segment() {
    let p = v(1.0, 2.0, 3.0);
    let run = polyline_run(&[p, p, p]);
    let out = BsplineFit::default().smooth_run(&run, 0.05).unwrap();
    assert!(out.pieces.is_empty());
    let run = polyline_run(&[p, v(2.0, 2.0, 3.0)]);
    let (out, rep) = smooth_and_verify(&run, 0.05, &BsplineFit::default());
    assert!(rep.within(0.05));
    assert_eq!(out.pieces.len(), 1);
}

/// Largest distance from `curve`, sampled at `n + 1` even parameters, to
/// the polyline `pts`: an independent check of a fit's bound.
fn sampled_distance(curve: &fairpath::geom::Nurbs, pts: &[Vec3], n: usize) -> f64 {
    let (a, b) = curve.domain();
    (0..=n)
        .map(|i| {
            let q = curve.eval(a + (b - a) * i as f64 / n as f64);
            fairpath::geom::distance_to_polyline(q, pts).unwrap().0
        })
        .fold(0.0, f64::max)
}

/// `curve` lies within `target` of the polyline `pts` (sampled at 20,001
/// parameters) and starts and ends exactly at its end points.
fn assert_within_with_exact_ends(curve: &fairpath::geom::Nurbs, pts: &[Vec3], target: f64) {
    let worst = sampled_distance(curve, pts, 20_000);
    assert!(worst <= target, "{worst}");
    let (a, b) = curve.domain();
    assert_eq!(curve.eval(a), pts[0]);
    assert_eq!(curve.eval(b), pts[pts.len() - 1]);
}

/// The span bound is an upper bound of the true distance: checked against
/// dense sampling of the fit.
#[test]
fn span_bound_holds_on_dense_samples() {
    let shape = Shape::Sine {
        amp: 3.0,
        wave: 20.0,
        len: 60.0,
    };
    let pts = cam_sample(&|t| shape.eval(t), 0.01, 4.0, 0.002, 11);
    let fit = fit_polyline(
        &pts,
        EndCondition::Free,
        EndCondition::Free,
        0.05 * BAND_USE,
        1.0,
    )
    .unwrap();
    let params = chord_params(&pts);
    let errs = span_errors(&fit.curve, &pts, &params);
    let bound = errs.iter().copied().fold(0.0, f64::max);
    assert!((bound - fit.bound).abs() <= 1e-12);
    let worst = sampled_distance(&fit.curve, &pts, 20_000);
    assert!(worst <= bound, "sampled {worst} > bound {bound}");
    assert!(bound <= 0.05 * BAND_USE);
    println!("span bound {bound:.5} mm, sampled {worst:.5} mm");
}

/// Raising the smoothing weights inside the band (seed 003's aim,
/// `fit_polyline_faired`): on a CAM-sampled sine with noise the raised fit
/// uses a larger weight, stays within the target (sampled densely, not
/// only by its own bound), keeps the end points, and bends less: its
/// `integral |C''|^2` and its peak curvature are both lower than those of
/// the fit at the default weight.
#[test]
fn raising_the_fairness_inside_the_band_lowers_the_bending() {
    use fairpath::smooth::{fit_polyline_faired, FAIRNESS_RAISES};
    let shape = Shape::Sine {
        amp: 3.0,
        wave: 20.0,
        len: 60.0,
    };
    let pts = cam_sample(&|t| shape.eval(t), 0.005, 4.0, 0.003, 17);
    let target = 0.05 * BAND_USE;
    let free = (EndCondition::Free, EndCondition::Free);
    let base = fit_polyline_faired(&pts, free.0, free.1, target, (1.0, 0.0), 0, None).unwrap();
    let raised = fit_polyline_faired(
        &pts,
        free.0,
        free.1,
        target,
        (1.0, 0.0),
        FAIRNESS_RAISES,
        None,
    )
    .unwrap();
    assert!(
        raised.lambda >= 16.0 * base.lambda,
        "{} {}",
        raised.lambda,
        base.lambda
    );
    // integral |C''|^2 and peak curvature by dense sampling.
    let bending = |c: &fairpath::geom::Nurbs| -> (f64, f64) {
        let (a, b) = c.domain();
        let n = 20_000;
        let h = (b - a) / n as f64;
        let mut sum = 0.0;
        let mut peak: f64 = 0.0;
        for i in 0..n {
            let t = a + h * (i as f64 + 0.5);
            sum += c.deriv2(t).norm_sq() * h;
            peak = peak.max(c.curvature(t));
        }
        (sum, peak)
    };
    let (e0, k0) = bending(&base.curve);
    let (e1, k1) = bending(&raised.curve);
    println!("bending {e0:.5} -> {e1:.5}, peak curvature {k0:.4} -> {k1:.4}");
    assert!(e1 < e0, "{e1} vs {e0}");
    assert!(k1 < 0.97 * k0, "{k1} vs {k0}");
    assert_within_with_exact_ends(&raised.curve, &pts, target);
}

/// Approximation theory: a cubic spline with `N` well-placed knots
/// approximates a smooth curve with error `O(N^-4)` (de Boor, A Practical
/// Guide to Splines, ch. XII), so the control-point count grows like
/// `tol^(-1/4)`: each 16-fold tighter tolerance about doubles it. Checked
/// loosely (factor 1.4 to 3.2 per 16-fold step) on a finely sampled curve,
/// where the data's own chord error stays far below the tolerances.
#[test]
fn control_points_grow_like_tolerance_to_the_minus_quarter() {
    let shape = Shape::Sine {
        amp: 5.0,
        wave: 40.0,
        len: 120.0,
    };
    // Not rounded: 1 um rounding would exceed the tightest tolerance.
    let pts = cam_sample_at(&|t| shape.eval(t), 2e-6, 1.0, 0.0, 1, 0.0);
    let mut counts = Vec::new();
    for tol in [0.2, 0.2 / 16.0, 0.2 / 256.0] {
        let fit = fit_polyline(
            &pts,
            EndCondition::Free,
            EndCondition::Free,
            tol * BAND_USE,
            1.0,
        )
        .unwrap();
        counts.push(fit.curve.points.len());
        println!(
            "tol {tol:.5}: {} control points, {} fits, bound {:.3e}",
            fit.curve.points.len(),
            fit.fits,
            fit.bound
        );
    }
    for w in counts.windows(2) {
        let r = w[1] as f64 / w[0] as f64;
        assert!((1.4..=3.2).contains(&r), "counts {counts:?}");
    }
}

/// A surface-raster-like row: a smooth 3D curve sampled at chord 0.002 mm
/// (segments about 1 mm), rounded to 1 um, at tolerance 0.05 mm. The fit's
/// peak curvature stays close to the true curve's; `bspline-corner`, which
/// bends only at the vertices, peaks far higher.
#[test]
fn surface_raster_peak_curvature_near_true_curve() {
    let f = |t: f64| {
        let x = 100.0 * t;
        v(x, 0.0, 5.0 * (x / 12.0).sin() + 1.5 * (x / 5.0 + 0.3).cos())
    };
    // True curvature of z(x): |z''| / (1 + z'^2)^(3/2).
    let true_peak = (0..=100000)
        .map(|i| {
            let x = 100.0 * i as f64 / 100000.0;
            let z1 = 5.0 / 12.0 * (x / 12.0).cos() - 1.5 / 5.0 * (x / 5.0 + 0.3).sin();
            let z2 = -5.0 / 144.0 * (x / 12.0).sin() - 1.5 / 25.0 * (x / 5.0 + 0.3).cos();
            z2.abs() / (1.0 + z1 * z1).powf(1.5)
        })
        .fold(0.0, f64::max);
    let pts = cam_sample(&f, 0.002, 4.0, 0.0, 5);
    let mean = chord_params(&pts).last().unwrap() / (pts.len() - 1) as f64;
    let run = polyline_run(&pts);
    let tol = 0.05;
    let (fit_out, fit) = smooth_and_verify(&run, tol, &BsplineFit::default());
    let (_, corner) = smooth_and_verify(&run, tol, &BsplineCorner::default());
    println!(
        "surface-raster-like row: {} segments, mean {:.3} mm; peak curvature: true {:.4}, \
         bspline-fit {:.4} ({} pieces, deviation {:.4}), bspline-corner {:.4} (deviation {:.4}) 1/mm",
        pts.len() - 1,
        mean,
        true_peak,
        fit.peak_curvature,
        fit_out.pieces.len(),
        fit.deviation_bound,
        corner.peak_curvature,
        corner.deviation_bound
    );
    assert!(fit.within(tol) && corner.within(tol));
    assert!(fit.peak_curvature <= 1.25 * true_peak);
    assert!(corner.peak_curvature >= 2.0 * fit.peak_curvature);
}

/// Reads the G1 moves of a simple G-code file (G0/G1 with X Y Z words,
/// absolute mm) as runs of points; `None` when the file is absent.
fn read_simple_ngc(name: &str) -> Option<Vec<Vec<Vec3>>> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/paths/synthetic")
        .join(name);
    let Ok(text) = std::fs::read_to_string(&path) else {
        eprintln!("{} not found: skipped", path.display());
        return None;
    };
    let mut runs: Vec<Vec<Vec3>> = Vec::new();
    let mut cur = v(0.0, 0.0, 0.0);
    let mut mode = 0;
    let mut run: Vec<Vec3> = Vec::new();
    for line in text.lines() {
        let line = line.split('(').next().unwrap().trim();
        let mut next = cur;
        for w in line.split_whitespace() {
            let (k, val) = w.split_at(1);
            let Ok(x) = val.parse::<f64>() else { continue };
            match k {
                "G" if x == 0.0 || x == 1.0 => mode = x as i32,
                "X" => next.x = x,
                "Y" => next.y = x,
                "Z" => next.z = x,
                _ => {}
            }
        }
        if next != cur {
            if mode == 1 {
                if run.is_empty() {
                    run.push(cur);
                }
                run.push(next);
            } else if run.len() > 1 {
                runs.push(std::mem::take(&mut run));
            } else {
                run.clear();
            }
            cur = next;
        }
    }
    if run.len() > 1 {
        runs.push(run);
    }
    Some(runs)
}

#[test]
fn shared_surface_raster_and_helix() {
    for (name, tol) in [
        ("surface-raster.ngc", 0.05),
        ("helix.ngc", 0.05),
        ("helix.ngc", 0.01),
    ] {
        let Some(runs) = read_simple_ngc(name) else {
            return;
        };
        for pts in runs {
            let run = polyline_run(&pts);
            let (out, fit) = smooth_and_verify(&run, tol, &BsplineFit::default());
            let (_, corner) = smooth_and_verify(&run, tol, &BsplineCorner::default());
            println!(
                "{name} at {tol}: {} segments -> {} pieces ({} fitted), kept corners {}, \
                 joints {:?}, deviation {:.4}; peak curvature fit {:.4} vs bspline-corner {:.4} 1/mm",
                pts.len() - 1,
                out.pieces.len(),
                fitted_pieces(&out),
                out.kept_corners.len(),
                fit.joint_counts(),
                fit.deviation_bound,
                fit.peak_curvature,
                corner.peak_curvature
            );
            assert!(fit.within(tol), "{name}: {fit:?}");
            assert!(fitted_pieces(&out) >= 1);
            for j in &fit.joints {
                assert!(
                    j.class == Continuity::G2
                        || out.kept_corners.iter().any(|k| k.at.dist(j.at) <= 1e-9),
                    "{name}: joint {j:?}"
                );
            }
            assert!(fit.peak_curvature < corner.peak_curvature);
            if name.starts_with("surface") {
                // One raster row alone (the first dense section), where the
                // step-over corners do not dominate the peak.
                let (k, m) = dense_sections(&pts, tol, &SectionOptions::default())[0];
                let row = polyline_run(&pts[k..=m]);
                let (_, f) = smooth_and_verify(&row, tol, &BsplineFit::default());
                let (_, c) = smooth_and_verify(&row, tol, &BsplineCorner::default());
                println!(
                    "{name} first row ({} segments): peak curvature fit {:.4} vs bspline-corner {:.4} 1/mm",
                    m - k,
                    f.peak_curvature,
                    c.peak_curvature
                );
                assert!(f.within(tol) && c.within(tol));
                assert!(2.0 * f.peak_curvature < c.peak_curvature);
            }
        }
    }
}

#[test]
fn a_zigzag_finer_than_the_tolerance_is_fitted_not_blended() {
    // Like LinuxCNC's performance/zigzag_0.002_0.0005.ngc: 90-degree turns
    // every 0.0508 mm, +-0.0127 mm about a line, at 0.05 mm: every vertex
    // turns sharply but lies within the band around its neighbours' chord,
    // so the run is one dense section and the fit runs straight through.
    let pts: Vec<Vec3> = (0..=400)
        .map(|i| {
            let y = if i == 0 || i == 400 {
                0.0
            } else if i % 2 == 1 {
                -0.0127
            } else {
                0.0127
            };
            v(i as f64 * 0.0508, y, 0.0)
        })
        .collect();
    let tol = 0.05;
    assert_eq!(
        dense_sections(&pts, tol, &SectionOptions::default()),
        vec![(0, 400)]
    );
    // With the wiggle rule off, the sharp turns are corners.
    let strict = SectionOptions {
        wiggle_per_tol: 0.0,
        ..Default::default()
    };
    assert!(dense_sections(&pts, tol, &strict).is_empty());
    let run = polyline_run(&pts);
    let fit = BsplineFit::default().smooth_run(&run, tol).unwrap();
    let rep = verify_run(&run.pieces, &fit.pieces, &VerifyOptions::new(tol));
    assert!(rep.within(tol), "{}", rep.deviation_bound);
    let corner = BsplineCorner::default().smooth_run(&run, tol).unwrap();
    assert!(fit.pieces.len() < 10, "{}", fit.pieces.len());
    assert!(corner.pieces.len() > 300, "{}", corner.pieces.len());
}

/// Regression, LinuxCNC `performance/LHchips4.ngc` lines 92-100 (XZ): a
/// 3.8 mm move between moves of 0.1-1.3 mm. Least squares saw the long
/// move only at its ends, the fit bulged off it, and knot insertion put
/// about 4,000 spans of 0.3 um into it (64 output pieces along one move)
/// without reducing the error. The fit must pass with spans no shorter
/// than a micrometre and no more control points than the search allows.
#[test]
fn long_move_between_short_ones_fits_without_micro_spans() {
    let xz = [
        (62.365, -17.009),
        (62.237, -16.907),
        (62.11, -16.817),
        (61.343, -16.32),
        (61.279, -16.276),
        (60.32, -15.428),
        (60.256, -15.36),
        (57.89, -12.541),
        (57.763, -12.363),
    ];
    let pts: Vec<Vec3> = xz.iter().map(|&(x, z)| v(x, 0.0, z)).collect();
    let fit = fit_polyline(
        &pts,
        EndCondition::Free,
        EndCondition::Free,
        0.05 * BAND_USE,
        1.0,
    )
    .expect("fit passes");
    let k = &fit.curve.knots;
    let shortest = k
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|&d| d > 0.0)
        .fold(f64::INFINITY, f64::min);
    println!(
        "{} control points, shortest span {shortest:.3e} mm, bound {:.4}",
        fit.curve.points.len(),
        fit.bound
    );
    assert!(shortest >= 1e-3, "span of {shortest:e} mm");
    assert!(fit.curve.points.len() <= 64);
    assert!(fit.bound <= 0.05 * BAND_USE);
}

/// Regression, LinuxCNC `performance/test_12mmflat.ngc` lines 16-24: a
/// raster step-over of 1 mm moves turning by 22 to 63 degrees, between
/// long moves. The cubic through the vertices overshot the moves between
/// them, no control-point count passed at 0.045 mm, and the step-over went
/// to corner transitions. With points added next to the turning vertices
/// (`fill_segments`) the fit passes; sampled densely, the curve stays
/// within the target of the polyline.
#[test]
fn raster_step_over_of_sharp_short_moves_fits_within_tolerance() {
    let pts = common::test_12mmflat_step_over();
    let target = 0.05 * 0.9 * BAND_USE;
    let fit = fit_polyline(&pts, EndCondition::Free, EndCondition::Free, target, 1.0)
        .expect("fit passes");
    assert!(fit.bound <= target, "{}", fit.bound);
    assert_within_with_exact_ends(&fit.curve, &pts, target);
}

/// The jerk term does what it says: with a larger weight, on the same data
/// and knots, the fit's `integral |C'''|^2` (exact: `C'''` is constant on a
/// span) is smaller, and with weight 0 the fit is `fit_cubic`'s.
#[test]
fn the_jerk_term_lowers_the_integral_of_the_third_derivative() {
    use fairpath::geom::fit::{averaged_knots, cubic_basis, fit_cubic, fit_cubic_weighted};
    let shape = Shape::Sine {
        amp: 2.0,
        wave: 15.0,
        len: 45.0,
    };
    let pts = cam_sample(&|t| shape.eval(t), 0.005, 4.0, 0.002, 5);
    let params = chord_params(&pts);
    let knots = averaged_knots(&params, pts.len() / 3);
    let free = (EndCondition::Free, EndCondition::Free);
    let jerk_integral = |c: &fairpath::geom::Nurbs| -> f64 {
        let k = &c.knots;
        (3..c.points.len())
            .filter(|&s| k[s + 1] > k[s])
            .map(|s| {
                let len = k[s + 1] - k[s];
                let (b0, b1) = (cubic_basis(k, s, k[s]), cubic_basis(k, s, k[s + 1]));
                let d3 = (0..4).fold(Vec3::ZERO, |acc, j| {
                    acc + c.points[s - 3 + j] * ((b1[2][j] - b0[2][j]) / len)
                });
                d3.norm_sq() * len
            })
            .sum()
    };
    let base = fit_cubic(&pts, &params, &knots, free.0, free.1, 1e-4).unwrap();
    let same = fit_cubic_weighted(&pts, &params, &knots, free.0, free.1, 1e-4, 0.0).unwrap();
    assert_eq!(base, same);
    let mut last = jerk_integral(&base);
    for mu in [1e-4, 1e-2, 1.0] {
        let c = fit_cubic_weighted(&pts, &params, &knots, free.0, free.1, 1e-4, mu).unwrap();
        let j = jerk_integral(&c);
        println!("mu {mu:e}: integral |C'''|^2 = {j:.4e}");
        assert!(j < last, "mu {mu}: {j} >= {last}");
        last = j;
    }
}
