//! `fairpath compare`: every smoothing method (and the untouched program as
//! the baseline) on one program, in one table.
//!
//! Each method smooths every run with the budget `smooth --format json`
//! gives it (the tolerance less the default chord), its curves are checked
//! by the independent verifier, and its exact path is planned on the
//! machine (as `fairpath simulate` plans the JSON output), rapids included.

use crate::parallel::verify_runs;
use crate::pipeline::{read_program, SmoothOptions};
use crate::simulate::{gcode_motions, simulate};
use crate::Format;
use anyhow::{anyhow, Context, Result};
use fairpath::feed::limits::MachineLimits;
use fairpath::geom::{curvature_variation_energy, Curve};
use fairpath::path::{Piece, Run};
use fairpath::smooth::verify::VerifyOptions;
use serde_json::json;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// Relative accuracy of the curvature variation energy in the table.
const ENERGY_ACCURACY: f64 = 1e-3;

/// One line of the table.
#[derive(Clone, Debug)]
pub struct Row {
    /// `original` for the baseline, else the method's name.
    pub method: String,
    /// Upper bound of the distance from the original (mm).
    pub max_deviation: f64,
    /// Whether every run verified: within the budget, endpoints exact.
    pub verified: bool,
    /// Joints by class: gaps, G0 (corners), G1, G2.
    pub joints: [usize; 4],
    /// Feed path length (mm).
    pub length: f64,
    /// Largest curvature of the feed path's curves (1/mm; corners of the
    /// baseline are counted in `joints`, not here).
    pub peak_curvature: f64,
    /// Curvature variation energy of the feed path (1/mm^3).
    pub energy: f64,
    /// Planned machining time (s), feed moves and rapids.
    pub time: f64,
    /// The part of `time` spent on feed moves (s): rapids are the same for
    /// every method.
    pub feed_time: f64,
    /// `time` over the baseline's.
    pub time_ratio: f64,
    /// Wall time of the smoothing alone (s).
    pub smoothing_time: f64,
}

/// What to compare.
pub struct CompareOptions {
    pub tolerance: f64,
    pub machine: MachineLimits,
    pub methods: Vec<String>,
    pub override_feed: bool,
}

fn row(
    method: &str,
    original: &[Run],
    smoothed: &[Run],
    budget: f64,
    (time, feed_time): (f64, f64),
    smoothing_time: f64,
) -> Row {
    let pairs: Vec<(&[Piece], &[Piece])> = original
        .iter()
        .zip(smoothed)
        .map(|(a, b)| (a.pieces.as_slice(), b.pieces.as_slice()))
        .collect();
    let reports = verify_runs(&pairs, &VerifyOptions::new(budget));
    let mut joints = [0; 4];
    for r in &reports {
        for (j, c) in joints.iter_mut().zip(r.joint_counts()) {
            *j += c;
        }
    }
    let acc = budget * 1e-4;
    let curves = || smoothed.iter().flat_map(|r| &r.pieces);
    Row {
        method: method.to_string(),
        max_deviation: reports.iter().map(|r| r.max_deviation).fold(0.0, f64::max),
        verified: reports.iter().all(|r| r.within(budget)),
        joints,
        length: curves()
            .map(|p| p.curve.length(acc))
            .fold(0.0, |a, b| a + b),
        peak_curvature: reports.iter().map(|r| r.peak_curvature).fold(0.0, f64::max),
        energy: curves()
            .filter(|p| !matches!(p.curve, Curve::Line(_)))
            .map(|p| curvature_variation_energy(&p.curve, ENERGY_ACCURACY))
            .fold(0.0, |a, b| a + b),
        time,
        feed_time,
        time_ratio: 1.0,
        smoothing_time,
    }
}

/// Runs the baseline and every method on the program at `path`.
pub fn compare(path: &Path, opts: &CompareOptions) -> Result<Vec<Row>> {
    let program = read_program(path)?;
    let runs = program.runs();
    // (total, feed moves only)
    let plan_time = |runs: &[Run]| -> Result<(f64, f64)> {
        let motions = gcode_motions(&program, runs);
        let sim = simulate(&motions, &opts.machine, opts.override_feed, None)?;
        Ok((sim.time(), sim.feed_time))
    };
    let mut rows = Vec::new();
    let base_time = plan_time(&runs)?;
    let budget0 =
        SmoothOptions::new(opts.tolerance, None, "bspline-corner", Format::Json)?.budget();
    rows.push(row("original", &runs, &runs, budget0, base_time, 0.0));
    for name in &opts.methods {
        let so = SmoothOptions::new(opts.tolerance, None, name, Format::Json)?;
        let budget = so.budget();
        let t0 = Instant::now();
        let mut smoothed = Vec::with_capacity(runs.len());
        for run in &runs {
            let line = run.pieces.first().map(|p| p.source_lines.0).unwrap_or(0);
            let s = so
                .method
                .smooth_run(run, budget)
                .with_context(|| format!("{name}: smoothing the run starting at line {line}"))?;
            smoothed.push(Run::new(s.pieces));
        }
        let smoothing_time = t0.elapsed().as_secs_f64();
        let time = plan_time(&smoothed).with_context(|| format!("{name}: planning"))?;
        rows.push(row(name, &runs, &smoothed, budget, time, smoothing_time));
    }
    let base_time = base_time.0;
    if base_time.is_nan() || base_time <= 0.0 {
        return Err(anyhow!("the program takes no time to run"));
    }
    for r in &mut rows {
        r.time_ratio = r.time / base_time;
    }
    Ok(rows)
}

const HEADER: [&str; 14] = [
    "method",
    "max_deviation_mm",
    "verified",
    "gaps",
    "g0",
    "g1",
    "g2",
    "length_mm",
    "peak_curvature_per_mm",
    "curvature_variation_energy",
    "time_s",
    "feed_time_s",
    "time_ratio",
    "smoothing_s",
];

/// The table as aligned text.
pub fn text(rows: &[Row]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<16} {:>11} {:>4} {:>22} {:>12} {:>12} {:>12} {:>10} {:>10} {:>7} {:>10}",
        "method",
        "max dev mm",
        "ok",
        "joints G2/G1/G0/gap",
        "length mm",
        "peak k 1/mm",
        "energy",
        "time s",
        "feed s",
        "ratio",
        "smooth s"
    );
    for r in rows {
        let joints = format!(
            "{}/{}/{}/{}",
            r.joints[3], r.joints[2], r.joints[1], r.joints[0]
        );
        let _ = writeln!(
            out,
            "{:<16} {:>11.6} {:>4} {:>22} {:>12.4} {:>12.4} {:>12.4e} {:>10.3} {:>10.3} {:>7.3} {:>10.4}",
            r.method,
            r.max_deviation,
            if r.verified { "yes" } else { "NO" },
            joints,
            r.length,
            r.peak_curvature,
            r.energy,
            r.time,
            r.feed_time,
            r.time_ratio,
            r.smoothing_time
        );
    }
    out
}

/// The table as CSV with a header row.
pub fn csv(rows: &[Row]) -> String {
    let mut out = HEADER.join(",");
    out.push('\n');
    for r in rows {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.method,
            r.max_deviation,
            r.verified,
            r.joints[0],
            r.joints[1],
            r.joints[2],
            r.joints[3],
            r.length,
            r.peak_curvature,
            r.energy,
            r.time,
            r.feed_time,
            r.time_ratio,
            r.smoothing_time
        );
    }
    out
}

/// The table as a JSON array of objects (keys as the CSV header).
pub fn json(rows: &[Row]) -> String {
    let v: Vec<_> = rows
        .iter()
        .map(|r| {
            json!({
                "method": r.method,
                "max_deviation_mm": r.max_deviation,
                "verified": r.verified,
                "gaps": r.joints[0],
                "g0": r.joints[1],
                "g1": r.joints[2],
                "g2": r.joints[3],
                "length_mm": r.length,
                "peak_curvature_per_mm": r.peak_curvature,
                "curvature_variation_energy": r.energy,
                "time_s": r.time,
                "feed_time_s": r.feed_time,
                "time_ratio": r.time_ratio,
                "smoothing_s": r.smoothing_time,
            })
        })
        .collect();
    serde_json::to_string_pretty(&v).expect("rows serialise")
}
