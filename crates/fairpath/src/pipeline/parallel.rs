//! Verification of many runs on all cores: the verifier is
//! single-threaded, so this splits the work into jobs (whole runs, and
//! chunks of long runs) and, with the `std` feature, runs them on scoped
//! threads (without it, one after the other: the same results).

use crate::path::Piece;
use crate::verify::{report_without_deviation, Deviation, RunReport, Verifier, VerifyOptions};
use alloc::vec::Vec;

/// Pieces per deviation job: long runs are measured in chunks this size.
const CHUNK: usize = 4096;

/// Runs `f(i)` for `i in 0..n`, results in order: with the `std` feature
/// on as many scoped threads as the machine has cores (at most `n`), each
/// taking the next index when done; without it in order on this thread.
pub fn par_map<T: Send, F: Fn(usize) -> T + Sync>(n: usize, f: F) -> Vec<T> {
    #[cfg(feature = "std")]
    {
        threaded(n, f)
    }
    #[cfg(not(feature = "std"))]
    {
        (0..n).map(f).collect()
    }
}

#[cfg(feature = "std")]
fn threaded<T: Send, F: Fn(usize) -> T + Sync>(n: usize, f: F) -> Vec<T> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Mutex;
    let threads = std::thread::available_parallelism()
        .map(|t| t.get())
        .unwrap_or(1)
        .min(n)
        .max(1);
    if threads <= 1 {
        return (0..n).map(f).collect();
    }
    let next = AtomicUsize::new(0);
    let out: Mutex<Vec<Option<T>>> = Mutex::new((0..n).map(|_| None).collect());
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                if i >= n {
                    break;
                }
                let r = f(i);
                out.lock().unwrap()[i] = Some(r);
            });
        }
    });
    out.into_inner()
        .unwrap()
        .into_iter()
        .map(|r| r.unwrap())
        .collect()
}

/// The same reports as `verify_run` on each `(original, smoothed)` pair.
pub fn verify_runs(pairs: &[(&[Piece], &[Piece])], opts: &VerifyOptions) -> Vec<RunReport> {
    // Per run: everything but the deviation, and the prepared original.
    let prepared: Vec<(RunReport, Option<Verifier>)> = par_map(pairs.len(), |i| {
        let (o, s) = pairs[i];
        let (report, measure) = report_without_deviation(o, s, opts);
        (report, measure.then(|| Verifier::new(o, opts)))
    });
    // Deviation jobs: chunks of the smoothed pieces of each run to measure.
    let mut jobs: Vec<(usize, usize, usize)> = Vec::new();
    for (i, (_, v)) in prepared.iter().enumerate() {
        if v.is_some() {
            let n = pairs[i].1.len();
            let mut a = 0;
            while a < n {
                let b = (a + CHUNK).min(n);
                jobs.push((i, a, b));
                a = b;
            }
        }
    }
    let results: Vec<Deviation> = par_map(jobs.len(), |j| {
        let (i, a, b) = jobs[j];
        prepared[i].1.as_ref().unwrap().deviation(&pairs[i].1[a..b])
    });
    let mut merged: Vec<Option<Deviation>> = alloc::vec![None; pairs.len()];
    for (&(i, _, _), d) in jobs.iter().zip(results) {
        merged[i] = Some(match merged[i] {
            Some(m) => m.merge(d),
            None => d,
        });
    }
    prepared
        .into_iter()
        .zip(merged)
        .map(|((mut report, _), d)| {
            if let Some(d) = d {
                report.set_deviation(d);
            }
            report
        })
        .collect()
}
