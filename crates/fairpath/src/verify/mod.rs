//! Independent verification of a smoothed run against the original: the
//! largest deviation, the continuity class of every joint, and the
//! endpoints. It shares no code with the smoothers beyond the geometry
//! kernel, and trusts nothing they report (not even `source_lines`).
//!
//! **Deviation** is the largest distance from any point of the smoothed
//! pieces to the original run (one-sided Hausdorff distance), found by
//! branch and bound and reported as an upper bound that exceeds the true
//! value by at most `accuracy` plus the flattening error of original arcs
//! (also `accuracy`):
//! * the original run is a set of segments (arcs and curves flattened with
//!   chord error `<= accuracy`, so distances to it differ from those to
//!   the original by at most that, either way: the bound adds it) in a
//!   uniform grid;
//! * on a straight piece, the distance to one fixed original segment is a
//!   convex function of position, so its value at the two ends bounds it in
//!   between: a span is certified when that bound is within `accuracy` of
//!   the distances measured at its ends, else it is halved;
//! * on a curved piece, the distance is 1-Lipschitz in arc length, so over a
//!   span of length `s` with end values `fa`, `fb` it is at most
//!   `(fa + fb + s) / 2`; spans are halved until that bound is below the
//!   largest deviation found so far plus `accuracy`.
//!
//! Spans whose bound is below 5% of the tolerance are not refined further
//! (the exact size of a deviation that small does not matter), so where
//! the whole run lies on the original the bound can be up to 5% of the
//! tolerance while the deviation found is 0.
//!
//! **Joints** are classed by position gap, tangent angle and the difference
//! of curvature vectors, with thresholds in [`JointTolerances`].

mod order;

pub use crate::geom::continuity::{classify_joint, Continuity, JointTolerances};
use crate::geom::{
    curvature_candidates, curvature_from, flatten_params, Curve, Extrema, ParamCurve, SegmentGrid,
    Vec3,
};
use crate::math;
use crate::path::Piece;
use alloc::collections::BTreeMap;
use alloc::vec::Vec;
pub use order::{follows_in_order, follows_in_order_within};

/// One joint of the smoothed run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Joint {
    /// Index of the piece that ends at the joint.
    pub after: usize,
    pub at: Vec3,
    pub class: Continuity,
}

/// What [`verify_run`] found.
#[derive(Clone, Debug, PartialEq)]
pub struct RunReport {
    /// Largest distance from the smoothed run to the original that was
    /// found (mm), to the original's segments (its arcs and curves
    /// flattened within `accuracy`).
    pub max_deviation: f64,
    /// A bound the true deviation never exceeds: `max_deviation + accuracy`,
    /// or 5% of the tolerance if that is more, plus `accuracy` where the
    /// original has arcs or curves (the flattening; see the module docs).
    pub deviation_bound: f64,
    /// Where it was found.
    pub worst_at: Vec3,
    pub joints: Vec<Joint>,
    /// Distance between the original and smoothed start points (0 = exact).
    pub start_gap: f64,
    pub end_gap: f64,
    /// Largest curvature found on the smoothed run (1/mm), cusps left
    /// out: samples (every knot of a spline among them), refined between
    /// them where a spline's samples show a peak narrower than their step
    /// (a near-cusp's spike between samples counts at its height). A
    /// lower bound of the true peak.
    pub peak_curvature: f64,
    /// Cusps found inside curves: points where a curve stops and turns
    /// (its derivative vanishes, or it turns on a radius below 1e-4 of
    /// the tolerance): back, as a fit through a reversal of
    /// the program must, or aside, as a spline with a control point
    /// repeated `degree` times does. The path stops there, as at a kept
    /// corner; curvature is not defined there (rounding makes it anything
    /// up to 1e28).
    pub cusps: usize,
}

impl RunReport {
    /// True when the deviation bound is within `tolerance` and both
    /// endpoints are exact.
    pub fn within(&self, tolerance: f64) -> bool {
        self.deviation_bound <= tolerance && self.start_gap == 0.0 && self.end_gap == 0.0
    }
    /// Number of joints of each class: `[gap, G0, G1, G2]`.
    pub fn joint_counts(&self) -> [usize; 4] {
        let mut c = [0; 4];
        for j in &self.joints {
            c[j.class as usize] += 1;
        }
        c
    }
}

/// Settings of the verifier.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VerifyOptions {
    /// The tolerance the smoothed run should keep (mm); sets the search
    /// radius of the grid and the joint thresholds.
    pub tolerance: f64,
    /// Accuracy of the deviation bound (mm).
    pub accuracy: f64,
}

impl VerifyOptions {
    /// Accuracy of a ten-thousandth of the tolerance.
    pub fn new(tolerance: f64) -> Self {
        VerifyOptions {
            tolerance,
            accuracy: tolerance * 1e-4,
        }
    }
}

/// The original run as segments in a grid, and its arcs and curves by
/// start point (a smoothed piece identical to an original one lies on the
/// original by definition).
struct Reference {
    grid: SegmentGrid,
    radius: f64,
    curves: BTreeMap<[u64; 3], Vec<Curve>>,
    /// Largest distance of a point of the original from the segments
    /// (the flattening's chord error; 0 for a run of lines).
    flattening: f64,
}

fn point_key(p: Vec3) -> [u64; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

impl Reference {
    fn new(original: &[Piece], opts: &VerifyOptions) -> Reference {
        let mut segs = Vec::new();
        let mut curves: BTreeMap<[u64; 3], Vec<Curve>> = BTreeMap::new();
        for p in original {
            match &p.curve {
                Curve::Line(l) => segs.push((l.p0, l.p1)),
                c => {
                    curves
                        .entry(point_key(c.start()))
                        .or_default()
                        .push(c.clone());
                    // Arcs (most of the curves of a program) in closed
                    // form: the bisection samples every span it tries.
                    let ts = match c {
                        Curve::Arc(a) => a
                            .chord_params(opts.accuracy, MAX_ARC_CHORDS)
                            .unwrap_or_else(|| flatten_params(c, opts.accuracy)),
                        _ => flatten_params(c, opts.accuracy),
                    };
                    for w in ts.windows(2) {
                        segs.push((c.eval(w[0]), c.eval(w[1])));
                    }
                }
            }
        }
        let radius = 2.0 * opts.tolerance;
        let flattening = if curves.is_empty() {
            0.0
        } else {
            opts.accuracy
        };
        Reference {
            grid: SegmentGrid::new(segs, radius),
            radius,
            curves,
            flattening,
        }
    }
    /// True when `c` is one of the original's arcs or curves, exactly.
    fn contains(&self, c: &Curve) -> bool {
        !matches!(c, Curve::Line(_))
            && self
                .curves
                .get(&point_key(c.start()))
                .is_some_and(|v| v.iter().any(|o| o == c))
    }
    fn dist(&self, q: Vec3) -> (f64, usize) {
        self.grid
            .nearest(q, self.radius)
            .unwrap_or((f64::INFINITY, 0))
    }
    fn dist_to(&self, q: Vec3, seg: usize) -> f64 {
        let (a, b) = self.grid.segments()[seg];
        crate::geom::point_segment_distance(q, a, b)
    }
}

/// Most chords an original arc is flattened into in closed form
/// ([`crate::geom::Arc::chord_params`]; beyond it the bisection of
/// [`flatten_params`] does it, within its own cap): a 10 m circle at the
/// accuracy of a 0.05 mm tolerance needs about 1e5.
const MAX_ARC_CHORDS: usize = 1 << 20;

/// The largest distance found from some pieces to the original run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deviation {
    /// Largest distance found (mm).
    pub found: f64,
    /// A bound the true largest distance never exceeds (mm).
    pub bound: f64,
    /// Where `found` was found.
    pub at: Vec3,
}

impl Deviation {
    /// The deviation of two sets of pieces together.
    pub fn merge(self, o: Deviation) -> Deviation {
        let (found, at) = if o.found > self.found || !o.found.is_finite() {
            (o.found, o.at)
        } else {
            (self.found, self.at)
        };
        Deviation {
            found,
            at,
            bound: self.bound.max(o.bound),
        }
    }
}

/// An original run prepared for deviation queries: its segments in a grid.
/// It is `Sync`, so callers with threads can measure chunks of a smoothed
/// run in parallel and [`Deviation::merge`] the results.
pub struct Verifier {
    reference: Reference,
    opts: VerifyOptions,
}

impl Verifier {
    pub fn new(original: &[Piece], opts: &VerifyOptions) -> Verifier {
        Verifier {
            reference: Reference::new(original, opts),
            opts: *opts,
        }
    }

    /// Largest distance from `pieces` to the original run (see the module
    /// documentation for the method and its accuracy).
    pub fn deviation(&self, pieces: &[Piece]) -> Deviation {
        let opts = &self.opts;
        let reference = &self.reference;
        let start = pieces.first().map(|p| p.start()).unwrap_or(Vec3::ZERO);
        let mut best = (0.0f64, start);
        let mut ctx = Refine {
            r: reference,
            acc: opts.accuracy,
            floor: opts.tolerance * 5e-2,
            pruned_max: 0.0,
            refined: 0,
        };
        // First pass: a coarse sample of every piece, to start the bound high.
        // Each span carries the bound of |C''| that holds on it.
        let mut spans: Vec<(usize, Sample, Sample, Option<f64>)> = Vec::new();
        for (pi, p) in pieces.iter().enumerate() {
            if reference.contains(&p.curve) {
                continue;
            }
            let (t0, t1) = p.curve.domain();
            let n = sample_count(&p.curve, opts.tolerance);
            let bounds = SecondDerivative::of(&p.curve);
            let mut prev = Sample::at(reference, &p.curve, t0);
            note(&mut best, prev.f, prev.q);
            let mut span = 0;
            let mut k = 1;
            while k <= n {
                let uniform = t0 + (t1 - t0) * k as f64 / n as f64;
                // Per-span bounds hold between breakpoints only: stop at
                // each one on the way.
                let (t, d2) = match &bounds {
                    SecondDerivative::Whole(d2) => (uniform, *d2),
                    SecondDerivative::PerSpan(v) => {
                        while span + 1 < v.len() && v[span].0 <= prev.t {
                            span += 1;
                        }
                        (uniform.min(v[span].0), v[span].1)
                    }
                };
                if t <= prev.t {
                    k += 1;
                    continue;
                }
                if t >= uniform {
                    k += 1;
                }
                let s = Sample::at(reference, &p.curve, t);
                note(&mut best, s.f, s.q);
                spans.push((pi, prev, s, d2));
                prev = s;
            }
        }
        // Second pass: refine each span.
        for &(pi, a, b, d2max) in &spans {
            let c = &pieces[pi].curve;
            ctx.refined = 0;
            ctx.refine(c, matches!(c, Curve::Line(_)), d2max, (a, b), &mut best, 0);
        }
        // The bound holds for the distance to the segments; the original
        // is within the flattening's chord error of them.
        Deviation {
            found: best.0,
            bound: (best.0 + opts.accuracy).max(ctx.pruned_max) + reference.flattening,
            at: best.1,
        }
    }
}

/// Bounds of `|C''|` on a smoothed piece: one for the whole curve, or one
/// per knot span (`(end parameter, bound)` in order) for curves whose
/// bound comes from their Bezier spans.
enum SecondDerivative {
    Whole(Option<f64>),
    PerSpan(Vec<(f64, Option<f64>)>),
}

impl SecondDerivative {
    fn of(c: &Curve) -> SecondDerivative {
        match c {
            Curve::Nurbs(n) if n.weights.is_some() || n.degree > 3 || !n.is_c1() => {
                // Each span is a rational Bezier curve, smooth inside: a
                // bound from its control points
                // ([`crate::geom::Nurbs::second_derivative_bound`]), with
                // the margin of the rounding of the knot insertion.
                let spans = n.bezier_spans();
                if spans.is_empty() {
                    return SecondDerivative::Whole(None);
                }
                SecondDerivative::PerSpan(
                    spans
                        .iter()
                        .map(|b| {
                            let end = b.domain().1;
                            (end, b.second_derivative_bound().map(|m| m * D2_MARGIN))
                        })
                        .collect(),
                )
            }
            _ => SecondDerivative::Whole(second_derivative_bound(c)),
        }
    }
}

/// Share of the tolerance below which a curve's motion over its whole
/// domain, at the parametric speed of a point, counts as stopped there,
/// and below which a radius of curvature counts as a turn on the spot (a
/// cusp: [`RunReport::cusps`]): 5 nm at 0.05 mm, where any feed turns
/// within one servo period (a corner followed exactly on the default
/// machine is passed at 0.05 mm/s and more, 50 nm a period), as the
/// planner takes it.
const CUSP_SHARE: f64 = 1e-4;

/// How far (a share of a spline's parameter domain) a narrow peak between
/// its samples is refined for [`RunReport::peak_curvature`]: a
/// billionth, finer than any peak a tool path has.
const PEAK_REFINE_SHARE: f64 = 1e-9;

/// Relative margin on a bound of `|C''|` computed in floating point.
const D2_MARGIN: f64 = 1.0 + 1e-6;

/// An upper bound of `|C''|` over the whole curve, where one is cheap and
/// sure: arcs (`r phi^2 + 2 |r1 - r0| phi`), polynomial C1 B-splines of
/// degree at most 3, whose `C''` is linear between knots (so its largest
/// norm is at a breakpoint). The chord argument needs C1: other NURBS are
/// bounded per knot span by [`SecondDerivative::of`].
fn second_derivative_bound(c: &Curve) -> Option<f64> {
    match c {
        Curve::Line(_) => Some(0.0),
        Curve::Arc(a) => Some(a.second_derivative_bound()),
        Curve::Nurbs(n) if n.weights.is_none() && n.degree <= 3 && n.is_c1() => {
            let bps = n.breakpoints();
            let mut m: f64 = 0.0;
            for w in bps.windows(2) {
                // Both one-sided values at each break: C'' may jump there.
                let h = (w[1] - w[0]) * 1e-9;
                m = m.max(n.deriv2(w[0]).norm()).max(n.deriv2(w[1] - h).norm());
            }
            Some(m * D2_MARGIN)
        }
        // Rational curves, higher degrees, kinks: see
        // [`SecondDerivative::of`], which bounds them per span.
        Curve::Nurbs(_) => None,
    }
}

/// Initial samples on curves, about eight tolerances apart (at least 8),
/// from a cheap upper bound of the length; one span on lines. Only a start:
/// the branch and bound refines wherever the bound requires it.
fn sample_count(c: &Curve, tolerance: f64) -> usize {
    let len = match c {
        Curve::Line(_) => return 1,
        Curve::Arc(a) => a.approx_length() + math::abs(a.r1 - a.r0) * a.sweep,
        Curve::Nurbs(n) => n.polygon_length(),
    };
    (math::ceil(len / (8.0 * tolerance)) as usize).clamp(8, 1 << 16)
}

/// What a verification measures besides the deviation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Measures {
    /// Everything [`RunReport`] holds.
    #[default]
    All,
    /// The end points' gaps only (joints and curvature left empty): all a
    /// check of a written output against its original asks, where the
    /// joints of a long written run (one per block, millions of them on a
    /// raster written as arcs) would be held for nothing.
    Ends,
}

/// Everything [`verify_run`] reports but the deviation: endpoints, joint
/// classes, peak curvature. Returns the report and whether a deviation
/// still has to be measured (false when the answer is already known).
pub fn report_without_deviation(
    original: &[Piece],
    smoothed: &[Piece],
    opts: &VerifyOptions,
) -> (RunReport, bool) {
    report_measuring(original, smoothed, opts, Measures::All)
}

/// [`report_without_deviation`], measuring what `measures` says.
pub fn report_measuring(
    original: &[Piece],
    smoothed: &[Piece],
    opts: &VerifyOptions,
    measures: Measures,
) -> (RunReport, bool) {
    let jt = JointTolerances::from_tolerance(opts.tolerance);
    let mut report = RunReport {
        max_deviation: 0.0,
        deviation_bound: 0.0,
        worst_at: Vec3::ZERO,
        joints: Vec::new(),
        start_gap: f64::INFINITY,
        end_gap: f64::INFINITY,
        peak_curvature: 0.0,
        cusps: 0,
    };
    if let (Some(o0), Some(s0)) = (original.first(), smoothed.first()) {
        report.start_gap = o0.start().dist(s0.start());
    }
    if let (Some(o1), Some(s1)) = (original.last(), smoothed.last()) {
        report.end_gap = o1.end().dist(s1.end());
    }
    if smoothed.is_empty() {
        // Allowed only for a run that does not move: its extent is then the
        // deviation and the endpoint gap.
        let p0 = original.first().map(|p| p.start()).unwrap_or(Vec3::ZERO);
        let extent = original
            .iter()
            .flat_map(|p| {
                let (a, b) = p.curve.domain();
                [p.start(), p.curve.eval(0.5 * (a + b)), p.end()]
            })
            .map(|q| q.dist(p0))
            .fold(0.0, f64::max);
        report.start_gap = extent;
        report.end_gap = extent;
        report.max_deviation = extent;
        report.deviation_bound = extent;
        return (report, false);
    }
    if measures == Measures::Ends {
        let measure = !original.is_empty();
        if !measure {
            report.max_deviation = f64::INFINITY;
            report.deviation_bound = f64::INFINITY;
        }
        return (report, measure);
    }
    for (i, w) in smoothed.windows(2).enumerate() {
        report.joints.push(Joint {
            after: i,
            at: w[0].end(),
            class: classify_joint(&w[0].curve, &w[1].curve, &jt),
        });
    }
    for p in smoothed {
        if !matches!(p.curve, Curve::Line(_)) {
            let (t0, t1) = p.curve.domain();
            // Below this parametric speed the curve moves less than
            // `CUSP_SHARE` of the tolerance over its whole domain: stopped.
            let stopped = CUSP_SHARE * opts.tolerance / (t1 - t0);
            // Above this curvature the curve turns within `CUSP_SHARE` of
            // the tolerance: it stops and turns there, a cusp as
            // much as where its speed vanishes (a fit through a reversal
            // whose control points are not exactly in line).
            let turned = 1.0 / (CUSP_SHARE * opts.tolerance);
            // The curvature at `t`, `None` at a cusp.
            let at = |t: f64| -> Option<f64> {
                let k = (p.curve.deriv1(t).norm() > stopped).then(|| p.curve.curvature(t))?;
                (k <= turned).then_some(k)
            };
            let n = sample_count(&p.curve, opts.tolerance);
            let mut cusps: Vec<f64> = Vec::new();
            let ts: Vec<f64> = (0..=n)
                .map(|k| t0 + (t1 - t0) * k as f64 / n as f64)
                .collect();
            // A spline's derivatives at each sample, evaluated once.
            let at_samples: Vec<(Vec3, Vec3)> = match &p.curve {
                Curve::Nurbs(nb) => ts.iter().map(|&t| nb.derivs12(t)).collect(),
                _ => Vec::new(),
            };
            let mut ks: Vec<f64> = Vec::with_capacity(n + 1);
            let mut moving: Vec<bool> = Vec::with_capacity(n + 1);
            for (j, &t) in ts.iter().enumerate() {
                let k = match at_samples.get(j) {
                    Some(&(d1, d2)) => (d1.norm() > stopped)
                        .then(|| curvature_from(d1, d2))
                        .filter(|&k| k <= turned),
                    None => at(t),
                };
                if k.is_none() {
                    cusps.push(t);
                }
                ks.push(k.unwrap_or(0.0));
                moving.push(k.is_some());
            }
            report.peak_curvature = ks.iter().copied().fold(report.peak_curvature, f64::max);
            // A spline's narrow peaks (a near-cusp) lie between samples:
            // the curvature where the samples show one narrower than their
            // step ([`Extrema::Narrow`]), between samples that all move (next to a sampled cusp the curvature is no
            // number); a point that turns out to be a cusp counts as one.
            if let Curve::Nurbs(nb) = &p.curve {
                let derivs = |t: f64| nb.derivs12(t);
                let accuracy = PEAK_REFINE_SHARE * (t1 - t0);
                let speeds: Vec<f64> = at_samples.iter().map(|(d1, _)| d1.norm()).collect();
                let sampled = (ks.as_slice(), speeds.as_slice());
                for t in curvature_candidates(derivs, &ts, sampled, accuracy, Extrema::Narrow) {
                    let j = ts.partition_point(|&s| s < t).min(n);
                    let (lo, hi) = (j.saturating_sub(1), (j + 1).min(n));
                    if !moving[lo..=hi].iter().all(|&m| m) {
                        continue;
                    }
                    let (d1, d2) = derivs(t);
                    let k = curvature_from(d1, d2);
                    if d1.norm() <= stopped || k > turned {
                        cusps.push(t);
                    } else {
                        report.peak_curvature = report.peak_curvature.max(k);
                    }
                }
                // Curvature peaks of corner transitions sit on their
                // knots, and a fit's cusps on its breakpoints.
                for t in nb.breakpoints() {
                    match at(t) {
                        Some(k) => report.peak_curvature = report.peak_curvature.max(k),
                        None => cusps.push(t),
                    }
                }
            }
            // One cusp per place (a sample and a breakpoint may both find it).
            cusps.sort_by(f64::total_cmp);
            cusps.dedup_by(|a, b| p.curve.eval(*a).dist(p.curve.eval(*b)) <= opts.tolerance);
            report.cusps += cusps.len();
        }
    }
    if original.is_empty() {
        report.max_deviation = f64::INFINITY;
        report.deviation_bound = f64::INFINITY;
        return (report, false);
    }
    (report, true)
}

impl RunReport {
    /// Sets the deviation fields from a measured [`Deviation`].
    pub fn set_deviation(&mut self, d: Deviation) {
        self.max_deviation = d.found;
        self.deviation_bound = d.bound;
        self.worst_at = d.at;
    }
}

/// Verifies `smoothed` against `original` (both continuous runs).
pub fn verify_run(original: &[Piece], smoothed: &[Piece], opts: &VerifyOptions) -> RunReport {
    let (mut report, measure) = report_without_deviation(original, smoothed, opts);
    if measure {
        report.set_deviation(Verifier::new(original, opts).deviation(smoothed));
    }
    report
}

fn note(best: &mut (f64, Vec3), f: f64, q: Vec3) {
    if f > best.0 || !f.is_finite() {
        *best = (f, q);
    }
}

struct Refine<'a> {
    r: &'a Reference,
    acc: f64,
    /// Spans bounded below this are not refined.
    floor: f64,
    /// Largest bound of a span left unrefined.
    pruned_max: f64,
    /// Splits of the current coarse span (see [`MAX_SPLITS_PER_SPAN`]).
    refined: usize,
}

/// Most times one span of the coarse sample is split. The bisection stops
/// where a span's upper bound is within the accuracy of the largest
/// distance found; a curve at a constant distance from the original (fuzz
/// input `hang-1717-17309`: a 10 mm arc centred on a line of the run, 10
/// mm from it everywhere) never gets there before the depth limit, and the
/// whole binary tree (2^48 spans) would be visited. Past this many splits
/// the rest of the span is not split: the upper bounds of its parts go
/// into the reported bound ([`Deviation::bound`] stays a bound, only
/// looser), so a candidate that far out is still rejected. Curves within
/// the tolerance need far fewer splits per span (their bound falls under
/// the largest distance found, or under the floor, quickly); a curved span
/// over many tiny segments of the original needs about two splits per
/// segment it covers. Straight pieces are not capped: their bisection
/// ends once both ends of a part are nearest to one segment of the
/// original, so their work is bounded by the segments they cover (a
/// straight piece merged over 2,000 collinear moves of
/// `linuxcnc/spindle/straight_spindleon.ngc` needs more than 4,096).
pub const MAX_SPLITS_PER_SPAN: usize = 1 << 12;

/// A point of a smoothed piece with its distance to the original and the
/// original segment nearest to it: found once, read by both spans it ends.
#[derive(Clone, Copy, Debug)]
struct Sample {
    t: f64,
    q: Vec3,
    f: f64,
    seg: usize,
}

impl Sample {
    fn at(r: &Reference, c: &Curve, t: f64) -> Sample {
        let q = c.eval(t);
        let (f, seg) = r.dist(q);
        Sample { t, q, f, seg }
    }
}

impl Refine<'_> {
    fn refine(
        &mut self,
        c: &Curve,
        straight: bool,
        d2max: Option<f64>,
        (a, b): (Sample, Sample),
        best: &mut (f64, Vec3),
        depth: u32,
    ) {
        let r = self.r;
        let chord = a.q.dist(b.q);
        // The distance to one fixed segment of the original is convex along
        // a line: its values at the ends, to the segments nearest to each
        // end, bound it in between.
        let convex = || {
            let ba = r.dist_to(a.q, a.seg).max(r.dist_to(b.q, a.seg));
            let bb = r.dist_to(a.q, b.seg).max(r.dist_to(b.q, b.seg));
            ba.min(bb)
        };
        let bound = if straight {
            convex().min(0.5 * (a.f + b.f + chord))
        } else {
            // Arc length over the span: chord times a margin that covers the
            // arc/chord ratio of spans short enough to be refined
            // (1 + k^2 s^2 / 24).
            let lipschitz = 0.5 * (a.f + b.f + chord * 1.05);
            // Second order: the curve is within h = max|C''| dt^2 / 8 of its
            // chord, and the distance to one segment is convex along the
            // chord, so it is at most max(g(qa), g(qb)) + h.
            match d2max {
                Some(d2) => {
                    let h = d2 * (b.t - a.t) * (b.t - a.t) / 8.0;
                    lipschitz.min(convex() + h)
                }
                None => lipschitz,
            }
        };
        if !bound.is_finite() {
            note(best, bound, a.q);
            return;
        }
        if bound <= best.0.max(self.floor) + self.acc
            || depth >= 48
            || (!straight && self.refined >= MAX_SPLITS_PER_SPAN)
            || (straight && bound <= a.f.max(b.f) + self.acc)
        {
            self.pruned_max = self.pruned_max.max(bound);
            return;
        }
        self.refined += 1;
        let m = Sample::at(r, c, 0.5 * (a.t + b.t));
        note(best, m.f, m.q);
        self.refine(c, straight, d2max, (a, m), best, depth + 1);
        self.refine(c, straight, d2max, (m, b), best, depth + 1);
    }
}
