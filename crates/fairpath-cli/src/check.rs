//! `fairpath check ORIGINAL SMOOTHED --tolerance T`.

use crate::pipeline::{compare_runs, group_by_source, parse_program};
use anyhow::{anyhow, Context, Result};
use fairpath::smooth::verify::{verify_run, VerifyOptions};
use std::path::Path;
use std::process::ExitCode;

pub fn run(original: &Path, smoothed: &Path, tolerance: f64) -> Result<ExitCode> {
    fairpath::smooth::check_tolerance(tolerance).map_err(|e| anyhow!("--tolerance: {e}"))?;
    let orig = crate::pipeline::read_program(original)?;
    let bytes =
        std::fs::read(smoothed).with_context(|| format!("cannot read {}", smoothed.display()))?;
    let original_runs = orig.runs();
    let is_json = bytes.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'{');
    let candidate = if is_json {
        let text = std::str::from_utf8(&bytes)
            .map_err(|_| anyhow!("{}: not UTF-8", smoothed.display()))?;
        let pieces =
            fairpath_gcode::read_json(text).map_err(|e| anyhow!("{}: {e}", smoothed.display()))?;
        group_by_source(&original_runs, &pieces)
    } else {
        parse_program(smoothed, &bytes)?.runs()
    };
    let verdict = compare_runs(&original_runs, &candidate, tolerance)?;
    println!(
        "fairpath check: {} against {} (tolerance {} mm)",
        smoothed.display(),
        original.display(),
        tolerance
    );
    println!("  runs checked:    {}", verdict.runs_checked);
    println!("  max deviation:   {:.6} mm (bound)", verdict.max_deviation);
    println!("  endpoints moved: {} runs", verdict.endpoint_failures);
    if is_json {
        // Joint classes are meaningful for exact curves only.
        let mut counts = [0usize; 4];
        for (a, b) in original_runs.iter().zip(&candidate) {
            let rep = verify_run(&a.pieces, &b.pieces, &VerifyOptions::new(tolerance));
            for (i, c) in rep.joint_counts().iter().enumerate() {
                counts[i] += c;
            }
        }
        println!(
            "  joints:          {} G2, {} G1, {} G0 (corner), {} gaps",
            counts[3], counts[2], counts[1], counts[0]
        );
    }
    if verdict.within {
        println!("  verdict:         PASS");
        Ok(ExitCode::SUCCESS)
    } else {
        println!("  verdict:         FAIL");
        Ok(ExitCode::from(3))
    }
}
