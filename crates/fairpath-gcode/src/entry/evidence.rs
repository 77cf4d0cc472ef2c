//! The evidence of a job in figures: what the summary prints, gathered
//! from the report of a whole program ([`Evidence::of`]) or added up part
//! by part ([`Evidence::add`]) when a long program is processed a part at
//! a time and no report of all its runs is ever held.
//!
//! The figures describe what was written: a run the writer kept as the
//! program had it ([`Report::kept`]) counts with its own pieces, joints,
//! length and curvature, not with the curves that were not written.

use super::Report;
use crate::pipeline::{JobTimes, Times, WrittenCheck};
use fairpath::budget::ToleranceBudget;
use fairpath::geom::Curve;
use fairpath::path::Run;
use fairpath::render::RenderStats;
use fairpath::smooth::{CornerReason, UnfairedReason};
use fairpath::verify::RunReport;

/// The evidence of a job in figures (see the module docs). Sums over the
/// runs are added run by run in program order, so a program processed in
/// parts gives the figures of the whole to the bit.
#[derive(Clone, Debug, PartialEq)]
pub struct Evidence {
    /// The method's name.
    pub method: String,
    /// The budget the text was written with ([`Report::budget`]).
    pub budget: ToleranceBudget,
    /// Feed moves of the input's runs, its rapids (untouched), its runs.
    pub feed_moves_in: usize,
    pub rapids: usize,
    pub runs: usize,
    /// Pieces of the curves, and those that are not lines.
    pub pieces_out: usize,
    pub curves_out: usize,
    pub transitions: usize,
    /// Corners kept as corners, by reason.
    pub kept_corners: Vec<(CornerReason, usize)>,
    /// Corners of the runs written as the program had them.
    pub corners_in_kept_runs: usize,
    /// `auto`'s choices: candidate and number of sections, most first.
    pub chosen: Vec<(&'static str, usize)>,
    /// Curves left as written although the method smooths their kind: the
    /// reason, how many, the first input line.
    pub unfaired: Vec<(UnfairedReason, usize, usize)>,
    pub dropped_zero_length: usize,
    pub merged_collinear: usize,
    pub absorbed_jogs: usize,
    /// Largest deviation of the curves from the original (as found, mm).
    pub max_deviation_curves: f64,
    /// Joints of the curves by class: gaps, C0 (corners), C1, C2.
    pub joints: [usize; 4],
    /// Length of the input's runs and of the curves (mm).
    pub length_before: f64,
    pub length_after: f64,
    pub peak_curvature: f64,
    /// Cusps inside curves (points where the path stops and turns: a
    /// reversal, or a corner such as a spline's repeated control point).
    pub cusps: usize,
    /// Planned times of the input, the exact curves and the written text.
    pub times: JobTimes,
    /// The verdict on the written text read back.
    pub written: WrittenCheck,
    /// What the written runs hold.
    pub rendered: RenderStats,
    /// Lines of the input and of the written program.
    pub lines_in: usize,
    pub lines_out: usize,
    /// Runs rendered again with a finer chord, and runs written as the
    /// program had them.
    pub retried_runs: usize,
    pub kept_runs: usize,
    /// See [`Report::g91_spline_runs`].
    pub g91_spline_runs: usize,
    /// See [`Report::block_capped`].
    pub block_capped: bool,
    /// The last part added ended in a window's cut, and every window of
    /// its run so far was kept as written (a run cut into windows counts
    /// once, and as kept only where all of it is).
    pub cut_run_kept: bool,
    /// The program has no moves: nothing was smoothed.
    pub no_moves: bool,
    /// Parts the program was processed in ([`super::smooth_in_parts`]; 1
    /// for a program read whole).
    pub parts: usize,
}

impl Evidence {
    /// Before any part: no runs, no lines, the budget and method of the
    /// job.
    pub fn new(method: &str, budget: ToleranceBudget, block_capped: bool) -> Evidence {
        let zero = Times {
            total: 0.0,
            feed: 0.0,
        };
        Evidence {
            method: method.to_string(),
            budget,
            feed_moves_in: 0,
            rapids: 0,
            runs: 0,
            pieces_out: 0,
            curves_out: 0,
            transitions: 0,
            kept_corners: CornerReason::ALL.into_iter().map(|r| (r, 0)).collect(),
            corners_in_kept_runs: 0,
            chosen: Vec::new(),
            unfaired: Vec::new(),
            dropped_zero_length: 0,
            merged_collinear: 0,
            absorbed_jogs: 0,
            max_deviation_curves: 0.0,
            joints: [0; 4],
            length_before: 0.0,
            length_after: 0.0,
            peak_curvature: 0.0,
            cusps: 0,
            times: JobTimes {
                input: zero,
                exact: zero,
                written: zero,
            },
            written: WrittenCheck {
                within: true,
                max_deviation: 0.0,
                endpoint_failures: 0,
                runs_checked: 0,
                failed_runs: Vec::new(),
            },
            rendered: RenderStats::default(),
            lines_in: 0,
            lines_out: 0,
            retried_runs: 0,
            kept_runs: 0,
            g91_spline_runs: 0,
            block_capped,
            cut_run_kept: false,
            no_moves: true,
            parts: 0,
        }
    }

    /// The evidence of a whole program's report; lengths measured to
    /// `length_accuracy` mm.
    pub fn of(report: &Report, length_accuracy: f64) -> Evidence {
        let mut e = Evidence::new(&report.method, report.budget, report.block_capped);
        e.add(report, length_accuracy);
        e
    }

    /// Adds the report of the next part of the program (its times are
    /// those of the program up to the part's end: they replace these).
    pub fn add(&mut self, report: &Report, length_accuracy: f64) {
        let runs_before = self.runs;
        self.budget = report.budget;
        for (i, r) in report.result.runs.iter().enumerate() {
            self.feed_moves_in += r.original.pieces.len();
            self.runs += 1;
            self.length_before += r.original.length(length_accuracy);
            // (Curves the method leaves as written are so in either case.)
            for u in &r.smoothed.unfaired {
                let line = u.source_lines.0;
                match self.unfaired.iter_mut().find(|e| e.0 == u.reason) {
                    Some(e) => {
                        e.1 += 1;
                        e.2 = e.2.min(line);
                    }
                    None => self.unfaired.push((u.reason, 1, line)),
                }
            }
            if let Some(own) = report.kept_run_report(i) {
                self.add_kept_run(&r.original, &own, length_accuracy);
                continue;
            }
            self.pieces_out += r.smoothed.pieces.len();
            self.curves_out += r
                .smoothed
                .pieces
                .iter()
                .filter(|p| !matches!(p.curve, Curve::Line(_)))
                .count();
            self.transitions += r.smoothed.transitions;
            for k in &r.smoothed.kept_corners {
                if let Some(c) = self.kept_corners.iter_mut().find(|c| c.0 == k.reason) {
                    c.1 += 1;
                }
            }
            for &name in &r.smoothed.chosen {
                match self.chosen.iter_mut().find(|c| c.0 == name) {
                    Some(c) => c.1 += 1,
                    None => self.chosen.push((name, 1)),
                }
            }
            self.dropped_zero_length += r.smoothed.dropped_zero_length;
            self.merged_collinear += r.smoothed.merged_collinear;
            self.absorbed_jogs += r.smoothed.absorbed_jogs;
            self.max_deviation_curves = self.max_deviation_curves.max(r.report.max_deviation);
            for (j, c) in self.joints.iter_mut().zip(r.report.joint_counts()) {
                *j += c;
            }
            for p in &r.smoothed.pieces {
                self.length_after += p.curve.length(length_accuracy);
            }
            self.peak_curvature = self.peak_curvature.max(r.report.peak_curvature);
            self.cusps += r.report.cusps;
        }
        // A run that goes on from the part before is that run, and its
        // first move the rest of the cut line.
        let (continued, _) = report.window_ends;
        if continued && !report.result.runs.is_empty() {
            self.runs -= 1;
            self.feed_moves_in -= 1;
        }
        let kept = kept_runs_of_part(
            &mut self.cut_run_kept,
            report.window_ends,
            &report.kept,
            report.kept_runs,
        );
        self.chosen.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
        self.unfaired.sort();
        self.times = report.times;
        let w = &report.written;
        self.written.within &= w.within;
        self.written.max_deviation = self.written.max_deviation.max(w.max_deviation);
        self.written.endpoint_failures += w.endpoint_failures;
        self.written.runs_checked += w.runs_checked;
        self.written
            .failed_runs
            .extend(w.failed_runs.iter().map(|f| f.map(|k| k + runs_before)));
        self.rendered.add(&report.stats);
        self.lines_in += report.lines_in;
        self.lines_out += report.lines_out;
        self.retried_runs += report.retried_runs;
        self.kept_runs += kept;
        self.g91_spline_runs += report.g91_spline_runs;
        self.rapids += report.rapids;
        self.no_moves &= report.no_moves;
        self.parts += 1;
    }

    /// Adds a run written as the program had it: its own pieces, and the
    /// verifier's figures of it as written, `own`
    /// ([`Report::kept_run_report`]).
    fn add_kept_run(&mut self, run: &Run, own: &RunReport, length_accuracy: f64) {
        let pieces = &run.pieces;
        self.pieces_out += pieces.len();
        self.curves_out += pieces
            .iter()
            .filter(|p| !matches!(p.curve, Curve::Line(_)))
            .count();
        let joints = own.joint_counts();
        for (j, c) in self.joints.iter_mut().zip(joints) {
            *j += c;
        }
        self.corners_in_kept_runs += joints[1];
        self.length_after += run.length(length_accuracy);
        self.peak_curvature = self.peak_curvature.max(own.peak_curvature);
        self.cusps += own.cusps;
    }

    /// True when the written program plans slower than the input.
    pub fn slower_than_input(&self) -> bool {
        self.times.written.total > self.times.input.total
    }
}

/// The runs of a part kept as the program wrote them, where a run cut
/// into windows counts once, in the part where it ends, and as kept only
/// where every window of it is: `kept` says which of the part's runs (or
/// windows) were kept, `ends` whether its first run goes on from the part
/// before and its last into the next ([`Report::window_ends`]), and
/// `cut_kept` whether every window so far of the run going on was kept
/// (updated for the next part); `count` is the part's own count of kept
/// runs ([`Report::kept_runs`]).
fn kept_runs_of_part(
    cut_kept: &mut bool,
    ends: (bool, bool),
    kept: &[bool],
    mut count: usize,
) -> usize {
    let (continued, cut) = ends;
    let n = kept.len();
    let first_kept = kept.first() == Some(&true);
    let last_kept = kept.last() == Some(&true);
    let goes_on_from_before = continued && n > 0;
    // The part is one window in the middle of a run.
    let middle = goes_on_from_before && cut && n == 1;
    let kept_so_far = goes_on_from_before && *cut_kept && first_kept;
    // The windows of cut runs are counted where their run ends.
    if goes_on_from_before && first_kept {
        count -= 1;
    }
    if cut && last_kept && !middle {
        count -= 1;
    }
    if goes_on_from_before && !middle && kept_so_far {
        count += 1;
    }
    *cut_kept = if middle {
        kept_so_far
    } else {
        cut && last_kept
    };
    count
}

#[cfg(test)]
mod tests {
    use super::kept_runs_of_part;

    /// The runs kept, counted part after part: `parts` gives each part's
    /// window ends and kept runs.
    fn count(parts: &[((bool, bool), &[bool])]) -> usize {
        let mut cut_kept = false;
        parts
            .iter()
            .map(|(ends, kept)| {
                let n = kept.iter().filter(|&&k| k).count();
                kept_runs_of_part(&mut cut_kept, *ends, kept, n)
            })
            .sum()
    }

    #[test]
    fn a_run_cut_into_windows_counts_once_and_as_kept_only_where_all_of_it_is() {
        // Runs not cut.
        assert_eq!(count(&[((false, false), &[true, false, true])]), 2);
        // One run in three windows, all kept: once.
        let all = [
            ((false, true), &[true][..]),
            ((true, true), &[true][..]),
            ((true, false), &[true][..]),
        ];
        assert_eq!(count(&all), 1);
        // Kept, rewritten, kept: not kept (`Cereal.ngc` in windows of one
        // line counted 74 of its 50 runs kept).
        let mixed = [
            ((false, true), &[true][..]),
            ((true, true), &[false][..]),
            ((true, false), &[true][..]),
        ];
        assert_eq!(count(&mixed), 0);
        // Runs before and after the cut run, in its first and last parts.
        let around = [
            ((false, true), &[true, true][..]),
            ((true, false), &[true, false, true][..]),
        ];
        assert_eq!(count(&around), 3);
        let around_rewritten = [
            ((false, true), &[true, false][..]),
            ((true, false), &[true, true][..]),
        ];
        assert_eq!(count(&around_rewritten), 2);
        // Two cut runs one after the other, the first kept, the second not.
        let two = [
            ((false, true), &[true][..]),
            ((true, true), &[true, false][..]),
            ((true, false), &[true][..]),
        ];
        assert_eq!(count(&two), 1);
    }
}
