//! `fairpath check ORIGINAL SMOOTHED --tolerance T`.
//!
//! When the original has block-delete (`/`) lines, both programs are read
//! twice, with the switch off (the `/` lines run) and on (they are
//! skipped, as LinuxCNC does with block delete on), and compared run by
//! run in each reading: the smoothed program must follow the original
//! either way the operator sets the switch.

use crate::read::parse_program_with;
use anyhow::{anyhow, Context, Result};
use fairpath::path::Run;
use fairpath::verify::{verify_run, VerifyOptions};
use fairpath_gcode::pipeline::{compare_runs_within, group_by_source};
use fairpath_gcode::{ParseOptions, Program};
use std::path::Path;
use std::process::ExitCode;

/// How far (mm) a run's end point may be from the original's when read
/// with the block-delete switch on. Absolute runs end on the original's
/// text in both readings; a G91 run then starts where the skipped `/` move
/// did not take the machine, and its written increments (the original's
/// path re-rounded) sum to the original's end only within f64 rounding of
/// positions accumulated from another start (around 1e-12 mm for programs
/// of metres and thousands of moves). A nanometre is far above that and
/// far below the finest G-code resolution (1e-4 mm).
pub const SWITCH_ON_ENDPOINT_MM: f64 = 1e-6;

/// The runs of `program`, consecutive runs with no move between them that
/// meet exactly joined into one: one stretch of feed path, however the
/// program's lines break it into runs.
fn joined_runs(program: &Program) -> Vec<Run> {
    let mut out: Vec<Run> = Vec::new();
    let mut last_move: Option<usize> = None;
    for (span, run) in program.run_spans().iter().zip(program.runs()) {
        if let (Some(prev), Some(end)) = (out.last_mut(), last_move) {
            let meets =
                prev.pieces.last().map(|p| p.end()) == run.pieces.first().map(|p| p.start());
            if end == span.moves.start && meets {
                let mut pieces = std::mem::take(&mut prev.pieces);
                pieces.extend(run.pieces);
                *prev = Run::new(pieces);
                last_move = Some(span.moves.end);
                continue;
            }
        }
        last_move = Some(span.moves.end);
        out.push(run);
    }
    out
}

/// Whether the program has a block-delete line.
fn has_block_delete(program: &Program) -> bool {
    program
        .lines()
        .iter()
        .any(|l| l.interpreted && l.text.trim_start().starts_with('/'))
}

pub fn run(original: &Path, smoothed: &Path, tolerance: f64) -> Result<ExitCode> {
    fairpath::smooth::check_tolerance(tolerance).map_err(|e| anyhow!("--tolerance: {e}"))?;
    let original_bytes =
        std::fs::read(original).with_context(|| format!("cannot read {}", original.display()))?;
    let bytes =
        std::fs::read(smoothed).with_context(|| format!("cannot read {}", smoothed.display()))?;
    let is_json = bytes.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'{');
    let off = ParseOptions::default();
    let orig = parse_program_with(original, &original_bytes, &off)?;
    // JSON holds the curves of one reading (the switch off).
    let readings: &[bool] = if has_block_delete(&orig) && !is_json {
        &[false, true]
    } else {
        &[false]
    };
    println!(
        "fairpath check: {} against {} (tolerance {} mm)",
        smoothed.display(),
        original.display(),
        tolerance
    );
    let mut pass = true;
    for &block_delete in readings {
        let opts = ParseOptions {
            block_delete,
            ..Default::default()
        };
        // With the switch on, stretches of path that the written program
        // ends differently (a motion word restored on a line of its own)
        // are compared whole.
        let runs_of = |p: Program| {
            if block_delete {
                joined_runs(&p)
            } else {
                p.runs()
            }
        };
        let original_runs = runs_of(parse_program_with(original, &original_bytes, &opts)?);
        let candidate: Vec<Run> = if is_json {
            let text = std::str::from_utf8(&bytes)
                .map_err(|_| anyhow!("{}: not UTF-8", smoothed.display()))?;
            let pieces = fairpath_gcode::read_json(text)
                .map_err(|e| anyhow!("{}: {e}", smoothed.display()))?;
            group_by_source(&original_runs, &pieces)
        } else {
            runs_of(parse_program_with(smoothed, &bytes, &opts)?)
        };
        if readings.len() > 1 {
            println!(
                "  block delete {}:",
                if block_delete {
                    "on (/ lines skipped)"
                } else {
                    "off (/ lines run)"
                }
            );
        }
        let slack = if block_delete {
            SWITCH_ON_ENDPOINT_MM
        } else {
            0.0
        };
        let verdict = match compare_runs_within(&original_runs, &candidate, tolerance, slack) {
            Ok(v) => v,
            // Runs that do not pair: this reading fails.
            Err(e) => {
                println!("  runs:            {e}");
                if readings.len() > 1 {
                    println!("  verdict:         FAIL");
                }
                pass = false;
                continue;
            }
        };
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
            println!("  joints:          {}", crate::summary::joints_text(counts));
        }
        if readings.len() > 1 {
            println!(
                "  verdict:         {}",
                if verdict.within { "PASS" } else { "FAIL" }
            );
        }
        pass &= verdict.within;
    }
    println!("  verdict:         {}", if pass { "PASS" } else { "FAIL" });
    Ok(if pass {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(3)
    })
}
