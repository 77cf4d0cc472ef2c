//! Method `fair`: the thesis' fairing inside a tolerance tube (seed 003,
//! Naseath 2007; the method itself is [`crate::geom::tube_fair`]) applied
//! to a run.
//!
//! * **B-spline pieces** of the run (cubic, non-rational NURBS from G5.2 or
//!   G6.2 programs read exactly, or from fairpath's JSON) are faired in a
//!   tube of radius `band_use * tolerance` around themselves.
//! * **Runs of lines** go through `bspline-fit` (seed 002's least-squares
//!   B-splines of dense sections, `bspline-corner` transitions at the
//!   corners between them, kept lines) at the whole tolerance, but with its
//!   fits held to [`FairOptions::fit_share`] of their band
//!   ([`crate::budget::FAIR_FIT_SHARE`] by default). The fitted curves are
//!   then faired in a tube of radius `band_use * (1 - fit_share) *
//!   tolerance` around themselves: the fit is within `fit_share *
//!   band_use * tolerance` of the lines (plus the cleaning of the run,
//!   [`crate::budget::CLEAN_SHARE`] of the tolerance), the faired curve
//!   within its tube of the fit at equal parameters, so by the triangle
//!   inequality the result is within `band_use * tolerance` plus the
//!   cleaning of the original. The thesis starts from a CAM spline and a
//!   G1 program has none, so which fit to fair is ours to choose
//!   ([`LineFit`]): by default the run is fitted both with `bspline-fit`'s
//!   sections and through its shallow corners however long their
//!   segments, both are faired, and the one of the lower peak curvature is
//!   kept. The corner transitions use the whole band
//!   already (as in `bspline-corner`) and are kept as they are: they are
//!   told from fits by their knot vector ([`TRANSITION_KNOTS`]; a fit that
//!   happened to have it would only be left unfaired). By default the fit
//!   is the plain least-squares fit (its fairness raises and its in-band
//!   relaxation off: flattening is the thesis' method's job here).
//! * Lines between sharp corners are kept as they are (the fit's
//!   sections leave them).
//! * **Joints**: a curve that joins another piece of the run tangent (G1
//!   or G2) keeps its first (or last) three control points, so its
//!   position, tangent and curvature at the joint do not change: a G2
//!   joint stays G2. A curve of the program at a corner of the run keeps
//!   only its end point, where that is faster by its speed caps and no
//!   higher in peak curvature than keeping three
//!   (`FairOptions::fair_between`). At the
//!   run's ends only the end point is kept ([`FairOptions::ends`]: the end
//!   tangent may turn, or with `slide-along-tangent` keeps its
//!   direction). Run endpoints stay bit for bit.
//! * Long fits come from `bspline-fit` cut into pieces of at most
//!   `max_piece_spans` spans; each piece is faired on its own with its
//!   joints kept, so the few spans next to a cut are not faired.
//!
//! * **Other B-splines** are written exactly as clamped curves first
//!   ([`as_fairable`]): a quadratic raised to degree 3, an unclamped curve
//!   clamped by knot insertion; a curve the fairing did not move stays as
//!   written. A curve of degree 1 is its control polygon, exactly: its
//!   lines go through the fit and the fairing as other lines do.
//! * **Rational B-splines and those of degree 4 and above** (LinuxCNC's
//!   G6.2 examples are mostly such: 18 of its 40) are faired by the same
//!   method, generalised (ours, [`crate::geom::tube_fair`]: the weights
//!   stay, the points move, the tube's bound holds); unless
//!   [`OtherCurves::Kept`] keeps them as written.
//! * **Curves the fairing cannot take** (circular and helical arcs, which
//!   are rational quadratics but not B-splines here: G2/G3, and the arcs a
//!   G5.2 block is read as, since LinuxCNC runs it so), **cannot move**
//!   (B-splines of at most [`MOST_FIXED_POINTS`] control points, all kept
//!   where they join their neighbours G2), and the rational and
//!   high-degree ones again: by default ([`OtherCurves::Sampled`]) the run is
//!   also smoothed with each of them sampled as chords within
//!   [`FAIR_SAMPLE_SHARE`] of the tolerance ([`Run::sampled`]), the chords
//!   fitted and faired as lines are, in the rest of the tolerance (so the
//!   result is within the chords' share plus the rest of the original, by
//!   the triangle inequality). The two smoothings are
//!   [`Fair::alternatives`]. As the registry builds `fair`
//!   (`choose::JudgedFair`), the planner on the user's machine chooses
//!   between them: the sampled one where it plans faster at every feed a
//!   G-code writer judges a run at. This type alone has no planner (the
//!   methods' layer sits below it) and estimates: the sampled smoothing
//!   is kept where both its highest demand and the demand's integral over the
//!   length ([`sampled_demands`], by [`FairOptions::peak_pass`]'s measure
//!   at its own feed, not the programmed one: by default the speed caps of
//!   fairpath's jerk-limited model at 400 mm/s, curvature, its rate of
//!   change and its steps where pieces meet, as arcs do) are lower than
//!   with the curves kept (or faired themselves, where they can be),
//!   compared over the pieces from the curves' input lines (the run's may
//!   peak elsewhere), corner transitions aside. So a smooth design curve
//!   whose fit would only add ripples of `dk/ds` (LinuxCNC's rational
//!   `Curva_Farfalla_p1.ngc` at 0.25 mm: slower at 400 mm/s, with a
//!   lower peak curvature; measurements: docs/tuning.md,
//!   `OtherCurves::Sampled`) is not sampled; it is faired itself. Where
//!   curves are kept as written (an arc whose sampling does not pay, or
//!   with [`OtherCurves::Kept`]) the B-splines among them are listed in
//!   [`SmoothedRun::unfaired`] with the reason, which the report and the
//!   CLI's summary show. Not an error: the rest of the program is faired
//!   and the kept curves are within the tolerance of themselves, while
//!   refusing the whole program for one exact arc would help no one.
//! * **Straightening** (ours, `geom::tube_fair::straighten`: the turning
//!   minimised inside the tube measured to the original curve, after the
//!   thesis' iterations): by default ([`Straighten::Judged`]) a run that
//!   holds a B-spline of the program is smoothed with and without it, and
//!   the planner on the user's machine keeps the faster
//!   (`choose::JudgedFair`); this type alone straightens only with
//!   [`Straighten::On`].
//!
//! The pipeline verifies the result as for every method.

use super::bspline_corner::TRANSITION_KNOTS;
use super::bspline_fit::{BsplineFit, BsplineFitOptions};
use super::fair_measures::{
    run_peak_curvature, run_turning, sampled_demands, shallow_corner_sections,
};
use super::fair_options::{FairOptions, LineFit, OtherCurves, Straighten, MOST_FIXED_POINTS};
use super::fit_sections::SectionOptions;
use super::run_memo::RunMemo;
use super::unfaired::{Unfaired, UnfairedReason};
use super::{check_tolerance, OptionError, SmoothError, SmoothedRun, Smoother};
use crate::budget::FAIR_SAMPLE_SHARE;
use crate::geom::elevate::clamped_with_degree;
use crate::geom::tube_fair::{
    as_fairable, Basis, Faired, PeakPass, TubeFairError, TubeFairOptions,
};
use crate::geom::{classify_joint, Continuity, Curve, JointTolerances, Line, Nurbs};
use crate::path::{Piece, Run};
use alloc::vec::Vec;

impl FairOptions {
    /// The tube options for radius `radius`, keeping the G2 joints asked.
    pub(super) fn tube(&self, radius: f64, keep_start: bool, keep_end: bool) -> TubeFairOptions {
        TubeFairOptions {
            radius,
            precision: self.precision,
            accuracy: self.accuracy,
            max_iterations: self.max_iterations,
            ends: self.ends,
            keep_g2_start: keep_start,
            keep_g2_end: keep_end,
            peak_guard: self.peak_guard,
            peak_pass: self.peak_pass,
            tube: self.tube,
            straighten: self.straighten == Straighten::On,
        }
    }

    /// `pass` at the feed of `piece` where the machine runs the programmed
    /// feeds: the peak pass works only where the shape, not the feed
    /// (mm/min), limits the speed.
    fn at_feed(&self, pass: PeakPass, piece: &Piece) -> PeakPass {
        if self.programmed_feeds {
            pass.at_feed(piece.feed.map(|f| f / 60.0))
        } else {
            pass
        }
    }

    /// Fairs `c`, the curve of `piece`, in a tube of `radius`, keeping its
    /// first (last) three control points where `keep.0` (`keep.1`).
    fn fair_keeping(
        &self,
        c: &Nurbs,
        piece: &Piece,
        radius: f64,
        (keep_start, keep_end): (bool, bool),
        memo: &RunMemo,
    ) -> Result<Faired, TubeFairError> {
        let mut opts = self.tube(radius, keep_start, keep_end);
        opts.peak_pass = self.at_feed(opts.peak_pass, piece);
        // Rational curves and those of degree 4 and above are faired as
        // the thesis' cubics are (the module documentation), unless they
        // are to be kept as written.
        match beyond_thesis(c) {
            Some(e) if self.other_curves == OtherCurves::Kept => Err(e),
            _ => as_fairable(c).and_then(|c| memo.fair_in_tube(&c, &opts)),
        }
    }

    /// Fairs `c`, the curve of `piece`, in a tube of `radius` between the
    /// pieces `prev` and `next` of its run (`None` at the run's ends).
    ///
    /// An end that meets its neighbour tangent keeps its first three
    /// control points, so the joint stays as it was (G2 where it was G2).
    /// An end at a corner need only keep its point: the corner stays a
    /// corner, and the curvature next to it may fall (the peak of
    /// LinuxCNC's `Curva_Mazatrol_p3.ngc` lies in the span next to its
    /// plunge). But a free end can also end the fairing sooner (the
    /// thesis' iterations stop when any point touches the tube), so the
    /// curve is then faired both ways and the free one is kept only where
    /// its speed caps take less time ([`sampled_demands`] at the run's
    /// feed) and its peak curvature is no higher ([`run_peak_curvature`];
    /// measurements: docs/tuning.md, `FairOptions::fair_between`).
    fn fair_between(
        &self,
        c: &Nurbs,
        piece: &Piece,
        radius: f64,
        (prev, next): (Option<&Curve>, Option<&Curve>),
        joints: &JointTolerances,
        memo: &RunMemo,
    ) -> Result<Faired, TubeFairError> {
        let fair_keeping = |keep: (bool, bool)| self.fair_keeping(c, piece, radius, keep, memo);
        let tangent = |a: &Curve, b: &Curve| classify_joint(a, b, joints) >= Continuity::G1;
        let keep = (
            prev.is_some_and(|a| tangent(a, &piece.curve)),
            next.is_some_and(|b| tangent(&piece.curve, b)),
        );
        let both = (prev.is_some(), next.is_some());
        let free = fair_keeping(keep);
        if keep == both {
            return free;
        }
        let pass = self.at_feed(
            match self.peak_pass {
                PeakPass::Off => PeakPass::Curvature,
                pass => pass,
            },
            piece,
        );
        let time_peak = |f: &Faired| {
            let p = [Piece {
                curve: Curve::from(f.curve.clone()),
                ..piece.clone()
            }];
            (sampled_demands(&p, pass).1, run_peak_curvature(&p))
        };
        match (free, fair_keeping(both)) {
            (Ok(free), Ok(kept)) => {
                let ((t_free, k_free), (t_kept, k_kept)) = (time_peak(&free), time_peak(&kept));
                Ok(if t_free < t_kept && k_free <= k_kept {
                    free
                } else {
                    kept
                })
            }
            (Ok(free), Err(_)) => Ok(free),
            (Err(e), _) => Err(e),
        }
    }
}

/// The `fair` method (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Fair {
    pub options: FairOptions,
}

impl Smoother for Fair {
    fn name(&self) -> &'static str {
        "fair"
    }

    fn smooth_run(&self, run: &Run, tolerance: f64) -> Result<SmoothedRun, SmoothError> {
        self.smooth_run_with(run, tolerance, &RunMemo::default())
    }
}

/// The two smoothings [`Fair`] chooses between on a run
/// ([`Fair::alternatives`]).
#[derive(Clone, Debug)]
pub struct FairAlternatives {
    /// The curves the fairing cannot take kept as written, the rest (rational
    /// and high-degree B-splines too) faired.
    pub kept: SmoothedRun,
    /// Where the run holds curves the fairing cannot take or cannot move
    /// (and [`OtherCurves::Sampled`]): the run with them sampled as chords
    /// within [`FAIR_SAMPLE_SHARE`] of the tolerance, fitted and faired as
    /// lines in the rest of it; `None` elsewhere, and where one of its
    /// curves stayed unfaired.
    pub sampled: Option<SmoothedRun>,
    /// The input lines of the sampled curves: where the two differ.
    sampled_lines: Vec<(usize, usize)>,
}

impl FairAlternatives {
    /// Whether [`FairAlternatives::sampled`] (if any) demands less than
    /// [`FairAlternatives::kept`] of
    /// `pass`'s speed caps both at its peak and in all (the demand's
    /// integral over the length: about the time at the caps' speeds),
    /// compared where they differ: over the pieces from the input lines
    /// of the sampled curves (the run's demand may peak elsewhere), but
    /// the corner transitions, which replace corners the curves kept make
    /// with their neighbours (a corner has no curvature to count). The
    /// demand is taken at the pass' own feed, not the programmed one:
    /// below it both would tie at the feed, and a fit that demands more at
    /// a feed override is no gain (the writer keeps a run that plans
    /// slower at the maximum feed as written). By the peak alone, fits
    /// whose lower peak comes with more demand all along would pass
    /// (measurements: docs/tuning.md, `OtherCurves::Sampled`). The choice
    /// of [`Fair`] without a planner; `choose` judges by its objective.
    pub fn sampled_demands_less(&self, pass: PeakPass) -> bool {
        let Some(sampled) = &self.sampled else {
            return false;
        };
        let pass = match pass {
            PeakPass::Off => PeakPass::Curvature,
            pass => pass,
        };
        let lines = &self.sampled_lines;
        let demand_there = |pieces: &[Piece]| {
            let near: Vec<Piece> = pieces
                .iter()
                .filter(|p| {
                    let transition =
                        matches!(&p.curve, Curve::Nurbs(c) if c.knots == TRANSITION_KNOTS);
                    !transition
                        && lines
                            .iter()
                            .any(|l| p.source_lines.0 <= l.1 && l.0 <= p.source_lines.1)
                })
                .cloned()
                .collect();
            sampled_demands(&near, pass)
        };
        let ((s_peak, s_time), (k_peak, k_time)) = (
            demand_there(&sampled.pieces),
            demand_there(&self.kept.pieces),
        );
        s_peak < k_peak && s_time < k_time
    }

    /// The smoothing [`Fair`] alone writes: the sampled one where it
    /// [demands less](FairAlternatives::sampled_demands_less) of `pass`'s
    /// speed caps, else the kept one.
    pub fn chosen_by_demand(self, pass: PeakPass) -> SmoothedRun {
        let less = self.sampled_demands_less(pass);
        match self.sampled {
            Some(sampled) if less => sampled,
            _ => self.kept,
        }
    }
}

impl Fair {
    /// The smoothings [`Fair`] chooses between on `run` within
    /// `tolerance` mm: the curves the fairing cannot take kept, and (where
    /// the run has such curves) sampled; each is within `tolerance` of the
    /// run.
    pub fn alternatives(&self, run: &Run, tolerance: f64) -> Result<FairAlternatives, SmoothError> {
        self.alternatives_with(run, tolerance, &RunMemo::default())
    }

    /// [`Fair::alternatives`], the fits and fairings shared through `memo`
    /// with other smoothings of the same run.
    pub fn alternatives_with(
        &self,
        run: &Run,
        tolerance: f64,
        memo: &RunMemo,
    ) -> Result<FairAlternatives, SmoothError> {
        check_tolerance(tolerance)?;
        self.options.validate()?;
        let kept = self.smooth_lines(run, tolerance, memo)?;
        // Curves the fairing cannot take, or cannot move: sampled, then
        // fitted and faired as lines with what their chords leave of the
        // tolerance. (A curve that jumps at a knot, or is invalid, is not
        // sampled: its chords would bridge the jump.)
        let other = |c: &Curve| match c {
            // A circular or helical arc is a rational curve too (G2/G3,
            // and the arcs LinuxCNC runs a G5.2 block as).
            Curve::Arc(_) => true,
            Curve::Nurbs(n) if n.degree > 1 => {
                beyond_thesis(n).is_some()
                    || as_fairable(n).is_ok_and(|c| c.points.len() <= MOST_FIXED_POINTS)
            }
            _ => false,
        };
        if self.options.other_curves == OtherCurves::Kept
            || !run.pieces.iter().any(|p| other(&p.curve))
        {
            return Ok(FairAlternatives {
                kept,
                sampled: None,
                sampled_lines: Vec::new(),
            });
        }
        let chord = FAIR_SAMPLE_SHARE * tolerance;
        let sampled_run = run.sampled(chord, other);
        let sampled = self.smooth_lines(&sampled_run, tolerance - chord, memo)?;
        let sampled_lines = run
            .pieces
            .iter()
            .filter(|p| other(&p.curve))
            .map(|p| p.source_lines)
            .collect();
        Ok(FairAlternatives {
            kept,
            sampled: sampled.unfaired.is_empty().then_some(sampled),
            sampled_lines,
        })
    }
}

impl Fair {
    /// [`Smoother::smooth_run`], the fits and fairings shared through
    /// `memo` with other smoothings of the same run.
    pub fn smooth_run_with(
        &self,
        run: &Run,
        tolerance: f64,
        memo: &RunMemo,
    ) -> Result<SmoothedRun, SmoothError> {
        Ok(self
            .alternatives_with(run, tolerance, memo)?
            .chosen_by_demand(self.options.peak_pass))
    }

    /// [`Smoother::smooth_run`] with the curves the fairing cannot take
    /// kept as written (and reported): lines fitted as
    /// [`FairOptions::lines`] says, then faired.
    fn smooth_lines(
        &self,
        run: &Run,
        tolerance: f64,
        memo: &RunMemo,
    ) -> Result<SmoothedRun, SmoothError> {
        let lines = run
            .pieces
            .iter()
            .filter(|p| matches!(p.curve, Curve::Line(_)))
            .count();
        let through = shallow_corner_sections(&self.options.fit.sections);
        match self.options.lines {
            LineFit::Sections => {
                self.smooth_fitted(run, tolerance, self.options.fit.sections, memo)
            }
            LineFit::ThroughShallowCorners => self.smooth_fitted(run, tolerance, through, memo),
            // (With fewer than two lines there is no corner between lines
            // for the two fits to differ at.)
            LineFit::Fairer if lines < 2 || through == self.options.fit.sections => {
                self.smooth_fitted(run, tolerance, self.options.fit.sections, memo)
            }
            LineFit::Fairer => {
                let a = self.smooth_fitted(run, tolerance, self.options.fit.sections, memo)?;
                let b = self.smooth_fitted(run, tolerance, through, memo)?;
                let lower_peak = run_peak_curvature(&b.pieces) < run_peak_curvature(&a.pieces);
                Ok(
                    if lower_peak && run_turning(&b.pieces) <= run_turning(&a.pieces) {
                        b
                    } else {
                        a
                    },
                )
            }
        }
    }
}

impl Fair {
    /// The method with runs of lines fitted by `sections`.
    fn smooth_fitted(
        &self,
        run: &Run,
        tolerance: f64,
        sections: SectionOptions,
        memo: &RunMemo,
    ) -> Result<SmoothedRun, SmoothError> {
        let o = &self.options;
        // Lines first: fitted within their share of the band, corners
        // blended within all of it.
        let fit = BsplineFitOptions {
            band_use: o.fit_share * o.fit.band_use,
            sections,
            ..o.fit
        };
        let lines_run;
        let run = match polylines_as_lines(run) {
            Some(r) => {
                lines_run = r;
                &lines_run
            }
            None => run,
        };
        let mut out = BsplineFit { options: fit }.smooth_run_with(run, tolerance, memo)?;
        // The run's own curves come through the fit unchanged, in order:
        // they get the whole band, the fits what they leave of it.
        let mut originals = run
            .pieces
            .iter()
            .filter(|p| !matches!(p.curve, Curve::Line(_)))
            .peekable();
        let n = out.pieces.len();
        let joints = JointTolerances::from_tolerance(tolerance);
        for i in 0..n {
            let piece: &Piece = &out.pieces[i];
            let from_input = originals.peek().is_some_and(|p| p.curve == piece.curve);
            if from_input {
                originals.next();
            }
            let Curve::Nurbs(c) = &piece.curve else {
                continue;
            };
            let room = if from_input {
                tolerance
            } else if c.knots == TRANSITION_KNOTS {
                continue; // a corner transition: the band is used up
            } else {
                (1.0 - o.fit_share) * tolerance
            };
            // The program's own curves get their ends freed at corners;
            // the fits' ends (at a corner, a transition or a line the
            // sections keep) stay as the fit made them: freeing them too
            // cost more computing than it gained (measurements:
            // docs/tuning.md, `FairOptions::fair_between`).
            let (prev, next) = (
                i.checked_sub(1).map(|j| &out.pieces[j].curve),
                out.pieces.get(i + 1).map(|p| &p.curve),
            );
            let faired = if from_input {
                o.fair_between(c, piece, o.band_use * room, (prev, next), &joints, memo)
            } else {
                o.fair_keeping(
                    c,
                    piece,
                    o.band_use * room,
                    (prev.is_some(), next.is_some()),
                    memo,
                )
            };
            match faired {
                // Unmoved: the curve as written (not its cubic form).
                Ok(f) if f.iterations.is_empty() => {}
                Ok(f) => out.pieces[i].curve = Curve::from(f.curve),
                Err(TubeFairError::BadOption {
                    option,
                    value,
                    expected,
                }) => {
                    return Err(SmoothError::BadOption(OptionError {
                        method: "fair",
                        option,
                        value,
                        expected,
                    }))
                }
                // Not a curve the thesis' method takes: kept as it is, and
                // said.
                Err(e) => out.unfaired.push(Unfaired {
                    source_lines: out.pieces[i].source_lines,
                    reason: UnfairedReason::from_error(&e).unwrap_or(UnfairedReason::Invalid),
                }),
            }
        }
        Ok(out)
    }
}

/// Why `c` is beyond the thesis' own curves (a non-rational cubic, or a
/// quadratic, which is one exactly): rational ([`TubeFairError::Rational`])
/// or of degree 4 and above ([`TubeFairError::Degree`]); `None` for the
/// thesis' curves.
fn beyond_thesis(c: &Nurbs) -> Option<TubeFairError> {
    if Basis::of(c).weights.is_some() {
        Some(TubeFairError::Rational)
    } else if c.degree > 3 {
        Some(TubeFairError::Degree(c.degree))
    } else {
        None
    }
}

/// `run` with each NURBS of degree 1 replaced by the lines of its control
/// polygon (clamped: the curve itself, exactly, end points bit for bit;
/// rational or not, each span is the straight segment between two control
/// points), `None` when it has none. Each line keeps the curve's input
/// lines and feed.
fn polylines_as_lines(run: &Run) -> Option<Run> {
    let is_polyline = |p: &Piece| matches!(&p.curve, Curve::Nurbs(c) if c.degree == 1);
    if !run.pieces.iter().any(is_polyline) {
        return None;
    }
    let mut pieces = Vec::with_capacity(run.pieces.len());
    for p in &run.pieces {
        let clamped = match &p.curve {
            Curve::Nurbs(c) if c.degree == 1 => clamped_with_degree(c, 1).ok(),
            _ => None,
        };
        let Some(c) = clamped else {
            pieces.push(p.clone());
            continue;
        };
        let first = pieces.len();
        let mut prev = c.points[0];
        for &q in &c.points[1..] {
            if q == prev {
                continue;
            }
            pieces.push(Piece {
                curve: Curve::Line(Line::new(prev, q)),
                ..p.clone()
            });
            prev = q;
        }
        if pieces.len() == first {
            // A polygon of one point: the curve as it is.
            pieces.push(p.clone());
        }
    }
    Some(Run::new(pieces))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Vec3;

    /// Regression (LinuxCNC's `Ruota_dentata_p1.ngc`: one G6.2 curve of
    /// degree 5, faired at the machine's maximum feed, where its peak pass
    /// runs to its bound): `auto`'s two `fair` candidates differ only in
    /// how they fit lines, so on a run of one spline they fair the same
    /// curve. Sharing the run's memo, the second makes no fairing of its
    /// own, and each gives what it gives alone.
    #[cfg(feature = "std")]
    #[test]
    fn ruota_dentata_fair_candidates_on_a_spline_share_their_fairings() {
        let (n, degree) = (40usize, 5usize);
        let points: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new(i as f64, 0.3 * libm::sin(i as f64), 0.0))
            .collect();
        let inner = n - degree;
        let knots: Vec<f64> = (0..n + degree + 1)
            .map(|i| i.saturating_sub(degree).min(inner) as f64)
            .collect();
        let curve = Nurbs {
            degree,
            knots,
            points,
            weights: None,
        };
        curve.validate().unwrap();
        let run = Run::new(alloc::vec![Piece {
            curve: Curve::from(curve),
            rapid: false,
            source_lines: (1, 1),
            feed: None,
        }]);
        let fair = |lines| Fair {
            options: FairOptions {
                lines,
                ..FairOptions::default()
            },
        };
        let memo = RunMemo::default();
        let a = fair(LineFit::Sections)
            .smooth_run_with(&run, 0.05, &memo)
            .unwrap();
        let made = memo.fairings_held();
        assert!(made > 0);
        let b = fair(LineFit::ThroughShallowCorners)
            .smooth_run_with(&run, 0.05, &memo)
            .unwrap();
        assert_eq!(memo.fairings_held(), made);
        assert_eq!(a, fair(LineFit::Sections).smooth_run(&run, 0.05).unwrap());
        assert_eq!(
            b,
            fair(LineFit::ThroughShallowCorners)
                .smooth_run(&run, 0.05)
                .unwrap()
        );
        assert_eq!(a.pieces, b.pieces);
    }

    /// Two arcs of radius 10 and 0.5 mm each joined tangentially into an
    /// S, or turning the same way: the S steps its curvature vector by 0.2
    /// 1/mm at the joint, which a planner passes at most at
    /// `sqrt(J Ts / 0.2)` (`feed::junction::jump_cap`), and
    /// [`sampled_demand`] charges that, and the step over the next arc's
    /// length as a `dk/ds`; the same arcs without a step demand only what
    /// their curvature does. [`sampled_demands`]' integral charges the
    /// jump's demand over the next arc. The arcs LinuxCNC runs a G5.2
    /// block as meet so: before the step was charged (it was lost at the
    /// joint's repeated point), `fair` left a rippled G5.2 line as it was
    /// at every tube radius.
    #[test]
    fn a_curvature_step_between_tangent_arcs_is_charged() {
        use crate::geom::Arc;
        let z = Vec3::new(0.0, 0.0, 1.0);
        let arc = |a: Vec3, b: Vec3, c: Vec3, cw: bool| Piece {
            curve: Curve::Arc(Box::new(Arc::from_center(a, b, c, z, cw, 1, 1e-9).unwrap())),
            rapid: false,
            source_lines: (1, 1),
            feed: None,
        };
        let (r, sweep) = (10.0f64, 0.05f64);
        let c1 = Vec3::new(0.0, -r, 0.0);
        let at = |c: Vec3, angle: f64, sign: f64| {
            c + Vec3::new(r * angle.sin(), sign * r * angle.cos(), 0.0)
        };
        let (o, p) = (Vec3::ZERO, at(c1, sweep, 1.0));
        let c2 = p + (p - c1);
        let first = arc(o, p, c1, true);
        let s = [first.clone(), arc(p, at(c2, 0.0, -1.0), c2, false)];
        let bend = [first, arc(p, at(c1, 2.0 * sweep, 1.0), c1, true)];
        let pass = PeakPass::DEFAULT_MACHINE;
        let (d_s, d_bend) = (sampled_demands(&s, pass), sampled_demands(&bend, pass));
        // The bend: `k^2 = 0.01`, so `cbrt(0.01 / J)`; the S: a step of
        // 0.2 at the joint, `sqrt(0.2 / (J Ts))` = 0.1 s/mm, above its
        // `dk/ds` (0.2 over the next arc, 0.5 mm: `cbrt(0.4 / J)`).
        let (j, ts) = (20000.0f64, 0.001);
        let bend_demand = (0.01 / j).cbrt();
        assert!((d_bend.0 - bend_demand).abs() < 1e-12, "{d_bend:?}");
        assert!((d_s.0 - (0.2 / (j * ts)).sqrt()).abs() < 1e-12, "{d_s:?}");
        assert!((0.2 / (r * sweep) / j).cbrt() < d_s.0);
        // Integrals over the chords: the bend at its demand, the S's
        // first arc at the bend's and its second at the jump's.
        let chord = 2.0 * r * (0.5 * sweep).sin();
        assert!(
            (d_bend.1 - 2.0 * chord * bend_demand).abs() < 1e-12,
            "{d_bend:?}"
        );
        assert!(
            (d_s.1 - chord * (bend_demand + 0.1)).abs() < 1e-12,
            "{d_s:?}"
        );
    }

    #[test]
    fn defaults_are_valid_and_bad_options_are_named() {
        assert_eq!(FairOptions::default().validate(), Ok(()));
        let e = FairOptions {
            fit_share: 1.0,
            ..FairOptions::default()
        }
        .validate()
        .unwrap_err();
        assert_eq!(
            (e.method, e.option, e.value.as_str()),
            ("fair", "fit_share", "1.0")
        );
        let e = FairOptions {
            accuracy: 0.0,
            ..FairOptions::default()
        }
        .validate()
        .unwrap_err();
        assert_eq!((e.method, e.option), ("fair", "accuracy"));
        let e = FairOptions {
            precision: 0,
            ..FairOptions::default()
        }
        .validate()
        .unwrap_err();
        assert_eq!((e.option, e.value.as_str()), ("precision", "0"));
    }
}
