//! Helpers shared by the integration tests.
#![allow(dead_code)]

use fairpath::geom::Vec3;
use fairpath::path::Run;

/// A run of G1 moves through `pts` at 1000 mm/min, input lines numbered
/// from 1.
pub fn polyline_run(pts: &[Vec3]) -> Run {
    polyline_run_with_feeds(pts, &[1000.0])
}

/// A run of G1 moves through `pts`, move `i` at `feeds[i % feeds.len()]`
/// mm/min.
pub fn polyline_run_with_feeds(pts: &[Vec3], feeds: &[f64]) -> Run {
    let mut run = Run::polyline(pts, None);
    for (i, p) in run.pieces.iter_mut().enumerate() {
        p.feed = Some(feeds[i % feeds.len()]);
    }
    run
}

pub fn v(x: f64, y: f64, z: f64) -> Vec3 {
    Vec3::new(x, y, z)
}

/// `p` turned about the axis (1, 2, 3) by 0.7 rad, then shifted by
/// (5, -3, 2): a rigid motion that takes a planar path out of every
/// principal plane.
pub fn rotate(p: Vec3) -> Vec3 {
    let k = v(1.0, 2.0, 3.0).normalized(0.0).unwrap();
    let (s, c) = (0.7f64.sin(), 0.7f64.cos());
    p * c + k.cross(p) * s + k * (k.dot(p) * (1.0 - c)) + v(5.0, -3.0, 2.0)
}

use fairpath::smooth::{SmoothedRun, Smoother};
use fairpath::verify::{verify_run, Continuity, RunReport, VerifyOptions};
use proptest::prelude::*;

/// The guarantees of every method: within tolerance, endpoints exact, a
/// finite peak curvature, every joint G2 but kept corners, pieces joined
/// bit for bit.
pub fn check_guarantees(out: &SmoothedRun, rep: &RunReport, tol: f64) -> Result<(), TestCaseError> {
    prop_assert!(
        rep.deviation_bound <= tol,
        "deviation {} > {} at {:?}",
        rep.deviation_bound,
        tol,
        rep.worst_at
    );
    prop_assert_eq!(rep.start_gap, 0.0);
    prop_assert_eq!(rep.end_gap, 0.0);
    prop_assert!(rep.peak_curvature.is_finite());
    for j in &rep.joints {
        if j.class != Continuity::G2 {
            let kept = out
                .kept_corners
                .iter()
                .any(|k| k.at.dist(j.at) <= tol * 1e-6);
            prop_assert!(kept, "joint {:?} is {:?} but not kept", j.at, j.class);
        }
    }
    for w in out.pieces.windows(2) {
        prop_assert_eq!(w[0].end(), w[1].start(), "pieces must join bit for bit");
    }
    Ok(())
}

/// Smooths the polyline `pts` with `smoother` and checks the guarantees
/// with the independent verifier.
pub fn check_smoothed(
    pts: &[Vec3],
    tol: f64,
    smoother: &dyn Smoother,
) -> Result<(), TestCaseError> {
    let run = polyline_run(pts);
    let out = smoother.smooth_run(&run, tol).unwrap();
    let rep = verify_run(&run.pieces, &out.pieces, &VerifyOptions::new(tol));
    check_guarantees(&out, &rep, tol)
}

pub fn pt2(scale: f64) -> impl Strategy<Value = Vec3> {
    (-scale..scale, -scale..scale).prop_map(|(x, y)| v(x, y, 0.0))
}

pub fn pt3(scale: f64) -> impl Strategy<Value = Vec3> {
    (-scale..scale, -scale..scale, -scale..scale).prop_map(|(x, y, z)| v(x, y, z))
}

/// Polylines with duplicates, exact reversals and collinear points mixed in.
pub fn degenerate(base: Vec<Vec3>, ops: Vec<u8>) -> Vec<Vec3> {
    let mut out: Vec<Vec3> = Vec::new();
    for (i, p) in base.into_iter().enumerate() {
        out.push(p);
        match ops.get(i).copied().unwrap_or(0) % 6 {
            1 => out.push(p),
            2 if out.len() >= 2 => {
                let q = out[out.len() - 2];
                out.push(q); // exact reversal
                out.push(p);
            }
            3 if out.len() >= 2 => {
                let q = out[out.len() - 2];
                out.pop();
                out.push(q.lerp(p, 0.5)); // collinear point
                out.push(p);
            }
            _ => {}
        }
    }
    out
}

/// Tolerances from a micrometre to half a millimetre.
pub fn tolerances() -> impl Strategy<Value = f64> {
    prop_oneof![Just(0.001), Just(0.01), Just(0.05), Just(0.5)]
}

/// A raster step-over of LinuxCNC's `performance/test_12mmflat.ngc` (lines
/// 16-24): 1 mm moves up a quarter circle, across the top (turns of 58 and
/// 63 degrees) and down again, between the long moves of two passes.
pub fn test_12mmflat_step_over() -> Vec<Vec3> {
    vec![
        v(180.73483, 19.86847, 0.49686),
        v(193.40333, 19.86847, 0.49686),
        v(194.30136, 19.86847, 0.86884),
        v(194.67333, 19.86847, 1.76686),
        v(195.13791, 20.4863, 2.88769),
        v(195.18549, 22.04913, 3.00167),
        v(194.67401, 22.86847, 1.76686),
        v(194.3018, 22.86847, 0.86859),
        v(193.40333, 22.86847, 0.49686),
        v(180.04786, 22.86847, 0.50403),
    ]
}

/// A seeded random source for the seeded tests (splitmix64): the same
/// numbers on every machine, uniform in `[0, 1)`.
pub struct Rng(pub u64);
impl Rng {
    pub fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E3779B97F4A7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Planned time (s) of `pieces` at the maximum feed on the thesis' machine
/// (400 mm/s, 4000 mm/s^2, 20000 mm/s^3), at rest at both ends.
pub fn planned_at_max_feed(pieces: &[fairpath::path::Piece]) -> f64 {
    let opts = fairpath::feed::plan::PlanOptions {
        limits: fairpath::feed::limits::MachineLimits::thesis(),
        override_feed: true,
        window: None,
        ends: Default::default(),
    };
    fairpath::feed::plan::plan_run(pieces, &opts)
        .expect("plans")
        .time
}

/// The `.rs` files under `dir`, recursively, appended to `out` (the tests
/// that read the crates' sources: `layers`, `doc_diaries`).
pub fn rust_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}
