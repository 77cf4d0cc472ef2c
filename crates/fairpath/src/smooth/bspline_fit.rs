//! Method `bspline-fit`: dense runs of short segments are replaced by a
//! least-squares cubic B-spline fitted within the tolerance (Zhong, Chang,
//! Rubio, Luo, "A local tool path smoothening scheme for micromachining";
//! seed 002), long lines and real corners are kept and blended as
//! `bspline-corner` does (seed 000).
//!
//! Steps, with what the seed says and what is done here:
//!
//! 1. **Run detection** (seed section 3: "segments shorter than a
//!    predefined threshold L"; nothing about angles or minimum size): see
//!    [`super::fit_sections`] for the rule (segment length, turning angle,
//!    implied chord error against the tolerance, minimum number of points).
//! 2. **Parameters** by chord length (seed eqs. 4-5), in mm instead of
//!    `[0, 1]` (the geometry is the same; `|C'|` is then about 1), after
//!    points on the polyline are added inside long segments and next to
//!    sharply turning vertices, where least squares would otherwise not see
//!    the moves between vertices (not in the seed; [`super::fit_fill`]).
//! 3. **Knots**: the seed's eq. 6 is the averaging formula for
//!    *interpolation*; for fewer control points than data its source (Piegl
//!    and Tiller eqs. 9.68-9.69) spreads the knots so that each span holds
//!    the same number of parameters: that is used ([`averaged_knots`]).
//! 4. **Control points**: the seed's linear least squares, plus a fairness
//!    term `lambda * integral |C''|^2 du` (the seed has none; without it,
//!    more control points than the data support wiggle inside the band).
//!    `lambda = fairness * s^3 / pi^4` for mean segment length `s`: a
//!    smoothing spline damps wavelengths below `2 pi (lambda / rho)^(1/4)`
//!    for `rho = 1 / s` data per mm, here two segments, i.e. noise and
//!    rounding, while its bias on a circle of radius `R`,
//!    `(lambda / rho) / R^3 = (s / pi)^4 / R^3`, stays below 2% of the
//!    tolerance for every vertex the detection accepts. When no fit passes,
//!    `lambda / 16` and then 0 are tried. When it passes, the weights are
//!    raised by 4 up to [`FAIRNESS_RAISES`] times while the fit still
//!    passes: the flattest fit the band allows, seed 003's aim of moving
//!    the path inside the tolerance tube to lower its curvature
//!    ([`fit_polyline_faired`]). Optionally
//!    ([`BsplineFitOptions::jerk_fairness`], off by default; `auto` tries
//!    it as a candidate) a jerk term `mu * integral |C'''|^2` spreads
//!    changes of curvature. The normal equations are banded
//!    (half bandwidth 3) and solved by banded Cholesky: linear time.
//! 5. **Check**: the seed checks the deviation at the data points only.
//!    Here [`span_errors`] bounds the distance from *every* point of the
//!    fit to the polyline (a proof in its documentation), and also requires
//!    every data point within the target of the fit. The target is
//!    `band_use * tolerance` ([`BAND_USE`] by default: the rest covers the
//!    dropped zero-length moves and the verifier's accuracy).
//! 6. **Control-point count**: the seed adds one control point at a time
//!    from 4. Here the count doubles until a fit passes, bisection narrows
//!    it to within 1/8, and from the largest failing count knots are
//!    inserted at the middle of every span whose bound fails (knots go
//!    where the error is) until it passes; the passing fit with fewer
//!    control points is kept. About `2 log2(h)` fits of linear cost.
//! 7. **Joins** (left open by the seed, section 4: "the connections between
//!    the approximated curves and long line segments should be solved in
//!    future work"): where a section meets a kept segment, the fit also
//!    takes a piece of that segment (a lead-in or lead-out of at most
//!    0.4 of it and 80 tolerances; [`super::fit_chain`]), so that
//!    it rounds the corner at the section's end vertex within the band
//!    instead of leaving that vertex along the segment. The fit starts
//!    exactly at the lead point (the end control point), tangent to the
//!    segment with zero curvature (the three end control points on the
//!    segment's line, [`EndCondition::Tangent`]), so the joint is G2; the
//!    rest of the segment and the corners beyond it are smoothed by
//!    `bspline-corner`, whose transitions also end tangent to their
//!    segments with zero curvature. At run ends (and next to arcs) the fit
//!    ends free at the vertex, like `bspline-corner`'s lines.
//! 8. **Output**: long fits are cut at every [`BsplineFitOptions::max_piece_spans`]-th
//!    knot into pieces that are the same curve (C2 joints), so each piece
//!    carries the input lines and the lowest feed of the moves it replaces.
//!
//! A section whose fit never passes is left to `bspline-corner`. Counts in
//! [`SmoothedRun`]: `transitions` counts the corners replaced, by transition
//! curves or by fits (the interior vertices of fitted sections).
//!
//! Files: this one holds the options and the method; the smoothing-weight
//! ladder and raises (steps 4 and seed 003) are in `fit_fairing.rs`, the
//! control-point search at given weights (steps 3, 5, 6) in `fit_search.rs`,
//! run detection in `fit_sections.rs`, the added points in `fit_fill.rs`,
//! and the walk along a chain with its joins (step 7) and output (step 8)
//! in `fit_chain.rs`.
//!
//! [`averaged_knots`]: crate::geom::fit::averaged_knots
//! [`span_errors`]: crate::geom::fit::span_errors
//! [`EndCondition::Tangent`]: crate::geom::fit::EndCondition::Tangent

use super::bspline_corner::{BsplineCorner, BsplineCornerOptions, BAND_USE};
use super::chains::smooth_by_chains;
use super::fit_sections::SectionOptions;
use super::{check_tolerance, SmoothError, SmoothedRun, Smoother};
use crate::geom::band_fit::RelaxOptions;
use crate::geom::Vec3;
use crate::path::Run;
use crate::smooth::{require, OptionError};

pub use super::fit_fairing::{
    fit_polyline, fit_polyline_faired, fit_polyline_weighted, SectionFit, FAIRNESS_RAISE,
    FAIRNESS_RAISES,
};
pub use super::run_memo::RunMemo;

/// Options of [`BsplineFit`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct BsplineFitOptions {
    /// Run detection thresholds.
    pub sections: SectionOptions,
    /// Options of the corner transitions in the sparse parts.
    pub corner: BsplineCornerOptions,
    /// Multiplier of the default fairness weight (module docs, step 4);
    /// 0 turns the smoothing term off.
    pub fairness: f64,
    /// Weight of the jerk term `mu * integral |C'''|^2`,
    /// `mu = jerk_fairness * s^5 / pi^4` for mean segment length `s`
    /// (default 0: the seed's fit with its bending term only). Not in the
    /// seed: it spreads changes of curvature (the curvature ramps next to
    /// corner transitions, above all) over more length, which a jerk-limited
    /// machine runs faster, at the price of a fit further from the data.
    pub jerk_fairness: f64,
    /// Times the smoothing weights are raised by [`FAIRNESS_RAISE`] while
    /// the fit stays within the tolerance ([`fit_polyline_faired`]; 0: the
    /// weights as given).
    pub fairness_raises: usize,
    /// Relax every fit towards the fairest curve within the band
    /// ([`relax_in_band`], seed 003's aim; `None`: the least-squares fit as
    /// it is).
    ///
    /// [`relax_in_band`]: crate::geom::band_fit::relax_in_band
    pub relax: Option<RelaxOptions>,
    /// Share of the tolerance the fits may use, in `(0, BAND_USE]`.
    pub band_use: f64,
    /// Most knot spans in one output piece.
    pub max_piece_spans: usize,
    /// Keep the run's first segment out of the fits, so that the run
    /// starts straight along it (G2 with a line before it; `auto` cuts
    /// runs into sections at the middle of long lines).
    pub line_at_start: bool,
    /// The same for the run's last segment.
    pub line_at_end: bool,
}

impl BsplineFitOptions {
    /// Checks the ranges of the options.
    pub fn validate(&self) -> Result<(), OptionError> {
        let m = "bspline-fit";
        self.sections.validate_for(m)?;
        self.corner.validate_for(m)?;
        let nonneg = |x: f64| x >= 0.0 && x.is_finite();
        let f = self.fairness;
        require(nonneg(f), m, "fairness", f, "must be >= 0 and finite")?;
        let j = self.jerk_fairness;
        require(nonneg(j), m, "jerk_fairness", j, "must be >= 0 and finite")?;
        let b = self.band_use;
        require(
            b > 0.0 && b <= BAND_USE,
            m,
            "band_use",
            b,
            "must be in (0, 0.998]",
        )?;
        let n = self.max_piece_spans;
        require(n > 0, m, "max_piece_spans", n, "must be positive")?;
        if let Some(r) = &self.relax {
            if let Err((option, expected)) = r.check() {
                return Err(OptionError {
                    method: m,
                    option,
                    value: alloc::format!("{r:?}"),
                    expected,
                });
            }
        }
        Ok(())
    }
}

impl Default for BsplineFitOptions {
    fn default() -> Self {
        BsplineFitOptions {
            sections: SectionOptions::default(),
            corner: BsplineCornerOptions::default(),
            fairness: 1.0,
            jerk_fairness: 0.0,
            fairness_raises: FAIRNESS_RAISES,
            relax: Some(RelaxOptions::default()),
            band_use: BAND_USE,
            max_piece_spans: 64,
            line_at_start: false,
            line_at_end: false,
        }
    }
}

/// The `bspline-fit` method (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BsplineFit {
    pub options: BsplineFitOptions,
}

impl BsplineFit {
    fn check_options(&self) -> Result<(), SmoothError> {
        Ok(self.options.validate()?)
    }
}

impl Smoother for BsplineFit {
    fn name(&self) -> &'static str {
        "bspline-fit"
    }

    fn smooth_run(&self, run: &Run, tolerance: f64) -> Result<SmoothedRun, SmoothError> {
        self.smooth_run_memo(run, tolerance, None)
    }

    /// A window of a longer run: its cut ends keep their segments (the cut
    /// line's halves) out of the fits, so that the run goes on straight
    /// across each cut ([`BsplineFitOptions::line_at_start`]).
    fn smooth_window(
        &self,
        run: &Run,
        tolerance: f64,
        cut: (bool, bool),
    ) -> Result<SmoothedRun, SmoothError> {
        let mut options = self.options;
        options.line_at_start |= cut.0;
        options.line_at_end |= cut.1;
        BsplineFit { options }.smooth_run_memo(run, tolerance, None)
    }
}

impl BsplineFit {
    /// [`Smoother::smooth_run`], taking the fits of its sections from
    /// `memo` where they were made before (and leaving its own there): the
    /// same result, for callers that fit the same run several ways
    /// (`auto`'s candidates and sections).
    pub fn smooth_run_with(
        &self,
        run: &Run,
        tolerance: f64,
        memo: &RunMemo,
    ) -> Result<SmoothedRun, SmoothError> {
        self.smooth_run_memo(run, tolerance, Some(memo))
    }

    fn smooth_run_memo(
        &self,
        run: &Run,
        tolerance: f64,
        memo: Option<&RunMemo>,
    ) -> Result<SmoothedRun, SmoothError> {
        check_tolerance(tolerance)?;
        self.check_options()?;
        // The corner options are checked by the method that uses them.
        BsplineCorner {
            options: self.options.corner,
        }
        .smooth_run(&Run::default(), tolerance)?;
        let (start, end) = (run.start(), run.end());
        smooth_by_chains(run, tolerance, |chain, out| {
            let at = |p: Option<Vec3>, q: Option<&Vec3>| p.is_some() && p.as_ref() == q;
            let keep = (
                self.options.line_at_start && at(start, chain.pts.first()),
                self.options.line_at_end && at(end, chain.pts.last()),
            );
            self.smooth_chain(chain, tolerance, keep, memo, out)
        })
    }
}
