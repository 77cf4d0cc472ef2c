//! The lower bound of `feed::lower_bound` never exceeds a planned time:
//! of the original run, and of a smoothed run (every method through
//! `auto`'s candidates is out of reach here, so `bspline-corner` and the
//! original stand for them; the CLI test compares every method).

use crate::common;
use common::{planned_at_max_feed as planned, polyline_run, v};
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::lower_bound::{
    in_order_gates_of, lower_bound_time, piece_speed, BandPaths, BoundOptions, InOrderGates,
};
use fairpath::geom::Vec3;
use fairpath::path::Piece;
use fairpath::verify::{follows_in_order, follows_in_order_within};
use proptest::prelude::*;

const TOL: f64 = 0.05;

fn bound(pieces: &[Piece]) -> f64 {
    lower_bound_time(
        pieces,
        &BoundOptions::new(TOL),
        &MachineLimits::thesis(),
        true,
    )
    .expect("bounds")
    .time
}

/// A raster of `passes` passes of `len` mm, step-over `w`.
fn raster(passes: usize, len: f64, w: f64) -> Vec<Vec3> {
    let mut pts = Vec::new();
    for i in 0..passes {
        let y = i as f64 * w;
        let (a, b) = if i % 2 == 0 { (0.0, len) } else { (len, 0.0) };
        pts.push(v(a, y, 0.0));
        pts.push(v(b, y, 0.0));
    }
    pts
}

#[test]
fn a_straight_line_is_bounded_by_the_rest_to_rest_double_s() {
    // Rest to rest over 100 mm: 0.5429 s planned, 0.5418 s bound (the
    // speed envelopes alone gave 0.411 s).
    let run = polyline_run(&[v(0.0, 0.0, 0.0), v(100.0, 0.0, 0.0)]);
    let (t, b) = (planned(&run.pieces), bound(&run.pieces));
    assert!(b <= t, "bound {b} above the plan {t}");
    assert!(b >= 0.99 * t, "bound {b} loose against the plan {t}");
}

#[test]
fn a_right_angle_and_a_step_over_raise_the_bound_above_the_straight_one() {
    let straight = polyline_run(&[v(0.0, 0.0, 0.0), v(100.0, 0.0, 0.0)]);
    let corner = polyline_run(&[v(0.0, 0.0, 0.0), v(50.0, 0.0, 0.0), v(50.0, 50.0, 0.0)]);
    // The corner's slow point is capped by the tightest turn (step 8 of
    // the module docs) and is a valley of the speed (step 5): 0.720 s for
    // the corner (planned 0.891 s), where the straight run's rest-to-rest
    // floor is 0.5418 s; before steps 5 and 8 and the envelopes' exact
    // times the corner was bounded at 0.5413 s.
    let b0 = bound(&straight.pieces);
    let b1 = bound(&corner.pieces);
    assert!(b1 >= 1.1 * b0, "corner {b1} vs straight {b0}");
    assert!(b1 <= planned(&corner.pieces));
    // A raster step-over of 1 mm: two passes of 50 mm.
    let step = polyline_run(&raster(2, 50.0, 1.0));
    let b2 = bound(&step.pieces);
    assert!(b2 > b0, "step-over {b2} vs straight {b0}");
    assert!(b2 <= planned(&step.pieces));
}

/// A small LCG from `state`: the same programs on every run.
fn seeded(mut state: u64) -> impl FnMut() -> f64 {
    move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A zigzag of 3 to 22 points along X.
fn random_zigzag(next: &mut impl FnMut() -> f64) -> Vec<Vec3> {
    let n = 3 + (next() * 20.0) as usize;
    (0..n)
        .map(|i| v(i as f64 * (0.2 + 5.0 * next()), 3.0 * next(), 0.5 * next()))
        .collect()
}

/// A raster of 2 to 7 passes, step-overs from 0.02 to 2 mm.
fn random_raster(next: &mut impl FnMut() -> f64) -> Vec<Vec3> {
    raster(
        2 + (next() * 6.0) as usize,
        1.0 + 60.0 * next(),
        0.02 + 2.0 * next(),
    )
}

#[test]
fn seeded_zigzags_and_rasters_stay_below_their_plans() {
    let mut next = seeded(0x2545_f491_4f6c_dd1d);
    for case in 0..40 {
        let pts: Vec<Vec3> = if case % 2 == 0 {
            random_zigzag(&mut next)
        } else {
            random_raster(&mut next)
        };
        let run = polyline_run(&pts);
        let (t, b) = (planned(&run.pieces), bound(&run.pieces));
        assert!(b <= t, "case {case}: bound {b} above the plan {t}: {pts:?}");
        assert!(b > 0.0);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn the_bound_never_exceeds_the_plan_of_a_zigzag(
        pts in prop::collection::vec((0.0f64..20.0, 0.0f64..20.0, 0.0f64..2.0), 2..12)
    ) {
        let pts: Vec<Vec3> = pts.into_iter().map(|(x, y, z)| v(x, y, z)).collect();
        prop_assume!(pts.windows(2).all(|w| w[0].dist(w[1]) > 10.0 * TOL));
        let run = polyline_run(&pts);
        let (t, b) = (planned(&run.pieces), bound(&run.pieces));
        prop_assert!(b <= t, "bound {} above the plan {}", b, t);
    }
}

#[test]
fn bad_tolerance_is_an_error() {
    let run = polyline_run(&[v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0)]);
    let o = BoundOptions::new(0.0);
    assert!(lower_bound_time(&run.pieces, &o, &MachineLimits::thesis(), true).is_err());
}

/// A right angle between two 50 mm legs rounded by a circular arc of
/// radius `r` (its apex `r (sqrt 2 - 1)` from the vertex).
fn rounded_corner(r: f64, n: usize) -> Vec<Vec3> {
    // Tangent points at distance r from the vertex (50, 0) along each leg.
    let mut pts = vec![v(0.0, 0.0, 0.0), v(50.0 - r, 0.0, 0.0)];
    let c = (50.0 - r, r);
    for k in 1..n {
        let t = -core::f64::consts::FRAC_PI_2 + core::f64::consts::FRAC_PI_2 * k as f64 / n as f64;
        pts.push(v(c.0 + r * t.cos(), c.1 + r * t.sin(), 0.0));
    }
    pts.push(v(50.0, r, 0.0));
    pts.push(v(50.0, 50.0, 0.0));
    pts
}

#[test]
fn a_corner_rounded_inside_the_band_takes_at_least_the_bound() {
    // The largest arc inside the band of a right angle has radius about
    // e (1 + sqrt 2) / (sqrt 2 - 1) = 0.29 mm at 0.05 mm; an arc of 0.1 mm
    // stays well inside. The bound of the sharp corner must not exceed the
    // plan of the rounded one (a band path of the sharp corner), sampled
    // finely (chords of 1 degree).
    let sharp = polyline_run(&[v(0.0, 0.0, 0.0), v(50.0, 0.0, 0.0), v(50.0, 50.0, 0.0)]);
    let b = bound(&sharp.pieces);
    for r in [0.05, 0.1] {
        let round = polyline_run(&rounded_corner(r, 90));
        let t = planned(&round.pieces);
        assert!(b <= t, "radius {r}: bound {b} above the plan {t}");
    }
}

/// The right angle of [`rounded_corner`] run by the widest turn its band
/// holds: lines `inset` inside the band's outer edges (`y = -(TOL -
/// inset)`, `x = 50 + TOL - inset`) joined by the circular arc of radius
/// `r` tangent to both, in chords of `90 / n` degrees; from the run's start
/// and to its end by lines (kinks of about 0.001 rad).
fn widest_turn(r: f64, inset: f64, n: usize) -> Vec<Vec3> {
    widest_turn_at(50.0, r, inset, n)
}

/// [`widest_turn`] at the right angle `(0,0) -> (len,0) -> (len,len)`.
fn widest_turn_at(len: f64, r: f64, inset: f64, n: usize) -> Vec<Vec3> {
    let o = TOL - inset;
    let c = (len + o - r, -o + r);
    let mut pts = vec![v(0.0, 0.0, 0.0), v(c.0, -o, 0.0)];
    for k in 1..n {
        let t = -core::f64::consts::FRAC_PI_2 + core::f64::consts::FRAC_PI_2 * k as f64 / n as f64;
        pts.push(v(c.0 + r * t.cos(), c.1 + r * t.sin(), 0.0));
    }
    pts.push(v(len + o, c.1, 0.0));
    pts.push(v(len, len, 0.0));
    pts
}

#[test]
fn the_widest_turn_inside_the_band_of_a_right_angle_takes_at_least_the_bound() {
    // The arc through the band's inner corner (50 - e, e) tangent to its
    // outer edges has radius 2 e / (1 - 1 / sqrt 2) = 0.341 mm at 0.05 mm:
    // no circular turn inside the band is wider, and the band path planned
    // here is as fast as a turn of that shape gets (0.931 s). The bound of
    // the sharp corner (0.720 s; 0.833 s in order) must stay below it. (The
    // envelopes let the acceleration reverse at once at the top of a
    // speed bump, so the bound does not charge all that slowing for the
    // turn costs; the module docs of `feed::lower_bound`.)
    let sharp = polyline_run(&[v(0.0, 0.0, 0.0), v(50.0, 0.0, 0.0), v(50.0, 50.0, 0.0)]);
    let (b, b_in_order) = (bound(&sharp.pieces), bound_in_order(&sharp.pieces));
    let pts = widest_turn(0.335, 0.001, 90);
    let wide = polyline_run(&pts);
    let dev = fairpath::verify::verify_run(
        &sharp.pieces,
        &wide.pieces,
        &fairpath::verify::VerifyOptions::new(TOL),
    );
    assert!(
        dev.within(TOL),
        "the turn leaves the band: {}",
        dev.deviation_bound
    );
    let t = planned(&wide.pieces);
    assert!(
        b <= t && b_in_order <= t,
        "bounds {b}, {b_in_order} above the plan {t}"
    );
}

#[test]
fn a_right_angle_between_short_legs_is_bounded_near_the_widest_circle() {
    // Between 3 mm legs the corner decides the time. The fan of walls
    // (step 9) caps its slow point at the speed of the widest circle
    // inside the band, curvature (1 - cos 45 deg) / (2 e): 13.3 mm/s under
    // `k^2 v^3 <= J`, where the three walls' `1 / (12 e)` allowed 19.3.
    let sharp = polyline_run(&[v(0.0, 0.0, 0.0), v(3.0, 0.0, 0.0), v(3.0, 3.0, 0.0)]);
    let b_in_order = bound_in_order(&sharp.pieces);
    let wide = polyline_run(&widest_turn_at(3.0, 0.335, 0.001, 90));
    let dev = fairpath::verify::verify_run(
        &sharp.pieces,
        &wide.pieces,
        &fairpath::verify::VerifyOptions::new(TOL),
    );
    assert!(dev.within(TOL), "the turn leaves the band");
    let t = planned(&wide.pieces);
    assert!(b_in_order <= t, "bound {b_in_order} above the plan {t}");
    // 0.268 s with the fan, 0.247 s with the three walls alone; the
    // widest circle, in chords of 1 degree, plans in 0.402 s.
    assert!(
        b_in_order > 0.26,
        "bound {b_in_order}: the fan's cap is lost"
    );
}

fn in_order(tol: f64) -> BoundOptions {
    BoundOptions {
        paths: BandPaths::InOrder,
        ..BoundOptions::new(tol)
    }
}

fn bound_in_order(pieces: &[Piece]) -> f64 {
    lower_bound_time(pieces, &in_order(TOL), &MachineLimits::thesis(), true)
        .expect("bounds")
        .time
}

/// The in-order gates of `original` on the thesis machine, every feed
/// overridden (as [`bound_in_order`]).
fn gates_of(original: &[Piece]) -> InOrderGates {
    in_order_gates_of(original, &in_order(TOL), &MachineLimits::thesis(), true)
}

/// Whether `path` passes the in-order gates of `original` in order,
/// within their feeds.
fn follows(original: &[Piece], path: &[Piece]) -> bool {
    let g = gates_of(original);
    let m = MachineLimits::thesis();
    let within = follows_in_order_within(
        path,
        &g.gates,
        &g.caps,
        |p| piece_speed(p, &m, true),
        1e-4 * TOL,
    );
    // The feeds are all the machine's: the order decides.
    assert_eq!(within, follows_in_order(path, &g.gates, 1e-4 * TOL));
    within
}

/// Asserts that no gate of `g` stands within `dist` mm of `at`.
fn assert_no_gate_within(g: &InOrderGates, at: Vec3, dist: f64) {
    assert!(
        g.gates.iter().all(|(q, _)| q.dist(at) > dist),
        "a gate within {dist} mm of {at:?}: {:?}",
        g.gates
    );
}

/// `bspline-corner`'s smoothing of `run` at [`TOL`].
fn bspline_corner_of(run: &fairpath::path::Run) -> Vec<Piece> {
    use fairpath::smooth::{BsplineCorner, Smoother};
    BsplineCorner::default()
        .smooth_run(run, TOL)
        .expect("smooths")
        .pieces
}

/// `bspline-fit`'s smoothing of `run` at [`TOL`].
fn bspline_fit_of(run: &fairpath::path::Run) -> Vec<Piece> {
    use fairpath::smooth::{BsplineFit, Smoother};
    BsplineFit::default()
        .smooth_run(run, TOL)
        .expect("fits")
        .pieces
}

/// A closed hexagon of radius 10 mm, up and down 3 mm in Z (the shape of
/// `synthetic/hexagon-3d.ngc`).
fn hexagon() -> Vec<Vec3> {
    (0..=6)
        .map(|k| {
            let a = core::f64::consts::FRAC_PI_3 * k as f64;
            v(
                10.0 * a.cos(),
                10.0 * a.sin(),
                if k % 2 == 1 { 3.0 } else { 0.0 },
            )
        })
        .collect()
}

#[test]
fn a_closed_contour_is_bounded_by_its_length_in_order_and_not_otherwise() {
    // A path that never leaves the start point is within the band of a
    // closed contour: the bound of every band path is the rest-to-rest
    // floor of a run of no length (2e-6 s here). Paths that follow the
    // contour in order must travel its 63 mm: the in-order bound is
    // 0.461 s (the contour planned: 1.690 s).
    let run = polyline_run(&hexagon());
    let t = planned(&run.pieces);
    let (any, ordered) = (bound(&run.pieces), bound_in_order(&run.pieces));
    assert!(ordered <= t, "in-order bound {ordered} above the plan {t}");
    assert!(
        ordered >= 63.0 / 400.0,
        "in-order bound {ordered} below the contour at the feed"
    );
    assert!(ordered > 2.0 * any, "in-order {ordered} vs any {any}");
    assert!(follows(&run.pieces, &run.pieces));
    // Stopping short of the contour does not follow it.
    let pts = hexagon();
    let half = polyline_run(&[pts[0], pts[1], pts[2], pts[3], pts[0]]);
    assert!(!follows(&run.pieces, &half.pieces));
}

#[test]
fn a_shortcut_across_a_raster_follows_it_only_where_the_passes_share_the_band() {
    // Passes 1 mm apart: a path that crosses over at once and runs the
    // second pass misses the first pass's gates.
    let pts = raster(2, 20.0, 1.0);
    let run = polyline_run(&pts);
    assert!(follows(&run.pieces, &run.pieces));
    let cut = polyline_run(&[pts[0], pts[3]]);
    assert!(!follows(&run.pieces, &cut.pieces));
    // Passes 0.06 mm apart share the band: a band path may cut across
    // there, but a path in order does not, so gates stand on both
    // passes and the shortcut misses them.
    let close_pts = raster(2, 20.0, 0.06);
    let close = polyline_run(&close_pts);
    assert!(!gates_of(&close.pieces).gates.is_empty());
    assert!(follows(&close.pieces, &close.pieces));
    let cut = polyline_run(&[close_pts[0], close_pts[3]]);
    assert!(!follows(&close.pieces, &cut.pieces));
}

#[test]
fn seeded_runs_stay_above_their_in_order_bound() {
    // The original follows itself in order: its plan is one of the paths
    // the in-order bound holds for. Zigzags, rasters (passes closer than
    // the band included) and closed polygons.
    let mut next = seeded(0x9e37_79b9_7f4a_7c15);
    for case in 0..45 {
        let pts: Vec<Vec3> = match case % 3 {
            0 => random_zigzag(&mut next),
            1 => random_raster(&mut next),
            _ => {
                let n = 3 + (next() * 9.0) as usize;
                let r = 0.5 + 20.0 * next();
                let mut p: Vec<Vec3> = (0..n)
                    .map(|k| {
                        let a = core::f64::consts::TAU * (k as f64 + 0.3 * next()) / n as f64;
                        v(r * a.cos(), r * a.sin(), next())
                    })
                    .collect();
                p.push(p[0]);
                p
            }
        };
        let run = polyline_run(&pts);
        let (t, b) = (planned(&run.pieces), bound_in_order(&run.pieces));
        assert!(
            b <= t,
            "case {case}: in-order bound {b} above the plan {t}: {pts:?}"
        );
        assert!(b > 0.0);
        assert!(follows(&run.pieces, &run.pieces), "case {case}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn the_in_order_bound_never_exceeds_the_plan_of_a_zigzag(
        pts in prop::collection::vec((0.0f64..20.0, 0.0f64..20.0, 0.0f64..2.0), 2..12)
    ) {
        let pts: Vec<Vec3> = pts.into_iter().map(|(x, y, z)| v(x, y, z)).collect();
        prop_assume!(pts.windows(2).all(|w| w[0].dist(w[1]) > 10.0 * TOL));
        let run = polyline_run(&pts);
        let (t, b) = (planned(&run.pieces), bound_in_order(&run.pieces));
        prop_assert!(b <= t, "in-order bound {} above the plan {}", b, t);
    }
}

/// The polyline `pts` with every inner vertex rounded by the circular arc
/// tangent to both legs whose middle passes `dev` from the vertex (chords
/// of at most 1 degree): a path inside the band of `pts` at any `dev`
/// below the tolerance, as long as the legs hold both tangent lengths.
fn filleted(pts: &[Vec3], dev: f64) -> Vec<Vec3> {
    let mut out = vec![pts[0]];
    for w in pts.windows(3) {
        let (a, vx, b) = (w[0], w[1], w[2]);
        let u1 = (vx - a).normalized(0.0).expect("leg");
        let u2 = (b - vx).normalized(0.0).expect("leg");
        let phi = u1.angle_to(u2);
        if phi < 1e-3 {
            out.push(vx);
            continue;
        }
        // Apex distance r (sec(phi / 2) - 1) = dev; tangent length
        // r tan(phi / 2).
        let r = dev / (1.0 / (0.5 * phi).cos() - 1.0);
        let d = r * (0.5 * phi).tan();
        let n1 = (u2 - u1 * u1.dot(u2)).normalized(0.0).expect("bend");
        let p1 = vx - u1 * d;
        let c = p1 + n1 * r;
        let steps = (phi.to_degrees().ceil() as usize).max(2);
        for k in 0..=steps {
            let t = phi * k as f64 / steps as f64;
            out.push(c - n1 * (r * t.cos()) + u1 * (r * t.sin()));
        }
    }
    out.push(*pts.last().expect("points"));
    out
}

#[test]
fn seeded_filleted_turns_plan_no_faster_than_the_bound() {
    // Step 8 caps a turn's slow point by the curvature Schur's theorem
    // asks of it: paths that round every vertex inside the band, at
    // deflections from 10 to 175 degrees and legs of 2 to 40 mm in 3D,
    // must plan no faster than the bound of the sharp polyline (both
    // kinds of band paths: these follow it in order).
    let mut next = seeded(0x5eed_0f5c_4a11_7e57);
    for case in 0..40 {
        let n = 3 + (next() * 5.0) as usize;
        let mut pts = vec![v(0.0, 0.0, 0.0)];
        let mut dir = v(1.0, 0.0, 0.0);
        for _ in 1..n {
            let len = 2.0 + 38.0 * next();
            let last = *pts.last().expect("points");
            pts.push(last + dir * len);
            // Turn by 10 to 175 degrees about a random axis across `dir`.
            let phi = (10.0 + 165.0 * next()).to_radians();
            let side = dir.any_perpendicular();
            let up = dir.cross(side);
            let spin = core::f64::consts::TAU * next();
            let n1 = side * spin.cos() + up * spin.sin();
            dir = (dir * phi.cos() + n1 * phi.sin())
                .normalized(0.0)
                .expect("direction");
        }
        let sharp = polyline_run(&pts);
        let dev = TOL * (0.3 + 0.65 * next());
        let round = polyline_run(&filleted(&pts, dev));
        let check = fairpath::verify::verify_run(
            &sharp.pieces,
            &round.pieces,
            &fairpath::verify::VerifyOptions::new(TOL),
        );
        if !check.within(TOL) {
            // Legs too short for both fillets: not a band path.
            continue;
        }
        let t = planned(&round.pieces);
        let (b, b_in_order) = (bound(&sharp.pieces), bound_in_order(&sharp.pieces));
        assert!(
            b <= t && b_in_order <= t,
            "case {case}: bounds {b}, {b_in_order} above the fillets' plan {t}: {pts:?}"
        );
    }
}

#[test]
fn wide_arcs_run_near_the_feed_stay_above_their_bound() {
    // Where a band path turns without slowing far, the bound comes within
    // half a percent of the plan (radius 100 mm: 0.6727 s against 0.6755
    // s; 400 mm: 1.3227 against 1.3300 s): arcs of 100 to 2000 mm radius
    // through 30 to 90 degrees, in 0.5-degree chords. A guard: it also
    // passed while the top cell of a window's least speeds was taken as
    // impossible (`an_envelope_from_the_feed_runs_at_the_feed`).
    for (radius, degrees) in [(100.0, 90.0), (400.0, 60.0), (2000.0, 30.0)] {
        let n = (2.0 * degrees) as usize;
        let pts: Vec<Vec3> = (0..=n)
            .map(|k| {
                let a = f64::to_radians(degrees) * k as f64 / n as f64;
                v(radius * a.sin(), radius * (1.0 - a.cos()), 0.0)
            })
            .collect();
        let run = polyline_run(&pts);
        let t = planned(&run.pieces);
        let (b, b_in_order) = (bound(&run.pieces), bound_in_order(&run.pieces));
        assert!(
            b <= t && b_in_order <= t,
            "radius {radius}: bounds {b}, {b_in_order} above the plan {t}"
        );
    }
}
#[test]
fn slow_points_in_order_are_chained_over_the_run() {
    // Step 10 of `feed::lower_bound`: a path in order slows to the walls'
    // cap at each sharp corner and climbs back between them at the jerk
    // limit, peaks included. Right angle between 50 mm legs: 0.753 s in
    // order before the chain, 0.801 s with it, 0.823 s with links
    // bounded through their peak speed and the slow points' acceleration
    // in cells, 0.833 s with step 9's fan (planned 0.891 s); a 1 mm
    // raster step-over 0.679 -> 0.802 -> 0.825 -> 0.835 s (planned 1.033
    // s); a 1.2 mm U-turn between 20 mm legs 0.469 -> 0.571 -> 0.591 ->
    // 0.605 s (planned 0.813 s).
    let corner = polyline_run(&[v(0.0, 0.0, 0.0), v(50.0, 0.0, 0.0), v(50.0, 50.0, 0.0)]);
    let step = polyline_run(&raster(2, 50.0, 1.0));
    let u_turn = polyline_run(&[
        v(0.0, 20.0, 0.0),
        v(0.0, 0.0, 0.0),
        v(1.2, 0.0, 0.0),
        v(1.2, 20.0, 0.0),
    ]);
    for (name, run, least) in [
        ("corner", &corner, 0.83),
        ("step-over", &step, 0.83),
        ("u-turn", &u_turn, 0.6),
    ] {
        let (b, t) = (bound_in_order(&run.pieces), planned(&run.pieces));
        assert!(b >= least, "{name}: in-order bound {b} below {least}");
        assert!(b <= t, "{name}: in-order bound {b} above the plan {t}");
    }
}

/// Three 20 mm moves along X in one run, the middle one at `slow`
/// mm/min, the others at 1200.
fn slow_middle(slow: f64) -> Vec<Piece> {
    let feeds = [1200.0, slow, 1200.0];
    (0..3)
        .map(|i| {
            let mut p = polyline_run(&[
                v(20.0 * i as f64, 0.0, 0.0),
                v(20.0 * (i + 1) as f64, 0.0, 0.0),
            ])
            .pieces
            .remove(0);
            p.feed = Some(feeds[i]);
            p
        })
        .collect()
}

#[test]
fn a_slow_feed_inside_a_run_bounds_paths_in_order_that_keep_it() {
    // 20 mm at F120 (2 mm/s) takes 10 s; the run's largest feed, 20
    // mm/s, would allow 3 s for the whole run. The stretches next to the
    // feed change take the faster feed (a few tolerances of slack and a
    // gate spacing each side).
    let m = MachineLimits::thesis();
    let run = slow_middle(120.0);
    let bound = |o: &BoundOptions| lower_bound_time(&run, o, &m, false).expect("bounds").time;
    let in_order_bound = bound(&in_order(TOL));
    assert!(
        in_order_bound > 0.95 * (10.0 + 40.0 / 20.0),
        "{in_order_bound}"
    );
    assert!(bound(&BoundOptions::new(TOL)) < 4.0);
    // The original keeps its feeds; the same path run at F1200 all
    // along does not, and is not a path the bound holds for.
    let g = in_order_gates_of(&run, &in_order(TOL), &m, false);
    let speed = |p: &Piece| piece_speed(p, &m, false);
    assert!(follows_in_order_within(
        &run,
        &g.gates,
        &g.caps,
        speed,
        1e-4 * TOL
    ));
    let fast = slow_middle(1200.0);
    assert!(!follows_in_order_within(
        &fast,
        &g.gates,
        &g.caps,
        speed,
        1e-4 * TOL
    ));
    assert!(follows_in_order(&fast, &g.gates, 1e-4 * TOL));
    // Planned as the planner plans it, the original takes longer.
    let opts = fairpath::feed::plan::PlanOptions {
        limits: m,
        override_feed: false,
        window: None,
        ends: Default::default(),
    };
    let planned = fairpath::feed::plan::plan_run(&run, &opts)
        .expect("plans")
        .time;
    assert!(
        planned >= in_order_bound,
        "{planned} below {in_order_bound}"
    );
}

#[test]
fn square_wave_corners_are_slow_points_between_their_nearest_gates() {
    // `synthetic/square-wave.ngc`: 23 right angles 5 mm apart at F3000.
    // Each corner's slow window runs between the nearest gates clear of
    // its walls' cap on either side of the vertex (before stop 93 the
    // window reached back to the start of the turn's window): in-order
    // bound 2.718 s at stop 92, 2.870 s with the links through their
    // peak speed and the slow points' acceleration in cells, 3.053 s with
    // the nearer windows, 3.531 s with step 9's fan, 3.589 s with its
    // sweeps (planned 5.434 s).
    let mut pts = vec![v(0.0, 0.0, 0.0)];
    for k in 0..6 {
        let x = 10.0 * k as f64;
        pts.push(v(x, 5.0, 0.0));
        pts.push(v(x + 5.0, 5.0, 0.0));
        pts.push(v(x + 5.0, 0.0, 0.0));
        pts.push(v(x + 10.0, 0.0, 0.0));
    }
    let mut run = polyline_run(&pts);
    for p in &mut run.pieces {
        p.feed = Some(3000.0);
    }
    let m = MachineLimits::thesis();
    let b = lower_bound_time(&run.pieces, &in_order(TOL), &m, false)
        .expect("bounds")
        .time;
    assert!(b > 3.55, "{b}");
    let opts = fairpath::feed::plan::PlanOptions {
        limits: m,
        override_feed: false,
        window: None,
        ends: Default::default(),
    };
    let planned = fairpath::feed::plan::plan_run(&run.pieces, &opts)
        .expect("plans")
        .time;
    assert!(b <= planned, "{b} above {planned}");
}

#[test]
fn plotter_owl_hairpin_tip_holds_no_gate_the_corner_methods_cut() {
    // `gcode-rs/plotter_owl.gcode` line 520: the pen runs 3.1 mm to a tip
    // and back at 12 degrees. Near the tip both legs share the band, and
    // every method's corner transition cuts inside it; a gate there (0.4
    // mm from the tip, 0.08 mm from the other leg) would leave every
    // smoothed path out of order. Farther along the legs stand apart.
    let run = polyline_run(&[
        v(26.55, 35.66, 0.0),
        v(28.93, 35.11, 0.0),
        v(31.86, 34.10, 0.0),
        v(27.84, 34.61, 0.0),
        v(24.38, 34.43, 0.0),
    ]);
    let tip = v(31.86, 34.10, 0.0);
    let g = gates_of(&run.pieces);
    assert!(!g.gates.is_empty());
    assert_no_gate_within(&g, tip, 0.5);
    assert!(follows(&run.pieces, &bspline_corner_of(&run)));
}

/// LinuxCNC's `line-arc-burnin.ngc` (`arc-intersections`), `bumps` arcs
/// long: lines of 2.54 mm each followed by an arc of 60 degrees and 2.54
/// mm radius, bulging 0.34 mm up and down in turn (each meets its lines
/// at 30 degrees), the arcs in chords of 1.5 degrees; it ends on an arc.
fn line_arc_burnin(bumps: usize) -> Vec<Vec3> {
    let (r, chord) = (2.54, 2.54);
    let h = (r * r - chord * chord / 4.0f64).sqrt();
    let mut pts = vec![v(0.0, 0.0, 0.0)];
    let mut x = 0.0;
    for k in 0..bumps {
        x += chord;
        pts.push(v(x, 0.0, 0.0));
        // The centre below the chord for a bump up, above for one down.
        let up = if k % 2 == 0 { 1.0 } else { -1.0 };
        let (cx, cy) = (x + chord / 2.0, -up * h);
        let (a0, a1) = ((0.0 - cy).atan2(x - cx), (0.0 - cy).atan2(x + chord - cx));
        for i in 1..=40 {
            let a = a0 + (a1 - a0) * i as f64 / 40.0;
            pts.push(v(cx + r * a.cos(), cy + r * a.sin(), 0.0));
        }
        x += chord;
    }
    pts
}

#[test]
fn line_arc_burnin_bumps_are_slow_points_of_the_half_feed_windows() {
    // No turn window holds a bump (its gates' slack swallows the 30-degree
    // kinks) and step 9's walls cap none (the arcs leave the walls' planes
    // within the sweep's reach), so its slow points are step 8's windows
    // over the bumps, capped between a quarter and 0.4 of the feed on the
    // thesis machine. In order, with the windows below a quarter of the
    // feed alone (stop 94): 0.545 s; with those below half of it in a
    // chain of their own: 0.748 s.
    let run = polyline_run(&line_arc_burnin(20));
    let b = bound_in_order(&run.pieces);
    assert!(b > 0.7, "{b}: the windows below half the feed are lost");
    // Still a bound: the run itself, and `bspline-fit`'s smoothing of it
    // (a band path that follows it in order), plan no faster.
    use fairpath::smooth::{BsplineFit, Smoother};
    let fit = BsplineFit::default().smooth_run(&run, TOL).expect("fits");
    assert!(follows(&run.pieces, &fit.pieces));
    for t in [planned(&run.pieces), planned(&fit.pieces)] {
        assert!(b <= t, "bound {b} above the plan {t}");
    }
}

/// A V-carved corner as `scripts/random-programs.py`'s engravings write
/// it: a stroke of `chord`-mm moves into the corner, a spike out along
/// the bisector of the turn `turn_deg` and up by `rise` mm over a leg of
/// `leg` mm, back down the same leg (an exact reversal), and the stroke
/// on out of the corner.
fn v_carved_corner(chord: f64, turn_deg: f64, leg: f64, rise: f64) -> Vec<Vec3> {
    let n = (3.0 / chord).ceil() as usize;
    let mut pts: Vec<Vec3> = (0..=n).map(|i| v(i as f64 * chord, 0.0, 0.0)).collect();
    let corner = *pts.last().expect("points");
    let turn = turn_deg.to_radians();
    // The bisector of the inside of the corner.
    let half = 0.5 * (core::f64::consts::PI + turn);
    let flat = (leg * leg - rise * rise).max(0.0).sqrt();
    pts.push(corner + v(flat * half.cos(), flat * half.sin(), rise));
    pts.push(corner);
    for i in 1..=n {
        let d = i as f64 * chord;
        pts.push(corner + v(d * turn.cos(), d * turn.sin(), 0.0));
    }
    pts
}

#[test]
fn v_carve_spike_tip_holds_a_gate_and_raises_the_bound() {
    // `r010_engrave.ngc` of `random-programs.py /tmp/eng 12 9701 engrave`:
    // spikes of 1.3 mm legs rising 0.92 mm at 93-degree corners of
    // strokes in 0.175 mm chords. Every method keeps the spike's tip (an
    // exact reversal) and stops there; with no gate within `hairpin_reach`
    // of the tip the bound charged at most the last 0.3 mm of each leg.
    let pts = v_carved_corner(0.175, 93.0, 1.3, 0.92);
    let tip = pts[pts.len() / 2];
    let run = polyline_run(&pts);
    let g = gates_of(&run.pieces);
    assert!(
        g.gates
            .iter()
            .any(|&(q, r)| q.dist(tip) < 1e-12 && r >= TOL),
        "no gate on the tip {tip:?}: {:?}",
        g.gates
    );
    let without = BoundOptions {
        reversal_half_angle: 0.0,
        ..in_order(TOL)
    };
    let m = MachineLimits::thesis();
    let b_without = lower_bound_time(&run.pieces, &without, &m, true)
        .expect("bounds")
        .time;
    let b = bound_in_order(&run.pieces);
    println!("in-order bound {b:.4} s, {b_without:.4} s without the tip gate");
    assert!(
        b > 1.2 * b_without,
        "{b} against {b_without} without the tip"
    );
    assert!(b <= planned(&run.pieces), "{b}");
    assert!(follows(&run.pieces, &run.pieces));
    for smoothed in [bspline_corner_of(&run), bspline_fit_of(&run)] {
        assert!(follows(&run.pieces, &smoothed));
        assert!(b <= planned(&smoothed));
    }
}

#[test]
fn seeded_v_carved_corners_stay_above_their_in_order_bound() {
    // Spikes of 0.02 to 3 mm (shorter than the band to many tolerances)
    // at turns of 20 to 160 degrees, strokes in chords of 0.01 to 0.4 mm:
    // the run itself and its corner and fit smoothings (which keep the
    // tips) pass the tip gates in order and plan no faster than the bound.
    let mut next = seeded(0x0c4e_5a11_7e57_0b1d);
    for case in 0..24 {
        let chord = 0.01 + 0.39 * next();
        let turn = 20.0 + 140.0 * next();
        let leg = 0.02 + 2.98 * next();
        let rise = leg * 0.8 * next();
        let pts = v_carved_corner(chord, turn, leg, rise);
        let run = polyline_run(&pts);
        let b = bound_in_order(&run.pieces);
        let t = planned(&run.pieces);
        assert!(b <= t, "case {case}: bound {b} above the plan {t}: {pts:?}");
        assert!(follows(&run.pieces, &run.pieces), "case {case}");
        for (name, smoothed) in [
            ("bspline-corner", bspline_corner_of(&run)),
            ("bspline-fit", bspline_fit_of(&run)),
        ] {
            assert!(
                follows(&run.pieces, &smoothed),
                "case {case}: {name} misses a gate (chord {chord}, turn {turn}, leg {leg}, rise {rise})"
            );
            let ts = planned(&smoothed);
            assert!(
                b <= ts,
                "case {case}: {name} plans {ts} below the bound {b}"
            );
        }
    }
}

#[test]
fn regression_r001_engrave_plunge_corner_is_no_reversal() {
    // `r001_engrave.ngc` (`random-programs.py /tmp/eng 12 9701 engrave`):
    // a plunge of 5.676 mm and a stroke at right angles. The plunge's end,
    // evaluated a rounding away from the stroke's start, left a leg of
    // 2e-16 mm pointing back up the plunge: the corner was taken for a
    // reversal's tip, whose gate `lotm`'s transition (inside the band)
    // passes outside.
    let run = polyline_run(&[
        v(105.543, 2.17, 5.0),
        v(105.543, 2.17, -0.676),
        v(105.422, 2.186, -0.676),
        v(105.301, 2.202, -0.676),
    ]);
    assert_no_gate_within(&gates_of(&run.pieces), v(105.543, 2.17, -0.676), 0.1);
    use fairpath::smooth::{Lotm, Smoother};
    let smoothed = Lotm::default().smooth_run(&run, TOL).expect("smooths");
    assert!(follows(&run.pieces, &smoothed.pieces));
}

#[test]
fn regression_cereal_v_carve_spike_dipping_at_its_tip_holds_no_tip_gate() {
    // `linuxcnc/performance/Cereal.ngc` line 2034: a V-carve spike up to
    // Z-0.169 that dips 0.035 mm and comes back up before running back
    // down its leg. The dip's bottom is an exact reversal on legs shorter
    // than a short move: the corner methods absorb the dip and round the
    // tip, 0.19 mm from it. A gate there left `auto`'s program out of
    // order.
    // Up a spike to `tip`, down `dip` mm and back up, and down to `base`.
    let spike = |tip: Vec3, dip: f64, base: Vec3| [tip, tip - v(0.0, 0.0, dip), tip, base];
    let mut pts = vec![v(42.593, -35.765, -1.019), v(42.990, -35.768, -1.013)];
    pts.extend(spike(
        v(43.485, -36.254, -0.172),
        0.036,
        v(43.0, -35.768, -1.013),
    ));
    pts.extend(spike(
        v(43.487, -35.281, -0.169),
        0.035,
        v(43.0, -35.768, -1.013),
    ));
    pts.extend([v(42.301, -35.759, -1.030), v(41.872, -35.734, -1.073)]);
    let run = polyline_run(&pts);
    let g = gates_of(&run.pieces);
    for dip in [pts[3], pts[7]] {
        assert_no_gate_within(&g, dip, 0.01);
    }
    let smoothed = bspline_corner_of(&run);
    assert!(follows(&run.pieces, &smoothed));
    assert!(bound_in_order(&run.pieces) <= planned(&smoothed));
}

/// `pts` with its spike's tip (the vertex `tip`, an exact reversal) turned
/// round on a half circle of radius `rho` inside the band's sleeve: up
/// the leg to `rho` below the tip, offset by `rho` along `side` (a unit
/// across the leg), round the half circle whose top is the tip, and back
/// down the other side to the vertex before the tip. A path in order
/// within `rho` of the run that never stops.
fn u_turned(pts: &[Vec3], tip: usize, rho: f64, side: Vec3) -> Vec<Piece> {
    use fairpath::geom::{Arc, Curve, Line};
    let (foot, top) = (pts[tip - 1], pts[tip]);
    let up = (top - foot).normalized(0.0).expect("leg");
    let w = (side - up * side.dot(up)).normalized(0.0).expect("across");
    let c = top - up * rho;
    let (s1, s2) = (c + w * rho, c - w * rho);
    let line = |a: Vec3, b: Vec3| Curve::Line(Line::new(a, b));
    let arc = Arc::from_center(s1, s2, c, w.cross(up), false, 1, 1e-12).expect("arc");
    let mut curves: Vec<Curve> = pts[..tip].windows(2).map(|p| line(p[0], p[1])).collect();
    curves.push(line(foot, s1));
    curves.push(Curve::Arc(Box::new(arc)));
    curves.push(line(s2, pts[tip + 1]));
    curves.extend(pts[tip + 1..].windows(2).map(|p| line(p[0], p[1])));
    curves
        .into_iter()
        .map(|curve| Piece {
            curve,
            rapid: false,
            source_lines: (1, 1),
            feed: Some(1000.0),
        })
        .collect()
}

#[test]
fn seeded_u_turns_inside_a_spikes_sleeve_plan_no_faster_than_the_bound() {
    // Step 12 caps the speed at a reversal's tip as if the path must turn
    // round inside the sleeve of width `2e` around its legs: paths that do
    // (half circles of 0.2 to 0.95 tolerances on the V-carved corners of
    // the test above, in random planes through the leg) pass the gates in
    // order, stay within the tolerance and plan no faster than the bound.
    let mut next = seeded(0x7195_0f5c_a11e_0b1d);
    let mut cases = 0;
    for case in 0..24 {
        let chord = 0.02 + 0.3 * next();
        let turn = 20.0 + 140.0 * next();
        let leg = 0.3 + 2.7 * next();
        let rise = leg * 0.8 * next();
        let pts = v_carved_corner(chord, turn, leg, rise);
        let tip = pts.len() / 2;
        let rho = TOL * (0.2 + 0.75 * next());
        let spin = core::f64::consts::TAU * next();
        let side = v(spin.cos(), spin.sin(), next() - 0.5);
        let run = polyline_run(&pts);
        let path = u_turned(&pts, tip, rho, side);
        let check = fairpath::verify::verify_run(
            &run.pieces,
            &path,
            &fairpath::verify::VerifyOptions::new(TOL),
        );
        assert!(check.within(TOL), "case {case}: {check:?}");
        assert!(follows(&run.pieces, &path), "case {case}");
        let b = bound_in_order(&run.pieces);
        let t = planned(&path);
        assert!(
            b <= t,
            "case {case}: the U-turn plans {t} below the bound {b} (chord {chord}, turn {turn}, leg {leg}, rise {rise}, rho {rho})"
        );
        cases += 1;
    }
    assert_eq!(cases, 24);
}

#[test]
fn a_spike_is_bounded_near_its_two_stops() {
    // Up a 3 mm leg and straight back: every path in order turns round
    // inside the sleeve of width `2e` around the leg, and step 12 caps
    // its speed there near a U-turn's (5.8 mm/s on the thesis machine at
    // 0.05 mm), so the bound comes near the two rest-to-rest moves the
    // corner methods plan; without the tip's gate (and so its slow point)
    // it charges little of the turn.
    let pts = [v(0.0, 0.0, 0.0), v(2.0, 1.0, 2.0), v(0.0, 0.0, 0.0)];
    let run = polyline_run(&pts);
    let t = planned(&run.pieces);
    let b = bound_in_order(&run.pieces);
    let without = BoundOptions {
        reversal_half_angle: 0.0,
        ..in_order(TOL)
    };
    let b_without = lower_bound_time(&run.pieces, &without, &MachineLimits::thesis(), true)
        .expect("bounds")
        .time;
    println!("spike: planned {t:.4} s, bound {b:.4} s, {b_without:.4} s without the tip");
    assert!(b <= t, "{b} above the plan {t}");
    assert!(b >= 0.88 * t, "{b} against the plan {t}");
    assert!(b_without < 0.8 * t, "{b_without} against the plan {t}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    /// Polylines that go out and straight back along some of their moves
    /// (exact reversals, each a tip of step 12), with moves from a
    /// hundredth of the tolerance to 5 mm: the in-order bound stays
    /// below the plan of the run itself, which stops at every tip.
    #[test]
    fn the_in_order_bound_with_tips_never_exceeds_the_plan(
        steps in prop::collection::vec(
            ((-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), 0.0005f64..5.0, any::<bool>()),
            1..10
        )
    ) {
        let mut pts = vec![v(0.0, 0.0, 0.0)];
        for ((x, y, z), len, back) in steps {
            let Some(d) = v(x, y, z).normalized(1e-3) else { continue };
            let last = *pts.last().expect("points");
            pts.push(last + d * len);
            if back {
                pts.push(last);
            }
        }
        prop_assume!(pts.len() >= 3);
        let run = polyline_run(&pts);
        let (t, b) = (planned(&run.pieces), bound_in_order(&run.pieces));
        prop_assert!(b <= t, "in-order bound {} above the plan {}: {:?}", b, t, pts);
    }
}

/// `scripts/fillet-radius.py`'s pass: a 30 x 20 mm rectangle from the
/// corner of its lower edge's fillet around, its corners rounded by G3
/// quarter circles of radius `r`, every move at `feed` mm/min.
fn filleted_rectangle(r: f64, feed: f64) -> Vec<Piece> {
    use fairpath::geom::{Arc, Curve, Line};
    let (w, h) = (30.0, 20.0);
    let corners = [(w - r, r), (w - r, h - r), (r, h - r), (r, r)];
    let mut pieces = Vec::new();
    let mut at = v(r, 0.0, 0.0);
    for (k, &(cx, cy)) in corners.iter().enumerate() {
        let a0 = (-90.0 + 90.0 * k as f64).to_radians();
        let (start, end) = (
            v(cx + r * a0.cos(), cy + r * a0.sin(), 0.0),
            v(cx - r * a0.sin(), cy + r * a0.cos(), 0.0),
        );
        for curve in [
            Curve::Line(Line::new(at, start)),
            Curve::from(
                Arc::from_center(start, end, v(cx, cy, 0.0), Vec3::Z, false, 1, 1e-9).unwrap(),
            ),
        ] {
            pieces.push(Piece {
                curve,
                rapid: false,
                source_lines: (1, 1),
                feed: Some(feed),
            });
        }
        at = end;
    }
    pieces
}

/// `scripts/fillet-radius.py`'s pass at 0.005 mm: every length of the
/// bound's argument is a multiple of the tolerance, so at a tolerance
/// small against a fillet (radius 0.92 mm, 184 tolerances) its windows
/// span only part of the turn, and the in-order bound of the filleted
/// rectangle at 100 mm/s was 1.118 s at 0.005 mm against 1.244 s at
/// 0.02 mm on the thesis machine (its plan: 1.929 s; `fairpath compare`
/// on the script's program, default machine: 1.231 against 1.357 s).
/// A path within 0.005 mm is within 0.02 mm: the bound now
/// takes the largest at the tolerance and at 4 and 16 times it
/// (`BoundOptions::wider`), and still does not exceed the plan of the
/// run itself (a path within every band of it).
#[test]
fn regression_fillet_radius_a_small_tolerance_bounds_no_less_than_a_wider_one() {
    let run = filleted_rectangle(0.92, 6000.0);
    let m = MachineLimits::thesis();
    let at = |tol: f64, wider: [f64; 2]| {
        let o = BoundOptions {
            wider,
            ..in_order(tol)
        };
        lower_bound_time(&run, &o, &m, false).expect("bounds").time
    };
    let alone = |tol: f64| at(tol, [1.0, 1.0]);
    let small = at(0.005, BoundOptions::new(0.005).wider);
    let opts = fairpath::feed::plan::PlanOptions {
        limits: m,
        override_feed: false,
        window: None,
        ends: Default::default(),
    };
    let t = fairpath::feed::plan::plan_run(&run, &opts)
        .expect("plans")
        .time;
    assert!(small >= alone(0.01) && small >= alone(0.02), "{small}");
    assert!(small > alone(0.005), "{small}");
    assert!(small <= t, "bound {small} above the plan {t}");
}

/// A planar spiral from radius `r0` growing by `pitch` per turn over
/// `turns` turns, in chords of about `chord` mm, led in from its centre.
fn spiral(r0: f64, pitch: f64, turns: f64, chord: f64) -> Vec<Vec3> {
    let mut pts = vec![v(0.0, 0.0, 0.0)];
    let mut a: f64 = 0.0;
    while a <= turns * core::f64::consts::TAU {
        let r = r0 + pitch * a / core::f64::consts::TAU;
        pts.push(v(r * a.cos(), r * a.sin(), 0.0));
        a += chord / r;
    }
    pts
}

/// The in-order bound of `pieces` with the curved gates turned off.
fn bound_in_order_straight(pieces: &[Piece]) -> f64 {
    let opts = BoundOptions {
        curved_turn: 0.0,
        ..in_order(TOL)
    };
    lower_bound_time(pieces, &opts, &MachineLimits::thesis(), true)
        .expect("bounds")
        .time
}

#[test]
fn a_small_spiral_in_order_is_bounded_through_its_curved_gates() {
    // `130207L.ngc`'s glyphs turn at radii of 0.2 to 0.5 mm, never
    // straight within half a tolerance over the reach: no straight gate
    // stood on them, and their in-order bound was little more than their
    // length's. A spiral from 0.3 mm, 0.2 mm apart per turn (passes
    // farther apart than the band), three turns in 0.02 mm chords.
    let run = polyline_run(&spiral(0.3, 0.2, 3.0, 0.02));
    let b = bound_in_order(&run.pieces);
    let b_straight = bound_in_order_straight(&run.pieces);
    println!("in-order bound {b:.4} s, {b_straight:.4} s with straight gates only");
    assert!(b > 1.3 * b_straight, "{b} against {b_straight}");
    assert!(follows(&run.pieces, &run.pieces));
    assert!(b <= planned(&run.pieces), "{b}");
    for smoothed in [bspline_corner_of(&run), bspline_fit_of(&run)] {
        assert!(follows(&run.pieces, &smoothed));
        assert!(b <= planned(&smoothed), "{b}");
    }
}

#[test]
fn corners_hold_no_curved_gate_their_cuts_pass_outside() {
    // A right angle cut at 0.045 mm from its legs passes the vertex at
    // 0.064 mm, outside a gate of radius e there: the hexagon's corners
    // (60 degrees, and 3 mm up or down) and a square's hold none (the
    // gates are the straight ones), so the corner methods' transitions
    // follow their gates.
    let straight = BoundOptions {
        curved_turn: 0.0,
        ..in_order(TOL)
    };
    for pts in [
        hexagon(),
        vec![
            v(0.0, 0.0, 0.0),
            v(10.0, 0.0, 0.0),
            v(10.0, 10.0, 0.0),
            v(0.0, 10.0, 0.0),
            v(0.0, 0.5, 0.0),
        ],
    ] {
        let run = polyline_run(&pts);
        let g = gates_of(&run.pieces);
        let m = MachineLimits::thesis();
        let g_straight = in_order_gates_of(&run.pieces, &straight, &m, true);
        assert_eq!(g.gates, g_straight.gates);
        for smoothed in [bspline_corner_of(&run), bspline_fit_of(&run)] {
            assert!(follows(&run.pieces, &smoothed));
        }
    }
}

#[test]
fn seeded_small_loops_stay_above_their_in_order_bound() {
    // Spirals from 0.1 to 2 mm, 0.12 to 1 mm apart per turn, one to three
    // turns, in chords of 0.005 to 0.1 mm: every path that follows the
    // curved gates in order (the run itself, its corner and fit
    // smoothings) plans no faster than the bound.
    let mut next = seeded(0x5b1a_c0de_0f1e_2ad5);
    for case in 0..16 {
        let r0 = 0.1 + 1.9 * next();
        let pitch = 0.12 + 0.88 * next();
        let turns = 1.0 + 2.0 * next();
        let chord = 0.005 + 0.095 * next();
        let run = polyline_run(&spiral(r0, pitch, turns, chord));
        let b = bound_in_order(&run.pieces);
        assert!(follows(&run.pieces, &run.pieces), "case {case}");
        let t = planned(&run.pieces);
        assert!(b <= t, "case {case}: bound {b} above the plan {t}");
        for (name, smoothed) in [
            ("bspline-corner", bspline_corner_of(&run)),
            ("bspline-fit", bspline_fit_of(&run)),
        ] {
            if follows(&run.pieces, &smoothed) {
                let ts = planned(&smoothed);
                assert!(b <= ts, "case {case}: {name} plans {ts} below {b}");
            } else {
                println!(
                    "case {case}: {name} does not follow (r0 {r0}, pitch {pitch}, chord {chord})"
                );
            }
        }
    }
}

#[test]
fn regression_butterfly_80_a_coarse_vertex_holds_no_curved_gate() {
    // `butterfly-80.ngc`'s vertices turn by 10 to 60 degrees between
    // chords of millimetres: one of 54 degrees turns by less than
    // `curved_turn` over 2e, and `bspline-corner`'s cut there passed 0.0507
    // mm from a curved gate of radius 0.05005 mm beside the vertex. A
    // zigzag turning 55 degrees left and right between legs of 2 to 3 mm
    // likewise: with a limit on each vertex's turn no curved gate stands
    // by its vertices and the cuts follow; without one they do not.
    let mut pts = vec![v(0.0, 0.0, 0.0)];
    let mut heading: f64 = 0.0;
    for k in 0..40 {
        let len = 2.0 + (0.37 * k as f64) % 1.0;
        let last = pts[pts.len() - 1];
        pts.push(last + v(len * heading.cos(), len * heading.sin(), 0.0));
        heading += if k % 2 == 0 { 55f64 } else { -55f64 }.to_radians();
    }
    let run = polyline_run(&pts);
    let cut = bspline_corner_of(&run);
    let m = MachineLimits::thesis();
    let follows_with = |opts: &BoundOptions| {
        let g = in_order_gates_of(&run.pieces, opts, &m, true);
        follows_in_order(&cut, &g.gates, 1e-4 * TOL)
    };
    assert!(follows(&run.pieces, &cut));
    let any_vertex = BoundOptions {
        curved_vertex_turn: 10.0,
        ..in_order(TOL)
    };
    assert!(!follows_with(&any_vertex));
}
