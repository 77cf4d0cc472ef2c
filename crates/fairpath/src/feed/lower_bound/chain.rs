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
/// Shares of the feed below which a Schur cap makes a slow point, in
/// ascending order: each share's windows join the walls' in a chain of
/// their own, and the largest bound is kept (a window with a high cap may
/// weaken the chain, so the higher share is tried beside the lower, not in
/// its place; measurements: docs/tuning.md, `SCHUR_CAP_SHARES`).
pub(super) const SCHUR_CAP_SHARES: [f64; 2] = [0.25, 0.5];

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
/// `speed_of` that. Only windows whose cap is below `share` of the feed
/// are returned.
pub(super) fn schur_windows(
    gates: &[super::Gate],
    e: f64,
    min_turn: f64,
    speed_of: impl Fn(f64) -> f64,
    feed: f64,
    share: f64,
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
                if cap < share * feed {
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

/// Cells the acceleration at a slow point is cut into, each sign
/// (measurements: docs/tuning.md, `ALPHA_CELLS`).
const ALPHA_CELLS: usize = 4;

/// A lower bound of the time of a run from rest to rest that passes a
/// point of speed at most `cap` inside each window of `slow` (disjoint,
/// in order), with `length(a, b)` a lower bound of its length between
/// gates `a` and `b` and `last_gate` its end gate (step 10).
///
/// The slow points `y_i` are passed in order. Each lies between two of
/// its window's cut gates (`WINDOW_PARTS` parts), so the link from one
/// to the next is at least as long as the run between the facing cut
/// gates (the part itself is not counted: the links on either side of
/// the point share it, in shares not known). At each point the
/// acceleration `a` is at least 0 or at most 0, and `|a| <=
/// sqrt(2 J cap)`: if `a(y) = alpha > 0`, the speed rose by at least
/// `alpha^2 / (2 J)` over the `alpha / J` before (`|j| <= J`, and at the
/// run's start `a = 0`). Rising through `y` at `alpha`, the link after it
/// starts with a rate of rise at most `alpha`, and the link before it
/// ends with the speed falling into `y` (a rate of rise `-alpha` seen
/// from inside it); falling, the other way round. `alpha`'s range is cut
/// into [`ALPHA_CELLS`] cells, each taken at its worst (the top of the
/// cell for the rise, its bottom for the fall). The bound is the least,
/// over every part, sign and cell at every point (a dynamic programme
/// along the chain), of the sum of [`link_time`] over the links.
pub(super) fn chain_time(
    slow: Vec<SlowWindow>,
    last_gate: usize,
    length: impl Fn(usize, usize) -> f64,
    lim: Limits,
) -> f64 {
    // A node's states: (gate before the part, gate after it, end into
    // the link before, start of the link after).
    type State = (usize, usize, LinkEnd, LinkEnd);
    let cells = ALPHA_CELLS;
    let states = |w: &SlowWindow| -> Vec<State> {
        let steepest = crate::math::sqrt(2.0 * lim.jmax * w.cap);
        let end = |accel: f64| LinkEnd {
            speed: w.cap,
            accel,
        };
        let parts = WINDOW_PARTS.min(w.last - w.first).max(1);
        let cut = |p: usize| w.first + (w.last - w.first) * p / parts;
        let mut out = Vec::with_capacity(2 * parts * cells);
        for p in 0..parts {
            let (a, b) = (cut(p), cut(p + 1));
            for c in 0..cells {
                let lo = steepest * c as f64 / cells as f64;
                let hi = steepest * (c + 1) as f64 / cells as f64;
                // Rising through the point at `lo..hi`: the speed falls
                // into the link before (seen from inside it) and rises
                // into the one after; falling, the other way round.
                out.push((a, b, end(-lo), end(hi)));
                out.push((a, b, end(hi), end(-lo)));
            }
        }
        out
    };
    let start: [State; 1] = [(0, 0, LinkEnd::REST, LinkEnd::REST)];
    let mut prev: Vec<State> = start.to_vec();
    let mut best: Vec<f64> = alloc::vec![0.0];
    for w in &slow {
        let cur = states(w);
        // Lengths between gates, each computed once per window (the
        // states share their parts' gates).
        let mut lengths: Vec<((usize, usize), f64)> = Vec::new();
        for &(a, b, _, _) in &cur {
            for key in prev.iter().map(|p| (p.1, a)).chain([(a, b)]) {
                if !lengths.iter().any(|(k, _)| *k == key) {
                    lengths.push((key, length(key.0, key.1)));
                }
            }
        }
        let length_of = |a: usize, b: usize| -> f64 {
            lengths
                .iter()
                .find(|(k, _)| *k == (a, b))
                .map_or_else(|| length(a, b), |&(_, l)| l)
        };
        let next: Vec<f64> = cur
            .iter()
            .map(|&(a, _, into, _)| {
                prev.iter()
                    .zip(&best)
                    .map(|(&(_, b, _, out), &t)| t + link_time(length_of(b, a), out, into, lim))
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

/// The fastest rise from a link's end to its peak speed `peak`, where
/// the acceleration is 0, with the speed never above `peak`: its time
/// and the distance it covers (both grow with `peak`).
///
/// A speed `v` with acceleration `a > 0` overshoots `peak` unless `v +
/// a^2 / (2 J) <= peak`; so of the ends allowed (speed at most
/// `end.speed`, rate of rise at most `end.accel`, negative where the speed
/// falls into the link) the rise starts from the highest such one, and
/// rises at the jerk limit to its top acceleration `ap` (at most `A`)
/// then falls back to 0: `(ap^2 - a^2) / (2 J) + ap^2 / (2 J) = peak -
/// v`. At every moment no profile from an allowed end that stays at or
/// below `peak` is faster than this one (its acceleration is the highest
/// the jerk allows until it must come down to stop at `peak`), so it
/// reaches `peak` first and covers the most distance in any time:
/// `rise + peak * (t - time)` over `t >= time`.
fn rise(end: LinkEnd, peak: f64, lim: Limits) -> (f64, f64) {
    let (j, a_max) = (lim.jmax, lim.amax);
    let v = end.speed.min(peak);
    let a = end
        .accel
        .min(crate::math::sqrt(2.0 * j * (peak - v).max(0.0)))
        .clamp(-a_max, a_max);
    let ap = crate::math::sqrt((j * (peak - v) + 0.5 * a * a).max(0.0)).max(a);
    let (ap, hold) = if ap > a_max {
        let gained = (a_max * a_max - a * a) / (2.0 * j) + a_max * a_max / (2.0 * j);
        (a_max, ((peak - v - gained) / a_max).max(0.0))
    } else {
        (ap, 0.0)
    };
    let (mut time, mut dist, mut speed, mut acc) = (0.0, 0.0, v, a);
    for (tau, jerk) in [((ap - a) / j, j), (hold, 0.0), (ap / j, -j)] {
        let tau = tau.max(0.0);
        dist += speed * tau + 0.5 * acc * tau * tau + jerk * tau * tau * tau / 6.0;
        speed += acc * tau + 0.5 * jerk * tau * tau;
        acc += jerk * tau;
        time += tau;
    }
    (time, dist)
}

/// A lower bound of the time over `d` mm from the link end `from` to a
/// fastest point at the other end, whose speed is at most `top`: the
/// speed `s` after `from` is at most `from.speed + g(s)` (the rate of
/// rise at most `from.accel + J s` and `A`) and at most `top`, so the
/// time is at least the `T` at which `int_0^T clamp(from.speed + g(s), 0,
/// top) ds` reaches `d` (bisection, kept on the side that does not).
fn climb_time(d: f64, from: LinkEnd, top: f64, lim: Limits) -> f64 {
    let top = top.min(lim.vmax);
    if top <= 0.0 {
        return f64::INFINITY;
    }
    let (j, a_max) = (lim.jmax, lim.amax);
    let a0 = from.accel.min(a_max);
    // The rate of rise reaches `A` at `s1`; before, v = v0 + a0 s + J
    // s^2 / 2; after, linear at `A`.
    let s1 = ((a_max - a0) / j).max(0.0);
    let covered = |t: f64| {
        let h1 = t.min(s1);
        let mut dist = clamped_integral(from.speed, a0, 0.5 * j, h1, top);
        if t > s1 {
            let v1 = from.speed + a0 * s1 + 0.5 * j * s1 * s1;
            dist += clamped_integral(v1, a_max, 0.0, t - s1, top);
        }
        dist
    };
    // Past the time the speed reaches `top` the distance grows at `top`:
    // a bracket.
    let (mut lo, mut hi) = (0.0, d / top);
    while covered(hi) < d {
        lo = hi;
        hi *= 2.0;
        if !hi.is_finite() {
            return f64::INFINITY;
        }
    }
    while hi - lo > LINK_PRECISION * 0.25 * hi {
        let mid = 0.5 * (lo + hi);
        if covered(mid) < d {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// `int_0^h clamp(b + a t + q t^2, 0, peak) dt`, exactly: the quadratic
/// is cut where it crosses `0` and `peak`.
fn clamped_integral(b: f64, a: f64, q: f64, h: f64, peak: f64) -> f64 {
    if h <= 0.0 {
        return 0.0;
    }
    let v = |t: f64| b + a * t + q * t * t;
    let prim = |t: f64| b * t + 0.5 * a * t * t + q * t * t * t / 3.0;
    let mut cuts = [0.0, h, h, h, h, h];
    let mut n = 1;
    for level in [0.0, peak] {
        // Roots of q t^2 + a t + (b - level) in (0, h).
        let c = b - level;
        let mut push = |t: f64| {
            if t > 0.0 && t < h {
                cuts[n] = t;
                n += 1;
            }
        };
        if q == 0.0 {
            if a != 0.0 {
                push(-c / a);
            }
            continue;
        }
        let disc = a * a - 4.0 * q * c;
        if disc < 0.0 {
            continue;
        }
        // The stable pair of roots.
        let r = -0.5 * (a + crate::math::sqrt(disc).copysign(a));
        if r != 0.0 {
            push(r / q);
            push(c / r);
        }
    }
    cuts[n] = h;
    let cuts = &mut cuts[..=n];
    cuts.sort_by(f64::total_cmp);
    cuts.windows(2)
        .map(|w| {
            let (t0, t1) = (w[0], w[1]);
            let mid = v(0.5 * (t0 + t1));
            if t1 <= t0 || mid <= 0.0 {
                0.0
            } else if mid >= peak {
                peak * (t1 - t0)
            } else {
                prim(t1) - prim(t0)
            }
        })
        .sum()
}

/// Cuts of the peak speed [`link_time`] makes at most, and the relative
/// gap at which it stops (measurements: docs/tuning.md, `LINK_SPLITS`).
const LINK_SPLITS: usize = 160;
const LINK_PRECISION: f64 = 1e-3;

/// A lower bound of the time over `d` mm of a link between two ends
/// (step 10).
///
/// If the link's fastest point is one of its ends, the speed stays under
/// that end's cap and climbs from the other end no faster than the jerk
/// and `A` allow ([`climb_time`], either way round). Otherwise its fastest
/// point has speed `P` (the feed at most) and acceleration 0. The part
/// before it takes at least the [`rise`] time `T1(P)` from the start and
/// covers at most `R1(P) + P (t1 - T1(P))` in its `t1`, and the same for
/// the part after it, seen from the end. So `t1 + t2 >= Phi(P) = T1 +
/// T2 + max(0, d - R1 - R2) / P` (the double-S's own time when both ends
/// are at rest), and the link takes at least the least `Phi` over `P`.
/// Over a range `[Pa, Pb]` of `P`, `Phi >= T1(Pa) + T2(Pa) + max(0, d -
/// R1(Pb) - R2(Pb)) / Pb` (both grow with `P`): a branch and bound over
/// ranges of `P`. A longer link never takes less: a profile over it,
/// scaled down in speed, runs `d` in the same time within every limit,
/// its ends' speeds and rates of rise scaled down too.
pub(super) fn link_time(d: f64, start: LinkEnd, end: LinkEnd, lim: Limits) -> f64 {
    if d.is_nan() || d <= 0.0 {
        return 0.0;
    }
    let at_ends = climb_time(d, start, end.speed, lim).min(climb_time(d, end, start.speed, lim));
    // The two sides' rise times and distances at a peak speed `p`.
    let sides = |p: f64| {
        let ((t1, r1), (t2, r2)) = (rise(start, p, lim), rise(end, p, lim));
        (t1 + t2, r1 + r2)
    };
    let phi = |p: f64, (t, r): (f64, f64)| t + (d - r).max(0.0) / p;
    // A range of peak speeds, by its bound (non-negative, so its bits
    // order as the numbers do): (bound, pa, pb, times at pa, distances
    // at pb).
    type Range = (u64, u64, u64, u64, u64);
    let range = |pa: f64, pb: f64, t: f64, r: f64| -> Range {
        let bound = if pb > 0.0 {
            t + (d - r).max(0.0) / pb
        } else {
            f64::INFINITY
        };
        (
            bound.to_bits(),
            pa.to_bits(),
            pb.to_bits(),
            t.to_bits(),
            r.to_bits(),
        )
    };
    let (low, high) = (sides(0.0), sides(lim.vmax));
    let mut ranges: alloc::collections::BinaryHeap<core::cmp::Reverse<Range>> =
        alloc::collections::BinaryHeap::with_capacity(2 * LINK_SPLITS);
    ranges.push(core::cmp::Reverse(range(0.0, lim.vmax, low.0, high.1)));
    let mut best = phi(lim.vmax, high);
    for _ in 0..LINK_SPLITS {
        let Some(&core::cmp::Reverse((lb, pa, pb, t, r))) = ranges.peek() else {
            break;
        };
        if f64::from_bits(lb) >= best * (1.0 - LINK_PRECISION) {
            break;
        }
        ranges.pop();
        let [pa, pb, t, r] = [pa, pb, t, r].map(f64::from_bits);
        let m = 0.5 * (pa + pb);
        let mid = sides(m);
        best = best.min(phi(m, mid));
        ranges.push(core::cmp::Reverse(range(pa, m, t, mid.1)));
        ranges.push(core::cmp::Reverse(range(m, pb, mid.0, r)));
    }
    let lb = ranges
        .peek()
        .map_or(best, |r| f64::from_bits(r.0 .0))
        .min(best);
    lb.min(at_ends)
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
    fn a_rest_to_rest_link_is_the_double_s_within_a_fifth_of_a_percent() {
        // The bound's two sides are the double-S's own rise and fall when
        // they meet at the peak, so on rest to rest it is close below it.
        for d in [0.5, 5.0, 20.0, 60.0, 400.0] {
            let exact = double_s(d, 0.0, 0.0).unwrap();
            let t = link_time(d, LinkEnd::REST, LinkEnd::REST, LIM);
            assert!(t <= exact * (1.0 + 1e-9), "{d}: {t} above {exact}");
            assert!(t >= 0.998 * exact, "{d}: {t} loose against {exact}");
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
        // The acceleration at the point is cut into cells: the steep
        // side's rise is that of its cell's top, the other side dips by
        // its cell's bottom; a valley on both sides is slower still.
        assert!(chained >= half + half_steep, "{chained}");
        assert!(chained > half + half_steep + 0.01 * chained, "{chained}");
        assert!(chained <= 2.0 * half, "{chained} against {half}");
    }

    #[test]
    fn a_window_capped_at_the_feed_costs_no_more_than_the_runs_double_s() {
        // A window of half the run in its middle, capped at the feed (or,
        // on 2 mm, at a speed the run never reaches), allows the run's
        // own double-S from rest to rest; its fastest point is the
        // window's, so the links' climbs to it are at the jerk limit.
        for (d, share) in [(40.0f64, 1.0f64), (400.0, 1.0), (2.0, 0.25)] {
            let gates = 40;
            let step = d / gates as f64;
            let slow = [SlowWindow {
                first: 10,
                last: 30,
                cap: LIM.vmax * share,
            }];
            let chained = chain_time(slow.to_vec(), gates, |a, b| step * (b - a) as f64, LIM);
            let exact = double_s(d, 0.0, 0.0).unwrap();
            assert!(
                chained <= exact * (1.0 + 1e-9),
                "{d}: {chained} above {exact}"
            );
        }
    }

    #[test]
    fn a_steep_end_bounds_the_slower_starts_it_allows() {
        // An end at most 20 mm/s rising at most 900 mm/s^2 allows a start
        // at 5 mm/s and rest: a short double-S from there peaks below 20
        // + 900^2 / (2 J), where that steep start would overshoot; the
        // link takes the start that stops at the peak.
        for d in [0.5, 1.0, 2.0, 4.0] {
            let exact = double_s(d, 5.0, 5.0).unwrap();
            let steep = LinkEnd {
                speed: 20.0,
                accel: 900.0,
            };
            let t = link_time(d, steep, valley(5.0), LIM);
            assert!(t <= exact * (1.0 + 1e-9), "{d}: {t} above {exact}");
        }
    }

    #[test]
    fn seeded_cuts_of_planned_double_s_are_above_their_links() {
        // Seeded: a planned double-S cut at a random moment gives two
        // links whose inner ends are passed with the acceleration there
        // (a rise out of the cut after it, a fall into it before it, seen
        // from inside each); each part takes at least its link's bound.
        let mut rng = crate::seeded::Rng(0x9E37_79B9_7F4A_7C15);
        let mut next = || rng.next();
        let mut checked = 0;
        for _ in 0..400 {
            let d = 0.05 + 80.0 * next() * next();
            let (v0, v1) = (LIM.vmax * next() * next(), LIM.vmax * next() * next());
            let Ok(plan) = DoubleS::plan(d, v0, v1, &LIM) else {
                continue;
            };
            let tc = plan.duration() * next();
            let cut = plan.eval(tc);
            if cut.q <= 0.0 || cut.q >= d {
                continue;
            }
            checked += 1;
            let before = link_time(
                cut.q,
                valley(v0),
                LinkEnd {
                    speed: cut.v,
                    accel: -cut.a,
                },
                LIM,
            );
            assert!(
                before <= tc * (1.0 + 1e-9),
                "{d} {v0} {v1} at {tc}: {before}"
            );
            let after = link_time(
                d - cut.q,
                LinkEnd {
                    speed: cut.v,
                    accel: cut.a,
                },
                valley(v1),
                LIM,
            );
            let rest = plan.duration() - tc;
            assert!(
                after <= rest * (1.0 + 1e-9),
                "{d} {v0} {v1} at {tc}: {after} above {rest}"
            );
        }
        assert!(checked > 200, "{checked}");
    }
}
