//! The gates of step 1 (module docs of [`super`]): points of a run every
//! band path passes within a radius of, in order, on straight stretches
//! of the run where nothing else of it comes near; and the lengths they
//! bound.

use super::samples::SampleGrid;
use super::{BandPaths, BoundOptions, MAX_SAMPLES};
use crate::geom::{flatten_params, ParamCurve, Vec3};
use crate::math;
use crate::path::Piece;
use alloc::vec::Vec;

/// A gate: a point every band path passes within `radius` of, in order.
#[derive(Clone, Copy, Debug)]
pub(super) struct Gate {
    pub(super) at: Vec3,
    pub(super) radius: f64,
    /// Arc length of the gate's point along the run's polyline.
    pub(super) along: f64,
}

/// Where the run comes back within `2e` of itself farther than the reach
/// along it (step 1's bridges): `(starts, reach)` sorted by start, `reach`
/// a running maximum.
pub(super) struct Bridges {
    starts: Vec<f64>,
    reach: Vec<f64>,
}

impl Bridges {
    /// Whether a bridge spans arc length `x`: two points `s1 <= x <= s2`
    /// farther apart along the run than the reach come within `2e`.
    pub(super) fn spans(&self, x: f64) -> bool {
        let i = self.starts.partition_point(|&st| st <= x);
        i > 0 && self.reach[i - 1] >= x
    }
}

/// The polyline of a run within `chord` of it, with arc lengths.
pub(super) fn polyline(pieces: &[Piece], chord: f64) -> (Vec<Vec3>, Vec<f64>) {
    let mut pts: Vec<Vec3> = Vec::new();
    for p in pieces {
        for t in flatten_params(&p.curve, chord) {
            let q = p.curve.eval(t);
            if pts.last().is_none_or(|l| l.dist(q) > 0.0) {
                pts.push(q);
            }
        }
    }
    let mut s = Vec::with_capacity(pts.len());
    let mut acc = 0.0;
    for (i, q) in pts.iter().enumerate() {
        if i > 0 {
            acc += q.dist(pts[i - 1]);
        }
        s.push(acc);
    }
    (pts, s)
}

/// The point at arc length `x` of the polyline.
pub(super) fn point_at(pts: &[Vec3], s: &[f64], x: f64) -> Vec3 {
    let i = s.partition_point(|&v| v <= x).clamp(1, pts.len() - 1);
    let (a, b) = (s[i - 1], s[i]);
    let t = if b > a {
        ((x - a) / (b - a)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    pts[i - 1].lerp(pts[i], t)
}

/// For each arc length, the farthest arc length a bridge starting at or
/// before it reaches (module docs, step 1): `(starts, reach)` sorted by
/// start, `reach` a running maximum.
fn bridges(pts: &[Vec3], s: &[f64], e: f64, r: f64) -> Bridges {
    let total = *s.last().unwrap_or(&0.0);
    let step = (0.5 * e).max(total / MAX_SAMPLES as f64);
    let reach_d = 2.0 * e + step;
    let grid = SampleGrid::new(pts, s, step, reach_d);
    let mut reach = alloc::vec![f64::NEG_INFINITY; grid.samples.len()];
    for (i, &(xi, pi)) in grid.samples.iter().enumerate() {
        grid.any_near(pi, |xj, pj| {
            if xj - xi > r - step && pi.dist(pj) <= reach_d {
                reach[i] = reach[i].max(xj + 0.5 * step);
            }
            false
        });
    }
    let starts: Vec<f64> = grid.samples.iter().map(|(x, _)| x - 0.5 * step).collect();
    let mut run = f64::NEG_INFINITY;
    for v in reach.iter_mut() {
        run = run.max(*v);
        *v = run;
    }
    Bridges { starts, reach }
}

/// The gates of a run (module docs, step 1), run ends included, and the
/// run's bridges (`None` for [`BandPaths::InOrder`], which needs none).
pub(super) fn gates(
    pts: &[Vec3],
    s: &[f64],
    e: f64,
    o: &BoundOptions,
) -> (Vec<Gate>, Option<Bridges>) {
    let tol = o.tolerance;
    let total = *s.last().unwrap_or(&0.0);
    let r = o.reach * tol;
    let mut out = alloc::vec![Gate {
        at: pts[0],
        radius: 0.0,
        along: 0.0,
    }];
    let spacing = o.gate_spacing * tol;
    if o.paths == BandPaths::InOrder {
        out.extend(in_order_gates(pts, s, e, o).into_iter().map(|(_, g)| g));
        out.push(Gate {
            at: *pts.last().unwrap_or(&pts[0]),
            radius: 0.0,
            along: total,
        });
        return (out, None);
    }
    let bridges = bridges(pts, s, e, r);
    let mut x = r.max(spacing);
    while x < total - r {
        if !bridges.spans(x) {
            if let Some(g) = straight_gate(pts, s, x, r, e, o.straightness * tol) {
                out.push(g);
            }
        }
        x += spacing;
    }
    out.push(Gate {
        at: *pts.last().unwrap_or(&pts[0]),
        radius: 0.0,
        along: total,
    });
    (out, Some(bridges))
}

/// The inner gates of [`BandPaths::InOrder`] on the polyline `pts` (arc
/// lengths `s`), each with its arc length: the straight gates of step 1
/// (every `gate_spacing` tolerances, radius `e + delta`) where no part of
/// the run farther than the reach `r` along it comes within `2e` of the
/// gate (sampled, the sampling step added). There the band is the one
/// straight stretch's, and a path that follows the run in order crosses
/// it once, through the gate.
fn in_order_gates(pts: &[Vec3], s: &[f64], e: f64, o: &BoundOptions) -> Vec<(f64, Gate)> {
    let tol = o.tolerance;
    let total = *s.last().unwrap_or(&0.0);
    let r = o.reach * tol;
    let spacing = (o.gate_spacing * tol).max(total / MAX_SAMPLES as f64);
    let step = (0.5 * e).max(total / MAX_SAMPLES as f64);
    let near = 2.0 * e + step;
    let grid = SampleGrid::new(pts, s, step, near);
    // Whether a sample farther than `r` along the run from `x` is within
    // `near` of `q`.
    let crowded = |x: f64, q: Vec3| {
        grid.any_near(q, |xj, pj| {
            math::abs(xj - x) > r - step && q.dist(pj) <= near
        })
    };
    let mut out = Vec::new();
    let mut x = r.max(spacing);
    while x < total - r {
        if let Some(g) = straight_gate(pts, s, x, r, e, o.straightness * tol) {
            if !crowded(x, g.at) {
                out.push((x, g));
            }
        }
        x += spacing;
    }
    out
}

/// A gate at arc length `x` if the polyline is straight enough around it.
fn straight_gate(pts: &[Vec3], s: &[f64], x: f64, r: f64, e: f64, max_delta: f64) -> Option<Gate> {
    let q = point_at(pts, s, x);
    let a = point_at(pts, s, x - r);
    let b = point_at(pts, s, x + r);
    let d = (b - a).normalized(r * 1e-6)?;
    let lo = s.partition_point(|&v| v <= x - r);
    let hi = s.partition_point(|&v| v < x + r);
    let mut chain = alloc::vec![a];
    chain.extend_from_slice(&pts[lo..hi]);
    chain.push(b);
    let mut delta: f64 = 0.0;
    let mut last = f64::NEG_INFINITY;
    for p in chain {
        let along = (p - q).dot(d);
        if along < last {
            return None;
        }
        last = along;
        delta = delta.max(((p - q) - d * along).norm());
    }
    (delta <= max_delta).then_some(Gate {
        at: q,
        radius: e + delta,
        along: x,
    })
}

/// The longest chain of gates from `a` to `b` (links of at most `max_link`
/// gates), each link `|q_i - q_j| - rho_i - rho_j`: a lower bound of the
/// length of any band path between passing gate `a` and gate `b`.
pub(super) fn chain_length(gates: &[Gate], a: usize, b: usize, max_link: usize) -> f64 {
    if b <= a {
        return 0.0;
    }
    let mut best = alloc::vec![f64::NEG_INFINITY; b - a + 1];
    best[0] = 0.0;
    for i in a..b {
        let bi = best[i - a];
        for j in (i + 1)..=(i + max_link).min(b) {
            let link = (gates[j].at.dist(gates[i].at) - gates[i].radius - gates[j].radius).max(0.0);
            let v = bi + link;
            if v > best[j - a] {
                best[j - a] = v;
            }
        }
    }
    best[b - a].max(0.0)
}

/// The inner gates [`BandPaths::InOrder`] puts on the run `pieces` (the
/// run's ends left out: they are kept exactly), each a point and its
/// radius: a path the bound holds for passes within the radius of each, in
/// order ([`crate::verify::follows_in_order`] checks that).
pub fn in_order_gates_of(pieces: &[Piece], opts: &BoundOptions) -> Vec<(Vec3, f64)> {
    let chord = opts.tolerance * opts.chord_share;
    let e = opts.tolerance + chord;
    let (pts, s) = polyline(pieces, chord);
    if pts.len() < 2 {
        return Vec::new();
    }
    in_order_gates(&pts, &s, e, opts)
        .into_iter()
        .map(|(_, g)| (g.at, g.radius))
        .collect()
}
