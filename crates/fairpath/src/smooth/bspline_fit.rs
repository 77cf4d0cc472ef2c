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

use super::bspline_corner::{BsplineCorner, BsplineCornerOptions, BAND_USE};
use super::chains::{smooth_by_chains, CleanTolerances, LineChain};
use super::fit_chain::{extend_sections, lead_point, push_fit, sub_chain, EXTEND_MAX_TURN};
use super::fit_fill::fill_segments;
use super::fit_sections::{dense_sections, SectionOptions};
use super::{check_tolerance, SmoothError, SmoothedRun, Smoother};
use crate::geom::band_fit::{relax_in_band, RelaxOptions};
use crate::geom::fit::{
    averaged_knots, chord_params, fit_cubic_weighted, span_errors, EndCondition,
};
use crate::geom::{Nurbs, Vec3};
use crate::path::Run;
use crate::smooth::{require, OptionError};
use alloc::vec::Vec;
use core::f64::consts::PI;

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

/// A fit of one section.
#[derive(Clone, Debug, PartialEq)]
pub struct SectionFit {
    /// The fitted clamped cubic B-spline, parameterised by chord length (mm).
    pub curve: Nurbs,
    /// Proven bound of its distance from the polyline (and of the data
    /// points' distance from it), mm.
    pub bound: f64,
    /// Fairness weight used (mm^3).
    pub lambda: f64,
    /// Number of least-squares fits solved in the search.
    pub fits: usize,
}

/// Rounds of knot insertion from the largest failing count.
const REFINE_ROUNDS: usize = 12;

/// Fits a cubic B-spline to the polyline `pts` (at least 2 points, no
/// zero-length segment) that starts at `pts[0]` and ends at the last point
/// exactly with the given end conditions, and whose every point lies within
/// `target` mm of the polyline (and every vertex within `target` of it).
/// `fairness` scales the smoothing term (module docs, step 4). `None` when
/// no fit passes.
pub fn fit_polyline(
    pts: &[Vec3],
    start: EndCondition,
    end: EndCondition,
    target: f64,
    fairness: f64,
) -> Option<SectionFit> {
    fit_polyline_weighted(pts, start, end, target, fairness, 0.0)
}

/// [`fit_polyline`] with the jerk term of
/// [`BsplineFitOptions::jerk_fairness`] as well.
pub fn fit_polyline_weighted(
    pts: &[Vec3],
    start: EndCondition,
    end: EndCondition,
    target: f64,
    fairness: f64,
    jerk_fairness: f64,
) -> Option<SectionFit> {
    fit_polyline_faired(pts, start, end, target, (fairness, jerk_fairness), 0, None)
}

/// Factor by which [`fit_polyline_faired`] raises the smoothing weights
/// at each step.
pub const FAIRNESS_RAISE: f64 = 4.0;

/// Default [`BsplineFitOptions::fairness_raises`]: up to `4^6 = 4096`
/// times the default weights.
pub const FAIRNESS_RAISES: usize = 6;

/// Least-squares solves per raise: the knots of the fit before, then
/// knots inserted where the raised fit misses.
const RAISE_SOLVES: usize = 3;

/// [`fit_polyline_weighted`] (weights `(fairness, jerk_fairness)`), then,
/// up to `raises` times, the same fit with both weights multiplied by
/// [`FAIRNESS_RAISE`], as long as it still passes: the fairest fit within
/// `target` that this ladder finds. Each raise solves on the knots of the
/// fit before it and, where it misses, inserts knots (at most
/// `RAISE_SOLVES` linear solves; a full control-point search per raise
/// planned the same but cost five times the fit on a 10,000-point row).
///
/// Seed 003 (Naseath 2007, chapter 3) lowers the curvature of a B-spline
/// tool path by moving its control points inside the tolerance tube,
/// iterating "until the spline touches the path tolerance". The weight of
/// a smoothing term plays that role here: raising it flattens the fit, and
/// the search (with its proven bound) keeps it within the band. The
/// seed's movement rules (categories, direction vectors, sensitivities)
/// are not used. On the issue-5 survey, 6 raises of 4 planned
/// `blur_torus.ngc` 0.74 -> 0.68 and `LHchips4.ngc` 0.65 -> 0.61 of the
/// original program; 2 raises of 16 and 8 of 2 did less.
pub fn fit_polyline_faired(
    pts: &[Vec3],
    start: EndCondition,
    end: EndCondition,
    target: f64,
    (fairness, jerk_fairness): (f64, f64),
    raises: usize,
    relax: Option<&RelaxOptions>,
) -> Option<SectionFit> {
    let n = pts.len().checked_sub(1)?;
    if n == 0 || target.is_nan() || target <= 0.0 {
        return None;
    }
    let mean = chord_params(pts)[n] / n as f64;
    if !(mean > 0.0 && mean.is_finite()) {
        return None;
    }
    // The smoothing weight follows the input's sampling, not the points
    // added on long segments.
    let lambda0 = fairness * mean * mean * mean / (PI * PI * PI * PI);
    let mu0 = jerk_fairness * mean * mean * mean * mean * mean / (PI * PI * PI * PI);
    let dense = fill_segments(pts, target);
    let pts = &dense[..];
    let params = chord_params(pts);
    let mut fits = 0;
    let ladder: &[(f64, f64)] = if lambda0 > 0.0 || mu0 > 0.0 {
        &[(lambda0, mu0), (lambda0 / 16.0, mu0 / 16.0), (0.0, 0.0)]
    } else {
        &[(0.0, 0.0)]
    };
    for (step, &(lambda, mu)) in ladder.iter().enumerate() {
        let Some((mut curve, mut bound)) =
            search(pts, &params, start, end, target, (lambda, mu), &mut fits)
        else {
            continue;
        };
        let mut lambda = lambda;
        // Raise the weights while the fit stays within the target (only
        // from the full weights: a section that needed less keeps it).
        if step == 0 {
            let mut mu = mu;
            for _ in 0..raises {
                let w = (lambda * FAIRNESS_RAISE, mu * FAIRNESS_RAISE);
                // The knots of the fit before, with knots inserted where
                // the raised fit misses (at most RAISE_SOLVES solves).
                let mut knots = curve.knots.clone();
                let mut passed = None;
                for _ in 0..RAISE_SOLVES {
                    let Some(a) = attempt(pts, &params, &knots, (start, end), w, &mut fits) else {
                        break;
                    };
                    if a.max <= target {
                        passed = Some((a.curve, a.max));
                        break;
                    }
                    let next = refine_knots(&a.curve.knots, &a.errs, target, min_span(&params));
                    if next.len() == knots.len() {
                        break;
                    }
                    knots = next;
                }
                let Some((c, b)) = passed else {
                    break;
                };
                (curve, bound, lambda, mu) = (c, b, w.0, w.1);
            }
        }
        // Relax towards the fairest curve the band allows, from the
        // default weights (the raised ones are what a least-squares fit
        // needed to flatten; the relaxation needs none of that).
        if let Some(opts) = relax {
            if let Ok(Some(r)) = relax_in_band(
                &curve,
                pts,
                &params,
                (start, end),
                target,
                (lambda0, mu0),
                opts,
            ) {
                (curve, bound) = (r.curve, r.bound);
            }
        }
        return Some(SectionFit {
            curve,
            bound,
            lambda,
            fits,
        });
    }
    None
}

/// One attempt: the curve and its largest span bound, with the span bounds.
struct Attempt {
    curve: Nurbs,
    errs: Vec<f64>,
    max: f64,
}

fn attempt(
    pts: &[Vec3],
    params: &[f64],
    knots: &[f64],
    ends: (EndCondition, EndCondition),
    (lambda, mu): (f64, f64),
    fits: &mut usize,
) -> Option<Attempt> {
    *fits += 1;
    let curve = fit_cubic_weighted(pts, params, knots, ends.0, ends.1, lambda, mu).ok()?;
    let errs = span_errors(&curve, pts, params);
    let max = errs.iter().copied().fold(0.0, f64::max);
    max.is_finite().then_some(Attempt { curve, errs, max })
}

/// Doubling, bisection, then knot insertion where the bound fails (module
/// docs, step 6). Returns the passing curve with fewest control points.
fn search(
    pts: &[Vec3],
    params: &[f64],
    start: EndCondition,
    end: EndCondition,
    target: f64,
    weights: (f64, f64),
    fits: &mut usize,
) -> Option<(Nurbs, f64)> {
    let smoothed = weights.0 > 0.0 || weights.1 > 0.0;
    let n = pts.len() - 1;
    let fixed = |e: EndCondition| match e {
        EndCondition::Free => 1,
        EndCondition::Tangent(_) => 3,
    };
    let h_min = (fixed(start) + fixed(end) + 1).max(4);
    // Without the smoothing term, at most one control point per data point
    // (Schoenberg-Whitney); with it, up to two per segment.
    let h_max = if smoothed { 2 * n + 8 } else { n + 1 }.max(h_min);
    let ends = (start, end);
    let try_count = |h: usize, fits: &mut usize| {
        let knots = averaged_knots(params, h);
        attempt(pts, params, &knots, ends, weights, fits)
    };
    let mut lo: Option<(usize, Attempt)> = None;
    let mut hi: Option<(usize, Attempt)> = None;
    let mut h = h_min;
    loop {
        match try_count(h, fits) {
            Some(a) if a.max <= target => {
                hi = Some((h, a));
                break;
            }
            Some(a) => lo = Some((h, a)),
            None => {}
        }
        if h >= h_max {
            break;
        }
        h = (2 * h).min(h_max);
    }
    // Bisection to within an eighth of the failing count.
    if let (Some((l, _)), Some((u, _))) = (&lo, &hi) {
        let (mut l, mut u) = (*l, *u);
        while u - l > (l / 8).max(1) {
            let mid = l + (u - l) / 2;
            match try_count(mid, fits) {
                Some(a) if a.max <= target => {
                    hi = Some((mid, a));
                    u = mid;
                }
                Some(a) => {
                    lo = Some((mid, a));
                    l = mid;
                }
                None => l = mid,
            }
        }
    }
    // Knot insertion from the largest failing count, to fewer control
    // points than the passing count (or the most the data support).
    let limit = hi.as_ref().map_or(usize::MAX, |(u, _)| *u);
    let min_span = min_span(params);
    let mut refined: Option<Attempt> = None;
    if let Some((_, mut a)) = lo {
        for _ in 0..REFINE_ROUNDS {
            let knots = refine_knots(&a.curve.knots, &a.errs, target, min_span);
            if knots.len() - 4 >= limit || knots.len() == a.curve.knots.len() {
                break;
            }
            match attempt(pts, params, &knots, ends, weights, fits) {
                Some(b) if b.max <= target => {
                    refined = Some(b);
                    break;
                }
                Some(b) => a = b,
                None => break,
            }
        }
    }
    match (refined, hi) {
        (Some(r), _) => Some((r.curve, r.max)),
        (None, Some((_, a))) => Some((a.curve, a.max)),
        (None, None) => None,
    }
}

/// The shortest knot span [`refine_knots`] splits, for data parameters
/// `params`.
fn min_span(params: &[f64]) -> f64 {
    MIN_SPAN_PER_SEGMENT
        * params
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min)
}

/// A knot span shorter than this share of the shortest data segment is not
/// split further: knots closer than the data cannot pull the fit nearer to
/// it, and only make the curvature ripple.
const MIN_SPAN_PER_SEGMENT: f64 = 0.25;

/// The knots plus the middle of every span whose bound exceeds `target`
/// and that is at least `min_span` long.
fn refine_knots(knots: &[f64], errs: &[f64], target: f64, min_span: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(knots.len() + errs.len());
    out.extend_from_slice(&knots[..4]);
    for (j, &e) in errs.iter().enumerate() {
        let s = 3 + j;
        let (a, b) = (knots[s], knots[s + 1]);
        if e > target && b - a >= min_span {
            let m = 0.5 * (a + b);
            if m > a && m < b {
                out.push(m);
            }
        }
        out.push(b);
    }
    out.extend_from_slice(&knots[knots.len() - 3..]);
    out
}

impl BsplineFit {
    fn check_options(&self) -> Result<(), SmoothError> {
        Ok(self.options.validate()?)
    }

    /// Smooths one chain: fits its dense sections, blends the corners
    /// between them. `keep_ends`: whether the chain's first (last) segment
    /// must stay out of the fits (a run end that [`BsplineFitOptions::line_at_start`]
    /// or `line_at_end` asks to keep straight).
    fn smooth_chain(
        &self,
        chain: &LineChain,
        tolerance: f64,
        keep_ends: (bool, bool),
        out: &mut SmoothedRun,
    ) {
        let o = &self.options;
        let corner = BsplineCorner { options: o.corner };
        let delta = tolerance * BAND_USE;
        let min_seg = CleanTolerances::from_tolerance(tolerance).min_segment;
        let q = &chain.pts;
        let nseg = chain.segments();
        // Sections to fit, last first. A section whose fit fails is split
        // around its sharpest vertex (the segment after it kept as a line
        // between the two fits) and the halves are tried on their own, so
        // one corner inside a section does not send all of it to the corner
        // method.
        // Sections that would take a run end's line it must keep lose it.
        let mut sections = dense_sections(q, tolerance, &o.sections);
        extend_sections(&mut sections, q, EXTEND_MAX_TURN);
        let mut todo: Vec<(usize, usize)> = sections
            .into_iter()
            .map(|(k, m)| {
                let k = if keep_ends.0 && k == 0 { 1 } else { k };
                let m = if keep_ends.1 && m == nseg {
                    nseg - 1
                } else {
                    m
                };
                (k, m)
            })
            .filter(|&(k, m)| m > k + 1)
            .collect();
        todo.reverse();
        // Where the last fit (or the chain start) left off: a vertex, and
        // the point on the segment after it where the fit ended (its lead-out).
        let mut cursor = (0, q[0]);
        while let Some((k, m)) = todo.pop() {
            let dir = |a: usize, b: usize| (q[b] - q[a]).normalized(0.0);
            let start = if k == 0 {
                EndCondition::Free
            } else {
                match dir(k - 1, k) {
                    Some(d) => EndCondition::Tangent(d),
                    None => continue,
                }
            };
            let end = if m == nseg {
                EndCondition::Free
            } else {
                match dir(m, m + 1) {
                    Some(d) => EndCondition::Tangent(d),
                    None => continue,
                }
            };
            // Lead-in and lead-out: the fit also takes a piece of the kept
            // segment before (after) it, so it can round the corner at its
            // end vertex instead of starting tangent to the segment there.
            let lead = |a: usize, b: usize| lead_point(q[a], q[b], tolerance, min_seg);
            let lead_in = if k > 0 && k > cursor.0 {
                lead(k, k - 1)
            } else {
                None
            };
            let lead_out = if m < nseg { lead(m, m + 1) } else { None };
            // The fit's ends as (vertex, point on the segment after it).
            let from = lead_in.map_or((k, q[k]), |p| (k - 1, p));
            let to = lead_out.map_or((m, q[m]), |p| (m, p));
            let section = sub_chain(chain, from, to);
            let Some(fit) = fit_polyline_faired(
                &section.pts,
                start,
                end,
                tolerance * o.band_use,
                (o.fairness, o.jerk_fairness),
                o.fairness_raises,
                o.relax.as_ref(),
            ) else {
                let min = o.sections.min_points;
                let turn = |i: usize| (q[i] - q[i - 1]).angle_to(q[i + 1] - q[i]);
                let sharpest =
                    (k + 1..m.saturating_sub(1)).max_by(|&a, &b| turn(a).total_cmp(&turn(b)));
                // A half too short to fit goes to the corner method; the
                // other is still tried (a sharp corner next to a section
                // end, such as a plunge, no longer sends all of it there).
                if let Some(j) = sharpest {
                    if m - j >= min {
                        todo.push((j + 1, m));
                    }
                    if j + 1 - k >= min {
                        todo.push((k, j));
                    }
                }
                continue;
            };
            if from.0 > cursor.0 || (from.0 == cursor.0 && from.1 != cursor.1) {
                corner.smooth_chain(&sub_chain(chain, cursor, from), delta, min_seg, out);
            }
            push_fit(&section, &fit.curve, o.max_piece_spans, out);
            out.transitions += (m - k + 1) - usize::from(k == 0) - usize::from(m == nseg);
            cursor = to;
        }
        if cursor.0 < nseg || cursor.1 != q[nseg] {
            let sub = sub_chain(chain, cursor, (nseg, q[nseg]));
            corner.smooth_chain(&sub, delta, min_seg, out);
        }
    }
}

impl Smoother for BsplineFit {
    fn name(&self) -> &'static str {
        "bspline-fit"
    }

    fn smooth_run(&self, run: &Run, tolerance: f64) -> Result<SmoothedRun, SmoothError> {
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
            self.smooth_chain(chain, tolerance, keep, out)
        })
    }
}
