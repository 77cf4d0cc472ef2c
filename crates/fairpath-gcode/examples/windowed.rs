//! A program smoothed part by part, its long runs cut into windows
//! ([`RunWindows`]): how the memory of a one-run program falls with the
//! window (measure with `/usr/bin/time -v`).
//!
//! ```sh
//! cargo run --release -p fairpath-gcode --example windowed -- \
//!     INPUT.ngc OUTPUT.ngc [METHOD [WINDOW_LINES [TOLERANCE]]]
//! ```
//!
//! `WINDOW_LINES` 0 cuts no run (as `fairpath smooth` does today).

use fairpath_gcode::pipeline::Phases;
use fairpath_gcode::{
    smooth_in_parts, Controller, PartSizes, Prepared, RunWindows, SmoothOptions, PART_LINES,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output, rest @ ..] = args.as_slice() else {
        return Err("usage: windowed INPUT OUTPUT [METHOD [WINDOW_LINES [TOLERANCE]]]".into());
    };
    let method = rest.first().map_or("bspline-corner", String::as_str);
    let window: usize = rest.get(1).map_or(Ok(4096), |w| w.parse())?;
    let tolerance: f64 = rest.get(2).map_or(Ok(0.05), |t| t.parse())?;
    let text = std::fs::read(input)?;
    let opts = SmoothOptions::new(tolerance, None, method, None, Controller::Generic)?;
    let prepared = Prepared::read(&text, opts.format())?;
    let sizes = PartSizes {
        lines: PART_LINES,
        windows: (window > 0).then_some(RunWindows {
            lines: window,
            min_cut_mm: 1.0,
        }),
    };
    // Written, then read back from the file for the check.
    let mut out = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(true)
        .open(output)?;
    let start = std::time::Instant::now();
    let (evidence, phases) =
        smooth_in_parts(&text, prepared, &opts, sizes, &mut out, Phases::new())?;
    eprintln!(
        "{method}, windows of {window} lines: {} lines in, {} out, {} parts, {:.2} s",
        evidence.lines_in,
        evidence.lines_out,
        evidence.parts,
        start.elapsed().as_secs_f64()
    );
    let t = evidence.times;
    eprintln!(
        "planned: input {:?} s, curves {:?} s, written {:?} s",
        t.input.total, t.exact.total, t.written.total
    );
    if std::env::var_os("FAIRPATH_TIMING").is_some() {
        eprintln!("{}", phases.report());
    }
    Ok(())
}
