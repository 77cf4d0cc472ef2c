//! What a smoothed program is written as ([`Format`]) and for whom
//! ([`Controller`]): the format's and the controller's names on the command
//! line, the controller's default format and method.
//!
//! With the `clap` feature both derive `clap::ValueEnum`, so that a command
//! line takes them by the names below (and shows the variants' documentation
//! as help) without a second list of names to keep in step.

/// Output format of `fairpath smooth`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Format {
    /// G1 moves only, spaced for the controller (in the program's units).
    #[cfg_attr(feature = "clap", value(name = "g1", alias = "gcode"))]
    G1,
    /// G2/G3 arcs (helical where a curve leaves its plane) and G1 lines.
    Arcs,
    /// LinuxCNC G5.2/G5.3 NURBS blocks for curves in the XY plane, arcs for
    /// the rest.
    #[cfg_attr(feature = "clap", value(name = "g5.2"))]
    G5_2,
    /// G6.2 NURBS blocks (Fanuc style: P order, K knots, R weights), 3D;
    /// arcs and lines as they are.
    #[cfg_attr(feature = "clap", value(name = "g6.2"))]
    G6_2,
    /// The exact curves (lines, arcs, NURBS) as JSON, always in mm.
    Json,
}

impl Format {
    /// The default share of the tolerance for writing the curves
    /// (`--chord`): [`fairpath::budget::EXACT_OUTPUT_SHARE`] for G6.2,
    /// which writes the smoothed B-splines exactly,
    /// [`fairpath::budget::OUTPUT_SHARE`] for the formats that approximate
    /// them (G1 chords, arcs, and G5.2, which LinuxCNC runs as arcs), and
    /// for JSON: exact too, but it holds the curves the G-code formats are
    /// written from (`fairpath compare` smooths once as JSON and writes
    /// each format from those curves, and a JSON output is what a G1 or
    /// arcs output of the same options approximates).
    pub fn default_output_share(self) -> f64 {
        match self {
            Format::G6_2 => fairpath::budget::EXACT_OUTPUT_SHARE,
            Format::G1 | Format::Arcs | Format::G5_2 | Format::Json => {
                fairpath::budget::OUTPUT_SHARE
            }
        }
    }

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Format::G1 => "g1",
            Format::Arcs => "arcs",
            Format::G5_2 => "g5.2",
            Format::G6_2 => "g6.2",
            Format::Json => "json",
        }
    }
}

/// The controller the written program is for: its default format and the
/// details of its dialect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Controller {
    /// Any RS274 control: G1, G2/G3 (IJK or R as the input), no blending
    /// mode written unless the program's own G64 blends beyond the
    /// blending share (see `emit::EmitOptions::budget_for`).
    Generic,
    /// LinuxCNC: `G64 P<blend> Q0` around every smoothed run (P alone
    /// would let it merge blocks; its blending is taken from the
    /// tolerance), blocks no shorter than 1.02 servo periods of travel.
    Linuxcnc,
    /// Fanuc-family controls: a decimal point in every number (without one
    /// `X5` reads as 5 um on controls without decimal-point input).
    Fanuc,
}

impl Controller {
    /// The format written when none is asked for: the one that plans
    /// fastest on the reference programs within the targets (README,
    /// "Output formats").
    pub fn default_format(self) -> Format {
        match self {
            Controller::Generic | Controller::Linuxcnc => Format::Arcs,
            Controller::Fanuc => Format::G6_2,
        }
    }

    /// The format written when none is asked for, for a program that
    /// holds NURBS (G6.2) feed moves when `nurbs`: G6.2, its own dialect,
    /// on a generic controller (a controller that runs the program runs
    /// G6.2; each run is still written in the form that plans fastest,
    /// NURBS, arcs or lines, see `emit::forms`), the controller's
    /// otherwise (LinuxCNC 2.9 has no G6.2; Fanuc's default is G6.2
    /// already). Arcs step in curvature where the exact spline does not,
    /// so a faired spline written as arcs plans faster than its input far
    /// less often than written as G6.2 (`docs/fair-outputs.md`).
    pub fn default_format_for(self, nurbs: bool) -> Format {
        match self {
            Controller::Generic if nurbs => Format::G6_2,
            _ => self.default_format(),
        }
    }

    /// The method used when none is asked for. LinuxCNC's planners cap
    /// the speed per block (the S-curve planner at every block end at the
    /// block's rest-to-rest peak speed; the trapezoid planner at a block
    /// length per 1.02 servo periods), so for LinuxCNC the fewest blocks
    /// within the tolerance run fastest: `arc-fit` (on LinuxCNC master it
    /// planned butterfly-80 faster than `auto`'s arcs and the raw program;
    /// measurements: docs/tuning.md, `Controller::default_method`, and
    /// docs/linuxcnc.md).
    /// Elsewhere `auto`, the curvature-continuous path.
    pub fn default_method(self) -> &'static str {
        match self {
            Controller::Linuxcnc => "arc-fit",
            Controller::Generic | Controller::Fanuc => "auto",
        }
    }

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Controller::Generic => "generic",
            Controller::Linuxcnc => "linuxcnc",
            Controller::Fanuc => "fanuc",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SmoothOptions;

    /// G6.2, which writes the smoothed B-splines exactly, takes a fiftieth
    /// of the tolerance for writing by default and leaves the rest to the
    /// smoothing; the formats that approximate them, and JSON (the curves
    /// `compare` writes every format from), a tenth; `--chord` overrides
    /// both.
    #[test]
    fn only_g6_2_writes_within_a_fiftieth_of_the_tolerance() {
        let tol = 0.05;
        for (format, share) in [
            (Format::G6_2, fairpath::budget::EXACT_OUTPUT_SHARE),
            (Format::G5_2, fairpath::budget::OUTPUT_SHARE),
            (Format::Arcs, fairpath::budget::OUTPUT_SHARE),
            (Format::G1, fairpath::budget::OUTPUT_SHARE),
            (Format::Json, fairpath::budget::OUTPUT_SHARE),
        ] {
            let b = SmoothOptions::new(tol, None, "fair", Some(format), Controller::Generic)
                .unwrap()
                .budget();
            assert!(
                (b.output + b.blend - share * tol).abs() < 1e-15,
                "{format:?}"
            );
            assert!((b.smoothing() - (1.0 - share) * tol).abs() < 1e-15);
            let asked =
                SmoothOptions::new(tol, Some(0.004), "fair", Some(format), Controller::Generic)
                    .unwrap()
                    .budget();
            assert!(
                (asked.output + asked.blend - 0.004).abs() < 1e-15,
                "{format:?}"
            );
        }
    }
}
