//! Writes a NURBS piece as a spline block: G6.2 (Fanuc NURBS
//! interpolation, also read by LinuxCNC master) or G5.2/G5.3 blocks
//! (LinuxCNC). Pure formatting: the caller places the text.
//!
//! What the written text guarantees (as it reads back, see
//! [`crate::spline`]):
//! * Coordinates are rounded to `decimals` in the program's units, so each
//!   control point moves by at most `sqrt(3)/2 10^-decimals` units; a NURBS
//!   point is a convex combination of its control points, so the curve
//!   moves by no more than that either.
//! * Weights are scaled so that the largest is 1 (the curve does not
//!   change) and written with at least [`WEIGHT_DIGITS`] significant
//!   digits: relative error `e <= 5e-10`, which moves the curve by at most
//!   `2 e / (1 - e)` times the largest distance between the curve and a
//!   control point (the rational basis functions change by that factor at
//!   most and sum to 1).
//! * Knots are written as integers (LinuxCNC master refuses others). When
//!   an affine map of the knot vector puts every knot within
//!   [`KNOT_ROUNDING`] (a fraction of the shortest knot span) of an
//!   integer no larger than [`MAX_KNOT`], those integers are written: a
//!   knot moves by at most `1e-9` of the span next to it, which moves the
//!   curve by about `1e-9` times the degree times the longest control
//!   polygon leg. Otherwise a non-rational cubic whose interior knots are
//!   simple gets its knots rounded to integers of their affine image on
//!   `[0, MAX_KNOT]` where that moves it by at most
//!   [`SplineWriteOptions::knot_shift_mm`], on a sure bound
//!   (`knot_shift_bound`): its control points are written as they are,
//!   so it stays C2. Only then is the curve written as its Bezier spans
//!   joined with knots of multiplicity `degree` at `1, 2, ...`: the knot
//!   values then do not change the curve, but its written control points
//!   are rounded on their own at every joint, which is only C0 as it
//!   reads back, and a jerk-limited planner meets a curvature step at each
//!   (a fit whose last span was shorter than the others: `auto` on the
//!   thesis' design wave read back slower than its curves, and was kept as
//!   written; measurements: docs/tuning.md, `write_spline`).
//! * No NaN, no empty block, the first control point written is the
//!   curve's first point (the caller makes it the current position, and
//!   gives its decimals in [`SplineWriteOptions::start_decimals`] when a
//!   short move before the block was written finer: a first control point
//!   that is not the current position reads back as a straight move of a
//!   fraction of a micrometre to it, with a corner at each end).

use crate::axes::AXIS_LETTERS;
use crate::error::WriteError;
use crate::write_gcode::fmt_fixed;
use fairpath::controller::linuxcnc::g5_2_blocks_of;
use fairpath::controller::Plane;
use fairpath::geom::{Nurbs, ParamCurve, Vec3};

/// Significant digits of written weights (at least).
pub const WEIGHT_DIGITS: i32 = 10;
/// Largest distance of a normalised knot from its integer, in units of the
/// shortest non-empty knot span, for the knots to be written as they are.
pub const KNOT_ROUNDING: f64 = 1e-9;
/// Largest integer knot written for a curve's own knot vector.
pub const MAX_KNOT: f64 = 1e6;
/// Multipliers of the shortest knot span tried as the unit of the
/// normalised knot vector (spans of 1/2, 1/3, ... of the shortest one).
const KNOT_UNITS: usize = 12;

/// How a spline block is written.
#[derive(Clone, Debug, PartialEq)]
pub struct SplineWriteOptions {
    /// Millimetres per program unit (1 for G21, 25.4 for G20).
    pub mm_per_unit: f64,
    /// Decimals of coordinates, in program units (at most 15).
    pub decimals: usize,
    /// Decimals of the first control point's coordinates when they are
    /// more than `decimals` (at most 15): the current position's, where the
    /// move before the block was written finer.
    pub start_decimals: Option<usize>,
    /// Write a decimal point in every coordinate, knot and weight (`X5.`,
    /// `K1.`): Fanuc controls read `X5` as 5 least increments (5 um).
    pub decimal_point: bool,
    /// Line ending written after every line.
    pub line_ending: &'static str,
    /// The program is in G91 at this point: the block is written between a
    /// `G90` and a `G91` line (its coordinates absolute).
    pub incremental: bool,
    /// An F word's value, as it is to be written (program units), put on
    /// the block's first line.
    pub feed: Option<String>,
    /// How far (mm) rounding the curve's knots to integers may move it
    /// when they do not normalise exactly (see the module docs); 0 writes
    /// such a curve as its Bezier spans.
    pub knot_shift_mm: f64,
}

impl Default for SplineWriteOptions {
    fn default() -> Self {
        SplineWriteOptions {
            mm_per_unit: 1.0,
            decimals: 4,
            start_decimals: None,
            decimal_point: false,
            line_ending: "\n",
            incremental: false,
            feed: None,
            knot_shift_mm: 0.0,
        }
    }
}

/// The G6.2 form to write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum G6Dialect {
    /// LinuxCNC master: `Q<method>` on the first line (1: biarcs at
    /// constant parameter steps, 2: biarcs at arc-length steps, 3: straight
    /// feeds), knot-only lines as `G6.2 K..`, and a `G1` to the end point
    /// after the block ([`g6_2_block`]). LinuxCNC runs G6.2 in the plane
    /// only, so the curve must lie in `plane` (through its first point).
    /// Orders 2 to 8.
    Linuxcnc { plane: Plane, method: u8 },
    /// Fanuc's form: no Q, knot-only lines as bare `K..`, 3D, degrees 1
    /// to `max_degree` (Fanuc: 3, orders 2 to 4, [`G6Dialect::FANUC`]; a
    /// generic control that runs a program of higher-order G6.2 blocks
    /// runs that order too).
    Fanuc { max_degree: usize },
}

impl G6Dialect {
    /// Fanuc's G6.2: orders 2 to 4.
    pub const FANUC: G6Dialect = G6Dialect::Fanuc { max_degree: 3 };
}

struct Fmt<'a> {
    o: &'a SplineWriteOptions,
}

impl Fmt<'_> {
    fn point(&self, s: String) -> String {
        if self.o.decimal_point && !s.contains('.') {
            s + "."
        } else {
            s
        }
    }
    fn coord(&self, v_mm: f64) -> String {
        self.coord_with(v_mm, self.o.decimals)
    }
    fn coord_with(&self, v_mm: f64, decimals: usize) -> String {
        self.point(fmt_fixed(v_mm / self.o.mm_per_unit, decimals))
    }
    fn knot(&self, k: f64) -> String {
        self.point(fmt_fixed(k, 0))
    }
    /// A weight (0 < w <= 1) with [`WEIGHT_DIGITS`] significant digits.
    fn weight(&self, w: f64) -> Result<String, WriteError> {
        let mag = w.log10().floor() as i32;
        let d = (WEIGHT_DIGITS - 1 - mag).clamp(0, 15) as usize;
        let s = fmt_fixed(w, d);
        let back: f64 = s.parse().unwrap_or(f64::NAN);
        if !(back > 0.0 && ((back - w) / w).abs() <= 0.5 * 10f64.powi(1 - WEIGHT_DIGITS)) {
            return Err(WriteError::SplineCurve(format!(
                "weight {w} (relative to the largest) is too small to write"
            )));
        }
        Ok(self.point(s))
    }
}

fn check_options(o: &SplineWriteOptions) -> Result<(), WriteError> {
    if !(o.mm_per_unit.is_finite() && o.mm_per_unit > 0.0) {
        return Err(WriteError::SplineOptions(
            "mm_per_unit must be positive and finite",
        ));
    }
    if o.decimals > 15 || o.start_decimals.is_some_and(|d| d > 15) {
        return Err(WriteError::SplineOptions("at most 15 decimals"));
    }
    if o.line_ending.is_empty() {
        return Err(WriteError::SplineOptions("empty line ending"));
    }
    Ok(())
}

fn check_curve(n: &Nurbs) -> Result<(), WriteError> {
    let ok = n.points.iter().all(|p| p.is_finite())
        && n.knots.iter().all(|k| k.is_finite())
        && n.weights
            .as_ref()
            .is_none_or(|w| w.iter().all(|w| w.is_finite() && *w > 0.0));
    if !ok {
        return Err(WriteError::NotFinite);
    }
    // The same checks as Nurbs::new (the fields are public).
    Nurbs::new(
        n.degree,
        n.knots.clone(),
        n.points.clone(),
        n.weights.clone(),
    )
    .map(|_| ())
    .map_err(|e| WriteError::SplineCurve(format!("invalid NURBS: {e:?}")))
}

/// Weights scaled so that the largest is 1 (all 1 for a B-spline).
fn unit_weights(n: &Nurbs) -> Vec<f64> {
    match &n.weights {
        None => vec![1.0; n.points.len()],
        Some(w) => {
            let m = w.iter().fold(0.0f64, |a, &b| a.max(b));
            w.iter().map(|x| x / m).collect()
        }
    }
}

/// Multiplicity of `k` at the start of `knots[from..]`.
fn run_len(knots: &[f64], from: usize) -> usize {
    knots[from..]
        .iter()
        .take_while(|&&k| k == knots[from])
        .count()
}

/// The knot vector as integers (an affine image within [`KNOT_ROUNDING`]
/// of the shortest span), when there is one.
fn integer_knots(knots: &[f64]) -> Option<Vec<f64>> {
    let (a, b) = (knots[0], knots[knots.len() - 1]);
    let min_span = knots
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|&d| d > 0.0)
        .fold(f64::INFINITY, f64::min);
    if !(min_span.is_finite() && b > a) {
        return None;
    }
    (1..=KNOT_UNITS).find_map(|unit| {
        let scale = unit as f64 / min_span;
        if (b - a) * scale > MAX_KNOT {
            return None;
        }
        let ks: Vec<f64> = knots.iter().map(|k| ((k - a) * scale).round()).collect();
        let close = knots
            .iter()
            .zip(&ks)
            .all(|(k, r)| ((k - a) * scale - r).abs() <= KNOT_ROUNDING * unit as f64);
        close.then_some(ks)
    })
}

/// The knots of the non-rational cubic `n` (clamped, interior knots
/// simple) rounded to integers of the affine image of them on
/// `[0, MAX_KNOT]`, where that keeps every span non-empty and moves the
/// curve by at most `max_shift_mm` ([`knot_shift_bound`]); `None` where it
/// does not. The finest integers are taken, not the coarsest that keep
/// within `max_shift_mm`: a knot moved by a share of its span moves the
/// curvature by about that share, and on the thesis' design wave (spans
/// of 100 and 101 units) the text read back planned slower than the
/// curves (measurements: docs/tuning.md, `rounded_knots`).
fn rounded_knots(n: &Nurbs, max_shift_mm: f64) -> Option<Vec<f64>> {
    let rational = n
        .weights
        .as_ref()
        .is_some_and(|w| w.iter().any(|&x| x != w[0]));
    let k = &n.knots;
    let m = k.len();
    let p = n.degree;
    if p != 3 || rational || max_shift_mm.is_nan() || max_shift_mm <= 0.0 {
        return None;
    }
    let interior = &k[p + 1..m - p - 1];
    let simple = interior.windows(2).all(|w| w[1] > w[0])
        && interior.first().is_none_or(|&x| x > k[p])
        && interior.last().is_none_or(|&x| x < k[m - p - 1]);
    let (a, b) = (k[0], k[m - 1]);
    if !simple || b.partial_cmp(&a) != Some(core::cmp::Ordering::Greater) {
        return None;
    }
    let scale = MAX_KNOT / (b - a);
    let ints: Vec<f64> = k.iter().map(|x| ((x - a) * scale).round()).collect();
    // Every span of the curve stays a span (its ends differ).
    let kept = k
        .windows(2)
        .zip(ints.windows(2))
        .all(|(w, r)| (w[1] > w[0]) == (r[1] > r[0]));
    if !kept {
        return None;
    }
    let mapped: Vec<f64> = ints.iter().map(|r| a + r / scale).collect();
    let moved = Nurbs::new(p, mapped, n.points.clone(), None).ok()?;
    (knot_shift_bound(n, &moved) <= max_shift_mm).then_some(ints)
}

/// A sure bound (mm, up to f64 rounding) of the distance at equal
/// parameters between two non-rational cubics on the same parameter
/// interval whose interior knots are simple (so both are C2): between
/// consecutive knots of either, each is one cubic polynomial, fixed by its
/// points and first derivatives at the two ends (its Bezier points `C0`,
/// `C0 + h C0' / 3`, `C1 - h C1' / 3`, `C1`), and the difference of two
/// cubics lies in the convex hull of the difference of their Bezier points.
fn knot_shift_bound(a: &Nurbs, b: &Nurbs) -> f64 {
    let mut breaks: Vec<f64> = a.knots.iter().chain(&b.knots).copied().collect();
    breaks.sort_by(f64::total_cmp);
    breaks.dedup();
    let bezier = |c: &Nurbs, t0: f64, t1: f64| {
        let h = t1 - t0;
        let (p0, p1) = (c.eval(t0), c.eval(t1));
        let (d0, d1) = (c.deriv1(t0), c.deriv1(t1));
        [p0, p0 + d0 * (h / 3.0), p1 - d1 * (h / 3.0), p1]
    };
    breaks
        .windows(2)
        .map(|w| {
            let (x, y) = (bezier(a, w[0], w[1]), bezier(b, w[0], w[1]));
            (0..4).map(|i| (x[i] - y[i]).norm()).fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

/// The curve with a clamped knot vector of integers, interior knots of
/// multiplicity at most the degree: its own knots when they normalise, or
/// when rounded they move it by at most `knot_shift_mm` ([`rounded_knots`];
/// see the module docs), else its Bezier spans joined at `1, 2, ...`.
fn integer_form(n: &Nurbs, knot_shift_mm: f64) -> Result<Nurbs, WriteError> {
    let p = n.degree;
    let m = n.knots.len();
    let clamped = run_len(&n.knots, 0) == p + 1 && run_len(&n.knots, m - p - 1) == p + 1;
    let mut i = p + 1;
    let mut interior_ok = true;
    while i < m - p - 1 {
        let r = run_len(&n.knots, i);
        interior_ok &= r <= p;
        i += r;
    }
    if clamped && interior_ok {
        if let Some(knots) = integer_knots(&n.knots) {
            return Ok(Nurbs { knots, ..n.clone() });
        }
        if let Some(knots) = rounded_knots(n, knot_shift_mm) {
            return Ok(Nurbs { knots, ..n.clone() });
        }
    }
    let spans = n.bezier_spans();
    let rational = n.weights.is_some();
    let mut points: Vec<Vec3> = Vec::new();
    let mut weights: Vec<f64> = Vec::new();
    let mut knots = vec![0.0; p + 1];
    for (s, span) in spans.iter().enumerate() {
        let w = span.weights.clone().unwrap_or_else(|| vec![1.0; p + 1]);
        if s > 0 {
            let (last, lw) = (points[points.len() - 1], weights[weights.len() - 1]);
            if last != span.points[0] || (rational && lw != w[0]) {
                return Err(WriteError::SplineCurve(
                    "the curve is not continuous (a knot repeated more than its degree)".into(),
                ));
            }
            knots.extend(std::iter::repeat_n(s as f64, p));
        }
        let skip = usize::from(s > 0);
        points.extend_from_slice(&span.points[skip..]);
        weights.extend_from_slice(&w[skip..]);
    }
    knots.extend(std::iter::repeat_n(spans.len() as f64, p + 1));
    Ok(Nurbs {
        degree: p,
        knots,
        points,
        weights: rational.then_some(weights),
    })
}

/// Checks that every control point lies in `plane` through the first one,
/// within half a unit of the last written decimal.
fn check_planar(points: &[Vec3], plane: Plane, o: &SplineWriteOptions) -> Result<(), WriteError> {
    let off0 = plane.off_plane(points[0]);
    let allowed = 0.5 * 10f64.powi(-(o.decimals as i32)) * o.mm_per_unit;
    let dev = points
        .iter()
        .map(|p| (plane.off_plane(*p) - off0).abs())
        .fold(0.0f64, f64::max);
    if dev > allowed {
        return Err(WriteError::NotPlanar {
            plane: plane.gword(),
            deviation_mm: dev,
            allowed_mm: allowed,
        });
    }
    Ok(())
}

/// One G6.2 block for `nurbs` (see the module docs for what is
/// guaranteed): the first line `G6.2 P<order> K X Y Z R [Q] [F]`, a line
/// `K X Y Z R` per further control point, then `order` knot-only lines.
/// All three axes are written on every control-point line. For LinuxCNC a
/// `G1 X Y Z` to the end point follows (a zero-length feed): after a G6.2
/// block master's interpreter keeps the position of the block's last line,
/// a knot-only line that gives the position before the block, and the next
/// move would start from there; the G1 leaves the motion mode at G1.
pub fn g6_2_block(
    nurbs: &Nurbs,
    dialect: G6Dialect,
    opts: &SplineWriteOptions,
) -> Result<String, WriteError> {
    check_options(opts)?;
    check_curve(nurbs)?;
    let max_degree = match dialect {
        G6Dialect::Fanuc { max_degree } => max_degree.min(Nurbs::MAX_DEGREE),
        G6Dialect::Linuxcnc { .. } => Nurbs::MAX_DEGREE,
    };
    if nurbs.degree > max_degree {
        return Err(WriteError::SplineCurve(format!(
            "degree {} is above {max_degree} for this dialect",
            nurbs.degree
        )));
    }
    if let G6Dialect::Linuxcnc { plane, method } = dialect {
        if !(1..=3).contains(&method) {
            return Err(WriteError::SplineOptions(
                "LinuxCNC's G6.2 method Q is 1, 2 or 3",
            ));
        }
        check_planar(&nurbs.points, plane, opts)?;
    }
    let n = integer_form(nurbs, opts.knot_shift_mm)?;
    let f = Fmt { o: opts };
    let w = unit_weights(&n);
    let eol = opts.line_ending;
    let mut out = String::new();
    if opts.incremental {
        out.push_str("G90");
        out.push_str(eol);
    }
    let order = n.degree + 1;
    for (i, p) in n.points.iter().enumerate() {
        if i == 0 {
            out.push_str(&format!("G6.2 P{order} "));
        }
        let d = match i {
            0 => opts.start_decimals.unwrap_or(opts.decimals),
            _ => opts.decimals,
        };
        out.push_str(&format!(
            "K{} X{} Y{} Z{} R{}",
            f.knot(n.knots[i]),
            f.coord_with(p.x, d),
            f.coord_with(p.y, d),
            f.coord_with(p.z, d),
            f.weight(w[i])?
        ));
        if i == 0 {
            if let G6Dialect::Linuxcnc { method, .. } = dialect {
                out.push_str(&format!(" Q{method}"));
            }
            if let Some(feed) = &opts.feed {
                out.push_str(&format!(" F{feed}"));
            }
        }
        out.push_str(eol);
    }
    for k in &n.knots[n.points.len()..] {
        if let G6Dialect::Linuxcnc { .. } = dialect {
            out.push_str("G6.2 ");
        }
        out.push_str(&format!("K{}", f.knot(*k)));
        out.push_str(eol);
    }
    if let G6Dialect::Linuxcnc { .. } = dialect {
        // Master's interpreter leaves its position at the last knot line's
        // (the position before the block): a zero-length feed to the end
        // point puts it right.
        let e = n.points[n.points.len() - 1];
        out.push_str(&format!(
            "G1 X{} Y{} Z{}",
            f.coord(e.x),
            f.coord(e.y),
            f.coord(e.z)
        ));
        out.push_str(eol);
    }
    if opts.incremental {
        out.push_str("G91");
        out.push_str(eol);
    }
    Ok(out)
}

/// Whether `knots` are LinuxCNC's G5.2 knot vector for their point count
/// up to an affine map (within [`KNOT_ROUNDING`] of a span).
/// The curve as G5.2/G5.3 blocks for LinuxCNC in `plane` (see the module
/// docs for what is guaranteed): a single block when its knot vector is
/// LinuxCNC's (clamped uniform, `g5_2_knots`) up to an affine map, else
/// one block per Bezier span (LinuxCNC fixes the knots from the number of
/// points, so only those two forms are exact). A block is `G5.2 P<w0>
/// L<order> [F]` (the current position is the first control point, `P` its
/// weight), a line `X Y P<w>` per further control point (the plane's two
/// axes), and `G5.3`. Degree 1 is raised to 2. The curve must lie in the
/// plane through its first point.
pub fn g5_2_blocks(
    nurbs: &Nurbs,
    plane: Plane,
    opts: &SplineWriteOptions,
) -> Result<String, WriteError> {
    check_options(opts)?;
    check_curve(nurbs)?;
    check_planar(&nurbs.points, plane, opts)?;
    let blocks = g5_2_blocks_of(nurbs);
    let f = Fmt { o: opts };
    let (a1, a2, _) = plane.axes();
    let letters = AXIS_LETTERS;
    let eol = opts.line_ending;
    let mut out = String::new();
    if opts.incremental {
        out.push_str("G90");
        out.push_str(eol);
    }
    for (bi, b) in blocks.iter().enumerate() {
        let w = unit_weights(b);
        out.push_str(&format!("G5.2 P{} L{}", f.weight(w[0])?, b.degree + 1));
        if bi == 0 {
            if let Some(feed) = &opts.feed {
                out.push_str(&format!(" F{feed}"));
            }
        }
        out.push_str(eol);
        for (p, wi) in b.points.iter().zip(&w).skip(1) {
            let c = p.to_array();
            out.push_str(&format!(
                "{}{} {}{} P{}",
                letters[a1],
                f.coord(c[a1]),
                letters[a2],
                f.coord(c[a2]),
                f.weight(*wi)?
            ));
            out.push_str(eol);
        }
        out.push_str("G5.3");
        out.push_str(eol);
    }
    if opts.incremental {
        out.push_str("G91");
        out.push_str(eol);
    }
    Ok(out)
}
