//! The written program's time comes from the reading the writer's check
//! made and the run times it already planned (`pipeline::plan_written`);
//! it must be what planning the written text afresh gives, to the last bit,
//! at the programmed feeds and with the feeds overridden, and the input's
//! and curves' times what `simulate` gives.

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
/// reads the same moves and runs as `parse`, and keeps no text.
#[test]
fn parse_motion_reads_the_same_motion_as_parse() {
    let shared = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/paths");
    let mut texts: Vec<String> = PROGRAMS.iter().map(|t| t.to_string()).collect();
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
