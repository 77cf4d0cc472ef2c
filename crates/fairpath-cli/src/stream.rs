//! `fairpath stream`: the planned motion of a program, one position per
//! servo period, as LinuxCNC's `halstreamer` reads it (one line per period,
//! X Y Z in mm separated by spaces). With `--tolerance` the program is
//! smoothed first (the default method); a fairpath JSON path is streamed as
//! it is. The stream is built and checked by `fairpath::feed::stream`.
//!
//! What a stream leaves out is said on the report: the rapids before the
//! first feed move and after the last (the stream starts where the first
//! feed move starts: the machine must be brought there first; the rig's
//! timing window is the same) unless `--lead-rapids`, and every non-motion
//! line inside it (spindle, coolant, tool, pauses), which a stream of
//! positions cannot carry. Dwells are held in the stream for their time.

use crate::simulate_command;
use crate::Controller;
use anyhow::{anyhow, bail, Context, Result};
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::PlanOptions;
use fairpath::feed::program::Motion;
use fairpath::feed::stream::StreamedKind;
use fairpath::feed::stream::{self as fstream, StreamOptions};
use fairpath::path::Run;
use fairpath::pipeline::PipelineError;
use std::fmt::Write as _;
use std::path::Path;

/// What the user asked for.
pub struct StreamArgs<'a> {
    pub program: &'a Path,
    pub output: &'a Path,
    /// Smooth first within this distance (a bare number in the
    /// program's units).
    pub tolerance: Option<crate::length::Length>,
    pub machine: MachineLimits,
    pub axis_jerk: [f64; 3],
    pub override_feed: bool,
    /// Keep the rapids before the first and after the last feed move.
    pub lead_rapids: bool,
}

/// One step of the program as the stream sees it.
enum Step {
    Motion(Motion),
    Dwell { seconds: f64, line: usize },
}

/// A non-motion line inside the stream: what it does and where.
struct LeftOut {
    /// Position among the executed lines (the numbering of moves).
    at: usize,
    /// Line of the source file.
    line: usize,
    text: String,
}

/// Lines that do something a position stream cannot: M, S and T words
/// (spindle, coolant, tool change, pauses, program end); dwells are
/// streamed and listed as well.
fn non_motion(line: &fairpath_gcode::ProgramLine) -> bool {
    line.interpreted
        && line
            .words
            .iter()
            .any(|w| matches!(w.letter, 'M' | 'S' | 'T') || (w.letter == 'G' && w.value == 4.0))
}

fn first_line(m: &Motion) -> usize {
    match m {
        Motion::Feed(r) => r.pieces.first().map_or(0, |p| p.source_lines.0),
        Motion::Rapid(p) => p.source_lines.0,
    }
}

/// The steps of a G-code program: its motions (smoothed runs when given)
/// with the dwells between them, and the non-motion lines.
fn gcode_steps(program: &fairpath_gcode::Program, runs: &[Run]) -> (Vec<Step>, Vec<LeftOut>) {
    let motions = program.motions(runs);
    let mut dwells = Vec::new();
    let mut left = Vec::new();
    for l in program.lines() {
        if !non_motion(l) {
            continue;
        }
        let is_dwell = l.words.iter().any(|w| w.letter == 'G' && w.value == 4.0);
        if is_dwell {
            let p = l
                .words
                .iter()
                .find(|w| w.letter == 'P')
                .map_or(0.0, |w| w.value);
            dwells.push((l.number, p));
        }
        left.push(LeftOut {
            at: l.number,
            line: l.source_line,
            text: l.text.trim().to_string(),
        });
    }
    let mut steps = Vec::with_capacity(motions.len() + dwells.len());
    let mut d = dwells.into_iter().peekable();
    for m in motions {
        let at = first_line(&m);
        while let Some(&(line, seconds)) = d.peek() {
            if line > at {
                break;
            }
            steps.push(Step::Dwell { seconds, line });
            d.next();
        }
        steps.push(Step::Motion(m));
    }
    for (line, seconds) in d {
        steps.push(Step::Dwell { seconds, line });
    }
    (steps, left)
}

/// `fairpath stream`.
pub fn run(a: &StreamArgs) -> Result<()> {
    crate::output::refuse_overwrite(a.program, a.output, "-o", None)?;
    let bytes = crate::read::read_bytes(a.program)?;
    let is_json = bytes.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'{');
    let mut report = String::new();
    // Moves a stream of X Y Z positions cannot carry: (executed line, source
    // line, what).
    let mut cannot: Vec<(usize, usize, &'static str)> = Vec::new();
    let (steps, left) = if is_json {
        if a.tolerance.is_some() {
            return Err(crate::usage::usage("--tolerance smooths a G-code program; a fairpath JSON path is streamed as it is (leave --tolerance out)"));
        }
        let motions = simulate_command::motions_of(a.program, &bytes)?;
        let _ = writeln!(
            report,
            "  path:            {} streamed as it is",
            a.program.display()
        );
        (motions.into_iter().map(Step::Motion).collect(), Vec::new())
    } else {
        let program = crate::read::parse_program(a.program, &bytes)?;
        for m in program.moves() {
            use fairpath_gcode::PinReason;
            let what = match m.pinned {
                Some(PinReason::SpecialMotion) => {
                    "spindle-synchronized motion, probing or a move in machine coordinates (G33, G33.1, G38.x, G53)"
                }
                Some(PinReason::ExtraAxes) => {
                    "a move of axes other than X Y Z (the stream holds X Y Z only)"
                }
                Some(PinReason::UnknownStart) => {
                    "a move from a position fairpath does not know (after G28/G30, offset or tool-length changes)"
                }
                _ => continue,
            };
            let source = program
                .lines()
                .get(m.line.saturating_sub(1))
                .map_or(m.line, |l| l.source_line);
            cannot.push((m.line, source, what));
        }
        let runs = match a.tolerance.map(|t| t.mm(program.units())) {
            Some(tol) => {
                // The servo interpolates between samples along chords; the
                // planner holds them within the machine's chord error, so
                // that share of the tolerance (at most the budget's
                // largest output share) goes to them and the rest to the
                // smoothing.
                let chord = a
                    .machine
                    .chord_error
                    .min(fairpath::budget::MAX_OUTPUT_SHARE * tol);
                // The stream runs the exact curves (no G-code is written):
                // `auto` ranks its candidates by their time, as for JSON.
                let mut opts = crate::smooth::options(
                    tol,
                    Some(chord),
                    "auto",
                    Some(fairpath_gcode::Format::Json),
                    Controller::Generic,
                )?;
                opts.set_machine(a.machine, a.override_feed)
                    .map_err(crate::smooth::option_error)?;
                let mut phases = fairpath_gcode::pipeline::Phases::new();
                let result =
                    fairpath_gcode::pipeline::smooth_curves(&program, &opts, &mut phases).map_err(|e| match e {
                        PipelineError::NotVerified {
                            line,
                            deviation,
                            share,
                            ..
                        } => anyhow!(
                            "refusing to stream: the smoothed curves of the run starting at line {line} leave their share of the tolerance ({deviation:.6} mm > {share} mm)"
                        ),
                        e => e.into(),
                    })?;
                let worst = result
                    .runs
                    .iter()
                    .map(|r| r.report.deviation_bound)
                    .fold(0.0f64, f64::max);
                // Each run streamed as smoothed and as written; the faster
                // is kept (both are within the tolerance: a run of long
                // moves with sharp corners can be faster stopped at each
                // corner than on tight transitions).
                let so = stream_options(a);
                let time_of = |pieces: &[fairpath::Piece]| -> Result<f64> {
                    fstream::stream(&[fstream::Motion::Run(pieces)], &so)
                        .map(|s| s.time)
                        .map_err(|e| anyhow!("{}: {e}", a.program.display()))
                };
                let keep_own: Vec<bool> = fairpath::pipeline::par_map(result.runs.len(), |k| {
                    let r = &result.runs[k];
                    Ok::<bool, anyhow::Error>(
                        time_of(&r.original.pieces)? < time_of(&r.smoothed.pieces)?,
                    )
                })
                .into_iter()
                .collect::<Result<_>>()?;
                let own = keep_own.iter().filter(|&&k| k).count();
                let _ = writeln!(
                    report,
                    "  smoothed:        {} runs by {}, deviation at most {:.4} mm (tolerance {} mm, {} mm of it for the servo's chords); {own} run(s) streamed as written (faster than their smoothing)",
                    result.runs.len(),
                    opts.method_name(),
                    worst,
                    tol,
                    chord
                );
                result
                    .runs
                    .into_iter()
                    .zip(keep_own)
                    .map(|(r, own)| {
                        if own {
                            r.original
                        } else {
                            Run::new(r.smoothed.pieces)
                        }
                    })
                    .collect()
            }
            None => {
                let _ = writeln!(
                    report,
                    "  path:            the program's own moves (no --tolerance: not smoothed)"
                );
                program.runs()
            }
        };
        gcode_steps(&program, &runs)
    };
    // The stream's window: from the first feed move to the last, unless the
    // lead rapids are asked for.
    let is_feed = |s: &Step| matches!(s, Step::Motion(Motion::Feed(_)));
    let (first, last) = match (
        steps.iter().position(is_feed),
        steps.iter().rposition(is_feed),
    ) {
        (Some(f), Some(l)) if !a.lead_rapids => (f, l),
        (Some(_), Some(_)) => (0, steps.len() - 1),
        _ => bail!(
            "{}: the program has no feed moves: nothing to stream",
            a.program.display()
        ),
    };
    let (lo_line, hi_line) = window_lines(&steps[first..=last]);
    if let Some((_, source, what)) = cannot.iter().find(|c| c.0 >= lo_line && c.0 <= hi_line) {
        bail!(
            "{}:{source}: cannot be streamed: {what}",
            a.program.display()
        );
    }
    let lead_in = steps[..first]
        .iter()
        .filter(|s| matches!(s, Step::Motion(_)))
        .count();
    let lead_out = steps[last + 1..]
        .iter()
        .filter(|s| matches!(s, Step::Motion(_)))
        .count();
    let window = &steps[first..=last];
    let motions: Vec<fstream::Motion> = window
        .iter()
        .map(|s| match s {
            Step::Motion(Motion::Feed(r)) => fstream::Motion::Run(&r.pieces),
            Step::Motion(Motion::Rapid(p)) => fstream::Motion::Rapid(p),
            Step::Dwell { seconds, .. } => fstream::Motion::Dwell(*seconds),
        })
        .collect();
    let opts = stream_options(a);
    let started = std::time::Instant::now();
    let st = fstream::stream(&motions, &opts).map_err(|e| {
        // Name the motion by its program line.
        let line_of = |i: usize| window.get(i).and_then(step_line).unwrap_or(0);
        match e {
            fstream::StreamError::Gap { index, gap } => anyhow!(
                "{}:{}: this move starts {gap:.4} mm from where the move of line {} ends: a move \
                 between them is one fairpath does not stream (spindle-synchronized motion, \
                 probing, a move to machine coordinates), and a stream cannot jump",
                a.program.display(),
                line_of(index),
                line_of(index.saturating_sub(1))
            ),
            fstream::StreamError::Plan { index, .. }
            | fstream::StreamError::NotWithinLimits { index, .. } => {
                anyhow!("{}:{}: {e}", a.program.display(), line_of(index))
            }
            e => anyhow!("{}: {e}", a.program.display()),
        }
    })?;
    let took = started.elapsed().as_secs_f64();
    let mut text = String::with_capacity(st.positions.len() * 42);
    for p in &st.positions {
        let _ = writeln!(text, "{:.9} {:.9} {:.9}", p.x, p.y, p.z);
    }
    crate::output::write_atomically(a.output, text.as_bytes())?;
    print!("{}", summary(a, &st, &report, took));
    let list = |which: &[&LeftOut]| -> String {
        let mut shown: Vec<String> = which
            .iter()
            .take(8)
            .map(|l| format!("line {}: {}", l.line, l.text))
            .collect();
        if which.len() > 8 {
            shown.push(format!("... ({} more)", which.len() - 8));
        }
        shown.join("; ")
    };
    let before: Vec<&LeftOut> = left.iter().filter(|l| l.at < lo_line).collect();
    let inside: Vec<&LeftOut> = left
        .iter()
        .filter(|l| l.at >= lo_line && l.at <= hi_line)
        .collect();
    let after: Vec<&LeftOut> = left.iter().filter(|l| l.at > hi_line).collect();
    if !before.is_empty() {
        println!(
            "  not in the stream: {} non-motion lines before it (do them before starting the stream): {}",
            before.len(),
            list(&before)
        );
    }
    if !inside.is_empty() {
        println!(
            "  not in the stream: {} non-motion lines inside it (spindle, coolant, tool, pauses; dwells are held for their time): {}",
            inside.len(),
            list(&inside)
        );
    }
    if !after.is_empty() {
        println!(
            "  not in the stream: {} non-motion lines after it: {}",
            after.len(),
            list(&after)
        );
    }
    if let Some(p) = st.positions.first() {
        if lead_in > 0 {
            println!(
                "  not in the stream: {lead_in} move(s) before the first feed move; the stream starts at X{:.4} Y{:.4} Z{:.4}: bring the machine there first (--lead-rapids streams them)",
                p.x, p.y, p.z
            );
        }
    }
    if lead_out > 0 {
        println!("  not in the stream: {lead_out} move(s) after the last feed move (--lead-rapids streams them)");
    }
    if st.excess > 0 {
        eprintln!(
            "warning: {} samples of the stream exceed a limit (see the peaks above)",
            st.excess
        );
    }
    Ok(())
}

fn stream_options(a: &StreamArgs) -> StreamOptions {
    StreamOptions {
        axis_jerk: a.axis_jerk,
        ..StreamOptions::new(PlanOptions {
            limits: a.machine,
            override_feed: a.override_feed,
            window: None,
            ends: Default::default(),
        })
    }
}

/// First and last (executed) line of the steps.
fn window_lines(window: &[Step]) -> (usize, usize) {
    let last = |s: &Step| match s {
        Step::Motion(m) => Some(last_line(m)),
        Step::Dwell { line, .. } => Some(*line),
    };
    (
        window.iter().find_map(step_line).unwrap_or(0),
        window.iter().rev().find_map(last).unwrap_or(usize::MAX),
    )
}

fn last_line(m: &Motion) -> usize {
    match m {
        Motion::Feed(r) => r.pieces.last().map_or(0, |p| p.source_lines.1),
        Motion::Rapid(p) => p.source_lines.1,
    }
}

fn step_line(s: &Step) -> Option<usize> {
    match s {
        Step::Motion(m) => Some(first_line(m)),
        Step::Dwell { line, .. } => Some(*line),
    }
}

fn summary(a: &StreamArgs, st: &fstream::Stream, report: &str, took: f64) -> String {
    let m = &a.machine;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "fairpath stream: {} -> {}",
        a.program.display(),
        a.output.display()
    );
    let _ = writeln!(
        s,
        "  machine:         max feed {} mm/min, acc {} mm/s^2, jerk {} mm/s^3 (axes X Y Z: {} / {} / {} mm/s^3), period {} s{}",
        m.max_feed * 60.0,
        m.acc,
        m.jerk,
        a.axis_jerk[0],
        a.axis_jerk[1],
        a.axis_jerk[2],
        m.period,
        if a.override_feed { ", feeds overridden" } else { "" }
    );
    s.push_str(report);
    let time_of = |k: StreamedKind| -> f64 {
        st.motions
            .iter()
            .filter(|x| x.kind == k)
            .map(|x| x.duration)
            .fold(0.0, |a, b| a + b)
    };
    let _ = writeln!(
        s,
        "  planned time: {:.4} s (feed {:.4} s, rapid {:.4} s, dwell {:.4} s); {} lines, one per period of {} s",
        st.time,
        time_of(StreamedKind::Feed),
        time_of(StreamedKind::Rapid),
        time_of(StreamedKind::Dwell),
        st.positions.len(),
        m.period
    );
    let p = &st.peaks;
    let _ = writeln!(
        s,
        "  as sampled:      speed {:.1} mm/s (limit {:.1}), acceleration {:.0} mm/s^2 (limit {}), jerk over 5 periods {:.0} mm/s^3 (limit {}), one period {:.0}",
        p.vel, m.max_feed, p.acc, m.acc, p.jerk_avg, m.jerk, p.jerk
    );
    let _ = writeln!(
        s,
        "  per axis X/Y/Z:  speed {:.1}/{:.1}/{:.1} mm/s, acceleration {:.0}/{:.0}/{:.0} mm/s^2, jerk over 5 periods {:.0}/{:.0}/{:.0} mm/s^3",
        p.axis_vel[0], p.axis_vel[1], p.axis_vel[2],
        p.axis_acc[0], p.axis_acc[1], p.axis_acc[2],
        p.axis_jerk_avg[0], p.axis_jerk_avg[1], p.axis_jerk_avg[2]
    );
    let replanned = st.motions.iter().filter(|x| x.plans > 1).count();
    let most = st.motions.iter().map(|x| x.plans).max().unwrap_or(0);
    let _ = writeln!(
        s,
        "  replanned:       {replanned} of {} motions slowed where the samples exceeded a limit (at most {most} plans of one); {:.3} s to stream",
        st.motions.len(),
        took
    );
    s
}

/// Per-axis jerk limits: the machine file's `axis_jerk`, else the path's.
pub fn axis_jerk(file: Option<&Path>, m: &MachineLimits) -> Result<[f64; 3]> {
    let Some(f) = file else {
        return Ok([m.jerk; 3]);
    };
    let text =
        std::fs::read_to_string(f).with_context(|| format!("cannot read {}", f.display()))?;
    let mf: crate::machine::MachineFile =
        toml::from_str(&text).map_err(|e| anyhow!("{}: {e}", f.display()))?;
    let j = mf.axis_jerk.unwrap_or([m.jerk; 3]);
    for (i, v) in j.iter().enumerate() {
        if !(v.is_finite() && *v > 0.0) {
            bail!(
                "{}: axis_jerk[{i}] must be a positive number, got {v}",
                f.display()
            );
        }
    }
    Ok(j)
}
