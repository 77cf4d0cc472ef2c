//! The written program's time comes from the reading the writer's check
//! made and the run times it already planned (`pipeline::plan_written`);
//! it must be what planning the written text afresh gives, to the last bit,
//! at the programmed feeds and with the feeds overridden, and the input's
//! and curves' times what `simulate` gives.

use crate::common;

use fairpath::feed::program::simulate;
use fairpath_gcode::pipeline::plan_text;
use fairpath_gcode::{smooth_program, Controller, Format, SmoothOptions};

const PROGRAMS: [&str; 3] = [
    include_str!("../../../examples/pocket-corners.ngc"),
    include_str!("../../../examples/rhombus.ngc"),
    include_str!("../../../examples/zigzag.ngc"),
];

#[test]
fn written_times_equal_a_fresh_plan_of_the_text() {
    for text in PROGRAMS {
        for method in ["none", "bspline-corner", "bspline-fit", "arc-fit"] {
            for format in [Format::Arcs, Format::G1, Format::G6_2] {
                for override_feed in [false, true] {
                    let mut opts =
                        SmoothOptions::new(0.05, None, method, Some(format), Controller::Generic)
                            .unwrap();
                    let machine = *opts.machine();
                    opts.set_machine(machine, override_feed).unwrap();
                    let (output, report) = smooth_program(text, &opts).unwrap();
                    let fresh = plan_text(&output.text, &opts).unwrap();
                    let what = format!("{method} {format:?} override {override_feed}");
                    assert_eq!(report.times.written, fresh, "{what}");
                    let program = fairpath_gcode::parse(text.as_bytes()).unwrap();
                    let sim = simulate(
                        &program.motions(&program.runs()),
                        &machine,
                        override_feed,
                        None,
                    )
                    .unwrap();
                    assert_eq!(report.times.input.total, sim.time(), "{what}");
                    assert_eq!(report.times.input.feed, sim.feed_time, "{what}");
                }
            }
        }
    }
}

/// `parse_motion` (what the writer's check reads the written text with)
/// reads the same moves and runs as `parse`, and keeps no text; consumed
/// into its outline and runs, it gives what `outline` and `runs` give.
#[test]
fn parse_motion_reads_the_same_motion_as_parse() {
    let shared = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/paths");
    let mut texts: Vec<String> = PROGRAMS.iter().map(|t| t.to_string()).collect();
    // Rapids, a pinned move (M8 on its line) and a run of one move.
    texts.push("G0 X0 Y0\nG1 X1 F100\nG1 X2 Y1 M8\nG1 X3\nG0 Z5\nG1 X4 Y4\nM2\n".into());
    for f in [
        "synthetic/helix.ngc",
        "linuxcnc/quick-tests/square_spiral.ngc",
        "linuxcnc/quick-tests/rick_combine.ngc",
    ] {
        if let Ok(t) = std::fs::read_to_string(shared.join(f)) {
            texts.push(t);
        }
    }
    for text in &texts {
        let full = fairpath_gcode::parse(text.as_bytes()).unwrap();
        let lean = fairpath_gcode::parse_motion(text.as_bytes()).unwrap();
        // What the check keeps of the reading, with the program consumed.
        assert_eq!(
            fairpath_gcode::pipeline::into_outline_and_runs(lean.clone()),
            (fairpath_gcode::pipeline::outline(&full), full.runs())
        );
        assert_eq!(full.runs(), lean.runs());
        assert_eq!(full.run_spans(), lean.run_spans());
        let pieces = |p: &fairpath_gcode::Program| -> Vec<_> {
            p.moves()
                .iter()
                .map(|m| (m.piece.clone(), m.line, m.kind, m.pinned))
                .collect()
        };
        assert_eq!(pieces(&full), pieces(&lean));
        assert_eq!(full.lines().len(), lean.lines().len());
        assert!(lean
            .lines()
            .iter()
            .all(|l| l.text.is_empty() && l.words.is_empty()));
    }
}

/// A run of more curves than `emit`'s long-run threshold (10,000): its
/// only candidate rendering is timed once, as written. The output still
/// verifies, is never slower than the input, and its reported time is a
/// fresh plan of the text (complete run only).
#[test]
#[ignore]
fn a_long_run_is_timed_as_written() {
    // A zigzag of 1 mm steps 0.1 mm high: its corners slow the input.
    let mut text = String::from("G21 G90 G17\nG0 X0 Y0\nG1 Z0 F3000\n");
    for i in 1..=10_500 {
        text.push_str(&format!("G1 X{i} Y{}\n", 0.1 * (i % 2) as f64));
    }
    text.push_str("G0 Z5\nM2\n");
    let opts = common::arcs_options(0.05, "bspline-corner");
    let (output, report) = smooth_program(&text, &opts).unwrap();
    assert!(report.written.within);
    assert_eq!(report.kept_runs, 0, "the run is written smoothed");
    assert!(report.times.written.total < report.times.input.total);
    assert_eq!(
        report.times.written,
        plan_text(&output.text, &opts).unwrap()
    );
}

/// `read_motion` (the writer's check streams the written text with it,
/// keeping no lines) gives what `parse` gives as motions and runs, on every
/// shared program under 1 MB (expanded ones included, through its
/// fallback), on programs with rapids, pinned moves, feed changes and text
/// after the end, and on written outputs in every G-code format; and it
/// refuses what `parse` refuses, at the same line.
#[test]
fn read_motion_streams_what_parse_reads() {
    let shared = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/paths");
    let mut texts: Vec<(String, String)> = PROGRAMS
        .iter()
        .enumerate()
        .map(|(i, t)| (format!("example {i}"), t.to_string()))
        .collect();
    texts.push((
        "rapids, pinned, feeds, after the end".into(),
        "G0 X0 Y0\nG1 X1 F100\nG1 X2 Y1 M8\nG1 X3\nG1 X4 F200\n#1=2\nG1 X5\nG0 Z5\n\
         G1 X4 Y4\nM2\nG1 X9\n"
            .into(),
    ));
    for text in PROGRAMS {
        for format in [Format::Arcs, Format::G1, Format::G5_2, Format::G6_2] {
            let opts =
                SmoothOptions::new(0.05, None, "auto", Some(format), Controller::Generic).unwrap();
            let (output, _) = smooth_program(text, &opts).unwrap();
            texts.push((format!("written {format:?}"), output.text));
        }
    }
    let mut stack = vec![shared];
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for e in entries.flatten() {
            let path = e.path();
            if path.is_dir() {
                stack.push(path);
            } else if e.metadata().is_ok_and(|m| m.len() < 1 << 20) {
                if let Ok(t) = std::fs::read_to_string(&path) {
                    texts.push((path.display().to_string(), t));
                }
            }
        }
    }
    let mut read = 0;
    for (name, text) in &texts {
        match fairpath_gcode::parse(text.as_bytes()) {
            Ok(full) => {
                let streamed = fairpath_gcode::read_motion(text.as_bytes())
                    .unwrap_or_else(|e| panic!("{name}: {e}"));
                assert_eq!(
                    streamed,
                    (fairpath_gcode::pipeline::outline(&full), full.runs()),
                    "{name}"
                );
                read += 1;
            }
            Err(e) => {
                let s = fairpath_gcode::read_motion(text.as_bytes())
                    .expect_err(&format!("{name}: streamed but parse refused: {e}"));
                assert_eq!(s.line, e.line, "{name}: {e} / {s}");
            }
        }
    }
    assert!(read > PROGRAMS.len() * 5, "{read} programs read");
}

/// The input's time of a run longer than a planning window
/// (`PlanWindows::DEFAULT`), which the pipeline plans window by window to
/// hold a window's plan instead of the run's: `simulate`'s whole plan, to
/// the bit, at the programmed feeds and overridden.
#[test]
fn a_run_longer_than_a_window_plans_the_input_time_of_the_whole_run() {
    use fairpath::feed::windowed::PlanWindows;
    let w = PlanWindows::DEFAULT;
    let n = w.step + 4 * w.overlap;
    // A wavy raster of short moves: speeds vary along it, so the windows'
    // plans must agree where they are stitched.
    let mut text = String::from("G21 G90\nG0 X0 Y0 Z1\nG1 Z0 F3000\n");
    for i in 1..=n {
        let x = i as f64 * 0.2;
        let y = (i as f64 * 0.05).sin() * 2.0 + if (i / 500) % 2 == 0 { 0.0 } else { 0.3 };
        text.push_str(&format!("G1 X{x:.4} Y{y:.4}\n"));
    }
    text.push_str("G0 Z5\nM2\n");
    for override_feed in [false, true] {
        let mut opts =
            SmoothOptions::new(0.05, None, "none", Some(Format::G1), Controller::Generic).unwrap();
        let machine = *opts.machine();
        opts.set_machine(machine, override_feed).unwrap();
        let (_, report) = smooth_program(&text, &opts).unwrap();
        let program = fairpath_gcode::parse(text.as_bytes()).unwrap();
        let runs = program.runs();
        assert!(runs.iter().any(|r| w.windows(r.pieces.len())));
        let sim = simulate(&program.motions(&runs), &machine, override_feed, None).unwrap();
        assert_eq!(
            report.times.input.total.to_bits(),
            sim.time().to_bits(),
            "override {override_feed}"
        );
    }
}
