//! Fairing inside a tolerance tube: the method of seed 003 (R. Naseath,
//! "Reducing curvature in tool paths by smoothing B-splines within a
//! tolerance", BYU 2007, chapter 3), built in full, in 3D, for open and
//! closed paths.
//!
//! The control points of a cubic B-spline are moved, iteration by
//! iteration, towards a straight line, each along a direction its category
//! gives it, each by a distance scaled by how strongly the curve follows
//! it, until the curve touches a tube of radius `R` around the original.
//! Same knots, same number of control points: only positions change.
//!
//! Section numbers are the thesis' own (its chapter 3 as printed; the
//! project's checklist counts them differently, 3.3 for categories up to
//! 3.8 for termination).
//!
//! | thesis | here |
//! |---|---|
//! | 3.2 overview, eq. 3-6 `k = (n-1)/n h / a^2`: flatter polygon, lower curvature | the whole module |
//! | 3.4 parsing: polygon, knots, `R`, precision, accuracy | [`fair_in_tube`], [`TubeFairOptions`] |
//! | 3.5 categories, line tests, smooth groups (eqs. 3-7 to 3-16) | [`categories`] |
//! | 3.6 direction vectors (eqs. 3-17 to 3-31, the 9.0 weight) | [`directions`] |
//! | 3.7 sensitivities, mock iteration (eqs. 3-32 to 3-38) | [`sensitivity`] |
//! | 3.8 maximum allowable distance (eq. 3-39), sampled at `precision` | [`tube`] |
//! | 3.9 move distances (eqs. 3-40 to 3-46, the worked example) | [`sensitivity`] |
//! | 3.10, 3.11 moving, termination | `iterate.rs` |
//! | 5.1 the U-to-V failure | [`guard`] |
//! | 5.1.1 closed paths | [`polygon`] |
//! | 5.1.2 3D | [`categories`], [`directions`] |
//! | beyond: the highest peaks lowered | [`peak`] |
//! | beyond: the turning minimised inside the tube | [`straighten`] |
//! | beyond: the tube measured to the original curve | [`slide`] |
//!
//! Where the thesis is silent or inconsistent, the choices (each
//! explained where it is made):
//! * a zero sign in the line tests counts as "not the same side" (a
//!   ripple; on the line through its neighbours, a still one);
//! * adjacent smooth groups are cut where the turning direction changes;
//! * a ripple point or single apex moves at most half way to the chord of
//!   its neighbours per iteration (all points move at once: a full step
//!   would swap a saw-tooth's phase instead of flattening it), and the
//!   other points of a smooth group no further than their apex;
//! * the maximum of eq. 3-40 is over the points that move;
//! * every polygon kept is inside the tube on a **sure bound** (the
//!   convex hull of the difference spline's Bezier spans), not only on the
//!   thesis' samples; a move that fails is made again with the sure
//!   allowance; the thesis' "previous polygon" is never needed, as no
//!   polygon outside the tube is ever taken;
//! * an iteration cap ([`TubeFairOptions::max_iterations`]);
//! * **ends never move** (the project's non-negotiable; the thesis lets
//!   them slide across the tube): [`EndRule`] pins them, or also keeps the
//!   direction of the end tangents; an end that joins a neighbouring piece
//!   keeps its first three control points (`keep_g2_start`, `keep_g2_end`),
//!   so position, tangent and curvature there are unchanged (the joint
//!   stays G2, indeed C2 in the curve's own parameter);
//! * **3D**: the line tests by the sign of the dot product of the two
//!   points' offsets from the line, everything else from sums, dot
//!   products and lengths, so a planar path tilted into 3D gives the same
//!   result as in its plane;
//! * **closed paths** (a clamped cubic whose first and last control points
//!   are the same point): indices wrap round the seam, which is pinned;
//! * **U to V**: a move that raises a span's peak curvature above the
//!   original's there is put back.
//!
//! Input: a clamped B-spline, the thesis' non-rational cubic (a NURBS
//! with equal weights is one) or, beyond the thesis, of any degree from 2
//! and rational (ours: its weights stay, its points move; the
//! difference curve is the rational basis applied to the moves, and its
//! Bezier spans' convex hulls still bound it, [`Basis`]; a control point's
//! parameter is its Greville abscissa at degrees other than 3,
//! [`sensitivity`]). [`as_fairable`] writes a quadratic, or an unclamped
//! curve, exactly as a clamped cubic (or a clamped curve of its own
//! degree) first ([`crate::geom::elevate`]).
//!
//! Constants of the thesis: [`APEX_WEIGHT`] (9.0), [`THESIS_PRECISION`]
//! (5), [`THESIS_ACCURACY`] (1%). Every other threshold is scaled from the
//! radius: `accuracy * R` is the resolution (how close to a line counts as
//! on it in the line tests, how tight the sure bound is, when the curve
//! touches the tube); [`STILL_SHARE`] of the radius is how close to the
//! chord of its neighbours a ripple point counts as on it.

pub mod categories;
pub mod directions;
pub mod guard;
mod iterate;
pub mod peak;
pub mod polygon;
pub mod sensitivity;
pub mod slide;
mod spans;
pub mod straighten;
pub mod tube;

pub use spans::Basis;

pub use directions::{APEX_WEIGHT, MIN_END_LEG_SHARE, RIPPLE_REACH_SHARE, STILL_SHARE};
pub use peak::PeakPass;
pub use slide::TubeMeasure;

use super::elevate::ElevateError;
use super::{Nurbs, NurbsError};
use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;
use polygon::Polygon;

/// Samples per knot interval the thesis used (section 4.2: "The precision
/// was set to 5").
pub const THESIS_PRECISION: usize = 5;

/// Share of the radius within which the thesis counted the curve as
/// touching the tube (section 4.2: "The accuracy of all tool paths was set
/// to 1%").
pub const THESIS_ACCURACY: f64 = 0.01;

/// Default iteration cap (ours: the thesis has none). The curve moves by
/// about `D_allow * min S` per iteration, so the allowance shrinks
/// geometrically and 1% is reached in tens of iterations on the thesis'
/// kinds of curves; the cap only bounds the work where it is not.
pub const DEFAULT_MAX_ITERATIONS: usize = 200;

/// Largest `precision` accepted (the work per iteration grows with it).
pub const MAX_PRECISION: usize = 1000;

/// Largest `max_iterations` accepted.
pub const MAX_ITERATIONS: usize = 100_000;

/// Fewest ring points for a closed path: the line tests look two points
/// either way. A closed curve with fewer is faired as an open one (its
/// ends, the seam, are pinned either way).
pub const MIN_RING: usize = 5;

/// What happens at the two ends of the curve (the run's endpoints, or the
/// seam of a closed path). Either way the end points themselves never
/// move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "kebab-case")
)]
pub enum EndRule {
    /// The end points stay; their neighbours move as their categories say
    /// (the end tangents may turn).
    #[default]
    Pinned,
    /// The end points stay and their neighbours slide along the end legs
    /// only, so the end tangents keep their directions.
    SlideAlongTangent,
}

/// Options of [`fair_in_tube`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TubeFairOptions {
    /// Radius `R` of the tube (mm): every point of the result lies within
    /// `R` of the original at the same parameter (of the original curve
    /// where [`TubeFairOptions::tube`] slides).
    pub radius: f64,
    /// Samples per knot interval of the thesis' maximum allowable distance
    /// ([`THESIS_PRECISION`]).
    pub precision: usize,
    /// Share of `R` within which the curve counts as touching the tube
    /// ([`THESIS_ACCURACY`]); `accuracy * R` is also how close to a line
    /// counts as on it and how tight the sure bound is.
    pub accuracy: f64,
    /// Most iterations ([`DEFAULT_MAX_ITERATIONS`]).
    pub max_iterations: usize,
    /// What the ends do.
    pub ends: EndRule,
    /// Keep the first three control points (the curve joins a neighbour
    /// there with G2).
    pub keep_g2_start: bool,
    /// Keep the last three control points.
    pub keep_g2_end: bool,
    /// Put back moves that raise the peak curvature locally ([`guard`]).
    pub peak_guard: bool,
    /// After the thesis' iterations, lower the highest peaks of curvature
    /// or of what it costs a planner with the room left in the tube
    /// ([`peak`], ours); [`PeakPass::Off`] for the thesis' method alone.
    pub peak_pass: PeakPass,
    /// How the iterations, the straightening and the peak pass measure
    /// the distance from the original ([`TubeMeasure`]: at equal
    /// parameters, the thesis' and the default, or to the original curve,
    /// ours).
    pub tube: TubeMeasure,
    /// After the thesis' iterations, minimise the turning inside the tube
    /// ([`straighten`], ours).
    pub straighten: bool,
}

impl TubeFairOptions {
    /// The thesis' settings for a tube of radius `radius`, ends pinned,
    /// the guard on, the peak pass on the default machine's speed caps.
    pub fn new(radius: f64) -> TubeFairOptions {
        TubeFairOptions {
            radius,
            precision: THESIS_PRECISION,
            accuracy: THESIS_ACCURACY,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            ends: EndRule::Pinned,
            keep_g2_start: false,
            keep_g2_end: false,
            peak_guard: true,
            peak_pass: PeakPass::DEFAULT_MACHINE,
            tube: TubeMeasure::EqualParameter,
            straighten: false,
        }
    }

    /// Checks every option's range, naming the first that fails.
    pub fn validate(&self) -> Result<(), TubeFairError> {
        let bad = |option: &'static str, value: String, expected: &'static str| {
            Err(TubeFairError::BadOption {
                option,
                value,
                expected,
            })
        };
        let r = self.radius;
        if !(r.is_finite() && r > 0.0) {
            return bad(
                "radius",
                format!("{r:?}"),
                "must be a positive number of mm",
            );
        }
        let p = self.precision;
        if !(1..=MAX_PRECISION).contains(&p) {
            return bad("precision", format!("{p}"), "must be in 1..=1000");
        }
        let a = self.accuracy;
        if !(a > 0.0 && a < 1.0) {
            return bad("accuracy", format!("{a:?}"), "must be in (0, 1)");
        }
        let n = self.max_iterations;
        if !(1..=MAX_ITERATIONS).contains(&n) {
            return bad("max_iterations", format!("{n}"), "must be in 1..=100000");
        }
        if !self.peak_pass.is_valid() {
            return bad(
                "peak_pass",
                format!("{:?}", self.peak_pass),
                "its limits must be positive numbers",
            );
        }
        Ok(())
    }

    /// `accuracy * R` (mm): the resolution of the fairing.
    pub fn resolution(&self) -> f64 {
        self.accuracy * self.radius
    }
}

/// Why a curve cannot be faired.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TubeFairError {
    /// An option out of range.
    #[error("option {option} = {value}: {expected}")]
    BadOption {
        option: &'static str,
        value: String,
        expected: &'static str,
    },
    /// The curve is not a valid NURBS.
    #[error("invalid curve: {0}")]
    Invalid(#[from] NurbsError),
    /// The weights differ, where only non-rational B-splines are taken
    /// (the fairing itself takes rational ones: kept for the callers that
    /// report such curves).
    #[error("the curve is rational (its weights differ): only non-rational B-splines are faired")]
    Rational,
    /// Degree 1 (a polyline), where a curve is asked for.
    #[error("the curve has degree {0}: only B-splines of degree 2 and above are faired")]
    Degree(usize),
    /// The knot vector does not start and end with `degree + 1` equal
    /// knots.
    #[error("the curve is not clamped (its first and last knots are not each degree + 1 times)")]
    NotClamped,
    /// A knot repeated more than the degree: the curve jumps there.
    #[error("the curve is not continuous at knot {0}")]
    Discontinuous(f64),
}

/// `curve` written exactly as a clamped B-spline [`fair_in_tube`] takes:
/// a curve of degree 3 or more as it is (clamped by knot insertion if it
/// is not), a quadratic raised to degree 3 (the same curve, each interior
/// knot once more, so it keeps its C1 continuity there), a NURBS with
/// equal weights without them; a rational curve keeps its weights (the
/// fairing moves its points only). Refused:
/// * degree 1 ([`TubeFairError::Degree`]): a polyline; as a cubic its
///   vertices are triple knots, corners the fairing cannot round (the
///   method `fair` takes such a curve as its lines instead);
/// * curves that jump at a knot ([`TubeFairError::Discontinuous`]).
pub fn as_fairable(curve: &Nurbs) -> Result<Nurbs, TubeFairError> {
    curve.validate()?;
    if curve.degree < 2 {
        return Err(TubeFairError::Degree(curve.degree));
    }
    if curve.degree >= 3 && super::elevate::is_clamped(curve) {
        return Ok(curve.clone());
    }
    let rational = spans::Basis::of(curve).weights.is_some();
    let c = Nurbs {
        weights: if rational {
            curve.weights.clone()
        } else {
            None
        },
        ..curve.clone()
    };
    super::elevate::clamped_with_degree(&c, curve.degree.max(3)).map_err(|e| match e {
        ElevateError::Invalid(e) => TubeFairError::Invalid(e),
        ElevateError::Discontinuous(t) => TubeFairError::Discontinuous(t),
        ElevateError::Degree { from, .. } => TubeFairError::Degree(from),
    })
}

/// How the iterations ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Termination {
    /// The sampled distance came within `accuracy * R` of the tube
    /// (section 3.11).
    Touching,
    /// The sure bound left no room for another move.
    TubeFull,
    /// No control point could move (all straight or pinned, or every move
    /// put back by the curvature guard).
    Stationary,
    /// `max_iterations` were done.
    IterationCap,
}

/// One iteration that was kept.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IterationRecord {
    /// Largest sampled distance from the original after it (mm).
    pub max_deviation: f64,
    /// Sure bound of that distance (mm), at most `R`.
    pub deviation_bound: f64,
    /// Largest control-point move (mm).
    pub largest_move: f64,
    /// Control points the curvature guard put back.
    pub undone: usize,
    /// Whether the move was made with the sure allowance (the thesis'
    /// sampled one would have left the tube).
    pub sure_step: bool,
}

/// A faired curve and what the fairing did.
#[derive(Clone, Debug, PartialEq)]
pub struct Faired {
    /// The same knots, weights and number of control points, points moved.
    pub curve: Nurbs,
    /// One record per iteration kept.
    pub iterations: Vec<IterationRecord>,
    pub termination: Termination,
    /// Whether it was faired as a closed path.
    pub closed: bool,
    /// Control points the curvature guard put back, in all.
    pub undone: usize,
    /// Sure bound of the distance from the original as the tube measures
    /// it ([`TubeFairOptions::tube`]; the iterations' at equal parameters)
    /// (mm), at most `R`.
    pub deviation_bound: f64,
    /// That distance sampled (mm).
    pub max_deviation: f64,
    /// What the peak pass did (all zero when it is off).
    pub peak_pass: peak::PeakPassRecord,
    /// What the straightening did (all zero when it is off).
    pub straightened: straighten::StraightenRecord,
}

/// Fairs the clamped B-spline `curve` (the thesis' non-rational cubic, or
/// of degree 2 and above, rational or not: the weights stay) inside a tube
/// of radius `opts.radius` around it (see the module documentation): every
/// point of the result lies within the radius of the original at the same
/// parameter, or with [`TubeMeasure::Sliding`] of the original curve (on a
/// sure bound either way), its end points are the original's bit for bit,
/// its knots and weights are the original's.
pub fn fair_in_tube(curve: &Nurbs, opts: &TubeFairOptions) -> Result<Faired, TubeFairError> {
    opts.validate()?;
    curve.validate()?;
    if curve.degree < 2 {
        return Err(TubeFairError::Degree(curve.degree));
    }
    let (u, m) = (&curve.knots, curve.points.len());
    let (k, ends) = (u.len(), curve.degree + 1);
    if u[..ends].iter().any(|&x| x != u[0]) || u[k - ends..].iter().any(|&x| x != u[k - 1]) {
        return Err(TubeFairError::NotClamped);
    }
    let basis = spans::Basis::of(curve);
    let pts = &curve.points;
    let closed = pts[0] == pts[m - 1] && m > MIN_RING;
    let poly = Polygon::new(m, closed);
    let n = poly.n;
    let mut pinned: Vec<bool> = (0..n).map(|i| poly.is_end(i)).collect();
    let keep = [(opts.keep_g2_start, 0isize), (opts.keep_g2_end, -1)];
    for (keep, from) in keep {
        if keep {
            for j in 0..3 {
                // Ring points 0, 1, 2 at the start; n-1, n-2, n-3 at the
                // end (a closed path: m-1 is the seam, ring point 0).
                let i = if from == 0 {
                    Some(j)
                } else if closed {
                    poly.at(0, -(j as isize))
                } else {
                    poly.at(n - 1, -(j as isize))
                };
                if let Some(i) = i.filter(|&i| i < n) {
                    pinned[i] = true;
                }
            }
        }
    }
    let legs = poly.end_legs().map(|(e, s)| pts[e].dist(pts[s]));
    let original = slide::Original::new(&basis, pts);
    let setup = iterate::Setup {
        basis,
        orig: pts,
        poly,
        pinned,
        legs,
        opts,
        original: original.as_ref(),
    };
    let mut out = setup.run();
    let mut peak_pass = peak::PeakPassRecord::default();
    let mut straightened = straighten::StraightenRecord::default();
    let reference = guard::PeakReference::new(&basis, pts, opts.accuracy);
    let movable: Vec<bool> = (0..m)
        .map(|i| {
            // Ring point of control point i (a closed path's last is
            // the seam), and whether the end rule lets it turn the
            // end tangent.
            let ring = if closed && i == m - 1 { 0 } else { i };
            let next_to_end = i == 1 || i + 2 == m;
            let slides = next_to_end && opts.ends == EndRule::SlideAlongTangent;
            !setup.pinned[ring] && !slides
        })
        .collect();
    if opts.straighten {
        let s = straighten::Straightening {
            basis,
            orig: pts,
            movable: movable.clone(),
            radius: opts.radius,
            resolution: opts.resolution(),
            reference: opts.peak_guard.then_some(&reference),
            tube: opts.tube,
            original: original.as_ref(),
        };
        straightened = s.run(&mut out.points, out.bound);
        if straightened.kept > 0.0 {
            out.bound = straightened.deviation_bound;
        }
    }
    if opts.peak_pass != PeakPass::Off {
        let pass = peak::Lowering {
            basis,
            orig: pts,
            movable,
            radius: opts.radius,
            resolution: opts.resolution(),
            reference: opts.peak_guard.then_some(&reference),
            measure: opts.peak_pass,
            floor: reference.floor,
            bound: out.bound,
            tube: opts.tube,
            original: original.as_ref(),
        };
        peak_pass = pass.run(&mut out.points);
        if peak_pass.moves > 0 {
            out.bound = peak_pass.deviation_bound;
        }
    }
    if peak_pass.moves > 0 || straightened.kept > 0.0 {
        out.sampled = opts.tube.sampled(
            &out.points,
            pts,
            original.as_ref(),
            &basis,
            opts.precision,
            opts.resolution(),
        );
    }
    let mut faired = curve.clone();
    faired.points = out.points;
    debug_assert!(faired.points[0] == pts[0] && faired.points[m - 1] == pts[m - 1]);
    Ok(Faired {
        curve: faired,
        iterations: out.records,
        termination: out.termination,
        closed,
        undone: out.undone,
        deviation_bound: out.bound,
        max_deviation: out.sampled,
        peak_pass,
        straightened,
    })
}
