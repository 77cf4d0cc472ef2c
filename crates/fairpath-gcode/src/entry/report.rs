//! The evidence of a smoothing job.

use crate::pipeline::{JobTimes, Phases, SmoothResult, WrittenCheck};
use fairpath::budget::ToleranceBudget;
use fairpath::geom::Curve;
use fairpath::render::RenderStats;
use fairpath::smooth::{CornerReason, UnfairedReason};
use fairpath::verify::{report_without_deviation, RunReport, VerifyOptions};
use std::borrow::Cow;

/// The evidence of a smoothing job.
#[derive(Clone, Debug)]
pub struct Report {
    /// Every run: the original, its curves, the verifier's report on them
    /// (against the smoothing share).
    pub result: SmoothResult,
    /// Planned times of the input, the exact curves and the written
    /// program, by the same model on the same machine and feeds.
    pub times: JobTimes,
    /// The budget the text was written with (for a program whose own G64
    /// blends beyond the share, a blending share taken out of the output
    /// share: [`EmitOptions::budget_for`](crate::emit::EmitOptions::budget_for)).
    pub budget: ToleranceBudget,
    /// The verdict on the written text read back, against the original.
    pub written: WrittenCheck,
    /// What the written runs hold.
    pub stats: RenderStats,
    /// Runs rendered again with a finer chord before they verified.
    pub retried_runs: usize,
    /// Of `kept_runs`, those in G91 where the format has only spline
    /// blocks (which would need G90 around them).
    pub g91_spline_runs: usize,
    /// Runs written as the program had them (no rendering planned faster).
    pub kept_runs: usize,
    /// Per run of `result`, in order: true where the run is written as the
    /// program had it, so that its curves are not what was written.
    pub kept: Vec<bool>,
    /// The method's name.
    pub method: String,
    /// The runs were judged by a planner that caps the speed at every block
    /// end (LinuxCNC's S-curve planner, for `arc-fit`), not by the blending
    /// model of the times.
    pub block_capped: bool,
    /// Lines of the input and of the written program.
    pub lines_in: usize,
    pub lines_out: usize,
    /// Rapids of the input (untouched).
    pub rapids: usize,
    /// The program has no moves (tool changes, coolant ...): nothing was
    /// smoothed.
    pub no_moves: bool,
    /// For a part of a long run cut into windows: its first run goes on
    /// from the part before ([`crate::Program::window_continued`]), its
    /// last into the next ([`crate::Program::window_cut`]).
    pub window_ends: (bool, bool),
    /// Wall-clock time of each step.
    pub phases: Phases,
}

impl Report {
    /// For run `i` written as the program had it ([`Report::kept`]), the
    /// verifier's figures of that run as written: joints (classified at the
    /// smoothing share, as the curves'), peak curvature, cusps; `None` for
    /// a run written smoothed. A run smoothed into itself (`none`) has its
    /// report already.
    pub fn kept_run_report(&self, i: usize) -> Option<Cow<'_, RunReport>> {
        if !self.kept.get(i).copied().unwrap_or(false) {
            return None;
        }
        let r = &self.result.runs[i];
        if r.smoothed.pieces == r.original.pieces {
            return Some(Cow::Borrowed(&r.report));
        }
        let verify = VerifyOptions::new(self.budget.smoothing());
        let p = &r.original.pieces;
        Some(Cow::Owned(report_without_deviation(p, p, &verify).0))
    }

    /// Shares of the tolerance the text was written with: smoothing,
    /// output, the controller's blending (mm).
    pub fn shares(&self) -> (f64, f64, f64) {
        (
            self.budget.smoothing(),
            self.budget.output,
            self.budget.blend,
        )
    }

    /// Largest deviation of the curves from the original (mm, as found).
    pub fn max_deviation_curves(&self) -> f64 {
        self.result
            .runs
            .iter()
            .map(|r| r.report.max_deviation)
            .fold(0.0, f64::max)
    }

    /// Bound of the written text's deviation from the original, read back
    /// (mm).
    pub fn max_deviation_written(&self) -> f64 {
        self.written.max_deviation
    }

    /// Joints of the curves by class: gaps, G0 (corners), G1, G2.
    pub fn joints(&self) -> [usize; 4] {
        let mut joints = [0; 4];
        for r in &self.result.runs {
            let c = r.report.joint_counts();
            for i in 0..4 {
                joints[i] += c[i];
            }
        }
        joints
    }

    /// `auto`'s choices: candidate and number of sections, most first.
    pub fn auto_chose(&self) -> Vec<(&'static str, usize)> {
        let mut chosen: Vec<(&'static str, usize)> = Vec::new();
        for &name in self.result.runs.iter().flat_map(|r| &r.smoothed.chosen) {
            match chosen.iter_mut().find(|c| c.0 == name) {
                Some(c) => c.1 += 1,
                None => chosen.push((name, 1)),
            }
        }
        chosen.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
        chosen
    }

    /// Corners kept as corners, by reason.
    pub fn kept_corners(&self) -> Vec<(CornerReason, usize)> {
        let mut kept = Vec::new();
        for reason in CornerReason::ALL {
            let n = self
                .result
                .runs
                .iter()
                .map(|r| {
                    r.smoothed
                        .kept_corners
                        .iter()
                        .filter(|k| k.reason == reason)
                        .count()
                })
                .sum();
            kept.push((reason, n));
        }
        kept
    }

    /// Curves left as written although the method smooths their kind
    /// (method `fair`: curves the thesis' fairing cannot take), by reason:
    /// the reason, how many, the first input line of the first.
    pub fn unfaired(&self) -> Vec<(UnfairedReason, usize, usize)> {
        let mut out: Vec<(UnfairedReason, usize, usize)> = Vec::new();
        for u in self.result.runs.iter().flat_map(|r| &r.smoothed.unfaired) {
            let line = u.source_lines.0;
            match out.iter_mut().find(|e| e.0 == u.reason) {
                Some(e) => {
                    e.1 += 1;
                    e.2 = e.2.min(line);
                }
                None => out.push((u.reason, 1, line)),
            }
        }
        out.sort();
        out
    }

    /// Pieces of the curves that are not lines.
    pub fn curves_out(&self) -> usize {
        self.result
            .runs
            .iter()
            .flat_map(|r| &r.smoothed.pieces)
            .filter(|p| !matches!(p.curve, Curve::Line(_)))
            .count()
    }

    /// True when the written program plans slower than the input.
    pub fn slower_than_input(&self) -> bool {
        self.times.written.total > self.times.input.total
    }
}
