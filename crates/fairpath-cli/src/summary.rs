//! The evidence printed after smoothing.

use fairpath_gcode::{Evidence, SmoothOptions};
use serde_json::json;
use std::fmt::Write;
use std::path::Path;
use std::time::Duration;

/// How the summary names the corners of runs written as the program had
/// them (text and JSON key).
pub const KEPT_RUN_CORNERS: &str = "in runs kept as written";

/// Joints by continuity class (`[gaps, C0, C1, C2]`, as
/// `RunReport::joint_counts`) in words: `C2` curvature continuous, `C1`
/// tangent continuous, `C0` a corner. Not G2/G1/G0, which in a G-code tool
/// read as arc, line and rapid.
pub fn joints_text(joints: [usize; 4]) -> String {
    let [gap, c0, c1, c2] = joints;
    format!("{c2} C2 (curvature continuous), {c1} C1 (tangent continuous), {c0} C0 (corner), {gap} gaps")
}

/// How an output path is named in messages: `<stdout>` for `-`.
pub fn output_name(path: &Path) -> String {
    if crate::read::is_stdio(path) {
        "<stdout>".to_string()
    } else {
        path.display().to_string()
    }
}

/// Figures for one smoothing job: the library's [`Evidence`] and what the
/// command adds (names, the tolerance in the program's units, the time
/// taken, the machine in words).
#[derive(Debug)]
pub struct Summary {
    pub input: String,
    pub output: String,
    pub method: String,
    pub format: &'static str,
    pub controller: &'static str,
    pub tolerance: f64,
    /// The program's units (G20/G21 at its first move): the tolerance is
    /// printed in them too where they are not mm.
    pub units: fairpath_gcode::Units,
    pub elapsed: Duration,
    /// The machine and feeds the times were planned with, in words.
    pub planned_on: String,
    /// The job's figures (runs, curves, deviations, joints, times ...).
    pub e: Evidence,
}

impl Summary {
    pub fn new(input: &Path, output: &Path, opts: &SmoothOptions, e: &Evidence) -> Summary {
        let m = opts.machine();
        let planned_on = format!(
            "V {} mm/s, A {} mm/s^2, J {} mm/s^3, Ts {} ms, junction deviation {} mm, {}{}",
            m.max_feed,
            m.acc,
            m.jerk,
            m.period * 1e3,
            m.junction_deviation,
            if m.block_time > 0.0 {
                format!("block time {} ms, ", m.block_time * 1e3)
            } else {
                String::new()
            },
            if opts.override_feed() {
                "feeds overridden to V"
            } else {
                "programmed feeds"
            }
        );
        Summary {
            input: crate::read::name(input),
            output: output_name(output),
            method: opts.method_name().to_string(),
            format: opts.format().name(),
            controller: opts.controller().name(),
            tolerance: opts.tolerance(),
            units: fairpath_gcode::Units::Mm,
            elapsed: Duration::ZERO,
            planned_on,
            e: e.clone(),
        }
    }

    /// True when the written program plans slower than the input.
    pub fn slower_than_input(&self) -> bool {
        self.e.times.written.total > self.e.times.input.total
    }

    /// Shares of the tolerance the text was written with: smoothing,
    /// output, the controller's blending (mm). The budget the writer used:
    /// a program's own looser G64 takes a blending share out of the output
    /// share (`budget_for`).
    pub fn shares(&self) -> (f64, f64, f64) {
        let b = &self.e.budget;
        (b.smoothing(), b.output, b.blend)
    }

    pub fn kept_total(&self) -> usize {
        self.e.kept_corners.iter().map(|k| k.1).sum::<usize>() + self.e.corners_in_kept_runs
    }

    /// The tolerance in the program's units (`None` for mm programs).
    pub fn tolerance_in_program_units(&self) -> Option<f64> {
        (self.units != fairpath_gcode::Units::Mm).then(|| self.tolerance / self.units.mm_per_unit())
    }

    /// The tolerance as printed: mm, and the program's units where they
    /// differ.
    fn tolerance_text(&self) -> String {
        match self.tolerance_in_program_units() {
            Some(t) => format!(
                "{} mm = {t} {}",
                self.tolerance,
                crate::length::unit_name(self.units)
            ),
            None => format!("{} mm", self.tolerance),
        }
    }

    pub fn text(&self) -> String {
        let mut s = String::new();
        let (sm, out, blend) = self.shares();
        let _ = writeln!(
            s,
            "fairpath smooth: {} -> {} ({}, {} for {}, tolerance {})",
            self.input,
            self.output,
            self.method,
            self.format,
            self.controller,
            self.tolerance_text()
        );
        let blend_text = if blend > 0.0 {
            format!(", controller blending {blend:.6} mm (G64 P)")
        } else {
            String::new()
        };
        let _ = writeln!(
            s,
            "  tolerance:       smoothing {sm:.6} mm, writing {out:.6} mm{blend_text}"
        );
        let _ = writeln!(
            s,
            "  moves in:        {} feed moves in {} runs, {} rapids (untouched)",
            self.e.feed_moves_in, self.e.runs, self.e.rapids
        );
        let _ = writeln!(
            s,
            "  curves:          {} pieces ({} curves; {} corners replaced by transitions or fits)",
            self.e.pieces_out, self.e.curves_out, self.e.transitions
        );
        if !self.e.chosen.is_empty() {
            let list: Vec<String> = self
                .e
                .chosen
                .iter()
                .map(|(name, n)| format!("{n} x {name}"))
                .collect();
            let _ = writeln!(s, "  auto chose:      {} (sections)", list.join("; "));
        }
        if !self.e.unfaired.is_empty() {
            let n: usize = self.e.unfaired.iter().map(|u| u.1).sum();
            let list: Vec<String> = self
                .e
                .unfaired
                .iter()
                .map(|(reason, n, line)| format!("{n} {reason}, first at line {line}"))
                .collect();
            let _ = writeln!(
                s,
                "  not faired:      {n} curve{} kept as written ({})",
                if n == 1 { "" } else { "s" },
                list.join("; ")
            );
        }
        let r = &self.e.rendered;
        let mut held = Vec::new();
        if r.arcs > 0 {
            held.push(format!("{} arcs ({} helical)", r.arcs, r.helical));
        }
        if r.lines > 0 {
            held.push(if r.fallback_lines > 0 {
                format!(
                    "{} lines ({} where arcs could not follow {} curves)",
                    r.lines, r.fallback_lines, r.fallback_pieces
                )
            } else {
                format!("{} lines", r.lines)
            });
        }
        if r.nurbs > 0 {
            held.push(format!("{} NURBS", r.nurbs));
        }
        if r.nurbs_as_arcs > 0 {
            held.push(format!(
                "{} curves the format cannot say written as arcs",
                r.nurbs_as_arcs
            ));
        }
        let _ = writeln!(
            s,
            "  written:         {} lines (input {}){}{}",
            self.e.lines_out,
            self.e.lines_in,
            if held.is_empty() {
                String::new()
            } else {
                format!("; runs hold {}", held.join(", "))
            },
            if self.e.retried_runs > 0 {
                format!(
                    "; {} runs rendered again with a finer chord",
                    self.e.retried_runs
                )
            } else {
                String::new()
            }
        );
        if self.e.kept_runs > 0 {
            let _ = writeln!(
                s,
                "                   {} of {} runs kept as the program wrote them (no faster when written)",
                self.e.kept_runs, self.e.runs
            );
        }
        if self.e.g91_spline_runs > 0 {
            let _ = writeln!(
                s,
                "                   ({} of them in G91: this format's spline blocks need G90 around them, which would end the run)",
                self.e.g91_spline_runs
            );
        }
        let _ = writeln!(
            s,
            "  cleaned:         {} zero-length moves dropped, {} straight-on vertices merged, {} tiny moves absorbed",
            self.e.dropped_zero_length, self.e.merged_collinear, self.e.absorbed_jogs
        );
        let _ = writeln!(
            s,
            "  max deviation:   {:.6} mm (curves), {:.6} mm (written output, bound)",
            self.e.max_deviation_curves, self.e.written.max_deviation
        );
        let _ = writeln!(s, "  joints:          {}", joints_text(self.e.joints));
        let mut kept: Vec<String> = self
            .e
            .kept_corners
            .iter()
            .filter(|k| k.1 > 0)
            .map(|(r, n)| format!("{n} {}", r.as_str()))
            .collect();
        if self.e.corners_in_kept_runs > 0 {
            kept.push(format!(
                "{} {KEPT_RUN_CORNERS}",
                self.e.corners_in_kept_runs
            ));
        }
        let _ = writeln!(
            s,
            "  kept corners:    {}{}",
            self.kept_total(),
            if kept.is_empty() {
                String::new()
            } else {
                format!(" ({})", kept.join(", "))
            }
        );
        let _ = writeln!(
            s,
            "  length:          {:.4} mm -> {:.4} mm",
            self.e.length_before, self.e.length_after
        );
        let cusps = match self.e.cusps {
            0 => String::new(),
            1 => "; 1 cusp, a point inside a curve where the path stops and turns".to_string(),
            n => format!("; {n} cusps, points inside curves where the path stops and turns"),
        };
        if self.e.peak_curvature > 0.0 {
            let _ = writeln!(
                s,
                "  peak curvature:  {:.4} 1/mm (radius {:.4} mm){cusps}",
                self.e.peak_curvature,
                1.0 / self.e.peak_curvature
            );
        } else if self.e.cusps > 0 {
            let _ = writeln!(s, "  peak curvature:  0{cusps}");
        } else {
            let _ = writeln!(s, "  peak curvature:  0 (no curves)");
        }
        let t = &self.e.times;
        let _ = writeln!(
            s,
            "  planned time:    input {:.3} s, curves {:.3} s, written {:.3} s ({:.3} of the input)",
            t.input.total,
            t.exact.total,
            t.written.total,
            t.written.total / t.input.total
        );
        let _ = writeln!(
            s,
            "                   (feed moves: {:.3} s, {:.3} s, {:.3} s; {})",
            t.input.feed, t.exact.feed, t.written.feed, self.planned_on
        );
        if self.e.block_capped {
            let _ = writeln!(
                s,
                "  note:            {} writes for LinuxCNC's S-curve planner, which caps the speed at every block end; runs were kept or rewritten by that model (fewer, longer blocks), while the times above are a blending controller's",
                self.method
            );
        }
        if self.slower_than_input() {
            let _ = writeln!(
                s,
                "  warning:         the written program plans slower than the input ({:.3} s > {:.3} s)",
                t.written.total, t.input.total
            );
        }
        let _ = writeln!(s, "  time taken:      {:.3} s", self.elapsed.as_secs_f64());
        s
    }

    pub fn json(&self) -> String {
        let mut kept: serde_json::Map<String, serde_json::Value> = self
            .e
            .kept_corners
            .iter()
            .map(|(r, n)| (r.as_str().to_string(), json!(n)))
            .collect();
        kept.insert(
            KEPT_RUN_CORNERS.to_string(),
            json!(self.e.corners_in_kept_runs),
        );
        json!({
            "input": self.input, "output": self.output, "method": self.method,
            "format": self.format, "controller": self.controller,
            "tolerance_mm": self.tolerance,
            "program_units": crate::length::unit_name(self.units),
            "tolerance_program_units": self.tolerance / self.units.mm_per_unit(),
            "smoothing_share_mm": self.shares().0,
            "output_share_mm": self.shares().1, "blend_share_mm": self.shares().2,
            "feed_moves_in": self.e.feed_moves_in, "runs": self.e.runs, "rapids": self.e.rapids,
            "pieces_out": self.e.pieces_out, "curves_out": self.e.curves_out, "transitions": self.e.transitions,
            "kept_corners": kept, "dropped_zero_length": self.e.dropped_zero_length,
            "auto_chose": self.e.chosen.iter().map(|(n, c)| json!({"candidate": n, "sections": c})).collect::<Vec<_>>(),
            "not_faired": self.e.unfaired.iter().map(|(r, n, l)| json!({"reason": r.to_string(), "curves": n, "first_line": l})).collect::<Vec<_>>(),
            "merged_collinear": self.e.merged_collinear,
            "absorbed_jogs": self.e.absorbed_jogs,
            "max_deviation_curves_mm": self.e.max_deviation_curves,
            "max_deviation_written_mm": self.e.written.max_deviation,
            "joints": {"C2": self.e.joints[3], "C1": self.e.joints[2], "C0": self.e.joints[1], "gap": self.e.joints[0]},
            "length_before_mm": self.e.length_before, "length_after_mm": self.e.length_after,
            "peak_curvature_per_mm": self.e.peak_curvature, "cusps": self.e.cusps,
            "time_s": self.elapsed.as_secs_f64(),
            "input_time_s": self.e.times.input.total,
            "curves_time_s": self.e.times.exact.total,
            "written_time_s": self.e.times.written.total,
            "input_feed_time_s": self.e.times.input.feed,
            "curves_feed_time_s": self.e.times.exact.feed,
            "written_feed_time_s": self.e.times.written.feed,
            "written_slower_than_input": self.slower_than_input(),
            "planned_on": self.planned_on,
            "lines_in": self.e.lines_in, "lines_out": self.e.lines_out,
            "written_arcs": self.e.rendered.arcs, "written_helical_arcs": self.e.rendered.helical,
            "written_lines": self.e.rendered.lines, "written_fallback_lines": self.e.rendered.fallback_lines,
            "written_fallback_curves": self.e.rendered.fallback_pieces,
            "written_nurbs": self.e.rendered.nurbs, "retried_runs": self.e.retried_runs,
            "g91_spline_runs": self.e.g91_spline_runs,
            "nurbs_written_as_arcs": self.e.rendered.nurbs_as_arcs,
            "kept_runs": self.e.kept_runs,
        })
        .to_string()
    }
}
