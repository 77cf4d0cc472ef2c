//! The verified pipeline on several threads gives what one thread gives:
//! runs smoothed in parallel come out in order and equal to the method run
//! by run, and `verify_runs` (a short run per job, a long run in chunks,
//! at most one prepared original per thread) reports what `verify_run`
//! reports on each pair.

use crate::common;

use common::{polyline_run, v};
use fairpath::budget::ToleranceBudget;
use fairpath::geom::Vec3;
use fairpath::path::{Piece, Run};
use fairpath::pipeline::{smooth_runs, verify_runs};
use fairpath::smooth::{BsplineCorner, BsplineFit, Smoother};
use fairpath::verify::{verify_run, VerifyOptions};

/// A seeded pseudo-random generator (SplitMix64), so that the runs are
/// the same on every machine.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A wandering polyline of `n` segments of 0.2 to 2 mm turning by up to
/// 100 degrees, starting at `origin`.
fn wander(rng: &mut Rng, origin: Vec3, n: usize) -> Run {
    let mut pts = vec![origin];
    let mut heading: f64 = 0.0;
    for _ in 0..n {
        heading += (rng.next() - 0.5) * 3.5;
        let len = 0.2 + 1.8 * rng.next();
        let p = *pts.last().unwrap();
        pts.push(
            p + v(
                len * heading.cos(),
                len * heading.sin(),
                0.1 * (rng.next() - 0.5),
            ),
        );
    }
    polyline_run(&pts)
}

fn runs(seed: u64, sizes: &[usize]) -> Vec<Run> {
    let mut rng = Rng(seed);
    sizes
        .iter()
        .enumerate()
        .map(|(i, &n)| wander(&mut rng, v(100.0 * i as f64, 0.0, 0.0), n))
        .collect()
}

#[test]
fn runs_smoothed_in_parallel_equal_the_method_run_by_run() {
    let budget = ToleranceBudget::new(0.05, None, 0.0).unwrap();
    let methods: [&dyn Smoother; 2] = [&BsplineCorner::default(), &BsplineFit::default()];
    for seed in 1..=4 {
        let input = runs(seed, &[3, 40, 1, 120, 17, 60, 2, 9]);
        for method in methods {
            let result = smooth_runs(input.clone(), method, &budget).unwrap();
            assert_eq!(result.runs.len(), input.len());
            for (r, run) in result.runs.iter().zip(&input) {
                assert_eq!(&r.original, run, "runs out of order (seed {seed})");
                let alone = method.smooth_run(run, budget.smoothing()).unwrap();
                assert_eq!(r.smoothed, alone, "{} seed {seed}", method.name());
                let report = verify_run(
                    &run.pieces,
                    &alone.pieces,
                    &VerifyOptions::new(budget.smoothing()),
                );
                assert_eq!(r.report, report, "{} seed {seed}", method.name());
            }
        }
    }
}

#[test]
fn verify_runs_reports_what_verify_run_reports_on_short_and_long_runs() {
    // One run longer than a chunk of 4096 pieces, among short ones.
    let input = runs(7, &[12, 5000, 3, 250, 1]);
    let tol = 0.05;
    let smoothed: Vec<Vec<Piece>> = input
        .iter()
        .map(|r| BsplineCorner::default().smooth_run(r, tol).unwrap().pieces)
        .collect();
    assert!(smoothed[1].len() > 2 * 4096, "the long run spans chunks");
    let pairs: Vec<(&[Piece], &[Piece])> = input
        .iter()
        .zip(&smoothed)
        .map(|(o, s)| (o.pieces.as_slice(), s.as_slice()))
        .collect();
    let opts = VerifyOptions::new(tol);
    let reports = verify_runs(&pairs, &opts);
    assert_eq!(reports.len(), pairs.len());
    for (i, ((o, s), got)) in pairs.iter().zip(&reports).enumerate() {
        let alone = verify_run(o, s, &opts);
        if s.len() <= 4096 {
            assert_eq!(got, &alone, "run {i}");
        } else {
            // Chunks are measured apart and merged: the same bound up to
            // the rounding of where each chunk's search stops.
            assert_eq!(got.joints, alone.joints, "run {i}");
            let d = (got.deviation_bound - alone.deviation_bound).abs();
            assert!(
                d <= 1e-3 * tol,
                "run {i}: {} against {}",
                got.deviation_bound,
                alone.deviation_bound
            );
            assert!(got.within(tol) && alone.within(tol), "run {i}");
        }
    }
}
