//! The gates of step 1 (module docs of [`super`]): points of a run every
//! band path passes within a radius of, in order, on straight stretches
//! of the run where nothing else of it comes near; and the lengths they
//! bound.

use super::curved::{curved_gate, windowed_turning};
use super::samples::SampleGrid;
use super::{BandPaths, BoundOptions, MachineLimits, MAX_SAMPLES};
use crate::geom::{flatten_params, ParamCurve, Vec3};
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

/// The polyline of a run within `chord` of it, its arc lengths, and the
/// arc length at which each piece ends.
pub(super) fn polyline(pieces: &[Piece], chord: f64) -> (Vec<Vec3>, Vec<f64>, Vec<f64>) {
    let mut pts: Vec<Vec3> = Vec::new();
    // Index of each piece's last point.
    let mut last = Vec::with_capacity(pieces.len());
    for p in pieces {
        for t in flatten_params(&p.curve, chord) {
            let q = p.curve.eval(t);
            if pts.last().is_none_or(|l| l.dist(q) > 0.0) {
                pts.push(q);
            }
        }
        last.push(pts.len().saturating_sub(1));
    }
    let mut s = Vec::with_capacity(pts.len());
    let mut acc = 0.0;
    for (i, q) in pts.iter().enumerate() {
        if i > 0 {
            acc += q.dist(pts[i - 1]);
        }
        s.push(acc);
    }
    let ends = last
        .iter()
        .map(|&i| s.get(i).copied().unwrap_or(0.0))
        .collect();
    (pts, s, ends)
}

/// Share of the tolerance by which [`feed_caps`] widens each stretch
/// between gates along the run: a written piece near a gate may come
/// from a move up to a few tolerances beyond it.
const FEED_SLACK: f64 = 3.0;

/// The speed cap (mm/s) of a path in order between each two consecutive
/// gates of `gates` (the run's ends included): the fastest of the
/// speeds `speeds` of the pieces (ending at arc lengths `ends`) whose
/// stretch of the run comes within [`FEED_SLACK`] tolerances `tol` of the
/// stretch between the two gates. Module docs, step 11.
pub(super) fn feed_caps(gates: &[Gate], ends: &[f64], speeds: &[f64], tol: f64) -> Vec<f64> {
    let slack = FEED_SLACK * tol;
    gates
        .windows(2)
        .map(|w| {
            let (lo, hi) = (w[0].along - slack, w[1].along + slack);
            // The first piece ending at or after `lo`, then on while the
            // pieces start at or before `hi`.
            let first = ends.partition_point(|&x| x < lo);
            let mut cap: f64 = 0.0;
            for k in first..ends.len() {
                let start = if k == 0 { 0.0 } else { ends[k - 1] };
                if start > hi {
                    break;
                }
                cap = cap.max(speeds[k]);
            }
            cap
        })
        .collect()
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
    tips: &[(f64, Vec3)],
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
        out.extend(
            in_order_gates(pts, s, e, o, tips)
                .into_iter()
                .map(|(_, g)| g),
        );
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
/// (every `gate_spacing` tolerances, radius `e + delta`), also where the
/// run comes back within `2e` of itself farther along it than
/// `hairpin_reach` tolerances (a raster's close passes, a closed
/// contour's ends, a stroke cut there and back): a path that follows the
/// run in order passes each, where a band path could cut across (such a
/// path fails [`crate::verify::follows_in_order`] instead). Nearer, at
/// the tip of a sharp hairpin that the corner methods cut inside the
/// band, no gate stands (sampled every `e / 2`, the step added).
///
/// An exact reversal (`tips`, [`tips_of`]: a V-carve corner's spike out
/// and back, a stroke retraced) is no such hairpin: every method keeps
/// its tip as a corner, the path stops there. A gate of radius `e`
/// stands on the tip (a path in order comes within `e` of every point of
/// the run), and the run coming back along the same legs does not take
/// the straight gates off them (a hit at the mirror image, about a tip
/// between them, of the gate's place along the run).
fn in_order_gates(
    pts: &[Vec3],
    s: &[f64],
    e: f64,
    o: &BoundOptions,
    tips: &[(f64, Vec3)],
) -> Vec<(f64, Gate)> {
    let tol = o.tolerance;
    let total = *s.last().unwrap_or(&0.0);
    let r = o.reach * tol;
    let spacing = (o.gate_spacing * tol).max(total / MAX_SAMPLES as f64);
    let hairpin = o.hairpin_reach * tol;
    let step = 0.5 * e;
    let near = 2.0 * e + step;
    // Whether the run at `y` is the leg through `x` coming back from a
    // tip between them.
    let retraced = |x: f64, y: f64| {
        let (lo, hi) = if x < y { (x, y) } else { (y, x) };
        let first = tips.partition_point(|&(t, _)| t <= lo);
        tips[first..]
            .iter()
            .take_while(|&&(t, _)| t < hi)
            .any(|&(t, _)| (x + y - 2.0 * t).abs() <= near + step)
    };
    // Whether the run between `r` and `hairpin` along it from `x` comes
    // within `near` of `q`, other than back along a retraced leg.
    let at_hairpin = |x: f64, q: Vec3| {
        let mut d = r;
        while d < hairpin {
            let hit = |y: f64| {
                (0.0..=total).contains(&y) && point_at(pts, s, y).dist(q) <= near && !retraced(x, y)
            };
            if hit(x + d) || hit(x - d) {
                return true;
            }
            d += step;
        }
        false
    };
    // Step 1's curved gates (`curved.rs`): where no straight gate stands
    // and the run turns gently.
    let turning = (o.curved_turn > 0.0).then(|| windowed_turning(pts, s, 2.0 * e));
    let mut out = Vec::new();
    let mut x = r.max(spacing);
    let mut next_tip = tips.iter().peekable();
    while x < total - r {
        let gate = straight_gate(pts, s, x, r, e, o.straightness * tol).or_else(|| {
            let turning = turning.as_ref()?;
            curved_gate(
                pts,
                s,
                x,
                r,
                e,
                turning,
                (o.curved_turn, o.curved_vertex_turn),
            )
        });
        if let Some(g) = gate {
            if !at_hairpin(x, g.at) {
                while let Some(&&(t, at)) = next_tip.peek().filter(|&&&(t, _)| t < x) {
                    out.push((t, tip_gate(t, at, e)));
                    next_tip.next();
                }
                out.push((x, g));
            }
        }
        x += spacing;
    }
    out.extend(next_tip.map(|&(t, at)| (t, tip_gate(t, at, e))));
    out
}

/// The gate of radius `e` on the tip `at` of a reversal, `t` along the
/// run.
fn tip_gate(t: f64, at: Vec3, e: f64) -> Gate {
    Gate {
        at,
        radius: e,
        along: t,
    }
}

/// The tips of the reversals of the polyline `pts` (arc lengths `s`)
/// that paths in order pass a gate on, as `opts` says
/// ([`BoundOptions::reversal_half_angle`],
/// [`BoundOptions::reversal_min_leg`]; none for [`BandPaths::Any`]).
pub(super) fn tips_of(pts: &[Vec3], s: &[f64], opts: &BoundOptions) -> Vec<(f64, Vec3)> {
    if opts.paths != BandPaths::InOrder || opts.reversal_half_angle <= 0.0 {
        return Vec::new();
    }
    let tol = opts.tolerance;
    reversal_tips(
        pts,
        s,
        opts.reversal_half_angle,
        opts.chord_share * tol,
        opts.reversal_min_leg * tol,
    )
}

/// Most polyline points [`reversal_tips`] looks past for a leg: more
/// than that within the flattening chord of a vertex are a cluster (moves
/// far inside the band, not a reversal's tip).
const TIP_CLUSTER: usize = 4;

/// The inner vertices of the polyline `pts` (arc lengths `s`) where it
/// turns back on itself: the half-angle between the legs in and out
/// (the angle between the way back and the way out, halved) is below
/// `max_half_angle` rad and both legs are longer than `long_leg` mm. A
/// leg is taken to the nearest point farther than `min_leg` mm (the
/// flattening chord: a piece's end evaluated a rounding away from the
/// next one's start leaves a leg of a few `1e-16` mm, on any heading),
/// and of points that close the last one stands for them. Each with its
/// arc length, in order.
pub(super) fn reversal_tips(
    pts: &[Vec3],
    s: &[f64],
    max_half_angle: f64,
    min_leg: f64,
    long_leg: f64,
) -> Vec<(f64, Vec3)> {
    let n = pts.len();
    // The leg from `pts[i]` to the nearest point farther than `min_leg`
    // before it (`back`) or after it.
    let leg = |i: usize, back: bool| {
        let mut j = i;
        for _ in 0..TIP_CLUSTER {
            j = if back { j.checked_sub(1)? } else { j + 1 };
            let q = *pts.get(j)?;
            if q.dist(pts[i]) > min_leg {
                return Some(q - pts[i]);
            }
        }
        None
    };
    (1..n.saturating_sub(1))
        .filter(|&i| {
            if pts[i + 1].dist(pts[i]) <= min_leg {
                return false;
            }
            match (leg(i, true), leg(i, false)) {
                (Some(back), Some(on)) => {
                    back.norm() > long_leg
                        && on.norm() > long_leg
                        && 0.5 * back.angle_to(on) < max_half_angle
                }
                _ => false,
            }
        })
        .map(|i| (s[i], pts[i]))
        .collect()
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
    best_chain(gates, a, b, max_link, |_, _, link| link)
}

/// The largest sum of `weigh(i, j, |q_j - q_i| - rho_i - rho_j)` over a
/// chain of gates from `a` to `b`, each link at most `max_link` gates
/// long ([`chain_length`]'s lengths; step 11's times).
pub(super) fn best_chain(
    gates: &[Gate],
    a: usize,
    b: usize,
    max_link: usize,
    weigh: impl Fn(usize, usize, f64) -> f64,
) -> f64 {
    if b <= a {
        return 0.0;
    }
    let mut best = alloc::vec![f64::NEG_INFINITY; b - a + 1];
    best[0] = 0.0;
    for i in a..b {
        let bi = best[i - a];
        for j in (i + 1)..=(i + max_link).min(b) {
            let link = (gates[j].at.dist(gates[i].at) - gates[i].radius - gates[j].radius).max(0.0);
            let v = bi + weigh(i, j, link);
            if v > best[j - a] {
                best[j - a] = v;
            }
        }
    }
    best[b - a].max(0.0)
}

/// The inner gates [`BandPaths::InOrder`] puts on a run, and the speeds
/// a path in order keeps to between them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InOrderGates {
    /// Each gate, a point and its radius (the run's ends left out: they
    /// are kept exactly). A path the bound holds for passes within the
    /// radius of each, in order.
    pub gates: Vec<(Vec3, f64)>,
    /// Speed caps, mm/s: `caps[i]` between passing gate `i - 1` and gate
    /// `i`, `caps[0]` from the run's start, the last to its end. A path
    /// the bound holds for runs no piece faster there (module docs, step
    /// 11).
    pub caps: Vec<f64>,
}

/// The [`InOrderGates`] of the run `pieces` for a machine `m`
/// ([`crate::verify::follows_in_order_within`] checks a path against
/// them).
pub fn in_order_gates_of(
    pieces: &[Piece],
    opts: &BoundOptions,
    m: &MachineLimits,
    override_feed: bool,
) -> InOrderGates {
    let chord = opts.tolerance * opts.chord_share;
    let e = opts.tolerance + chord;
    let (pts, s, ends) = polyline(pieces, chord);
    if pts.len() < 2 {
        return InOrderGates::default();
    }
    let opts = BoundOptions {
        paths: BandPaths::InOrder,
        ..*opts
    };
    let (all, _) = gates(&pts, &s, e, &opts, &tips_of(&pts, &s, &opts));
    let speeds: Vec<f64> = pieces
        .iter()
        .map(|p| super::piece_speed(p, m, override_feed))
        .collect();
    InOrderGates {
        caps: feed_caps(&all, &ends, &speeds, opts.tolerance),
        gates: all[1..all.len() - 1]
            .iter()
            .map(|g| (g.at, g.radius))
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> Vec3 {
        Vec3::new(x, y, z)
    }

    /// The arc lengths of a polyline.
    fn lengths(pts: &[Vec3]) -> Vec<f64> {
        let mut s = alloc::vec![0.0];
        for w in pts.windows(2) {
            s.push(s.last().copied().unwrap_or(0.0) + w[0].dist(w[1]));
        }
        s
    }

    const HALF_ANGLE: f64 = 1e-6;
    const CHORD: f64 = 5e-5;
    const LONG: f64 = 0.1;

    #[test]
    fn a_spike_has_one_tip_even_with_its_tip_point_twice() {
        // The tip evaluated at the end of the way out and again, a
        // rounding away, at the start of the way back.
        let tip = v(1.0, 1.0, 0.5);
        let pts = [
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            tip,
            tip + v(0.0, 0.0, 2e-16),
            v(1.0, 0.0, 0.0),
            v(2.0, 0.0, 0.0),
        ];
        let tips = reversal_tips(&pts, &lengths(&pts), HALF_ANGLE, CHORD, LONG);
        assert_eq!(tips.len(), 1, "{tips:?}");
        assert!(tips[0].1.dist(tip) < 1e-12);
    }

    #[test]
    fn a_corner_with_a_rounding_leg_is_no_tip() {
        // A plunge's end a rounding short of the stroke's start: the leg
        // of 2e-16 mm between them points back up the plunge.
        let pts = [
            v(0.0, 0.0, 5.0),
            v(0.0, 0.0, -0.676 - 2e-16),
            v(0.0, 0.0, -0.676),
            v(-0.121, 0.016, -0.676),
        ];
        assert!(reversal_tips(&pts, &lengths(&pts), HALF_ANGLE, CHORD, LONG).is_empty());
    }

    #[test]
    fn a_reversal_on_a_short_leg_is_no_tip() {
        let pts = [
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(1.0, 0.0, -0.035),
            v(1.0, 0.0, 0.0),
            v(2.0, 0.0, 0.0),
        ];
        assert!(reversal_tips(&pts, &lengths(&pts), HALF_ANGLE, CHORD, LONG).is_empty());
        // The same dip, deep enough: a tip.
        let deep = [pts[0], pts[1], v(1.0, 0.0, -0.2), pts[3], pts[4]];
        assert_eq!(
            reversal_tips(&deep, &lengths(&deep), HALF_ANGLE, CHORD, LONG).len(),
            1
        );
    }
}
