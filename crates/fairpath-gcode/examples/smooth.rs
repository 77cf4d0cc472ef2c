//! A G-code program smoothed within 0.05 mm by `auto`, with the planned
//! time before and after:
//!
//! ```sh
//! cargo run -p fairpath-gcode --example smooth [INPUT.ngc [OUTPUT.ngc]]
//! ```
//!
//! Without arguments it smooths the bundled `examples/pocket-corners.ngc`
//! and prints the written program.

use fairpath_gcode::{smooth_program, Controller, SmoothOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let program = match args.next() {
        Some(path) => std::fs::read_to_string(path)?,
        None => include_str!("../../../examples/pocket-corners.ngc").to_string(),
    };
    let opts = SmoothOptions::new(0.05, None, "auto", None, Controller::Generic)?;
    let (output, report) = smooth_program(&program, &opts)?;
    let (before, after) = (report.times.input.total, report.times.written.total);
    eprintln!("planned time: {before:.3} s before, {after:.3} s after");
    match args.next() {
        Some(path) => std::fs::write(path, &output.text)?,
        None => print!("{}", output.text),
    }
    Ok(())
}
