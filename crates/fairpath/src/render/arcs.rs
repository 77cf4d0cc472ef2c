//! A curve as G2/G3 arcs: an arc spline by biarcs, fine where the machine
//! will be fast and the curvature changes, coarse elsewhere.
//!
//! Method: biarc interpolation of points and tangents sampled on the curve
//! (Bolton 1975; Meek and Walton, "Approximating smooth planar curves by
//! arc splines", J. Comput. Appl. Math. 59, 1995: a biarc between points
//! of a smooth curve with its tangents there is within O(h^3) of it and
//! tangent-continuous with its neighbours), with the interval halved until
//! three things hold:
//!
//! 1. **Deviation**: the curve's points (sampled) are within the chord
//!    share of the biarc, and the biarc's points within it of the curve's
//!    sampled polyline (both directions, so neither can bulge unseen).
//! 2. **Curvature steps**: where two arcs meet, the curvature vector jumps;
//!    a jerk-limited controller passes a jump `dk` at most at
//!    `v = sqrt(J Ts / dk)` (the normal acceleration steps by `v^2 dk`
//!    within one interpolation period, `super::super::feed::junction`). With
//!    `v` the speed planned for the exact curve there, each arc's curvature
//!    vector at its ends must be within half of `J Ts / v^2` of the
//!    curve's, so neighbours differ by at most that and the joint does not
//!    slow the machine. Where the curve's curvature changes as fast as the
//!    jerk allows this asks for arcs one interpolation period long; where
//!    it is constant, one arc covers all of it.
//! 3. **3D**: a curve that is not in a principal plane is written as
//!    helical arcs in the plane nearest its osculating plane among those
//!    that keep at least [`MIN_IN_PLANE`] of its tangent ([`arc_plane`]),
//!    rising linearly along the normal within each biarc. The rise rate
//!    then steps between biarcs: a kink of angle `theta` that the
//!    controller blends over the shorter neighbour, so a curvature of about
//!    `2 theta / L`, held to the same curvature-step share as 2. That is
//!    the curve's bending out of the plane, which halving does not reduce:
//!    where it is too much, or the tangent leaves every plane, the whole
//!    piece is written as G1 ([`super::lines`]; an arc next to a line steps
//!    the curvature by all of the arc's, so a piece is all arcs or all
//!    lines).
//!
//! An interval is not halved for the curvature steps below the length the
//! machine covers in `min_block_periods` interpolation periods at the
//! planned speed (LinuxCNC spends at least 1.02 periods on any block):
//! there the biarc is kept if it passes 1. Where the curve is sharper than
//! the controller's smallest arc, or a biarc fails 1 at what a written
//! coordinate resolves, that stretch becomes G1 lines within the chord
//! share (the machine nearly stops there).

use super::speed::PlannedSpeed;
use super::{Emitted, RenderOptions, RenderStats};
use crate::geom::biarc::{biarc, piece_distance_bound, Biarc};
use crate::geom::{
    curvature_vector_from, flatten_params_between, point_segment_distance, Curve, Line, ParamCurve,
    Plane, Vec3,
};
use alloc::boxed::Box;
use alloc::vec::Vec;

/// Least share of a tangent's length that must lie in the plane of the
/// arcs: steeper than 60 degrees to the plane, the projection is too
/// singular for arcs (the piece is written as G1).
pub const MIN_IN_PLANE: f64 = 0.5;

pub use crate::budget::DEVIATION_USE;

/// Points of the curve (and of each arc) sampled per biarc.
pub const SAMPLES: usize = 16;

/// Largest turn of one arc (rad). Keeps the distance tests meaningful and
/// the G2/G3 words far from the half-circle ambiguity of the R form.
pub const MAX_SWEEP: f64 = core::f64::consts::FRAC_PI_2;

/// Share of the speed-safe curvature step `J Ts / v^2` each side of a
/// joint may differ from the curve.
pub const STEP_SHARE: f64 = 0.5;

/// Relative margin by which the even arcs (`even_arcs`) must let the
/// planner pass their joints faster than the biarcs to be written, or
/// within which they are written when they are fewer.
const EVEN_GAIN: f64 = 1e-3;

/// Curvature (1/mm) below which an arc is written as a line, times the
/// chord share (mm): `STRAIGHT_CURVATURE_CHORD / chord`, a radius a billion
/// times the chord share (5,000 km at 0.005 mm), where a G2's centre words
/// would be numbers no controller resolves. The line is held to the chord
/// share like any arc ([`Fitter::try_interval`] checks the distance of what
/// it builds), so this only decides the form, never the deviation.
pub(crate) const STRAIGHT_CURVATURE_CHORD: f64 = 1e-9;

/// Most halvings of a piece's parameter interval.
const MAX_DEPTH: u32 = 48;

/// The principal plane for arcs through `pts` (points of a stretch of
/// curve): a plane they lie in (their coordinate along its normal varies
/// by at most `planar` mm), else, among the planes that keep at least
/// [`MIN_IN_PLANE`] of every tangent in `frames` (unit tangent, curvature
/// vector), the one with the least curvature out of the plane
/// (`|k . n|`): helical arcs rise linearly, so the curve's curvature along
/// the normal is what they cannot follow (the plane nearest to the
/// osculating plane).
pub fn arc_plane(pts: &[Vec3], frames: &[(Vec3, Vec3)], planar: f64) -> Option<Plane> {
    let mut best: Option<(f64, Plane)> = None;
    for plane in Plane::ALL {
        let (lo, hi) = pts
            .iter()
            .map(|p| plane.local(*p)[2])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), h| {
                (a.min(h), b.max(h))
            });
        if hi - lo <= planar {
            return Some(plane);
        }
        let n = plane.normal();
        let mut share = f64::INFINITY;
        let mut out_of_plane = 0.0f64;
        for (t, k) in frames {
            let l = plane.local(*t);
            share = share.min(crate::math::sqrt(l[0] * l[0] + l[1] * l[1]));
            out_of_plane = out_of_plane.max(crate::math::abs(k.dot(n)));
        }
        if share >= MIN_IN_PLANE && best.is_none_or(|(s, _)| out_of_plane < s) {
            best = Some((out_of_plane, plane));
        }
    }
    best.map(|(_, p)| p)
}

/// What became of one interval.
enum Outcome {
    Accept(Box<Biarc>),
    Split,
    /// G1 lines for this interval: it is as short as splitting goes (a
    /// cusp or a corner sharper than the smallest arc, where the machine
    /// nearly stops, so a step from an arc's curvature to a line's costs
    /// nothing there).
    LocalLines,
    /// The whole piece as G1: the curve leaves every plane or bends out of
    /// it more than helical arcs follow, which halving does not change.
    PieceLines,
}

struct Fitter<'a, C: ParamCurve + ?Sized> {
    c: &'a C,
    piece: usize,
    speed: &'a PlannedSpeed,
    opts: &'a RenderOptions,
    /// Curvature (1/mm) below which an arc is a line.
    straight: f64,
    /// Spread along a plane's normal below which points lie in it.
    planar: f64,
}

impl<C: ParamCurve + ?Sized> Fitter<'_, C> {
    /// The curvature step a joint planned at `v` mm/s can take without
    /// slowing the machine: `J Ts / v^2`.
    fn step(&self, v: f64) -> f64 {
        let m = &self.opts.limits;
        if v > 0.0 {
            m.jerk * m.period / (v * v)
        } else {
            f64::INFINITY
        }
    }

    fn try_interval(&self, ta: f64, tb: f64, pa: Vec3, pb: Vec3, depth: u32) -> Outcome {
        let c = self.c;
        let v = self.speed.max_over(self.piece, ta, tb);
        let min_len = self.opts.block_length(v).max(self.opts.min_arc_length);
        let chord = pa.dist(pb);
        // Splitting for the deviation may go down to what a written
        // coordinate resolves; splitting for speed stops at one block time.
        let can_split = depth < MAX_DEPTH && chord > 2.0 * self.opts.min_arc_length;
        let split_for_speed = can_split && chord > 2.0 * min_len;
        let fail = if can_split {
            Outcome::Split
        } else {
            Outcome::LocalLines
        };
        // Unit tangents and curvature vectors at both ends and the middle,
        // one evaluation of the curve each.
        let frame = |t: f64| {
            let (d1, d2) = c.derivs12(t);
            d1.normalized(0.0)
                .map(|u| (u, curvature_vector_from(d1, d2)))
        };
        let (Some(fa), Some(fb)) = (frame(ta), frame(tb)) else {
            return fail;
        };
        let (ua, ub) = (fa.0, fb.0);
        let samples = self.samples(ta, tb, pa, pb);
        let frames: Vec<(Vec3, Vec3)> = [Some(fa), frame(0.5 * (ta + tb)), Some(fb)]
            .into_iter()
            .flatten()
            .collect();
        let Some(plane) = arc_plane(&samples, &frames, self.planar) else {
            return Outcome::PieceLines;
        };
        let Some(b) = biarc(plane, pa, ua, pb, ub, MIN_IN_PLANE, self.straight) else {
            return fail;
        };
        // Shape: each arc turns by at most MAX_SWEEP, has a radius the
        // controller accepts and is not shorter than a written coordinate
        // can resolve.
        for a in [&b.first, &b.second] {
            if let Curve::Arc(arc) = a {
                if arc.r0.min(arc.r1) < self.opts.min_radius {
                    // Where the curve itself is that sharp, halving does
                    // not help: lines there (the machine nearly stops).
                    let sharpest = [ta, 0.5 * (ta + tb), tb]
                        .iter()
                        .map(|&t| c.curvature(t))
                        .fold(0.0, f64::max);
                    return if sharpest * self.opts.min_radius > 0.5 {
                        Outcome::LocalLines
                    } else {
                        fail
                    };
                }
                if arc.sweep > MAX_SWEEP || arc.approx_length() < self.opts.min_arc_length {
                    return fail;
                }
            }
        }
        // Three tests decide the outcome, in this order: deviation
        // (`fail`), kinks (`PieceLines`), curvature steps (`Split`, where
        // the interval may be split for speed). The deviation test is by
        // far the dearest, and its answer does not matter where there is
        // no kink and the steps are too large: a failed deviation test
        // splits the interval too (`fail` is `Split` wherever
        // `split_for_speed`). So the steps are tested first.
        let kinked = self.kinked(&b, ua, ub, v);
        if split_for_speed && !kinked && self.steps_too_far(&b, ta, tb, v) {
            return Outcome::Split;
        }
        if !self.within(&b, &samples) {
            return fail;
        }
        if kinked {
            return Outcome::PieceLines;
        }
        Outcome::Accept(Box::new(b))
    }

    /// Kinks against the curve's tangent at the ends (helical arcs whose
    /// rise rate differs from the curve's): the blend curvature they cost,
    /// about `2 theta / L`, does not shrink when the interval is halved (it
    /// is the curve's curvature out of the plane), so a stretch with one is
    /// written as G1.
    fn kinked(&self, b: &Biarc, ua: Vec3, ub: Vec3, v: f64) -> bool {
        let step = self.step(v) * self.opts.step_share;
        let len1 = b.first.length(self.opts.chord * 1e-3);
        let len2 = b.second.length(self.opts.chord * 1e-3);
        let ka = b.first.unit_tangent(0.0).map_or(0.0, |t| t.angle_to(ua));
        let kb = b.second.unit_tangent(1.0).map_or(0.0, |t| t.angle_to(ub));
        2.0 * ka > step * len1 || 2.0 * kb > step * len2
    }

    /// Whether the curvature steps of biarc `b` against the curve at the
    /// interval's ends, or at its own joint, exceed what the planned speed
    /// `v` passes ([`Fitter::step`] times the step share).
    fn steps_too_far(&self, b: &Biarc, ta: f64, tb: f64, v: f64) -> bool {
        let step = self.step(v) * self.opts.step_share;
        let c = self.c;
        let kc_a = c.curvature_vector(ta);
        let kc_b = c.curvature_vector(tb);
        let (k1a, k1b) = (b.first.curvature_vector(0.0), b.first.curvature_vector(1.0));
        let (k2a, k2b) = (
            b.second.curvature_vector(0.0),
            b.second.curvature_vector(1.0),
        );
        (k1a - kc_a).norm() > step || (k2b - kc_b).norm() > step || (k2a - k1b).norm() > 2.0 * step
    }

    /// The interval's end points and [`SAMPLES`] points between, in order.
    fn samples(&self, ta: f64, tb: f64, pa: Vec3, pb: Vec3) -> Vec<Vec3> {
        let mut v = Vec::with_capacity(SAMPLES + 2);
        v.push(pa);
        for k in 1..=SAMPLES {
            v.push(
                self.c
                    .eval(ta + (tb - ta) * k as f64 / (SAMPLES + 1) as f64),
            );
        }
        v.push(pb);
        v
    }

    /// Both directions of the deviation test, on the curve's samples `poly`
    /// (see the module docs).
    fn within(&self, b: &Biarc, poly: &[Vec3]) -> bool {
        let lim = DEVIATION_USE * self.opts.chord;
        for &q in &poly[1..poly.len() - 1] {
            let d1 = piece_distance_bound(&b.first, q).unwrap_or(f64::INFINITY);
            let d2 = piece_distance_bound(&b.second, q).unwrap_or(f64::INFINITY);
            if d1.min(d2) > lim {
                return false;
            }
        }
        points_near_polyline([&b.first, &b.second], poly, lim)
    }
}

/// Whether the points at eighths of each of `pieces` lie within `lim` of
/// the polyline `poly` (a curve's samples; the other direction of the
/// deviation test). The polyline is within its own chord error of the
/// curve, which the margin of [`DEVIATION_USE`] covers for pieces this
/// short. Only whether some segment is within `lim` matters, and the
/// points run along the polyline: the search starts at the segment the
/// previous point found and goes forward first (the same answer as the
/// nearest segment's, found in about one step instead of all of them).
pub(super) fn points_near_polyline<'a>(
    pieces: impl IntoIterator<Item = &'a Curve>,
    poly: &[Vec3],
    lim: f64,
) -> bool {
    let segments = poly.len() - 1;
    let mut hint = 0;
    for a in pieces {
        for k in 1..8 {
            let q = a.eval(k as f64 / 8.0);
            let near = |i: usize| point_segment_distance(q, poly[i], poly[i + 1]) <= lim;
            match (hint..segments).chain(0..hint).find(|&i| near(i)) {
                Some(i) => hint = i,
                None => return false,
            }
        }
    }
    true
}

/// Counts `a` in `counts` (an arc, helical or not, or a line).
pub(super) fn count_piece(a: &Curve, counts: &mut RenderStats) {
    match a {
        Curve::Arc(arc) => {
            counts.arcs += 1;
            if arc.rise != 0.0 {
                counts.helical += 1;
            }
        }
        _ => counts.lines += 1,
    }
}

/// Arcs for piece `piece` of a run, curve `c`, appended to `out`; they
/// start at `c.start()` and end at `c.end()` exactly and join exactly. When
/// some stretch of the curve cannot be followed by arcs (see the module
/// docs), the whole piece is written as G1 instead
/// ([`super::lines::lines_for_curve`]): where an arc meets a line the
/// curvature steps from the arc's to none, the largest step of all, so a
/// curve is better all arcs or all lines.
pub(crate) fn arcs_for_curve(
    c: &Curve,
    piece: usize,
    speed: &PlannedSpeed,
    opts: &RenderOptions,
    caps_of: &dyn Fn(&super::lines::Spacing) -> super::lines::Caps,
    out: &mut Emitted,
    stats: &mut RenderStats,
) {
    match super::bezier_spline_of(c) {
        Some(spans) => arcs_for(&spans, piece, speed, opts, caps_of, out, stats),
        None => arcs_for(c, piece, speed, opts, caps_of, out, stats),
    }
}

/// [`arcs_for_curve`] on `c` as it is given.
fn arcs_for<C: ParamCurve + ?Sized>(
    c: &C,
    piece: usize,
    speed: &PlannedSpeed,
    opts: &RenderOptions,
    caps_of: &dyn Fn(&super::lines::Spacing) -> super::lines::Caps,
    out: &mut Emitted,
    stats: &mut RenderStats,
) {
    let (t0, t1) = c.domain();
    let f = Fitter {
        c,
        piece,
        speed,
        opts,
        straight: STRAIGHT_CURVATURE_CHORD / opts.chord,
        planar: opts.chord * 1e-3,
    };
    let mut arcs = Emitted::default();
    let mut counts = RenderStats::default();
    // Intervals to do, the leftmost last (popped first). A closed curve
    // starts as its two halves.
    let mut todo: Vec<(f64, f64, Vec3, Vec3, u32)> = if c.start() == c.end() {
        let tm = 0.5 * (t0 + t1);
        let pm = c.eval(tm);
        alloc::vec![(tm, t1, pm, c.end(), 1), (t0, tm, c.start(), pm, 1)]
    } else {
        alloc::vec![(t0, t1, c.start(), c.end(), 0)]
    };
    while let Some((ta, tb, pa, pb, depth)) = todo.pop() {
        // An interval that does not move (the curve stands still there).
        if pa == pb && c.eval(0.5 * (ta + tb)) == pa {
            continue;
        }
        match f.try_interval(ta, tb, pa, pb, depth) {
            Outcome::Accept(b) => {
                let b = *b;
                let v = speed.max_over(piece, ta, tb);
                for a in [b.first, b.second] {
                    count_piece(&a, &mut counts);
                    arcs.push(a, v);
                }
            }
            Outcome::Split => {
                let tm = 0.5 * (ta + tb);
                let pm = c.eval(tm);
                todo.push((tm, tb, pm, pb, depth + 1));
                todo.push((ta, tm, pa, pm, depth + 1));
            }
            Outcome::LocalLines => {
                let v = speed.max_over(piece, ta, tb);
                let ts = flatten_params_between(c, ta, tb, DEVIATION_USE * opts.chord);
                let n = ts.len();
                let mut prev = pa;
                for (i, &t) in ts.iter().enumerate().skip(1) {
                    let q = if i + 1 == n { pb } else { c.eval(t) };
                    if q != prev {
                        arcs.push(Curve::Line(Line::new(prev, q)), v);
                        counts.lines += 1;
                        counts.fallback_lines += 1;
                    }
                    prev = q;
                }
            }
            Outcome::PieceLines => {
                let before = stats.lines;
                super::lines::lines_for_curve(c, piece, speed, opts, caps_of, out, stats);
                stats.fallback_lines += stats.lines - before;
                stats.fallback_pieces += 1;
                return;
            }
        }
    }
    if counts.fallback_lines > 0 {
        counts.fallback_pieces = 1;
    }
    // Arcs stepping evenly (`even_arcs`), where the curve lends itself and
    // the planner passes their joints faster than the biarcs' (as fast and
    // they are fewer); where the biarcs are as good, as on a circle, they
    // are the curve itself.
    if let Some((even, even_v)) =
        super::even_arcs::even_arcs(c, piece, speed, opts, f.straight, f.planar)
    {
        use super::even_arcs::joint_speed_ratio;
        let ends = (c.curvature_vector(t0), c.curvature_vector(t1));
        let accuracy = opts.chord * 1e-3;
        let r_even = joint_speed_ratio(&even, &even_v, ends, opts, accuracy);
        let r_bi = joint_speed_ratio(&arcs.curves, &arcs.speeds, ends, opts, accuracy);
        let better = r_even > (1.0 + EVEN_GAIN) * r_bi
            || (r_even >= (1.0 - EVEN_GAIN) * r_bi && even.len() < arcs.curves.len());
        if better {
            let mut even_counts = RenderStats::default();
            let mut even_out = Emitted::default();
            for (a, v) in even.into_iter().zip(even_v) {
                count_piece(&a, &mut even_counts);
                even_out.push(a, v);
            }
            arcs = even_out;
            counts = even_counts;
        }
    }
    out.curves.extend(arcs.curves);
    out.speeds.extend(arcs.speeds);
    stats.add(&counts);
}
