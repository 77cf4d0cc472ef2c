//! Verification of many runs on all cores: the verifier is
//! single-threaded, so this splits the work into jobs (whole runs, and
//! chunks of long runs) and, with the `std` feature, runs them on scoped
//! threads (without it, one after the other: the same results).

use crate::path::Piece;
use crate::verify::{report_measuring, Deviation, Measures, RunReport, Verifier, VerifyOptions};
use alloc::vec::Vec;

/// Pieces per deviation job: long runs are measured in chunks this size
/// (a caller that measures a run as it comes, chunk after chunk from its
/// start, merging in order, finds the same deviation to the bit).
pub const VERIFY_CHUNK: usize = 4096;
const CHUNK: usize = VERIFY_CHUNK;

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
///
/// A prepared original (its segments in a grid) can be far larger than
/// its run, so at most one per thread is held at a time: a short run is
/// one job that prepares, measures and drops its original; a long run is
/// prepared once and its smoothed pieces are measured in chunks of
/// `CHUNK` pieces on all threads, one long run after the other.
pub fn verify_runs(pairs: &[(&[Piece], &[Piece])], opts: &VerifyOptions) -> Vec<RunReport> {
    verify_runs_measuring(pairs, opts, Measures::All)
}

/// [`verify_runs`], measuring what `measures` says besides the deviation.
pub fn verify_runs_measuring(
    pairs: &[(&[Piece], &[Piece])],
    opts: &VerifyOptions,
    measures: Measures,
) -> Vec<RunReport> {
    let is_long = |i: usize| pairs[i].1.len() > CHUNK;
    let short: Vec<usize> = (0..pairs.len()).filter(|&i| !is_long(i)).collect();
    let short_reports = par_map(short.len(), |j| {
        let (o, s) = pairs[short[j]];
        let (mut report, measure) = report_measuring(o, s, opts, measures);
        if measure {
            report.set_deviation(Verifier::new(o, opts).deviation(s));
        }
        report
    });
    let mut reports: Vec<Option<RunReport>> = (0..pairs.len()).map(|_| None).collect();
    for (i, report) in short.into_iter().zip(short_reports) {
        reports[i] = Some(report);
    }
    for i in (0..pairs.len()).filter(|&i| is_long(i)) {
        let (o, s) = pairs[i];
        let (mut report, measure) = report_measuring(o, s, opts, measures);
        if measure {
            let verifier = Verifier::new(o, opts);
            let chunks = s.len().div_ceil(CHUNK);
            let merged = par_map(chunks, |c| {
                verifier.deviation(&s[c * CHUNK..((c + 1) * CHUNK).min(s.len())])
            })
            .into_iter()
            .reduce(Deviation::merge);
            if let Some(d) = merged {
                report.set_deviation(d);
            }
        }
        reports[i] = Some(report);
    }
    reports.into_iter().flatten().collect()
}
