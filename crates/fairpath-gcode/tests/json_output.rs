//! Every method's curves written as fairpath's JSON verify against the
//! program they came from.

use fairpath_gcode::{smooth_program, Controller, Format, SmoothOptions};

/// Regression (`arc-fit -f json` on `examples/pocket-corners.ngc` was
/// refused: its arcs, written as rational quadratic NURBS, got a deviation
/// bound of 0.081 mm for a distance of 0.005 mm).
#[test]
fn every_method_writes_pocket_corners_as_json() {
    let text = include_str!("../../../examples/pocket-corners.ngc");
    for &method in fairpath::choose::METHODS {
        let opts = SmoothOptions::new(0.05, None, method, Some(Format::Json), Controller::Generic)
            .unwrap();
        let (output, report) =
            smooth_program(text, &opts).unwrap_or_else(|e| panic!("{method}: {e}"));
        assert!(output.text.starts_with('{'), "{method}");
        assert!(
            report.written.max_deviation <= 0.05,
            "{method}: {}",
            report.written.max_deviation
        );
    }
}
