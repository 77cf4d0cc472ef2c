//! `fairpath check ORIGINAL SMOOTHED --tolerance T [--format json]`: the
//! verdict and the worst place (the point of the smoothed path farthest
//! from the original found by the verifier, the line of the original
//! nearest to it, its coordinates and the distance).
//!
//! When the original has block-delete (`/`) lines, both programs are read
//! twice, with the switch off (the `/` lines run) and on (they are
//! skipped, as LinuxCNC does with block delete on), and compared run by
//! run in each reading: the smoothed program must follow the original
//! either way the operator sets the switch.

use crate::length::{unit_name, Length};
use crate::read::{is_stdio, name, parse_program_with, read_bytes, read_motion_of};
use crate::usage::{usage, EXIT_NOT_VERIFIED};
use anyhow::{anyhow, Result};
use fairpath::geom::{distance_to_polyline, flatten_params, ParamCurve, Vec3};
use fairpath::path::{Piece, Run};
use fairpath::verify::{verify_run, VerifyOptions};
use fairpath_gcode::pipeline::{compare_runs_reported, group_by_source};
use fairpath_gcode::{ParseOptions, Program, Units};
use serde_json::json;
use std::path::Path;
use std::process::ExitCode;

/// Share of the tolerance the pieces are flattened to when the original
/// piece nearest the worst place is looked for: it picks the line, the
/// distance printed is the verifier's.
const LOCATE_CHORD_SHARE: f64 = 0.01;

/// Where the smoothed program is farthest from the original.
#[derive(Clone, Debug, PartialEq)]
pub struct WorstPlace {
    /// Distance found there (mm): the verifier's largest; its bound is
    /// the verdict's `max deviation`.
    pub deviation: f64,
    /// The point of the smoothed path (mm).
    pub at: Vec3,
    /// The line of the original (in the file) nearest to it, and its text.
    pub original_line: Option<(usize, String)>,
    /// The block-delete reading it was found in (`true`: switch on).
    pub block_delete: bool,
}

/// The line (of `program`'s source file) of the piece of `pieces` nearest
/// to `q`, with its text.
fn nearest_line(
    program: &Program,
    pieces: &[Piece],
    q: Vec3,
    chord: f64,
) -> Option<(usize, String)> {
    let mut best: Option<(f64, usize)> = None;
    for p in pieces {
        let pts: Vec<Vec3> = flatten_params(&p.curve, chord)
            .into_iter()
            .map(|t| p.curve.eval(t))
            .collect();
        let d = if pts.len() < 2 {
            (p.start() - q).norm()
        } else {
            distance_to_polyline(q, &pts).map_or(f64::INFINITY, |(d, _)| d)
        };
        if best.is_none_or(|(b, _)| d < b) {
            best = Some((d, p.source_lines.0));
        }
    }
    let (_, line) = best?;
    let l = program.lines().get(line.checked_sub(1)?)?;
    Some((l.source_line, l.text.clone()))
}

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

/// `fairpath check`: prints the verdict (text or, with `json`, one
/// object) and returns exit status 0 or [`EXIT_NOT_VERIFIED`].
pub fn run(original: &Path, smoothed: &Path, tolerance: Length, json: bool) -> Result<ExitCode> {
    if is_stdio(original) && is_stdio(smoothed) {
        return Err(usage(
            "the original and the smoothed program cannot both be standard input (-)",
        ));
    }
    let original_bytes = read_bytes(original)?;
    let bytes = read_bytes(smoothed)?;
    let is_json = bytes.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'{');
    let off = ParseOptions::default();
    let orig = parse_program_with(original, &original_bytes, &off)?;
    let units = orig.units();
    let block_delete_lines = has_block_delete(&orig);
    // The reading with the switch off is this one: not read again (a long
    // program held twice, and the candidate beside them, was the peak).
    let mut orig = Some(orig);
    let tolerance_mm = tolerance.mm(units);
    fairpath::smooth::check_tolerance(tolerance_mm)
        .map_err(|e| usage(format!("--tolerance {tolerance}: {e}")))?;
    let tolerance = tolerance_mm;
    // JSON holds the curves of one reading (the switch off).
    let readings: &[bool] = if block_delete_lines && !is_json {
        &[false, true]
    } else {
        &[false]
    };
    let mut out = String::new();
    let mut say = |line: String| {
        if !json {
            out.push_str(&line);
            out.push('\n');
        }
    };
    let in_units = |mm: f64| mm / units.mm_per_unit();
    say(format!(
        "fairpath check: {} against {} (tolerance {} mm{})",
        name(smoothed),
        name(original),
        tolerance,
        if units == Units::Mm {
            String::new()
        } else {
            format!(" = {} {}", in_units(tolerance), unit_name(units))
        }
    ));
    let mut pass = true;
    let mut worst: Option<WorstPlace> = None;
    let mut max_deviation = 0.0f64;
    let mut runs_checked = 0;
    let mut endpoints_moved = 0;
    let mut problems: Vec<String> = Vec::new();
    let mut joints_total: Option<[usize; 4]> = None;
    for &block_delete in readings {
        let opts = ParseOptions {
            block_delete,
            ..Default::default()
        };
        // With the switch on, stretches of path that the written program
        // ends differently (a motion word restored on a line of its own)
        // are compared whole.
        let runs_of = |p: &Program| {
            if block_delete {
                joined_runs(p)
            } else {
                p.runs()
            }
        };
        let original_program = match orig.take().filter(|_| !block_delete) {
            Some(p) => p,
            None => parse_program_with(original, &original_bytes, &opts)?,
        };
        let original_runs = runs_of(&original_program);
        let candidate: Vec<Run> = if is_json {
            let text = std::str::from_utf8(&bytes)
                .map_err(|_| anyhow!("{}: not UTF-8", name(smoothed)))?;
            let pieces =
                fairpath_gcode::read_json(text).map_err(|e| anyhow!("{}: {e}", name(smoothed)))?;
            group_by_source(&original_runs, &pieces)
        } else {
            // Its motion only (no lines held) where the switch is off.
            if block_delete {
                runs_of(&parse_program_with(smoothed, &bytes, &opts)?)
            } else {
                read_motion_of(smoothed, &bytes)?.1
            }
        };
        if readings.len() > 1 {
            say(format!(
                "  block delete {}:",
                if block_delete {
                    "on (/ lines skipped)"
                } else {
                    "off (/ lines run)"
                }
            ));
        }
        let slack = if block_delete {
            SWITCH_ON_ENDPOINT_MM
        } else {
            0.0
        };
        let (verdict, pairs) =
            match compare_runs_reported(&original_runs, &candidate, tolerance, slack) {
                Ok(v) => v,
                // Runs that do not pair: this reading fails.
                Err(e) => {
                    say(format!("  runs:            {e}"));
                    if readings.len() > 1 {
                        say("  verdict:         FAIL".to_string());
                    }
                    problems.push(e.to_string());
                    pass = false;
                    continue;
                }
            };
        say(format!("  runs checked:    {}", verdict.runs_checked));
        say(format!(
            "  max deviation:   {:.6} mm (bound)",
            verdict.max_deviation
        ));
        say(format!(
            "  endpoints moved: {} runs",
            verdict.endpoint_failures
        ));
        runs_checked += verdict.runs_checked;
        endpoints_moved += verdict.endpoint_failures;
        max_deviation = max_deviation.max(verdict.max_deviation);
        // The worst place of this reading: the pair with the largest
        // distance found, and the original's line nearest to it.
        if let Some(p) = pairs
            .iter()
            .max_by(|a, b| a.report.max_deviation.total_cmp(&b.report.max_deviation))
        {
            let chord = tolerance * LOCATE_CHORD_SHARE;
            let place = WorstPlace {
                deviation: p.report.max_deviation,
                at: p.report.worst_at,
                original_line: nearest_line(
                    &original_program,
                    &original_runs[p.original].pieces,
                    p.report.worst_at,
                    chord,
                ),
                block_delete,
            };
            say(worst_text(&place, original, units));
            if worst.as_ref().is_none_or(|w| place.deviation > w.deviation) {
                worst = Some(place);
            }
        }
        if is_json {
            // Joint classes are meaningful for exact curves only.
            let mut counts = [0usize; 4];
            for (a, b) in original_runs.iter().zip(&candidate) {
                let rep = verify_run(&a.pieces, &b.pieces, &VerifyOptions::new(tolerance));
                for (i, c) in rep.joint_counts().iter().enumerate() {
                    counts[i] += c;
                }
            }
            say(format!(
                "  joints:          {}",
                crate::summary::joints_text(counts)
            ));
            let total = joints_total.get_or_insert([0; 4]);
            for (t, c) in total.iter_mut().zip(counts) {
                *t += c;
            }
        }
        if readings.len() > 1 {
            say(format!(
                "  verdict:         {}",
                if verdict.within { "PASS" } else { "FAIL" }
            ));
        }
        pass &= verdict.within;
    }
    say(format!(
        "  verdict:         {}",
        if pass { "PASS" } else { "FAIL" }
    ));
    if json {
        let worst = worst.map(|w| {
            json!({
                "deviation_mm": w.deviation,
                "at_mm": [w.at.x, w.at.y, w.at.z],
                "at_program_units": [in_units(w.at.x), in_units(w.at.y), in_units(w.at.z)],
                "original_line": w.original_line.as_ref().map(|l| l.0),
                "original_text": w.original_line.as_ref().map(|l| l.1.clone()),
                "block_delete": w.block_delete,
            })
        });
        let v = json!({
            "original": name(original),
            "smoothed": name(smoothed),
            "tolerance_mm": tolerance,
            "program_units": unit_name(units),
            "tolerance_program_units": in_units(tolerance),
            "pass": pass,
            "runs_checked": runs_checked,
            "max_deviation_mm": max_deviation,
            "endpoints_moved": endpoints_moved,
            "worst": worst,
            "joints": joints_total.map(|[gap, c0, c1, c2]| json!({"C2": c2, "C1": c1, "C0": c0, "gap": gap})),
            "problems": problems,
        });
        println!("{v}");
    } else {
        print!("{out}");
    }
    Ok(if pass {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(EXIT_NOT_VERIFIED)
    })
}

/// The worst place as `check` prints it: the original's line and text,
/// the point in mm (and in the program's units where they differ), the
/// distance.
fn worst_text(w: &WorstPlace, original: &Path, units: Units) -> String {
    let coords = |k: f64| format!("X{:.4} Y{:.4} Z{:.4}", w.at.x / k, w.at.y / k, w.at.z / k);
    let at = if units == Units::Mm {
        format!("{} mm", coords(1.0))
    } else {
        format!(
            "{} mm ({} {})",
            coords(1.0),
            coords(units.mm_per_unit()),
            unit_name(units)
        )
    };
    if w.deviation == 0.0 {
        return "  worst place:     none: the smoothed path lies on the original".to_string();
    }
    let line = match &w.original_line {
        Some((n, text)) => format!("line {n} of {}: {}", name(original), text.trim()),
        None => format!("in {}", name(original)),
    };
    format!(
        "  worst place:     {:.6} mm from the original, near {line}\n                   at {at}",
        w.deviation
    )
}
