//! The run-wide chain of slow points (module docs of [`super`], step
//! 10): the speed must come down to each corner's cap and climb back
//! between them, and every climb turns round at its peak at the jerk
//! limit.

use super::Limits;
use alloc::vec::Vec;

/// A stretch of the run where some point is at most `cap` mm/s: the path
/// passes it between passing gates `first` and `last` (gate indices).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SlowWindow {
    pub(super) first: usize,
    pub(super) last: usize,
    pub(super) cap: f64,
}

/// One end of a link, seen from inside it: the speed there is at most
/// `speed`, and the speed's rate of rise into the link at most `accel`
/// (0 at a valley or at rest).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct LinkEnd {
    pub(super) speed: f64,
    pub(super) accel: f64,
}

impl LinkEnd {
    /// At rest with zero acceleration (a run's ends).
    pub(super) const REST: LinkEnd = LinkEnd {
        speed: 0.0,
        accel: 0.0,
    };
}

/// End chords of the turns [`schur_windows`] tries, in gates.
const SCHUR_CHORDS: [usize; 5] = [1, 2, 4, 8, 16];
/// Lengths of those turns' windows, in end chords.
const SCHUR_SPANS: [usize; 5] = [2, 3, 4, 6, 8];
/// Share of the feed below which a Schur cap makes a slow point
/// (measurements: docs/tuning.md, `SCHUR_CAP_SHARE`).
const SCHUR_CAP_SHARE: f64 = 0.25;

/// Slow windows of paths in order from Schur's comparison (module docs,
/// step 10): for gates `i < j <= k < l` the tangent turns by at least
/// `alpha` ([`super::turn_between`]) over a stretch whose ends are at
/// most `D` apart, so its curvature reaches `k_need = 2 sin(alpha / 2) /
/// D` unless it is longer than `pi / K` (step 8). A path in order stays
/// within `e` of `c([s_i, s_l])` there, a set of diameter at most
/// `s_l - s_i + 2e =: Delta`, and an arc of curvature at most `K` and
/// length `pi / K` has its ends `2 / K` apart (Schur again), so in the
/// second case `K >= 2 / Delta`. Either way the window holds a point of
/// curvature at least `min(k_need, 2 / Delta)`, whose speed is at most
/// `speed_of` that.
pub(super) fn schur_windows(
    gates: &[super::Gate],
    e: f64,
    min_turn: f64,
    speed_of: impl Fn(f64) -> f64,
    feed: f64,
) -> Vec<SlowWindow> {
    let mut out = Vec::new();
    for i in 0..gates.len() {
        for m in SCHUR_CHORDS {
            for n in SCHUR_SPANS {
                let l = i + m * n;
                if l >= gates.len() {
                    continue;
                }
                let Some(t) = super::schur_turn(gates, (i, i + m), (l - m, l), min_turn) else {
                    continue;
                };
                let delta = gates[l].along - gates[i].along + 2.0 * e;
                if delta <= 0.0 {
                    continue;
                }
                let cap = speed_of(t.k_need.min(2.0 / delta));
                if cap < SCHUR_CAP_SHARE * feed {
                    out.push(SlowWindow {
                        first: i,
                        last: l,
                        cap,
                    });
                }
            }
        }
    }
    out
}

/// The speed reached over `x` mm from speed `c` with zero acceleration
/// at jerk `jerk` (`c t + J t^3 / 6 = x`, then `v = c + J t^2 / 2`): how
/// fast a slow point capped at `c` may be `x` away, [`pick_disjoint`]'s
/// order.
fn slowness(c: f64, x: f64, jerk: f64) -> f64 {
    let x = x.max(0.0);
    let (mut lo, mut hi) = (0.0, crate::math::cbrt(6.0 * x / jerk));
    for _ in 0..24 {
        let t = 0.5 * (lo + hi);
        if c * t + jerk * t * t * t / 6.0 < x {
            lo = t;
        } else {
            hi = t;
        }
    }
    c + 0.5 * jerk * hi * hi
}

/// Disjoint windows out of `candidates`, the slowest first (any disjoint
/// choice bounds the run). A window's slowness is the speed its slow
/// point could rise to, from its cap at the jerk limit, over half the
/// window's length (`along(first..last)`, mm): a long window pins its
/// slow point less.
pub(super) fn pick_disjoint(
    candidates: Vec<SlowWindow>,
    along: impl Fn(usize, usize) -> f64,
    jerk: f64,
) -> Vec<SlowWindow> {
    let rise = |w: &SlowWindow| slowness(w.cap, 0.5 * along(w.first, w.last), jerk);
    let mut candidates: Vec<(f64, SlowWindow)> =
        candidates.into_iter().map(|w| (rise(&w), w)).collect();
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut taken: alloc::collections::BTreeMap<usize, SlowWindow> = Default::default();
    for (_, w) in candidates {
        // The taken window starting last before `w` ends must end by
        // `w`'s start (one starting inside `w` is that one).
        let clash = taken
            .range(..w.last)
            .next_back()
            .is_some_and(|(_, t)| t.last > w.first);
        if !clash {
            taken.insert(w.first, w);
        }
    }
    taken.into_values().collect()
}

/// Parts a slow window is cut into (by its gates) for where its slow
/// point lies: the link lengths lose at most a part on each side
/// (measurements: docs/tuning.md, `WINDOW_PARTS`).
const WINDOW_PARTS: usize = 4;

/// A lower bound of the time of a run from rest to rest that passes a
/// point of speed at most `cap` inside each window of `slow` (disjoint,
/// in order), with `length(a, b)` a lower bound of its length between
/// gates `a` and `b` and `last_gate` its end gate (step 10).
///
/// The slow points `y_i` are passed in order. Each lies between two of
/// its window's cut gates (`WINDOW_PARTS` parts), so the link from one
/// to the next is at least as long as the run between the facing cut
/// gates. At each point the acceleration is either at least 0 or at most
/// 0. If `a(y) = alpha > 0`, the speed rose by at least `alpha^2 / (2 J)`
/// over the `alpha / J` before (`|j| <= J`, and at the run's start `a =
/// 0`), so `alpha <= sqrt(2 J cap)`; the same for `a(y) < 0` after it. So
/// each point is a valley on one side (rate of rise 0 into that link)
/// and has a rate of rise at most `sqrt(2 J cap)` into the other. The
/// bound is the least, over every part and sign at every point (a
/// dynamic programme along the chain), of the sum of [`link_time`] over
/// the links.
pub(super) fn chain_time(
    slow: Vec<SlowWindow>,
    last_gate: usize,
    length: impl Fn(usize, usize) -> f64,
    lim: Limits,
) -> f64 {
    // A node's states: (gate before the part, gate after it, end into
    // the link before, start of the link after).
    type State = (usize, usize, LinkEnd, LinkEnd);
    let states = |w: &SlowWindow| -> Vec<State> {
        let steep = LinkEnd {
            speed: w.cap,
            accel: crate::math::sqrt(2.0 * lim.jmax * w.cap),
        };
        let valley = LinkEnd {
            speed: w.cap,
            accel: 0.0,
        };
        let parts = WINDOW_PARTS.min(w.last - w.first).max(1);
        let cut = |p: usize| w.first + (w.last - w.first) * p / parts;
        let mut out = Vec::with_capacity(2 * parts);
        for p in 0..parts {
            let (a, b) = (cut(p), cut(p + 1));
            out.push((a, b, valley, steep));
            out.push((a, b, steep, valley));
        }
        out
    };
    let start: [State; 1] = [(0, 0, LinkEnd::REST, LinkEnd::REST)];
    let mut prev: Vec<State> = start.to_vec();
    let mut best: Vec<f64> = alloc::vec![0.0];
    for w in &slow {
        let cur = states(w);
        let next: Vec<f64> = cur
            .iter()
            .map(|&(a, _, into, _)| {
                prev.iter()
                    .zip(&best)
                    .map(|(&(_, b, _, out), &t)| t + link_time(length(b, a), out, into, lim))
                    .fold(f64::INFINITY, f64::min)
            })
            .collect();
        prev = cur;
        best = next;
    }
    prev.iter()
        .zip(&best)
        .map(|(&(_, b, _, out), &t)| t + link_time(length(b, last_gate), out, LinkEnd::REST, lim))
        .fold(f64::INFINITY, f64::min)
}

/// One side of a link's peak: from an end `end`, the rise over `t1`
/// seconds to the peak, where the acceleration is 0. With `a(0) <=
/// end.accel`, `a(t1) = 0` and `|j| <= J`, `a(s) <= min(end.accel + J s,
/// J (t1 - s), A)`: the speed at `s` is at most `end.speed + g(s)`, `g`
/// the integral of that bound.
struct Rise {
    speed: f64,
    /// Break points of the acceleration bound `(s, a)`, from `(0, _)` to
    /// `(t1, 0)`; linear between them.
    knots: [(f64, f64); 5],
    len: usize,
}

impl Rise {
    fn new(end: LinkEnd, t1: f64, lim: Limits) -> Rise {
        let (alpha, j, a_max) = (end.accel, lim.jmax, lim.amax);
        let acc = |s: f64| (alpha + j * s).min(j * (t1 - s)).min(a_max).max(0.0);
        // The bound is the least of three lines: it bends only where two
        // of them cross.
        let mut cuts = [(a_max - alpha) / j, t1 - a_max / j, 0.5 * (t1 - alpha / j)];
        cuts.sort_by(f64::total_cmp);
        let mut knots = [(0.0, acc(0.0)); 5];
        let mut len = 1;
        for s in cuts {
            if s > knots[len - 1].0 && s < t1 {
                knots[len] = (s, acc(s));
                len += 1;
            }
        }
        knots[len] = (t1, 0.0);
        Rise {
            speed: end.speed,
            knots,
            len: len + 1,
        }
    }

    /// The highest speed the side can reach: at its peak.
    fn top(&self) -> f64 {
        self.speed
            + self.knots[..self.len]
                .windows(2)
                .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
                .sum::<f64>()
    }

    /// An upper bound of the distance covered over the side with the
    /// speed also at most `peak`: `int min(speed + g(s), peak) ds`, split
    /// where the first reaches the second (any split point bounds it).
    fn distance(&self, peak: f64) -> f64 {
        let t1 = self.knots[self.len - 1].0;
        let (mut g, mut dist) = (0.0, 0.0);
        for w in self.knots[..self.len].windows(2) {
            let ((s0, a0), (s1, a1)) = (w[0], w[1]);
            let h = s1 - s0;
            if h <= 0.0 {
                continue;
            }
            let base = self.speed + g;
            let g1 = g + 0.5 * (a0 + a1) * h;
            if self.speed + g1 <= peak {
                // v = base + a0 t + q t^2 on the piece.
                dist += base * h + h * h * (2.0 * a0 + a1) / 6.0;
                g = g1;
                continue;
            }
            // Crosses `peak` on this piece: where base + a0 t + q t^2 =
            // peak (the stable root), then at the peak to t1.
            let q = (a1 - a0) / (2.0 * h);
            let rem = (peak - base).max(0.0);
            let disc = (a0 * a0 + 4.0 * q * rem).max(0.0);
            let root = a0 + crate::math::sqrt(disc);
            let tau = if root > 0.0 {
                (2.0 * rem / root).min(h)
            } else {
                0.0
            };
            dist += base * tau + 0.5 * a0 * tau * tau + q * tau * tau * tau / 3.0;
            return dist + peak * (t1 - (s0 + tau));
        }
        dist
    }
}

/// An upper bound of the distance covered in a link from `start` to
/// `end` that rises for `t1` s to its fastest point and falls for `t2` s
/// after it: each side's [`Rise::distance`] under the peak speed, at
/// most the feed and both sides' tops.
fn reach(start: LinkEnd, end: LinkEnd, t1: f64, t2: f64, lim: Limits) -> f64 {
    let (up, down) = (Rise::new(start, t1, lim), Rise::new(end, t2, lim));
    let peak = up.top().min(down.top()).min(lim.vmax);
    up.distance(peak) + down.distance(peak)
}

/// Cells [`link_time`] splits at most, and the relative size of the
/// cell at which it stops (measurements: docs/tuning.md, `LINK_SPLITS`).
const LINK_SPLITS: usize = 160;
const LINK_PRECISION: f64 = 1e-3;

/// A lower bound of the time over `d` mm of a link between two ends
/// (step 10).
///
/// If the link's fastest point is one of its ends, its speed stays at
/// most the faster end's cap: `d / max(c1, c2)`. Otherwise let `t1` be
/// the time from the start to the fastest point (speed `V`, the feed at
/// most) and `t2` from there to the end. The acceleration there is 0, so
/// with `|j| <= J` the acceleration `s` after the start is at most
/// `min(a0 + J s, J (t1 - s), A)`, and likewise before the end: the speed
/// is under both [`Rise`] bounds and `V`, and the link covers at most
/// [`reach`]`(t1, t2)`. So `t1 + t2` is at least the least over the `(t1,
/// t2)` that may cover `d`: found by branch and bound over cells of
/// `(t1, t2)`, a cell bounded by its lowest `t1 + t2` where [`reach`] at
/// its highest corner covers `d` (it grows with both) and dropped where
/// it does not. A longer link never takes less: a profile over it,
/// scaled down in speed, runs `d` in the same time within every limit,
/// its ends' speeds and rates of rise scaled down too.
pub(super) fn link_time(d: f64, start: LinkEnd, end: LinkEnd, lim: Limits) -> f64 {
    if d.is_nan() || d <= 0.0 {
        return 0.0;
    }
    // The fastest point at an end: the speed stays at most the faster
    // end's (the rise bounds below need the acceleration 0 at the peak).
    let knee = start.speed.max(end.speed).min(lim.vmax);
    let at_ends = if knee > 0.0 { d / knee } else { f64::INFINITY };
    let covers = |t1: f64, t2: f64| reach(start, end, t1, t2, lim) >= d;
    // A side time at which both sides together cover d: every profile
    // with t1 + t2 below `top` has both in [0, top].
    let mut side = 0.5 * d / lim.vmax;
    while !covers(side, side) {
        side *= 2.0;
        if !side.is_finite() || side > at_ends {
            return at_ends;
        }
    }
    let top = 2.0 * side;
    // Cells by their lowest t1 + t2 (non-negative, so its bits order as
    // the numbers do): (bits, t1 range, t2 range).
    type Cell = (u64, [u64; 2], [u64; 2]);
    let cell = |a: [f64; 2], b: [f64; 2]| -> Cell {
        (
            (a[0] + b[0]).to_bits(),
            [a[0].to_bits(), a[1].to_bits()],
            [b[0].to_bits(), b[1].to_bits()],
        )
    };
    let mut cells: alloc::collections::BinaryHeap<core::cmp::Reverse<Cell>> =
        alloc::collections::BinaryHeap::with_capacity(4 * LINK_SPLITS);
    cells.push(core::cmp::Reverse(cell([0.0, top], [0.0, top])));
    for _ in 0..LINK_SPLITS {
        let Some(core::cmp::Reverse((lb, r1, r2))) = cells.pop() else {
            return top.min(at_ends);
        };
        let (lb, r1, r2) = (
            f64::from_bits(lb),
            r1.map(f64::from_bits),
            r2.map(f64::from_bits),
        );
        if (r1[1] - r1[0]) + (r2[1] - r2[0]) <= LINK_PRECISION * lb {
            return lb.min(top).min(at_ends);
        }
        let (m1, m2) = (0.5 * (r1[0] + r1[1]), 0.5 * (r2[0] + r2[1]));
        for a in [[r1[0], m1], [m1, r1[1]]] {
            for b in [[r2[0], m2], [m2, r2[1]]] {
                if covers(a[1], b[1]) {
                    cells.push(core::cmp::Reverse(cell(a, b)));
                }
            }
        }
    }
    cells
        .peek()
        .map_or(top, |c| f64::from_bits(c.0 .0).min(top))
        .min(at_ends)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feed::DoubleS;

    const LIM: Limits = Limits {
        vmax: 400.0,
        amax: 4000.0,
        jmax: 20000.0,
    };

    fn valley(speed: f64) -> LinkEnd {
        LinkEnd { speed, accel: 0.0 }
    }

    fn double_s(d: f64, v0: f64, v1: f64) -> Option<f64> {
        DoubleS::plan(d, v0, v1, &LIM).ok().map(|p| p.duration())
    }

    #[test]
    fn a_rest_to_rest_link_is_the_double_s_within_two_percent() {
        // The bound's two sides are the double-S's own rise and fall when
        // they meet at the peak, so on rest to rest it is close below it.
        for d in [0.5, 5.0, 20.0, 60.0, 400.0] {
            let exact = double_s(d, 0.0, 0.0).unwrap();
            let t = link_time(d, LinkEnd::REST, LinkEnd::REST, LIM);
            assert!(t <= exact * (1.0 + 1e-9), "{d}: {t} above {exact}");
            assert!(t >= 0.98 * exact, "{d}: {t} loose against {exact}");
        }
    }

    #[test]
    fn seeded_links_are_below_every_planned_double_s() {
        // Seeded: random lengths and end speeds; wherever the planner
        // finds a double-S from v0 to v1 (zero end accelerations), the
        // link with caps at least v0, v1 takes no longer.
        let mut rng = crate::seeded::Rng(0x2545_F491_4F6C_DD1D);
        let mut next = || rng.next();
        let mut checked = 0;
        for _ in 0..400 {
            let d = 0.05 + 80.0 * next() * next();
            let (v0, v1) = (LIM.vmax * next() * next(), LIM.vmax * next() * next());
            let Some(exact) = double_s(d, v0, v1) else {
                continue;
            };
            checked += 1;
            let start = LinkEnd {
                speed: (v0 * (1.0 + next())).min(LIM.vmax),
                accel: 1000.0 * next(),
            };
            let t = link_time(d, start, valley(v1), LIM);
            assert!(
                t <= exact * (1.0 + 1e-9),
                "{d} {v0} {v1}: {t} above {exact}"
            );
        }
        assert!(checked > 200, "{checked}");
    }

    #[test]
    fn seeded_picks_are_disjoint_in_order_and_keep_the_slowest() {
        // Any disjoint choice bounds the run; overlapping windows would
        // let two slow points share one stretch.
        let mut rng = crate::seeded::Rng(0x5EED_0092);
        for _ in 0..50 {
            let candidates: Vec<SlowWindow> = (0..40)
                .map(|_| {
                    let first = rng.below(200);
                    SlowWindow {
                        first,
                        last: first + 1 + rng.below(30),
                        cap: 400.0 * rng.next(),
                    }
                })
                .collect();
            let picked = pick_disjoint(candidates.clone(), |a, b| 0.3 * (b - a) as f64, LIM.jmax);
            assert!(!picked.is_empty());
            for w in picked.windows(2) {
                assert!(w[0].last <= w[1].first, "{:?}", w);
            }
            for w in &picked {
                assert!(candidates.contains(w));
            }
            // The slowest candidate is taken first, so always kept.
            let slowest = candidates
                .iter()
                .min_by(|a, b| {
                    let s = |w: &SlowWindow| {
                        slowness(w.cap, 0.15 * (w.last - w.first) as f64, LIM.jmax)
                    };
                    s(a).total_cmp(&s(b))
                })
                .unwrap();
            assert!(picked.contains(slowest), "{slowest:?}");
        }
    }

    #[test]
    fn a_slow_point_between_two_rests_costs_more_than_none() {
        // 40 mm from rest to rest through a point capped at 20 mm/s in the
        // middle: two rises to it and back are slower than one.
        let one = link_time(40.0, LinkEnd::REST, LinkEnd::REST, LIM);
        let slow = [SlowWindow {
            first: 5,
            last: 5,
            cap: 20.0,
        }];
        let chained = chain_time(slow.to_vec(), 10, |a, b| 4.0 * (b - a) as f64, LIM);
        assert!(chained > 1.15 * one, "{chained} against {one}");
        // Each side of the point may be the steep one.
        let steep = LinkEnd {
            speed: 20.0,
            accel: crate::math::sqrt(2.0 * LIM.jmax * 20.0),
        };
        let half = link_time(20.0, LinkEnd::REST, valley(20.0), LIM);
        let half_steep = link_time(20.0, LinkEnd::REST, steep, LIM);
        assert!(half_steep < half);
        assert!((chained - half - half_steep).abs() < 1e-9 * chained);
    }
}
