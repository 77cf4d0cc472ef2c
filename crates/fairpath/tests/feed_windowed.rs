//! A long run's time planned window by window
//! (`fairpath::feed::windowed`): the whole plan's, to the bit, where the
//! windows agree with it (not always: the module docs), the same however
//! its pieces come, and the time `simulate` gives the run.

use crate::common;

use common::Rng;
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{plan_time_shaped, Corners, PlanOptions, RunEnds};
use fairpath::feed::program::Motion;
use fairpath::feed::shaping::Shaping;
use fairpath::feed::windowed::{
    plan_time_in_windows, plan_time_windowed, PlanWindows, WindowedTimer,
};
use fairpath::geom::{Arc, Curve, Vec3};
use fairpath::path::Piece;
use fairpath::smooth::{BsplineCorner, Smoother};

/// Small windows, so that runs of a few thousand pieces take many: 256
/// pieces a step, 128 of overlap (64 mm of the 0.5 mm moves below, past
/// the distance in which any machine drawn here reaches its feed).
const SMALL: PlanWindows = PlanWindows {
    step: 256,
    overlap: 128,
};

/// Windows whose step is longer than two overlaps, as the default's: 400
/// pieces a step, 100 of overlap.
const LONG_STEP: PlanWindows = PlanWindows {
    step: 400,
    overlap: 100,
};

/// A raster of `rows` passes over a bumpy surface, moves of about
/// `step` mm, with a step-over between passes.
fn raster(rng: &mut Rng, rows: usize, step: f64) -> Vec<Vec3> {
    let len = 100.0;
    let per_row = (len / step) as usize;
    let mut pts = Vec::new();
    for r in 0..rows {
        let y = r as f64 * 1.5;
        for k in 0..=per_row {
            let s = k as f64 * step;
            let x = if r % 2 == 0 { s } else { len - s };
            let z = (x * 0.3).sin() * 2.0 + (y * 0.2).cos() + 0.01 * rng.unit();
            pts.push(Vec3::new(x, y, z));
        }
    }
    pts
}

fn opts(m: MachineLimits, override_feed: bool) -> PlanOptions {
    PlanOptions {
        limits: m,
        override_feed,
        window: None,
        ends: RunEnds::AtRest,
    }
}

#[test]
fn seeded_random_rasters_plan_the_same_time_in_windows_as_whole() {
    let mut rng = Rng(19);
    let mut stitched = 0;
    let mut cases = 0;
    for case in 0..24 {
        let step = 0.3 + rng.unit() * 0.5;
        let pts = raster(&mut rng, 6 + case % 4, step);
        let feeds = [1200.0 + rng.unit() * 20000.0, 3000.0];
        let run = common::polyline_run_with_feeds(&pts, &feeds);
        let smoothed = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
        let m = MachineLimits {
            max_feed: 50.0 + rng.unit() * 350.0,
            acc: 1000.0 + rng.unit() * 9000.0,
            jerk: 10000.0 + rng.unit() * 90000.0,
            ..MachineLimits::thesis()
        };
        let corners = [Corners::Blended, Corners::Followed, Corners::BlockCapped][case % 3];
        for pieces in [&run.pieces, &smoothed.pieces] {
            // Also with a step longer than two overlaps (the default's
            // shape), where the last window ends short of a step.
            stitched +=
                check_against_whole(&mut rng, pieces, m, corners, &[SMALL, LONG_STEP], case);
            cases += 2;
        }
    }
    // The windows were stitched, not planned whole, in nearly every case.
    assert!(stitched * 10 >= cases * 9, "{stitched} of {cases} stitched");
}

/// `pieces` planned on `m` with `corners`, at the programmed feeds and
/// overridden: in SMALL windows the time is the whole plan's, to the bit,
/// and a timer handed the pieces in parts of random sizes (from 1 piece
/// to several windows) gives the time in each of `windows` that
/// `plan_time_in_windows` gives, or says it could not stitch them as it
/// does. Returns how many of the two plans SMALL windows stitched.
fn check_against_whole(
    rng: &mut Rng,
    pieces: &[Piece],
    m: MachineLimits,
    corners: Corners,
    windows: &[PlanWindows],
    case: usize,
) -> usize {
    assert!(SMALL.windows(pieces.len()), "case {case}: one window");
    let mut stitched = 0;
    for override_feed in [false, true] {
        let po = opts(m, override_feed);
        let whole = plan_time_shaped(pieces, &po, &Shaping::none(), corners).unwrap();
        let w = plan_time_windowed(pieces, &po, corners, SMALL).unwrap();
        assert_eq!(whole.to_bits(), w.to_bits(), "case {case}: {whole} {w}");
        for &w in windows {
            let streamed = streamed_time(rng, pieces, &po, corners, w);
            match plan_time_in_windows(pieces, &po, corners, w).unwrap() {
                Some(t) => assert_eq!(streamed, Some(t.to_bits()), "case {case}"),
                None => assert_eq!(streamed, None, "case {case}"),
            }
        }
        if plan_time_in_windows(pieces, &po, corners, SMALL)
            .unwrap()
            .is_some()
        {
            stitched += 1;
        }
    }
    stitched
}

/// The time a [`WindowedTimer`] gives `pieces` handed to it in parts of
/// random sizes, as bits (`None`: it could not stitch them).
fn streamed_time(
    rng: &mut Rng,
    pieces: &[Piece],
    po: &PlanOptions,
    corners: Corners,
    w: PlanWindows,
) -> Option<u64> {
    let mut timer = WindowedTimer::new(po, corners, w).unwrap();
    let mut at = 0;
    while at < pieces.len() {
        let len = match rng.unit() {
            u if u < 0.3 => 1 + (u * 10.0) as usize,
            u => 1 + (u * 3.0 * (w.step + 2 * w.overlap) as f64) as usize,
        };
        let end = (at + len).min(pieces.len());
        timer.push(&pieces[at..end]).unwrap();
        at = end;
    }
    timer.finish().unwrap().map(f64::to_bits)
}

/// One circle cut into many arcs: every joint is G2 and the cap never
/// falls, so the plan is one segment from the start to the end and no
/// two windows hold segments alike: planned whole.
#[test]
fn a_run_of_one_segment_is_planned_whole() {
    let (r, n) = (50.0, 2000);
    let at = |k: usize| {
        let a = k as f64 * core::f64::consts::TAU / n as f64 * 0.999;
        Vec3::new(r * a.cos(), r * a.sin(), 0.0)
    };
    let pieces: Vec<Piece> = (0..n)
        .map(|k| {
            let z = Vec3::new(0.0, 0.0, 1.0);
            let arc = Arc::from_center(at(k), at(k + 1), Vec3::ZERO, z, false, 0, 1e-9).unwrap();
            Piece {
                curve: Curve::from(arc),
                rapid: false,
                source_lines: (k + 1, k + 1),
                feed: Some(6000.0),
            }
        })
        .collect();
    let po = opts(MachineLimits::thesis(), false);
    let whole = plan_time_shaped(&pieces, &po, &Shaping::none(), Corners::Blended).unwrap();
    assert_eq!(
        plan_time_in_windows(&pieces, &po, Corners::Blended, SMALL).unwrap(),
        None
    );
    let w = plan_time_windowed(&pieces, &po, Corners::Blended, SMALL).unwrap();
    assert_eq!(whole.to_bits(), w.to_bits());
    // A timer that no longer holds the run says it must be planned whole.
    let mut rng = Rng(5);
    let streamed = streamed_time(&mut rng, &pieces, &po, Corners::Blended, SMALL);
    assert_eq!(streamed, None);
}

/// A run that fits one window, a bounded look-ahead and ends at the cap
/// are planned whole.
#[test]
fn short_runs_bounded_look_ahead_and_ends_at_the_cap_are_planned_whole() {
    let mut rng = Rng(3);
    let pts = raster(&mut rng, 4, 0.5);
    let run = common::polyline_run_with_feeds(&pts, &[3000.0, 3000.0]);
    let m = MachineLimits::thesis();
    let short = &run.pieces[..300];
    assert_eq!(
        plan_time_in_windows(short, &opts(m, false), Corners::Blended, SMALL).unwrap(),
        None
    );
    // A timer given a run of one window plans it whole: the same time.
    let whole = plan_time_shaped(short, &opts(m, false), &Shaping::none(), Corners::Blended);
    let streamed = streamed_time(&mut rng, short, &opts(m, false), Corners::Blended, SMALL);
    assert_eq!(streamed, Some(whole.unwrap().to_bits()));
    for po in [
        PlanOptions {
            window: Some(50),
            ..opts(m, false)
        },
        PlanOptions {
            ends: RunEnds::AtCap,
            ..opts(m, false)
        },
    ] {
        assert_eq!(
            plan_time_in_windows(&run.pieces, &po, Corners::Blended, SMALL).unwrap(),
            None
        );
        assert!(WindowedTimer::new(&po, Corners::Blended, SMALL).is_none());
        let whole = plan_time_shaped(&run.pieces, &po, &Shaping::none(), Corners::Blended);
        let w = plan_time_windowed(&run.pieces, &po, Corners::Blended, SMALL);
        assert_eq!(whole.unwrap().to_bits(), w.unwrap().to_bits());
    }
}

/// Runs of chords much shorter than the windows' overlap is long (a
/// Lissajous curve in chords of 10 um to 0.2 mm: SMALL's overlap is 1.3
/// to 26 mm of them, where the machine needs up to 50 mm to reach its
/// feed), at one programmed feed: the time in windows is the whole
/// plan's, to the bit, stitched or planned whole. (With the feed changing
/// from piece to piece it is not: see the module docs of
/// `feed::windowed`, "Where windows are not the whole plan".)
#[test]
fn seeded_random_runs_of_chords_far_shorter_than_the_overlap_plan_as_whole() {
    let mut rng = Rng(61565);
    let mut stitched = 0;
    for case in 0..24 {
        let step = 0.01 * (20.0f64).powf(rng.unit());
        let (a, b, phase) = (
            20.0 + 20.0 * rng.unit(),
            10.0 + 20.0 * rng.unit(),
            rng.unit(),
        );
        let at = |t: f64| Vec3::new(a * t.sin(), b * (2.0 * t + phase).sin(), 0.0);
        let n = (150.0 / step) as usize;
        let pts: Vec<Vec3> = (0..=n)
            .map(|k| at(k as f64 / n as f64 * core::f64::consts::TAU))
            .collect();
        let run = common::polyline_run_with_feeds(&pts, &[3000.0]);
        let m = MachineLimits {
            max_feed: 100.0 + rng.unit() * 300.0,
            acc: 1000.0 + rng.unit() * 5000.0,
            jerk: 10000.0 + rng.unit() * 40000.0,
            ..MachineLimits::thesis()
        };
        let corners = [Corners::Blended, Corners::Followed, Corners::BlockCapped][case % 3];
        stitched += check_against_whole(&mut rng, &run.pieces, m, corners, &[SMALL], case);
    }
    // Many are stitched (22 of 48 when written), not planned whole.
    assert!(stitched >= 12, "{stitched} stitched");
}

/// A run longer than a default window whose windows are not its whole
/// plan (chords of 4 um, the feed changing from piece to piece: every
/// joint a minimum of the cap) is timed by `simulate` as its windows
/// are, the time every other plan of fairpath gives it (the writer's
/// check, `auto`'s objective, the plans carried across parts); its
/// segments stay the whole plan's. (`butterfly-80.ngc` written as G5.2
/// with `--override-feed`: the summary said 13.493901 s where `simulate`
/// planned the whole run, 13.493546 s.)
#[test]
fn simulate_times_a_long_run_by_its_default_windows() {
    let step = 0.004;
    let at = |t: f64| Vec3::new(30.0 * t.sin(), 20.0 * (2.0 * t + 0.3).sin(), 0.0);
    let n = (150.0 / step) as usize;
    let pts: Vec<Vec3> = (0..=n)
        .map(|k| at(k as f64 / n as f64 * core::f64::consts::TAU))
        .collect();
    let run = common::polyline_run_with_feeds(&pts, &[6000.0, 3000.0]);
    let w = PlanWindows::DEFAULT;
    assert!(w.windows(run.pieces.len()));
    let m = MachineLimits::thesis();
    let po = opts(m, false);
    let sim =
        fairpath::feed::program::simulate(&[Motion::Feed(run.clone())], &m, false, None).unwrap();
    let windows = plan_time_in_windows(&run.pieces, &po, Corners::Blended, w).unwrap();
    let whole = fairpath::feed::plan::plan_run(&run.pieces, &po).unwrap();
    assert_eq!(Some(sim.feed_time), windows);
    assert_eq!(sim.plans[0].1.segments.len(), whole.segments.len());
    // Here the windows are not the whole plan (else this tests nothing).
    assert_ne!(windows, Some(whole.time));
}
