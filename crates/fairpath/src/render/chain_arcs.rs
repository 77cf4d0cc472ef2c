//! Consecutive short pieces as one staircase of arcs, a cell per corner.
//!
//! Why: a run smoothed corner by corner (`bspline-corner`, `ctm`, `lotm`)
//! is lines and transitions; each transition's curvature rises from none
//! to its peak and falls back, so the exact curves carry a bump of
//! curvature at every input vertex, and arcs that follow each bump
//! ([`super::even_arcs`], [`super::arcs`]) need a dozen arcs per corner on
//! a densely sampled surface (`surface-raster-large.ngc`: 1.5 million arcs
//! for 139 thousand lines). Within the chord share the written path need
//! not follow the bumps: an arc per corner, whose curvature is the turn of
//! the corner over the stretch from the middle of the line before it to
//! the middle of the line after it (the discrete curvature of the
//! input's vertices), stays near the curves where the corners turn little
//! over short lines, and its steps from arc to arc are the change of that
//! curvature from vertex to vertex, small on a smooth surface, where the
//! bumps of the curves step by their whole peak.
//!
//! Method: the chain's pieces are sampled (the chord's samples of each
//! curve and [`PIECE_SAMPLES`] uniform ones) in the principal plane of
//! [`super::arcs::arc_plane`]; the cells run between the middles of the
//! chain's lines and the joints of two curves (a cell shorter than a
//! block at the planned speed joins the next). Cell `i`, of in-plane
//! length `h_i`, takes the chain's mean curvature over it,
//! `(theta(b_{i+1}) - theta(b_i)) / h_i`; the means are smoothed
//! ([`SMOOTH_PASSES`] passes of `[1 2 1]`, weighted by length so that
//! the turn is kept), because a short cell's turn carries the noise of
//! the input's vertices. At each end of the chain the cells ramp from the
//! chain's own curvature there (a line's none) to the means, in steps the
//! planned speed passes. The arcs' points drift from the chain's by what
//! the staircase misses in each cell, so the arcs go in segments of
//! [`SEGMENT_CELLS`], each from where the one before ends, whose
//! curvatures take the least-norm correction (Gauss-Newton, as
//! [`super::even_arcs`] does for one curve) that ends it at the chain's
//! point and direction there; the ramps' arcs take less of it the nearer
//! the chain's end, so that they stay graded. The arcs are written only
//! where they pass what the renderer's other arcs pass: the chord share
//! both ways (every sample near an arc, every arc's points near the
//! samples' polyline), and curvature steps, at the chain's ends against
//! its curves and between arcs, that the speed planned for the curves
//! passes (`step_share J Ts / v^2` each side). A chain that does not pass
//! is halved, down to [`MIN_CHAIN`] pieces; the pieces of no chain are
//! rendered one by one.
//!
//! A chain holds lines and NURBS of one feed, at most
//! [`CHAIN_PIECES`](super::CHAIN_PIECES) of them, and never crosses a
//! multiple of it in the run's piece numbers. A curve joins a chain only
//! if one arc over it can stay near it: its turn times its length within
//! [`CELL_BULGE`] chord shares. Input arcs stay arcs (they break chains).

use super::arcs::{arc_plane, points_near_polyline, MAX_SWEEP, MIN_IN_PLANE};
use super::even_arcs::{solve3, walk};
use super::lines::FINE_CHORD;
use super::speed::PlannedSpeed;
use super::{RenderOptions, CHAIN_PIECES};
use crate::budget::DEVIATION_USE;
use crate::geom::biarc::{arc_from_tangent, in_plane_direction, piece_distance_bound};
use crate::geom::{
    curvature_vector_from, flatten_params_between, BezierSpline, Curve, ParamCurve, Vec3,
};
use crate::math;
use crate::path::Piece;
use alloc::vec::Vec;

/// Uniform samples per curve of the chain, besides the chord error's.
const PIECE_SAMPLES: usize = 8;

/// A curve joins a chain where its turn (rad) times its length is at most
/// this many chord shares: an arc of the curve's mean curvature over it
/// bulges from it by about an eighth of that product.
const CELL_BULGE: f64 = 4.0;

/// Gauss-Newton iterations at most.
const MAX_ITERATIONS: usize = 12;

/// Arcs per stretch whose end is held to the chain's point and direction.
const SEGMENT_CELLS: usize = 8;

/// Passes of the `[1 2 1]` smoothing of the cells' curvatures.
const SMOOTH_PASSES: usize = 2;

/// Most cells a ramp at an end of the chain replaces.
const RAMP_CELLS: usize = 4;

/// Most arcs of a ramp at an end of the chain.
const MAX_RAMP: usize = 16;

/// Share of the steps allowed that a ramp takes (the correction of the
/// segment's end changes them a little).
const EVEN_MARGIN: f64 = 0.8;

/// Accuracy of the segments' ends, in chord shares (far below what the
/// chord share and the written decimals resolve).
const GN_ACCURACY: f64 = 1e-5;

/// A piece's curve as it is sampled: polynomial splines by their Bezier
/// spans (the same curve, sampled at a fraction of the cost).
enum View<'a> {
    Spans(BezierSpline),
    Curve(&'a Curve),
}

impl View<'_> {
    fn of(c: &Curve) -> View<'_> {
        match super::bezier_spline_of(c) {
            Some(s) => View::Spans(s),
            None => View::Curve(c),
        }
    }
    fn curve(&self) -> &dyn ParamCurve {
        match self {
            View::Spans(s) => s,
            View::Curve(c) => *c,
        }
    }
}

/// Whether `p` may be in a chain (a line, or a curve an arc can stay
/// near over its length).
fn chainable(p: &Piece, chord: f64) -> bool {
    if p.rapid {
        return false;
    }
    match &p.curve {
        Curve::Line(_) => true,
        Curve::Nurbs(_) => {
            let c = &p.curve;
            let (t0, t1) = c.domain();
            let turn = match (c.unit_tangent(t0), c.unit_tangent(t1)) {
                (Some(a), Some(b)) => a.angle_to(b),
                _ => return false,
            };
            let len = (c.end() - c.start()).norm();
            turn * len <= CELL_BULGE * chord
        }
        Curve::Arc(_) => false,
    }
}

/// The end (exclusive) of the chain that starts at piece `from`, before
/// `end`: `from` itself where no chain of two curves or more starts there.
pub(crate) fn chain_end(pieces: &[Piece], from: usize, end: usize, chord: f64) -> usize {
    let limit = ((from / CHAIN_PIECES + 1) * CHAIN_PIECES).min(end);
    let Some(first) = pieces.get(from) else {
        return from;
    };
    if !chainable(first, chord) {
        return from;
    }
    let mut j = from + 1;
    while j < limit && pieces[j].feed == first.feed && chainable(&pieces[j], chord) {
        j += 1;
    }
    let curves = pieces[from..j]
        .iter()
        .filter(|p| !matches!(p.curve, Curve::Line(_)))
        .count();
    if curves >= 2 {
        j
    } else {
        from
    }
}

/// A chain written as arcs: the pieces it replaces, its arcs, the speed
/// planned over each and the input lines each replaces.
pub(crate) struct Chained {
    pub(crate) range: core::ops::Range<usize>,
    pub(crate) arcs: Vec<Curve>,
    pub(crate) speeds: Vec<f64>,
    pub(crate) lines: Vec<(usize, usize)>,
}

/// Fewest pieces a chain is halved to when its arcs do not pass.
const MIN_CHAIN: usize = 6;

/// The chains of arcs that pass within the chain `range`, in order: the
/// whole, or, where it does not pass, each half, down to [`MIN_CHAIN`]
/// pieces (the pieces of no chain are rendered one by one).
pub(crate) fn cover(
    pieces: &[Piece],
    range: core::ops::Range<usize>,
    speed: &PlannedSpeed,
    opts: &RenderOptions,
) -> Vec<Chained> {
    let mut out = Vec::new();
    let mut todo = alloc::vec![range];
    while let Some(r) = todo.pop() {
        let curves = pieces[r.clone()]
            .iter()
            .filter(|p| !matches!(p.curve, Curve::Line(_)))
            .count();
        if curves < 2 {
            continue;
        }
        match chain_arcs(pieces, r.clone(), speed, opts) {
            Some((arcs, speeds, lines)) => out.push(Chained {
                range: r,
                arcs,
                speeds,
                lines,
            }),
            None if r.len() >= 2 * MIN_CHAIN => {
                let mid = r.start + r.len() / 2;
                todo.push(mid..r.end);
                todo.push(r.start..mid);
            }
            None => {}
        }
    }
    out
}

/// One sample of a chain.
struct Sample {
    piece: usize,
    t: f64,
    p: Vec3,
    tangent: Vec3,
    kvec: Vec3,
}

/// Arcs for the chain `pieces[range]` (module docs), from its start to
/// its end exactly and tangent to it there, each within [`DEVIATION_USE`]
/// of the chord share of the chain, with the planned speed over each and
/// the input lines each replaces; `None` where they do not pass.
#[allow(clippy::type_complexity)]
pub(crate) fn chain_arcs(
    pieces: &[Piece],
    range: core::ops::Range<usize>,
    speed: &PlannedSpeed,
    opts: &RenderOptions,
) -> Option<(Vec<Curve>, Vec<f64>, Vec<(usize, usize)>)> {
    let chord = opts.chord;
    let straight = super::arcs::STRAIGHT_CURVATURE_CHORD / chord;
    let planar = chord * 1e-3;
    // Samples, and where each line's middle and each joint of two curves
    // fall among them (the cells' boundaries).
    let mut samples: Vec<Sample> = Vec::new();
    let mut cuts: Vec<usize> = alloc::vec![0];
    let last_piece = range.end - 1;
    for i in range.clone() {
        let view = View::of(&pieces[i].curve);
        let c = view.curve();
        let (t0, t1) = c.domain();
        let is_line = matches!(pieces[i].curve, Curve::Line(_));
        let ts: Vec<f64> = if is_line {
            alloc::vec![t0, 0.5 * (t0 + t1), t1]
        } else {
            let mut ts = flatten_params_between(c, t0, t1, FINE_CHORD * chord);
            ts.extend((1..PIECE_SAMPLES).map(|k| t0 + (t1 - t0) * k as f64 / PIECE_SAMPLES as f64));
            ts.sort_by(f64::total_cmp);
            ts.dedup();
            ts
        };
        let prev_curve = i > range.start && !matches!(pieces[i - 1].curve, Curve::Line(_));
        if !is_line && prev_curve {
            cuts.push(samples.len() - 1);
        }
        for (k, &t) in ts.iter().enumerate() {
            if k == 0 && i > range.start {
                continue;
            }
            let (p, d1, d2) = c.eval_derivs12(t);
            samples.push(Sample {
                piece: i,
                t,
                p,
                tangent: d1.normalized(0.0)?,
                kvec: curvature_vector_from(d1, d2),
            });
            if is_line && k == 1 && i > range.start && i < last_piece {
                cuts.push(samples.len() - 1);
            }
        }
    }
    let n = samples.len();
    if n < 3 {
        return None;
    }
    cuts.push(n - 1);
    cuts.dedup();
    let pts: Vec<Vec3> = samples.iter().map(|s| s.p).collect();
    let frames: Vec<(Vec3, Vec3)> = samples.iter().map(|s| (s.tangent, s.kvec)).collect();
    let Some(plane) = arc_plane(&pts, &frames, planar) else {
        return None;
    };
    let mut theta: Vec<f64> = Vec::with_capacity(n);
    let mut s: Vec<f64> = Vec::with_capacity(n);
    let mut prev: Option<[f64; 2]> = None;
    for j in 0..n {
        let d = in_plane_direction(plane, samples[j].tangent, MIN_IN_PLANE)?;
        theta.push(match prev {
            None => math::atan2(d[1], d[0]),
            Some(p) => {
                theta[j - 1] + math::atan2(p[0] * d[1] - p[1] * d[0], p[0] * d[0] + p[1] * d[1])
            }
        });
        prev = Some(d);
        let l = plane.local(pts[j]);
        s.push(if j == 0 {
            0.0
        } else {
            let q = plane.local(pts[j - 1]);
            s[j - 1] + math::hypot(l[0] - q[0], l[1] - q[1])
        });
    }
    let total = s[n - 1];
    if !(total > 0.0 && total.is_finite()) {
        return None;
    }
    // Cells no shorter than one block at the planned speed, nor than the
    // shortest arc: a short one joins the cell after it (the last, the one
    // before).
    let v_at = |j: usize| speed.at(samples[j].piece, samples[j].t);
    let mut bounds: Vec<usize> = alloc::vec![cuts[0]];
    for &c in &cuts[1..] {
        let a = *bounds.last()?;
        let len = s[c] - s[a];
        let v = v_at(a).max(v_at(c));
        if len >= opts.block_length(v).max(opts.min_arc_length) || c == n - 1 {
            bounds.push(c);
        }
    }
    if bounds.len() >= 3 {
        let m = bounds.len();
        let len = s[bounds[m - 1]] - s[bounds[m - 2]];
        let v = v_at(bounds[m - 2]).max(v_at(bounds[m - 1]));
        if len < opts.block_length(v).max(opts.min_arc_length) {
            bounds.remove(m - 2);
        }
    }
    // Boundaries as in-plane arc lengths; the end cells split at a third
    // (the third outside).
    let b: Vec<f64> = bounds.iter().map(|&j| s[j]).collect();
    if b.len() < 2 {
        return None;
    }
    let locate = |x: f64| {
        let j = s.partition_point(|&v| v <= x).clamp(1, n - 1);
        let (sa, sb) = (s[j - 1], s[j]);
        let f = if sb > sa {
            ((x - sa) / (sb - sa)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (j, f)
    };
    let theta_at = |x: f64| {
        let (j, f) = locate(x);
        theta[j - 1] + (theta[j] - theta[j - 1]) * f
    };
    let point_at = |x: f64| {
        let (j, f) = locate(x);
        let (a, c) = (plane.local(pts[j - 1]), plane.local(pts[j]));
        [a[0] + (c[0] - a[0]) * f, a[1] + (c[1] - a[1]) * f]
    };
    let m = &opts.limits;
    let step = |v: f64| {
        if v > 0.0 {
            opts.step_share * m.jerk * m.period / (v * v)
        } else {
            f64::INFINITY
        }
    };
    // Cells (lengths, curvatures): the chain's mean curvature over each.
    let mut h: Vec<f64> = b.windows(2).map(|w| w[1] - w[0]).collect();
    let mut k: Vec<f64> = b
        .windows(2)
        .map(|w| (theta_at(w[1]) - theta_at(w[0])) / (w[1] - w[0]))
        .collect();
    // The end cells ramp from the chain's own curvature at its ends to
    // their mean in steps the planned speed passes.
    let in_plane_k = |j0: usize, j1: usize| {
        let ds = s[j1] - s[j0];
        if ds > 0.0 {
            (theta[j1] - theta[j0]) / ds
        } else {
            0.0
        }
    };
    // The means of neighbouring cells differ by the noise of the input's
    // vertices (a turn's error over a short cell is a large error of
    // curvature, where the path moves little): smoothed a few passes,
    // weighted by the cells' lengths so that the turn is kept, the steps
    // are the path's and the points move by about `dk h^2 / 8`, which the
    // segments' ends then hold (the deviation is checked below).
    for _ in 0..SMOOTH_PASSES {
        let turn: Vec<f64> = k.iter().zip(&h).map(|(a, b)| a * b).collect();
        let cells = k.len();
        if cells < 3 {
            break;
        }
        let mut next = k.clone();
        for i in 1..cells - 1 {
            next[i] =
                (turn[i - 1] + 2.0 * turn[i] + turn[i + 1]) / (h[i - 1] + 2.0 * h[i] + h[i + 1]);
        }
        k = next;
    }
    // The fastest the curves are planned over samples `j0..=j1`.
    let v_over = |j0: usize, j1: usize| (j0..=j1).map(v_at).fold(0.0f64, f64::max);
    // The end cells ramp from the chain's own curvature at its ends to
    // the cells' means, in steps the planned speed passes; how much of
    // the correction of its segment's end each arc takes: the ramps' arcs
    // less the nearer the chain's end (the end arcs none), so that the
    // ramps stay graded.
    let mut weight: Vec<f64> = alloc::vec![1.0; h.len()];
    let reach = RAMP_CELLS.min(bounds.len() - 1);
    let v_head = v_over(0, bounds[reach]);
    let v_tail = v_over(bounds[bounds.len() - 1 - reach], n - 1);
    let block = |v: f64| opts.block_length(v).max(opts.min_arc_length);
    ramp_start(
        (&mut h, &mut k, &mut weight),
        in_plane_k(0, 1),
        EVEN_MARGIN * step(v_head),
        block(v_head),
    );
    h.reverse();
    k.reverse();
    weight.reverse();
    ramp_start(
        (&mut h, &mut k, &mut weight),
        in_plane_k(n - 2, n - 1),
        EVEN_MARGIN * step(v_tail),
        block(v_tail),
    );
    h.reverse();
    k.reverse();
    weight.reverse();
    let count = h.len();
    if h.iter().any(|&x| x < opts.min_arc_length) {
        return None;
    }
    let mut b: Vec<f64> = Vec::with_capacity(count + 1);
    b.push(0.0);
    for &x in &h {
        b.push(b[b.len() - 1] + x);
    }
    b[count] = total;
    let l0 = plane.local(pts[0]);
    let l1 = plane.local(pts[n - 1]);
    let (theta0, theta1) = (theta[0], theta[n - 1]);
    let accuracy = GN_ACCURACY * chord;
    // Segment after segment of SEGMENT_CELLS arcs, from where the one
    // before ends: its curvatures corrected (least norm) so that it ends
    // at the chain's point and direction there.
    let mut at = [l0[0], l0[1]];
    let mut dir = theta0;
    let mut i0 = 0;
    while i0 < count {
        let mut i1 = (i0 + SEGMENT_CELLS).min(count);
        if count - i1 < SEGMENT_CELLS / 2 {
            i1 = count;
        }
        let target = if i1 == count {
            [l1[0], l1[1]]
        } else {
            point_at(b[i1])
        };
        let target_dir = if i1 == count { theta1 } else { theta_at(b[i1]) };
        let (hs, ks, ws) = (&h[i0..i1], &mut k[i0..i1], &weight[i0..i1]);
        let scale = (b[i1] - b[i0]) / (i1 - i0) as f64;
        let mut converged = false;
        for _ in 0..MAX_ITERATIONS {
            let (p, a) = walk(at, dir, hs, ks);
            let end = p[i1 - i0];
            let r = [
                end[0] - target[0],
                end[1] - target[1],
                (a - target_dir) * scale,
            ];
            if r.iter().all(|v| math::abs(*v) <= accuracy) {
                converged = true;
                break;
            }
            let col = |i: usize| {
                let mid = [0.5 * (p[i][0] + p[i + 1][0]), 0.5 * (p[i][1] + p[i + 1][1])];
                let (dx, dy) = (end[0] - mid[0], end[1] - mid[1]);
                [-hs[i] * dy, hs[i] * dx, hs[i] * scale]
            };
            let mut jjt = [[0.0f64; 3]; 3];
            for i in 0..hs.len() {
                let cl = col(i);
                for (a, row) in jjt.iter_mut().enumerate() {
                    for (c, x) in row.iter_mut().enumerate() {
                        *x += ws[i] * cl[a] * cl[c];
                    }
                }
            }
            let y = solve3(jjt, [-r[0], -r[1], -r[2]])?;
            for i in 0..hs.len() {
                let cl = col(i);
                ks[i] += ws[i] * (cl[0] * y[0] + cl[1] * y[1] + cl[2] * y[2]);
            }
            if !ks.iter().all(|v| v.is_finite()) {
                return None;
            }
        }
        if !converged {
            return None;
        }
        let (p, a) = walk(at, dir, hs, ks);
        at = p[i1 - i0];
        dir = a;
        i0 = i1;
    }
    let start = [l0[0], l0[1]];
    let (p, _) = walk(start, theta0, &h, &k);
    let rise = |x: f64| l0[2] + (l1[2] - l0[2]) * x / total;
    let mut out: Vec<Curve> = Vec::with_capacity(count);
    let mut at = pts[0];
    let mut dir = in_plane_direction(plane, samples[0].tangent, MIN_IN_PLANE)?;
    let mut angle = theta0;
    for i in 0..count {
        let to = if i + 1 == count {
            pts[n - 1]
        } else {
            plane.point([p[i + 1][0], p[i + 1][1], rise(b[i + 1])])
        };
        let a = arc_from_tangent(plane, at, dir, to, straight)?;
        if let Curve::Arc(arc) = &a {
            if arc.r0.min(arc.r1) < opts.min_radius
                || arc.sweep > MAX_SWEEP
                || arc.approx_length() < opts.min_arc_length
            {
                return None;
            }
        }
        angle += k[i] * h[i];
        dir = [math::cos(angle), math::sin(angle)];
        at = to;
        out.push(a);
    }
    // Speeds over each arc (the samples it spans), and the lines it
    // replaces.
    let mut speeds = Vec::with_capacity(count);
    let mut lines = Vec::with_capacity(count);
    for i in 0..count {
        let (ja, _) = locate(b[i]);
        let (jb, _) = locate(b[i + 1]);
        let (ja, jb) = (ja - 1, jb.min(n - 1));
        let mut v = 0.0f64;
        let (mut lo, mut hi) = (usize::MAX, 0);
        for smp in &samples[ja..=jb] {
            v = v.max(speed.at(smp.piece, smp.t));
            let sl = pieces[smp.piece].source_lines;
            lo = lo.min(sl.0);
            hi = hi.max(sl.1);
        }
        speeds.push(v);
        lines.push((lo, hi));
    }
    if !passes(&out, &speeds, &samples, &pts, opts) {
        return None;
    }
    Some((out, speeds, lines))
}

/// Replaces the first cells of `(h, k, weight)` (lengths, curvatures,
/// shares of the correction) by a ramp from curvature `from` to the mean
/// of the cell after them, in steps of at most `room`, of sub-cells no
/// shorter than `block`: over as few cells as give it room (at most
/// [`RAMP_CELLS`]).
fn ramp_start(
    (h, k, w): (&mut Vec<f64>, &mut Vec<f64>, &mut Vec<f64>),
    from: f64,
    room: f64,
    block: f64,
) {
    let cells = h.len();
    if cells < 2 || !(room > 0.0) {
        return;
    }
    let mut chosen = None;
    for c in 1..=RAMP_CELLS.min(cells - 1) {
        let len: f64 = h[..c].iter().sum();
        let target = k[c];
        let r = math::ceil(math::abs(target - from) / room).max(1.0);
        if r <= MAX_RAMP as f64 && len / r >= block {
            chosen = Some((c, r as usize, len, target));
            break;
        }
    }
    let (c, r, len, target) = match chosen {
        Some(x) => x,
        None => {
            let c = RAMP_CELLS.min(cells - 1);
            let len: f64 = h[..c].iter().sum();
            let r = if block > 0.0 {
                math::floor(len / block)
            } else {
                1.0
            };
            (c, (r as usize).clamp(1, MAX_RAMP), len, k[c])
        }
    };
    h.splice(0..c, core::iter::repeat_n(len / r as f64, r));
    k.splice(
        0..c,
        (0..r).map(|i| from + (target - from) * (i + 1) as f64 / (r + 1) as f64),
    );
    w.splice(0..c, (0..r).map(|i| i as f64 / r as f64));
}

/// Whether `arcs` (planned speeds `v` over each) pass: curvature steps at
/// the chain's ends against its curves and between arcs that the planned
/// speed passes, and the chord share both ways against the samples.
fn passes(
    arcs: &[Curve],
    v: &[f64],
    samples: &[Sample],
    pts: &[Vec3],
    opts: &RenderOptions,
) -> bool {
    let m = &opts.limits;
    let step = |v: f64| {
        if v > 0.0 {
            opts.step_share * m.jerk * m.period / (v * v)
        } else {
            f64::INFINITY
        }
    };
    let n = arcs.len();
    let (first, last) = (&samples[0], &samples[samples.len() - 1]);
    if (arcs[0].curvature_vector(0.0) - first.kvec).norm() > step(v[0])
        || (arcs[n - 1].curvature_vector(1.0) - last.kvec).norm() > step(v[n - 1])
    {
        return false;
    }
    for i in 0..n - 1 {
        let dk = (arcs[i + 1].curvature_vector(0.0) - arcs[i].curvature_vector(1.0)).norm();
        if dk > 2.0 * step(v[i].max(v[i + 1])) {
            return false;
        }
    }
    let kink = arcs[n - 1]
        .unit_tangent(1.0)
        .map_or(f64::INFINITY, |a| a.angle_to(last.tangent));
    let len = arcs[n - 1].length(opts.chord * 1e-3);
    if 2.0 * kink > step(v[n - 1]) * len {
        return false;
    }
    let lim = DEVIATION_USE * opts.chord;
    let mut hint = 0;
    for &q in &pts[1..pts.len() - 1] {
        let near = |i: usize| piece_distance_bound(&arcs[i], q).is_some_and(|d| d <= lim);
        match (hint..arcs.len()).chain(0..hint).find(|&i| near(i)) {
            Some(i) => hint = i,
            None => return false,
        }
    }
    points_near_polyline(arcs, pts, lim)
}
