//! Invariants of rendering curves as arcs and G1 lines (`fairpath::render`):
//! the pieces stay within the chord share of the curve (checked by the
//! independent verifier, with the curve as the original), start and end
//! where it does and join exactly, arcs join tangent, and where the
//! renderer had room the curvature steps between neighbours are what the
//! planned speed passes (`v^2 dk <= J Ts`).

use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{plan_run, PlanOptions};
use fairpath::geom::{Arc, Curve, Line, Nurbs, ParamCurve, Plane, Vec3};
use fairpath::path::Piece;
use fairpath::render::{
    absorb_lines, nurbs_fits, render_range, render_run, CurveForm, LineAbsorber, NurbsLimits,
    PlannedSpeed, RenderOptions, Rendered,
};
use fairpath::verify::{verify_run, VerifyOptions};
use proptest::prelude::*;

fn piece(c: Curve) -> Piece {
    Piece {
        curve: c,
        rapid: false,
        source_lines: (1, 1),
        feed: None,
    }
}

fn opts(form: CurveForm, chord: f64) -> RenderOptions {
    RenderOptions {
        form,
        chord,
        limits: MachineLimits::thesis(),
        min_block_periods: 1.02,
        min_radius: 0.00254,
        step_share: fairpath::render::arcs::STEP_SHARE,
        min_arc_length: 4e-6,
    }
}

fn plan_opts() -> PlanOptions {
    PlanOptions {
        limits: MachineLimits::thesis(),
        override_feed: true,
        window: None,
        ends: Default::default(),
    }
}

/// A clamped cubic B-spline through `pts` as control points.
fn bspline(pts: &[Vec3]) -> Nurbs {
    let n = pts.len();
    let mut knots = vec![0.0; 4];
    for i in 1..n - 3 {
        knots.push(i as f64);
    }
    knots.extend([(n - 3) as f64; 4]);
    Nurbs::new(3, knots, pts.to_vec(), None).unwrap()
}

/// Renders `pieces` with the plan of exactly those pieces.
fn render(pieces: &[Piece], o: &RenderOptions) -> Vec<Piece> {
    let plan = plan_run(pieces, &plan_opts()).unwrap();
    let speed = PlannedSpeed::new(pieces.len(), &plan, o.limits.period);
    render_run(pieces, &speed, o).unwrap().pieces
}

/// The shared invariants; returns the rendered pieces.
fn check(original: &[Piece], o: &RenderOptions) -> Result<Vec<Piece>, TestCaseError> {
    let out = render(original, o);
    prop_assert!(!out.is_empty());
    prop_assert_eq!(out[0].start(), original[0].start());
    prop_assert_eq!(out.last().unwrap().end(), original.last().unwrap().end());
    for w in out.windows(2) {
        prop_assert_eq!(w[0].end(), w[1].start(), "pieces join exactly");
    }
    for p in &out {
        prop_assert!(p.start().is_finite() && p.end().is_finite());
        if let Curve::Arc(a) = &p.curve {
            prop_assert!(
                Plane::of_normal(a.normal).is_some(),
                "arc in a principal plane"
            );
        }
    }
    let rep = verify_run(original, &out, &VerifyOptions::new(o.chord));
    prop_assert!(
        rep.deviation_bound <= o.chord,
        "deviation {} > chord {}",
        rep.deviation_bound,
        o.chord
    );
    Ok(out)
}

fn pt2(r: f64) -> impl Strategy<Value = Vec3> {
    (-r..r, -r..r).prop_map(|(x, y)| Vec3::new(x, y, 0.0))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn arcs_of_planar_curves_stay_within_the_chord_and_join_tangent(
        pts in prop::collection::vec(pt2(20.0), 4..10),
        chord in 0.001..0.02f64,
        plane in 0usize..3,
    ) {
        let plane = Plane::ALL[plane];
        let pts: Vec<Vec3> = pts.iter().map(|p| plane.point([p.x, p.y, 1.5])).collect();
        prop_assume!(pts.windows(2).any(|w| w[0].dist(w[1]) > 0.1));
        let original = vec![piece(Curve::from(bspline(&pts)))];
        let out = check(&original, &opts(CurveForm::Arcs, chord))?;
        // Arcs follow a planar curve in its own plane, tangent to each
        // other wherever both neighbours are arcs.
        for w in out.windows(2) {
            if let (Curve::Arc(a), Curve::Arc(b)) = (&w[0].curve, &w[1].curve) {
                prop_assert!(a.rise.abs() < 1e-12, "rise {}", a.rise);
                let ta = a.unit_tangent(1.0).unwrap();
                let tb = b.unit_tangent(0.0).unwrap();
                prop_assert!(ta.angle_to(tb) < 1e-6, "kink {}", ta.angle_to(tb));
            }
        }
    }

    #[test]
    fn lines_of_planar_curves_stay_within_the_chord(
        pts in prop::collection::vec(pt2(20.0), 4..10),
        chord in 0.001..0.02f64,
    ) {
        prop_assume!(pts.windows(2).any(|w| w[0].dist(w[1]) > 0.1));
        let original = vec![piece(Curve::from(bspline(&pts)))];
        let out = check(&original, &opts(CurveForm::Lines, chord))?;
        prop_assert!(out.iter().all(|p| matches!(p.curve, Curve::Line(_))));
    }

    #[test]
    fn curves_in_3d_stay_within_the_chord(
        pts in prop::collection::vec((-5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64), 4..8),
        chord in 0.002..0.02f64,
    ) {
        let pts: Vec<Vec3> = pts.iter().map(|&(x, y, z)| Vec3::new(x, y, z)).collect();
        prop_assume!(pts.windows(2).any(|w| w[0].dist(w[1]) > 0.1));
        let original = vec![piece(Curve::from(bspline(&pts)))];
        check(&original, &opts(CurveForm::Arcs, chord))?;
    }
}

#[test]
fn a_circle_is_a_few_arcs_of_its_radius() {
    let arc = Arc::from_center(
        Vec3::new(10.0, 0.0, 0.0),
        Vec3::new(0.0, 10.0, 0.0),
        Vec3::ZERO,
        Vec3::Z,
        false,
        1,
        0.0,
    )
    .unwrap();
    let original = vec![piece(Curve::from(Nurbs::from_circular_arc(&arc)))];
    let out = check(&original, &opts(CurveForm::Arcs, 0.005)).unwrap();
    assert!(out.len() <= 4, "{} pieces", out.len());
    for p in &out {
        let Curve::Arc(a) = &p.curve else {
            panic!("not an arc: {:?}", p.curve)
        };
        assert!((a.r0 - 10.0).abs() < 1e-9 && (a.r1 - 10.0).abs() < 1e-9);
    }
}

#[test]
fn a_helix_is_helical_arcs() {
    // A quarter turn of radius 5 rising 2 mm, as a cubic approximation.
    let arc = Arc::from_center(
        Vec3::new(5.0, 0.0, 0.0),
        Vec3::new(0.0, 5.0, 2.0),
        Vec3::ZERO,
        Vec3::Z,
        false,
        1,
        0.0,
    )
    .unwrap();
    let original = vec![piece(Curve::from(Nurbs::approximate(&arc, 1e-7)))];
    let o = opts(CurveForm::Arcs, 0.005);
    let out = check(&original, &o).unwrap();
    assert!(out.len() <= 16, "{} pieces", out.len());
    for p in &out {
        let Curve::Arc(a) = &p.curve else {
            panic!("not an arc: {:?}", p.curve)
        };
        assert!(a.rise > 0.0 && a.normal == Vec3::Z);
    }
}

#[test]
fn joints_step_no_more_than_the_planned_speed_passes() {
    // A spiral-like curve whose curvature keeps changing: arcs must be
    // short where the machine is fast.
    let pts: Vec<Vec3> = (0..12)
        .map(|i| {
            let t = i as f64 * 0.6;
            let r = 2.0 + 1.5 * t;
            Vec3::new(r * t.cos(), r * t.sin(), 0.0)
        })
        .collect();
    let original = vec![piece(Curve::from(bspline(&pts)))];
    let o = opts(CurveForm::Arcs, 0.005);
    let out = render(&original, &o);
    let plan = plan_run(&original, &plan_opts()).unwrap();
    let speed = PlannedSpeed::new(1, &plan, o.limits.period);
    let c = &original[0].curve;
    let m = &o.limits;
    let (mut checked, mut over) = (0, 0);
    for w in out.windows(2) {
        let (Curve::Arc(a), Curve::Arc(b)) = (&w[0].curve, &w[1].curve) else {
            continue;
        };
        // The joint's parameter on the curve, by its nearest sample.
        let q = a.p1;
        let ts: Vec<f64> = (0..=4000)
            .map(|k| k as f64 / 4000.0 * c.domain().1)
            .collect();
        let t = ts
            .iter()
            .copied()
            .min_by(|x, y| c.eval(*x).dist(q).total_cmp(&c.eval(*y).dist(q)))
            .unwrap();
        let v = speed.at(0, t);
        let shortest = a.approx_length().min(b.approx_length());
        if shortest < 2.0 * 1.02 * m.period * v {
            continue; // no room to split further: one block time
        }
        checked += 1;
        let dk = (b.curvature_vector(0.0) - a.curvature_vector(1.0)).norm();
        if v * v * dk > m.jerk * m.period * 1.01 {
            over += 1;
        }
    }
    assert!(checked > 10, "{checked} joints checked");
    assert_eq!(
        over, 0,
        "{over} of {checked} joints step more than v^2 dk <= J Ts"
    );
}

/// Nine points of a circle of radius 10 tilted 45 degrees to every axis
/// plane.
fn tilted_circle_points() -> Vec<Vec3> {
    let n = Vec3::new(1.0, 1.0, 1.0).normalized(0.0).unwrap();
    let u = n.any_perpendicular().normalized(0.0).unwrap();
    let w = n.cross(u);
    (0..9)
        .map(|i| {
            let a = i as f64 * 0.5;
            u * (10.0 * a.cos()) + w * (10.0 * a.sin())
        })
        .collect()
}

#[test]
fn a_curve_that_leaves_every_plane_is_written_as_g1() {
    let pts = tilted_circle_points();
    let original = vec![piece(Curve::from(bspline(&pts)))];
    let out = check(&original, &opts(CurveForm::Arcs, 0.005)).unwrap();
    assert!(out.iter().all(|p| matches!(p.curve, Curve::Line(_))));
}

/// The counts tell the curves that fell back to G1 from the lines
/// written for them (the writer judges a long run's all-G1 candidate by
/// the former): a tilted curve between two planar ones is one curve and
/// many lines.
#[test]
fn a_curve_written_as_g1_counts_as_one_curve_of_many_lines() {
    let tilted = tilted_circle_points();
    let (a, b) = (tilted[0], tilted[8]);
    let planar = |from: Vec3, dir: f64| -> Vec<Vec3> {
        (0..6)
            .map(|i| {
                let x = i as f64 * dir;
                from + Vec3::new(x, 0.2 * x * x, 0.0)
            })
            .collect()
    };
    let mut before = planar(a, -1.0);
    before.reverse();
    let curves = vec![
        piece(Curve::from(bspline(&before))),
        piece(Curve::from(bspline(&tilted))),
        piece(Curve::from(bspline(&planar(b, 1.0)))),
    ];
    let o = opts(CurveForm::Arcs, 0.005);
    let plan = plan_run(&curves, &plan_opts()).unwrap();
    let speed = PlannedSpeed::new(curves.len(), &plan, o.limits.period);
    let r = render_run(&curves, &speed, &o).unwrap();
    assert_eq!(r.stats.fallback_pieces, 1, "{:?}", r.stats);
    assert!(r.stats.fallback_lines > 10, "{:?}", r.stats);
    assert!(r.stats.arcs > 0, "{:?}", r.stats);
}

#[test]
fn lines_are_equal_within_stretches_that_change_by_at_most_a_factor() {
    let arc = Arc::from_center(
        Vec3::new(10.0, 0.0, 0.0),
        Vec3::new(-10.0, 0.0, 0.0),
        Vec3::ZERO,
        Vec3::Z,
        false,
        1,
        0.0,
    )
    .unwrap();
    let original = vec![piece(Curve::from(arc))];
    let out = check(&original, &opts(CurveForm::Lines, 0.005)).unwrap();
    let lens: Vec<f64> = out.iter().map(|p| p.start().dist(p.end())).collect();
    let mut changes = 0;
    for w in lens.windows(2) {
        if (w[0] - w[1]).abs() > 1e-6 {
            changes += 1;
            let r = w[0].max(w[1]) / w[0].min(w[1]);
            assert!(
                r <= 2.0 * fairpath::render::lines::SPACING_RATIO,
                "{} -> {}",
                w[0],
                w[1]
            );
        }
    }
    // Few stretches: the speed ramps at the ends, even in the middle.
    assert!(
        changes * 10 < lens.len(),
        "{changes} changes in {} moves",
        lens.len()
    );
}

#[test]
fn spline_formats_keep_only_the_curves_they_can_say() {
    let planar = bspline(&[
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(1.0, 2.0, 1.0),
        Vec3::new(3.0, 2.0, 1.0),
        Vec3::new(4.0, 0.0, 1.0),
    ]);
    let mut spatial = planar.clone();
    spatial.points[2].z = 1.5;
    let fanuc = NurbsLimits {
        max_degree: 3,
        planar_mm: None,
        xy_only: false,
        linuxcnc_g5_2: false,
    };
    let in_plane = NurbsLimits {
        planar_mm: Some(1e-9),
        ..fanuc
    };
    assert!(nurbs_fits(&planar, &fanuc, 0.005));
    assert!(nurbs_fits(&spatial, &fanuc, 0.005));
    assert!(nurbs_fits(&planar, &in_plane, 0.005));
    assert!(!nurbs_fits(&spatial, &in_plane, 0.005));
    let quartic = Nurbs::new(
        4,
        vec![0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0],
        (0..5)
            .map(|i| Vec3::new(i as f64, (i % 2) as f64, 0.0))
            .collect(),
        None,
    )
    .unwrap();
    assert!(!nurbs_fits(&quartic, &fanuc, 0.005));
    // In the NURBS form the spatial curve is written as arcs or lines, the
    // planar one as it is.
    let form = CurveForm::Nurbs(in_plane);
    let out = render(&[piece(Curve::from(planar.clone()))], &opts(form, 0.005));
    assert_eq!(out.len(), 1);
    let out = render(&[piece(Curve::from(spatial))], &opts(form, 0.005));
    assert!(out.iter().all(|p| !matches!(p.curve, Curve::Nurbs(_))));
}

#[test]
fn planned_speed_interpolates_the_plan() {
    let line = Curve::Line(fairpath::geom::Line::new(
        Vec3::ZERO,
        Vec3::new(300.0, 0.0, 0.0),
    ));
    let pieces = vec![piece(line)];
    let plan = plan_run(&pieces, &plan_opts()).unwrap();
    let sp = PlannedSpeed::new(1, &plan, 0.001);
    // Rest at both ends, the machine's feed in the middle of 300 mm.
    assert!(sp.at(0, 0.0) < 1.0 && sp.at(0, 1.0) < 1.0);
    assert!((sp.at(0, 0.5) - 400.0).abs() < 1.0);
    assert!((sp.max_over(0, 0.0, 1.0) - 400.0).abs() < 1.0);
    assert!(sp.max_over(0, 0.0, 0.001) < sp.max_over(0, 0.0, 0.2));
    // Unknown pieces plan no speed.
    assert_eq!(sp.at(3, 0.5), 0.0);
}

/// The speed sampled from a plan's taken segments (each dropped once
/// sampled: how the writer holds a long run) is the speed sampled from the
/// plan, sample for sample.
#[test]
fn planned_speed_from_taken_segments_is_the_plans() {
    let pts: Vec<Vec3> = (0..60)
        .map(|i| Vec3::new(i as f64 * 0.7, if i % 2 == 0 { 0.0 } else { 0.4 }, 0.0))
        .collect();
    let pieces: Vec<Piece> = pts
        .windows(2)
        .map(|w| piece(Curve::Line(fairpath::geom::Line::new(w[0], w[1]))))
        .collect();
    let plan = plan_run(&pieces, &plan_opts()).unwrap();
    assert!(plan.segments.len() > 10, "{} segments", plan.segments.len());
    for dt in [0.001, 0.0123] {
        let whole = PlannedSpeed::new(pieces.len(), &plan, dt);
        let taken = PlannedSpeed::from_segments(pieces.len(), plan.segments.clone(), dt);
        assert_eq!(whole, taken, "dt {dt}");
        assert!(whole.max_over(30, 0.0, 1.0) > 0.0);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// A long run is rendered in parts side by side (`render_range`): the
    /// parts, concatenated and their short lines merged (`absorb_lines`),
    /// must be the rendering of the whole run, in every form.
    #[test]
    fn a_run_rendered_in_parts_is_the_run_rendered_whole(
        pts in prop::collection::vec(pt2(20.0), 9..18),
        cut in 1usize..8,
        form in 0usize..2,
    ) {
        prop_assume!(pts.windows(2).all(|w| w[0].dist(w[1]) > 0.1));
        // Lines and curves alternating: segments and a B-spline through
        // the points between them.
        let mut pieces = Vec::new();
        for w in pts.windows(5).step_by(4) {
            pieces.push(piece(Curve::Line(fairpath::geom::Line::new(w[0], w[1]))));
            pieces.push(piece(Curve::from(bspline(&w[1..5]))));
        }
        let form = [CurveForm::Arcs, CurveForm::Lines][form];
        let o = opts(form, 0.005);
        let plan = plan_run(&pieces, &plan_opts()).unwrap();
        let speed = PlannedSpeed::new(pieces.len(), &plan, o.limits.period);
        let whole = render_run(&pieces, &speed, &o).unwrap();
        let cut = cut.min(pieces.len());
        let a = render_range(&pieces, 0..cut, &speed, &o).unwrap();
        let b = render_range(&pieces, cut..pieces.len(), &speed, &o).unwrap();
        let mut joined = a;
        joined.pieces.extend(b.pieces);
        joined.speeds.extend(b.speeds);
        joined.stats.add(&b.stats);
        absorb_lines(&mut joined, &o);
        prop_assert_eq!(&joined.pieces, &whole.pieces);
        prop_assert_eq!(joined.stats, whole.stats);
        // One planned speed per piece, kept with it through the merges:
        // positive, and no faster than the machine.
        prop_assert_eq!(&joined.speeds, &whole.speeds);
        prop_assert_eq!(whole.speeds.len(), whole.pieces.len());
        for &v in &whole.speeds {
            prop_assert!(v > 0.0 && v <= o.limits.max_feed * (1.0 + 1e-9), "speed {}", v);
        }
    }
}

/// A long run is written as it is rendered, part after part, through a
/// `LineAbsorber` (the writer never holds its whole rendering): the parts
/// it gives, concatenated, must be the run rendered whole, short lines
/// merged alike, also where a part starts inside a chain of short lines
/// whose merges share one shift budget.
#[test]
fn a_run_rendered_part_after_part_through_the_absorber_is_the_run_rendered_whole() {
    let o = opts(CurveForm::Arcs, 0.005);
    // Lines of 1 mm, each followed by a chain of short lines (0.001 mm,
    // under SHORT_LINE_SHARE of the chord) bending by 2e-6 mm each, so that
    // a chain merges until ABSORB_SHIFT_SHARE of the chord is spent; a
    // B-spline bend after every third chain.
    let mut pieces: Vec<Piece> = Vec::new();
    let end = |pieces: &[Piece]| pieces.last().map_or(Vec3::ZERO, |p| p.end());
    let line = |a: Vec3, d: Vec3| piece(Curve::Line(Line::new(a, a + d)));
    for k in 0..40 {
        let dir = if k % 2 == 0 { 1.0 } else { -1.0 };
        pieces.push(line(end(&pieces), Vec3::new(dir, 0.0, 0.0)));
        for j in 0..(k % 6) {
            let bend = 2e-6 * (j + 1) as f64;
            pieces.push(line(end(&pieces), Vec3::new(dir * 0.001, bend, 0.0)));
        }
        if k % 3 == 2 {
            let at = end(&pieces);
            let c = [
                at,
                at + Vec3::new(dir * 0.5, 0.0, 0.0),
                at + Vec3::new(dir * 0.5, 0.5, 0.0),
                at + Vec3::new(0.0, 0.5, 0.0),
            ];
            pieces.push(piece(Curve::from(bspline(&c))));
        }
    }
    let plan = plan_run(&pieces, &plan_opts()).unwrap();
    let speed = PlannedSpeed::new(pieces.len(), &plan, o.limits.period);
    let whole = render_run(&pieces, &speed, &o).unwrap();
    assert!(whole.stats.absorbed_lines > 10, "{:?}", whole.stats);
    let chained = pieces
        .iter()
        .filter(|p| p.curve.length(1e-9) < 0.002)
        .count();
    assert!(
        whole.stats.absorbed_lines < chained,
        "some chains spend the shift"
    );
    let mut state = 11u64;
    for _ in 0..20 {
        let mut absorber = LineAbsorber::new(&o);
        let mut joined = Rendered::default();
        let mut start = 0;
        while start < pieces.len() {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let len = 1 + (state >> 60) as usize;
            let end = (start + len).min(pieces.len());
            let part = absorber.push(render_range(&pieces, start..end, &speed, &o).unwrap());
            joined.pieces.extend(part.pieces);
            joined.speeds.extend(part.speeds);
            joined.stats.add(&part.stats);
            start = end;
        }
        let last = absorber.finish();
        joined.pieces.extend(last.pieces);
        joined.speeds.extend(last.speeds);
        for (i, (a, b)) in joined.pieces.iter().zip(&whole.pieces).enumerate() {
            assert_eq!(a, b, "piece {i}");
        }
        assert_eq!(joined.pieces.len(), whole.pieces.len());
        assert_eq!(joined.speeds, whole.speeds);
        assert_eq!(joined.stats, whole.stats);
    }
}

/// Issue 21, `surface-raster.ngc`'s step-overs: a corner transition out of
/// every principal plane (a pass rising along X, then a step along Y) is
/// written as G1, and its spacing changes only where the curvature step
/// that leaves is passed at the planned speed (`kappa v^2 <= step_share J
/// Ts`, `render/lines.rs`): none in the slow middle of the turn, where
/// every change of spacing once slowed the machine to 2.5 mm/s.
#[test]
fn a_step_over_written_as_g1_changes_spacing_only_where_the_speed_passes() {
    let corner = Vec3::new(80.0, 0.0, 3.471);
    let a = Vec3::new(-0.925, 0.0, -0.38).normalized(0.0).unwrap();
    let b = Vec3::new(0.0, 1.0, -0.0065).normalized(0.0).unwrap();
    let theta = 0.5 * a.angle_to(b);
    let l = fairpath::smooth::edge_for_deviation(0.045, theta);
    let p = |d: Vec3, k: f64| corner + d * (k * l);
    let transition =
        fairpath::smooth::transition_curve([p(a, 2.0), p(a, 1.0), corner, p(b, 1.0), p(b, 2.0)]);
    let pieces = vec![
        piece(Curve::Line(Line::new(p(a, 40.0), p(a, 2.0)))),
        piece(Curve::from(transition.clone())),
        piece(Curve::Line(Line::new(p(b, 2.0), p(b, 4.0)))),
    ];
    let o = opts(CurveForm::Arcs, 0.0045);
    let plan = plan_run(&pieces, &plan_opts()).unwrap();
    let speed = PlannedSpeed::new(pieces.len(), &plan, o.limits.period);
    let out = render_run(&pieces, &speed, &o).unwrap().pieces;
    // The transition's moves: all but the two lines.
    let moves = &out[1..out.len() - 1];
    assert!(moves.len() > 20, "{} moves", moves.len());
    assert!(moves.iter().all(|m| matches!(m.curve, Curve::Line(_))));
    let samples: Vec<(f64, Vec3)> = (0..=4000)
        .map(|i| {
            let t = i as f64 / 4000.0;
            (t, transition.eval(t))
        })
        .collect();
    let m = &o.limits;
    let mut changes = 0usize;
    for w in moves.windows(2) {
        let (l1, l2) = (w[0].start().dist(w[0].end()), w[1].start().dist(w[1].end()));
        let q = w[0].end();
        let (t, _) = samples
            .iter()
            .min_by(|x, y| x.1.dist(q).total_cmp(&y.1.dist(q)))
            .unwrap();
        let kappa = transition.curvature(*t);
        let v = speed.at(1, *t);
        // Moves of one stretch are equal along the fine polyline, which
        // differs from their chords by up to `(kappa d)^2 / 24` (about
        // 1e-3 in the middle of this turn): a change of stretch is a
        // change of spacing by more than 1%.
        if (l1 - l2).abs() <= 1e-2 * l1.max(l2) {
            continue;
        }
        changes += 1;
        // The curvature steps by `kappa (1 + rho) / 2` at a change of
        // spacing by the ratio `rho` (module docs of `render/lines.rs`):
        // the planned speed passes it where that times `v^2` is at most
        // `J Ts`; the renderer ends its stretches at half of that
        // (`step_share`).
        let rho = l1.max(l2) / l1.min(l2);
        assert!(
            kappa * (1.0 + rho) / 2.0 * v * v <= m.jerk * m.period,
            "spacing {l1} -> {l2} at t = {t}: kappa {kappa}, v {v}"
        );
    }
    // Here the whole turn is one stretch: its ends are straight enough
    // that the spacing changes where the lines begin.
    eprintln!("{} moves, {changes} changes of spacing", moves.len());
}

/// Regression (`spiral_lines.ngc` by `bspline-fit` in G1, 20.1 s written
/// against 7.5 s of curves): each piece was cut into moves on its own, so
/// at a joint the machine passes fast while the curve bends the spacing
/// jumped (0.051 to 0.553 mm there), the blend circles stopped meeting and
/// the curvature stepped by the curve's whole. An arc runs G2 into a curve
/// whose curvature changes fast: the moves on both sides of the joint are
/// cut alike.
#[test]
fn lines_keep_their_spacing_across_a_joint_passed_fast() {
    let r = 10.0;
    let arc = quarter_arc(r);
    // At (0, r) the arc runs along -x, its centre towards -y.
    let (p0, t, n) = (arc.p1, Vec3::new(-1.0, 0.0, 0.0), Vec3::new(0.0, -1.0, 0.0));
    // A cubic leaving G2 (curvature 1/r at its start: 2c / (3 a^2)) and
    // then turning the other way within a few millimetres.
    let a = 1.0;
    let c = 1.5 * a * a / r;
    let p1 = p0 + t * a;
    let p2 = p1 + t * 1.0 + n * c;
    let p3 = p2 + t * 1.0 - n * 0.5;
    let bez = Nurbs::new(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
        vec![p0, p1, p2, p3],
        None,
    )
    .unwrap();
    let pieces = vec![piece(Curve::from(arc)), piece(Curve::from(bez))];
    let o = opts(CurveForm::Lines, 0.005);
    let out = render(&pieces, &o);
    assert_g2_joint(&pieces);
    assert_spacing_kept_at(&out, p0);
}

/// Asserts that the two pieces of `pieces` meet G2.
fn assert_g2_joint(pieces: &[Piece]) {
    assert_eq!(
        fairpath::geom::classify_joint(
            &pieces[0].curve,
            &pieces[1].curve,
            &fairpath::geom::JointTolerances::from_tolerance(1e-3)
        ),
        fairpath::geom::Continuity::G2
    );
}

/// Asserts that the written moves `out` meet at `joint` and that the
/// moves on either side of it differ in length by at most
/// `SPACING_RATIO`.
fn assert_spacing_kept_at(out: &[Piece], joint: Vec3) {
    let at = out
        .iter()
        .position(|p| p.end() == joint)
        .expect("the joint is a vertex");
    let (before, after) = (out[at].curve.length(1e-9), out[at + 1].curve.length(1e-9));
    let ratio = before.max(after) / before.min(after);
    assert!(
        ratio <= fairpath::render::lines::SPACING_RATIO,
        "moves of {before} and {after} mm at the joint"
    );
}

/// A quarter circle of radius `r` about the origin in XY, from (r, 0) to
/// (0, r), counter-clockwise.
fn quarter_arc(r: f64) -> Arc {
    Arc::from_center(
        Vec3::new(r, 0.0, 0.0),
        Vec3::new(0.0, r, 0.0),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
        false,
        1,
        0.0,
    )
    .unwrap()
}

/// A reversal inside a curve (one of `auto`'s fits of LinuxCNC's
/// `test-active-states.ngc` goes out 1.5 mm and back, stopping at the
/// turn) as G1 lines: the curvature has no bound at the turn, and the
/// chord error's spacing `sqrt(8 e / kappa)` fell to the shortest block,
/// 1 nm, for the whole curve: 3 million lines, 2.3 s and 826 MB for that
/// 36-line program. A move of arc length `2 e` lies within `e` of its
/// chord whatever the curve does, so the chord error's spacing need not
/// fall below it: the lines stay far fewer, and within the chord share.
#[test]
fn test_active_states_reversal_is_rendered_in_few_lines() {
    let p = |x: f64| Vec3::new(x, 0.0, 0.0);
    // The fit as `auto` made it: along X and back, its off-axis parts of
    // 1e-19 mm the fit's rounding, stopping at its inner knot, where the
    // flattening samples it (straight on each side) and the curvature has
    // no bound.
    let (k, y) = (2.6522922259114483, 6.68109958063731e-20);
    let there_and_back = Nurbs::new(
        3,
        vec![0.0, 0.0, 0.0, 0.0, k, 2.0 * k, 2.0 * k, 2.0 * k, 2.0 * k],
        vec![
            p(0.0),
            Vec3::new(1.005711759853755, y, 0.0),
            Vec3::new(2.011468340085841, 2.0 * y, 0.0),
            Vec3::new(1.0057117598537548, y, 0.0),
            p(0.0),
        ],
        None,
    )
    .unwrap();
    assert!(
        there_and_back.deriv1(k).norm() < 1e-12,
        "it stops at its inner knot"
    );
    let curve = Curve::from(there_and_back);
    let length = curve.length(1e-6);
    // Between two lines, as in its run.
    let original = [
        piece(Curve::Line(Line::new(Vec3::new(0.0, 5.0, 0.0), p(0.0)))),
        piece(curve),
        piece(Curve::Line(Line::new(p(0.0), Vec3::new(0.0, -5.0, 0.0)))),
    ];
    let o = opts(CurveForm::Lines, 0.005);
    check(&original, &o).unwrap();
    // The lines made, those merged into their neighbours after (on a
    // straight curve, nearly all of them) included.
    let plan = plan_run(&original, &plan_opts()).unwrap();
    let speed = PlannedSpeed::new(original.len(), &plan, o.limits.period);
    let stats = render_run(&original, &speed, &o).unwrap().stats;
    let made = stats.lines + stats.absorbed_lines;
    // 754,298 at the shortest block (4 nm) before; 4,260 now, where the
    // curvature-step rule still asks for short moves as the speed falls
    // to the stop.
    assert!(
        made < 10_000,
        "{made} lines made for a {length:.3} mm curve"
    );
}

/// `lines_keep_their_spacing_across_a_joint_passed_fast` written as arcs
/// (`test_12mmflat.ngc`'s 3D step-overs at 0.05 mm): out of every
/// principal plane, arcs cannot follow the curves and each is written as
/// G1, and those lines were cut with no regard to their neighbours', so
/// the spacing jumped where two such curves meet and the machine passes
/// fast. They are now cut as the G1 format cuts them: the moves on both
/// sides of the joint alike.
#[test]
fn test_12mmflat_curves_written_as_lines_among_arcs_keep_their_spacing() {
    // Turned by 0.5 rad about X, then about Y: out of every plane.
    let turn = |p: Vec3| {
        let (s, c) = 0.5f64.sin_cos();
        let p = Vec3::new(p.x, c * p.y - s * p.z, s * p.y + c * p.z);
        Vec3::new(c * p.x + s * p.z, p.y, -s * p.x + c * p.z)
    };
    let cubic = |q: [Vec3; 4]| {
        Nurbs::new(
            3,
            vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
            q.to_vec(),
            None,
        )
        .unwrap()
    };
    // A quarter circle of radius 10 as a cubic, then a cubic leaving it G2
    // and turning the other way within a few millimetres.
    let k = 10.0 * 0.5523;
    let p = |x: f64, y: f64| turn(Vec3::new(x, y, 0.0));
    let round = cubic([p(10.0, 0.0), p(10.0, k), p(k, 10.0), p(0.0, 10.0)]);
    let kv = round.curvature_vector(1.0);
    let (kappa, n) = (kv.norm(), kv.normalized(0.0).unwrap());
    let t = round.deriv1(1.0).normalized(0.0).unwrap();
    let p0 = round.eval(1.0);
    let p1 = p0 + t * 1.0;
    let p2 = p1 + t * 1.0 + n * (1.5 * kappa);
    let p3 = p2 + t * 1.0 - n * 0.5;
    let pieces = vec![
        piece(Curve::from(round)),
        piece(Curve::from(cubic([p0, p1, p2, p3]))),
    ];
    assert_g2_joint(&pieces);
    let out = render(&pieces, &opts(CurveForm::Arcs, 0.005));
    assert!(out.iter().all(|p| matches!(p.curve, Curve::Line(_))));
    assert_spacing_kept_at(&out, p0);
}

/// A wave (amplitude `amp` mm, wavelength `wl` mm) in `plane`, sampled
/// every `step` mm over `n` vertices, its coordinates rounded to `round`
/// mm as a CAM system writes them, smoothed corner by corner
/// (`bspline-corner` at 0.045 mm): lines and transitions, a bump of
/// curvature at every vertex.
fn corner_smoothed_wave(
    n: usize,
    step: f64,
    amp: f64,
    wl: f64,
    round: f64,
    plane: Plane,
) -> Vec<Piece> {
    use fairpath::smooth::{BsplineCorner, Smoother};
    let pts: Vec<Vec3> = (0..n)
        .map(|i| {
            let x = i as f64 * step;
            let y = amp * (std::f64::consts::TAU * x / wl).sin();
            let r = |v: f64| (v / round).round() * round;
            plane.point([r(x), r(y), 2.0])
        })
        .collect();
    let mut run = fairpath::Run::polyline(&pts, None);
    for p in run.pieces.iter_mut() {
        p.feed = Some(4000.0);
    }
    BsplineCorner::default()
        .smooth_run(&run, 0.045)
        .unwrap()
        .pieces
}

/// At the programmed feed (4000 mm/min, as the raster's), a densely
/// sampled wave smoothed corner by corner is written a chain of
/// arcs, a few per corner (`render::chain_arcs`), not a dozen arcs
/// following each corner's bump: within the chord share of the curves
/// (the independent verifier), from the first curve's start to the last
/// one's end, tangent throughout, and planned at least as fast as the
/// curves (the regression of `surface-raster-large.ngc`, whose arcs were
/// 12 times its lines and planned 14% slower than its curves).
#[test]
fn a_densely_sampled_wave_smoothed_at_its_corners_is_written_an_arc_per_corner() {
    for plane in Plane::ALL {
        let curves = corner_smoothed_wave(400, 0.5, 3.0, 60.0, 0.001, plane);
        let corners = curves
            .iter()
            .filter(|p| !matches!(p.curve, Curve::Line(_)))
            .count();
        let o = opts(CurveForm::Arcs, 0.005);
        let po = PlanOptions {
            override_feed: false,
            ..plan_opts()
        };
        let plan = plan_run(&curves, &po).unwrap();
        let speed = PlannedSpeed::new(curves.len(), &plan, o.limits.period);
        let r = render_run(&curves, &speed, &o).unwrap();
        assert!(r.stats.chained > curves.len() * 9 / 10, "{:?}", r.stats);
        // (The renderer of one piece at a time wrote 4,509 arcs here.)
        assert!(
            r.pieces.len() < 3 * corners,
            "{} pieces for {corners} corners",
            r.pieces.len()
        );
        assert_eq!(r.pieces[0].start(), curves[0].start());
        assert_eq!(r.pieces.last().unwrap().end(), curves.last().unwrap().end());
        for w in r.pieces.windows(2) {
            assert_eq!(w[0].end(), w[1].start());
            let (a, b) = (w[0].curve.unit_tangent(1.0), w[1].curve.unit_tangent(0.0));
            let kink = a.zip(b).map_or(0.0, |(a, b)| a.angle_to(b));
            assert!(kink < 1e-6, "kink {kink}");
        }
        let rep = verify_run(&curves, &r.pieces, &VerifyOptions::new(o.chord));
        assert!(
            rep.deviation_bound <= o.chord,
            "deviation {}",
            rep.deviation_bound
        );
        let written = plan_run(&r.pieces, &po).unwrap();
        assert!(
            written.time <= plan.time,
            "written {} s, curves {} s",
            written.time,
            plan.time
        );
    }
}

/// A run of chains rendered in parts whose bounds are multiples of
/// [`CHAIN_PIECES`] is the run rendered whole.
#[test]
fn chains_rendered_in_parts_at_chain_bounds_are_the_run_rendered_whole() {
    use fairpath::render::CHAIN_PIECES;
    let curves = corner_smoothed_wave(700, 0.5, 3.0, 60.0, 0.001, Plane::Xy);
    assert!(curves.len() > CHAIN_PIECES);
    let o = opts(CurveForm::Arcs, 0.005);
    let plan = plan_run(&curves, &plan_opts()).unwrap();
    let speed = PlannedSpeed::new(curves.len(), &plan, o.limits.period);
    let whole = render_run(&curves, &speed, &o).unwrap();
    let mut joined = render_range(&curves, 0..CHAIN_PIECES, &speed, &o).unwrap();
    let b = render_range(&curves, CHAIN_PIECES..curves.len(), &speed, &o).unwrap();
    joined.pieces.extend(b.pieces);
    joined.speeds.extend(b.speeds);
    joined.stats.add(&b.stats);
    absorb_lines(&mut joined, &o);
    assert_eq!(joined.pieces, whole.pieces);
    assert_eq!(joined.speeds, whole.speeds);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Chains of arcs keep the renderer's invariants on random waves,
    /// whatever their noise and plane: within the chord share of the
    /// curves, ends exact, joined exactly.
    #[test]
    fn chains_of_arcs_stay_within_the_chord(
        amp in 0.5..8.0f64,
        wl in 10.0..120.0f64,
        step in 0.2..1.5f64,
        round in prop::sample::select(vec![0.0001, 0.001, 0.01]),
        plane in 0usize..3,
        chord in 0.002..0.01f64,
    ) {
        let curves = corner_smoothed_wave(120, step, amp, wl, round, Plane::ALL[plane]);
        check(&curves, &opts(CurveForm::Arcs, chord))?;
    }
}

/// Regression, LinuxCNC's `Cereal.ngc` (a V-carve; `auto` at 0.05 mm
/// written as G1 with a 0.001 mm output share): a section cut on a spur's
/// leg left a fit that runs up the leg to the tip and straight back to
/// where it started, a closed piece whose control points all lie on the
/// leg. Its curvature is zero wherever sampled, so its spacing was its
/// whole length, one move from its start to its end, and a move that ends
/// where it starts was dropped unlooked-at: the written program turned
/// back 0.218 mm short of the spur's tip (within the band of the leg).
/// Here the same curve (its knots, and its control points' distances
/// along the leg) on the x axis, where its curvature is zero exactly.
#[test]
fn regression_cereal_a_closed_piece_is_written_to_its_tip() {
    let x = |x: f64| Vec3::new(x, 0.0, 0.0);
    let knots = vec![
        0.0,
        0.0,
        0.0,
        0.0,
        0.17814677324136774,
        0.25295861992589336,
        0.327770466610419,
        0.5059172398517867,
        0.5059172398517867,
        0.5059172398517867,
        0.5059172398517867,
    ];
    let points = [0.0, 0.05938, 0.1437, 0.1864, 0.1437, 0.05938, 0.0].map(x);
    let spur = Nurbs::new(3, knots, points.to_vec(), None).unwrap();
    let (t0, t1) = spur.domain();
    let tip = (0..=2000)
        .map(|k| spur.eval(t0 + (t1 - t0) * k as f64 / 2000.0))
        .max_by(|a, b| a.x.total_cmp(&b.x))
        .unwrap();
    assert!(tip.x > 0.15, "{tip:?}");
    let pieces = vec![
        piece(Curve::Line(Line::new(x(-0.3274), x(0.0)))),
        piece(Curve::from(spur)),
        piece(Curve::Line(Line::new(x(0.0), x(-0.3274)))),
    ];
    let chord = 0.001;
    for form in [CurveForm::Lines, CurveForm::Arcs] {
        let out = render(&pieces, &opts(form, chord));
        let reach = out
            .iter()
            .flat_map(|q| match &q.curve {
                Curve::Line(l) => vec![l.p0, l.p1],
                c => {
                    let (a, b) = c.domain();
                    (0..=64)
                        .map(|k| c.eval(a + (b - a) * k as f64 / 64.0))
                        .collect()
                }
            })
            .map(|q| q.dist(tip))
            .fold(f64::INFINITY, f64::min);
        assert!(reach <= chord, "{form:?}: the tip passed {reach} mm off");
    }
}
