//! Straightening (ours, beyond the thesis): after the thesis' iterations,
//! the curve's turning `integral |k| ds` is minimised over all movable
//! control points at once, inside the tube, with no span's curvature peak
//! above the original's near it and no stretch's curvature rising more
//! than a slack.
//!
//! Why: the thesis' objective is a straighter curve (its Tables 4-1 and 4-6
//! measure the average curvature, the turning over the length), and its
//! iterations pursue it by a heuristic that stops everywhere as soon as
//! the curve touches the tube anywhere (eq. 3-39 is one allowance for
//! all). On a square whose corners an interpolation turned into ripples
//! (the thesis' case 6), the corners touch first and the ripples beside
//! them, which cap the speed between the corners, stay. Minimising the
//! turning itself flattens every ripple as far as the tube lets it,
//! whatever touches elsewhere; the caps on the curvature (the U-to-V
//! guard of [`super::guard`] as a constraint, and each stretch's own) stop
//! it buying straight legs with a sharper corner (the turning of a
//! monotone bend is its angle, whatever its shape). Even so, on a smooth
//! curve the curvature lowered between its peaks steepens its ramps,
//! which a jerk-limited planner pays for (`|dk/ds| v^3 <= J`): the
//! straightening is off in [`super::TubeFairOptions`] by default, and
//! method `fair` has the planner judge it run by run.
//!
//! The problem, with `C` the curve, `O` the original and `u_i` the
//! [`STRAIGHTEN_SAMPLES`] midpoints of equal steps of each span:
//! minimise `T = sum w_i |C'(u_i) x C''(u_i)| / |C'(u_i)|^2` (the midpoint
//! rule of `integral k |C'| du`) subject to `d_i < R` (`d_i` the distance
//! from `C(u_i)` to `O`, as the tube measures it: at the equal parameter,
//! or to the nearest point, [`super::slide`]), each sample's curvature
//! below its own at the start plus [`START_SLACK`] of its span's peak
//! (the turning may not be bought by sharpening one stretch to flatten
//! another), and each span's peak below the original's highest near it
//! (the guard's U-to-V rule, [`PeakReference`]) and its own at the start
//! plus the slack. A log barrier (Boyd and Vandenberghe, Convex
//! Optimization, section 11.2: `T - mu sum ln(slack of each constraint)`,
//! `mu` divided by [`BARRIER_DIVISOR`] each of [`BARRIER_ROUNDS`] rounds) keeps every
//! iterate strictly inside; each round is solved by L-BFGS (Nocedal and
//! Wright, Numerical Optimization, 2nd ed., algorithm 7.4) with a
//! backtracking (Armijo) line search that rejects infeasible points. The
//! gradients are in closed form: with `c = C' x C''`, `s = |C'|` and the
//! basis functions `N_j`, `N'_j`, `N''_j` at `u_i`,
//! `d|c|/dP_j = N'_j (C'' x c^) + N''_j (c^ x C')` and
//! `ds/dP_j = N'_j C' / s`; the distance's is `N_j (C - O) / d` (the
//! nearest point does not move to first order).
//!
//! The samples are not a bound: the result is kept only when the sure
//! bound of the tube ([`super::slide::sliding_bound_on`] or
//! [`super::tube::deviation_bound_on`]) is within `R` on every span and
//! no span's peak (its samples, each maximum of the curvature and
//! minimum of the speed refined: a near-cusp between samples is a spike
//! the sampled turning does not see) rises above the original's near it; otherwise the move
//! is halved towards the start until they hold, or dropped.

use super::guard::{PeakReference, PEAK_ACCURACY};
use super::slide::{Original, TubeMeasure};
use super::spans::{bezier_derivatives, bezier_of_span, nonempty_spans, Basis};
use super::tube::difference;
use crate::geom::cubic_span::cubic_basis;
use crate::geom::{curvature_from, sampled_peak, Extrema, Vec3, NARROW};
use crate::math;
use alloc::vec;
use alloc::vec::Vec;

/// Samples per knot span (ours): the turning of a cubic span, whose
/// curvature has at most a few extrema, to well under a percent.
pub const STRAIGHTEN_SAMPLES: usize = 16;

/// Share of `R` the samples keep clear of the tube (ours): the curve can
/// bulge between samples, and the sure bound that decides is exact to
/// `accuracy * R`; with this margin the whole move usually passes.
pub const SAMPLE_MARGIN: f64 = 0.05;

/// How far a span's peak, and each sample's curvature, may rise above
/// where the barrier starts, as a share of the span's peak there (ours):
/// the barrier needs the start strictly inside its caps, and a corner a
/// little sharper may buy much flatter ripples beside it, while a larger
/// share lets the turning be bought by sharper bends (measurements:
/// docs/tuning.md, "Straightening and the sliding tube").
pub const START_SLACK: f64 = 0.03;

/// Relative margin over the original's peaks that keeps a start whose
/// peak equals them strictly inside the barrier; the sure check compares
/// with the peaks themselves, and halves a move that rose into it.
const CAP_TIE: f64 = 1e-9;

/// Spans either way whose peaks a span's cap takes in: the degree, as the
/// guard's reference ([`PeakReference`]).
const NEAR_REACH: usize = 3;

/// Shares of the thesis' move from the original that the barrier may start
/// at, the first strictly inside: the original itself last.
const START_SHARES: [f64; 6] = [1.0, 0.95, 0.9, 0.8, 0.6, 0.0];

/// Rounds of the barrier (ours): `mu` falls from a tenth of the mean
/// turning per sample by [`BARRIER_DIVISOR`] each round.
pub const BARRIER_ROUNDS: usize = 4;

/// What `mu` is divided by between rounds.
pub const BARRIER_DIVISOR: f64 = 10.0;

/// Most L-BFGS iterations per round (ours): what a small curve (the
/// thesis' square, 26 spans) may take.
pub const ROUND_ITERATIONS: usize = 400;

/// Fewest L-BFGS iterations per round a large curve is allowed (ours).
pub const MIN_ROUND_ITERATIONS: usize = 50;

/// Sample evaluations (samples times iterations) one round may spend
/// (ours): a curve of up to 32 spans gets [`ROUND_ITERATIONS`], a larger
/// one proportionally fewer, down to [`MIN_ROUND_ITERATIONS`], so the work
/// per curve is bounded whatever its size (the line search's extra
/// evaluations aside). On LinuxCNC's `Ruota_dentata_p3.ngc` (curves of 64
/// spans) straightening at 400 iterations a round planned no faster than
/// at 100 and took several times the computing time (measurements:
/// docs/tuning.md, "Straightening and the sliding tube").
pub const ROUND_WORK: usize = ROUND_ITERATIONS * STRAIGHTEN_SAMPLES * 32;

/// The iterations a round over `samples` samples may take
/// ([`ROUND_WORK`]).
pub fn round_iterations(samples: usize) -> usize {
    (ROUND_WORK / samples.max(1)).clamp(MIN_ROUND_ITERATIONS, ROUND_ITERATIONS)
}

/// Pairs L-BFGS remembers.
const MEMORY: usize = 6;

/// Most halvings of a step in the line search, and of the whole move when
/// the sure bound or the guard refuses it.
const HALVINGS: usize = 30;

/// Relative decrease of the barrier objective over [`STALL_WINDOW`]
/// iterations under which a round ends (ours: a millionth of the turning
/// is far below any gain worth the work).
const STALL: f64 = 1e-6;

/// Iterations over which [`STALL`] is judged: L-BFGS steps on a barrier
/// vary in size, and a single short one says little.
const STALL_WINDOW: usize = 10;

/// What the straightening did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StraightenRecord {
    /// L-BFGS iterations over all rounds.
    pub iterations: usize,
    /// Turning `integral |k| ds` (radians, sampled) before and after.
    pub turning_before: f64,
    pub turning_after: f64,
    /// Share of the optimiser's move kept (1 all of it, 0 none).
    pub kept: f64,
    /// Sure bound of the result's distance from the original (mm).
    pub deviation_bound: f64,
}

/// The curve being straightened and what bounds it.
pub(super) struct Straightening<'a> {
    pub basis: Basis<'a>,
    pub orig: &'a [Vec3],
    /// Control points that may move.
    pub movable: Vec<bool>,
    pub radius: f64,
    /// `accuracy * R`: the tightness of the sure bound.
    pub resolution: f64,
    pub reference: Option<&'a PeakReference>,
    pub tube: TubeMeasure,
    /// The original's spans (a non-rational cubic's: the only curves
    /// straightened).
    pub original: Option<&'a Original<'a>>,
}

/// One sample: its span, parameter, weight, basis rows and peak cap.
struct Sample {
    span: usize,
    t: f64,
    w: f64,
    n: [[f64; 4]; 3],
    /// The span's peak cap.
    cap: f64,
    /// This sample's own cap: its curvature where the barrier starts,
    /// plus [`START_SLACK`] of the span's peak there.
    k_cap: f64,
}

/// Value, gradient (per control point) and turning at a point.
struct Eval {
    f: f64,
    grad: Vec<Vec3>,
    turning: f64,
}

impl Straightening<'_> {
    /// Straightens `cur` (see the module documentation); `bound` is the
    /// sure bound of its distance from the original now.
    pub fn run(&self, cur: &mut [Vec3], bound: f64) -> StraightenRecord {
        let mut record = StraightenRecord {
            deviation_bound: bound,
            ..StraightenRecord::default()
        };
        let Some(o) = self.original else {
            return record;
        };
        if !self.movable.iter().any(|&m| m) {
            return record;
        }
        let start: Vec<Vec3> = cur.to_vec();
        // The caps: no span above the original's peaks near it (the
        // guard), nor above the peaks near it where the barrier starts, so
        // that it never buys straighter legs with sharper corners than the
        // iterations left.
        // The peaks near each span, measured as the barrier measures them
        // (the guard's own samples may fall short of a broad peak's top,
        // which would put the original itself outside its caps).
        let orig_near = self.reference.map(|_| self.near_peaks(self.orig));
        let own = |x: &[Vec3]| self.reference.map(|_| self.own_peaks(x));
        let caps = |x: &[Vec3]| match (&orig_near, own(x)) {
            (Some(o), Some(n)) => Some((o.clone(), n)),
            _ => None,
        };
        let samples = self.samples(&start, caps(&start).as_ref());
        if samples.is_empty() {
            return record;
        }
        let mut v: Vec<f64> = samples.iter().map(|s| s.t).collect();
        let Some(first) = self.eval(o, &samples, &start, &mut v, 0.0, 1.0) else {
            return record; // a sample beyond the tube or a cap
        };
        record.turning_before = first.turning;
        record.turning_after = first.turning;
        let mut mu = 0.1 * first.turning / samples.len() as f64;
        // The barrier's start: strictly inside its margin, the curve drawn
        // back towards the original as far as needed (the thesis'
        // iterations stop touching the tube), its caps from there.
        let Some((mut x, samples)) = START_SHARES.iter().find_map(|&share| {
            let x: Vec<Vec3> = self
                .orig
                .iter()
                .zip(&start)
                .map(|(a, b)| *a + (*b - *a) * share)
                .collect();
            let samples = self.samples(&x, caps(&x).as_ref());
            self.eval(o, &samples, &x, &mut v, mu, 1.0 - SAMPLE_MARGIN)
                .map(|_| (x, samples))
        }) else {
            return record;
        };
        for _ in 0..BARRIER_ROUNDS {
            record.iterations += self.minimise(o, &samples, &mut x, &mut v, mu);
            mu /= BARRIER_DIVISOR;
        }
        // The sure checks, halving the move towards the start until they
        // hold.
        let mut share = 1.0;
        for _ in 0..HALVINGS {
            let trial: Vec<Vec3> = start
                .iter()
                .zip(&x)
                .map(|(a, b)| *a + (*b - *a) * share)
                .collect();
            let turning = self
                .eval(o, &samples, &trial, &mut v, 0.0, 1.0)
                .map(|e| e.turning);
            if let (Some(turning), Some(b)) = (turning, self.sure(&trial, orig_near.as_deref())) {
                if turning < record.turning_before {
                    cur.copy_from_slice(&trial);
                    record.turning_after = turning;
                    record.kept = share;
                    record.deviation_bound = b;
                }
                return record;
            }
            share *= 0.5;
        }
        record
    }

    /// Each span's highest curvature on `x` (0 for empty spans), by knot
    /// index: [`STRAIGHTEN_SAMPLES`] equal steps, every sampled maximum of
    /// the curvature and minimum of the speed refined to [`PEAK_ACCURACY`]
    /// ([`sampled_peak()`], [`Extrema::All`]). The speed minima matter: the
    /// turning the barrier minimises is sampled, and a move that folds a
    /// span into a near-cusp between samples (its turning, up to a half
    /// turn, concentrated where no sample sees it) looks straighter to it;
    /// the curvature's own samples and their refinement miss such a spike,
    /// its speed's minimum finds it (seed 17415750764187490486 of the
    /// property tests: a peak of 8.5e27 1/mm passed).
    fn own_peaks(&self, x: &[Vec3]) -> Vec<f64> {
        let u = self.basis.knots;
        let mut own = vec![0.0f64; x.len()];
        for s in nonempty_spans(&self.basis, x.len()) {
            let bez = bezier_of_span(u, x, s);
            own[s] = sampled_peak(
                |tau| bezier_derivatives(&bez, tau),
                (0.0, 1.0),
                STRAIGHTEN_SAMPLES,
                PEAK_ACCURACY,
                Extrema::All,
            );
        }
        own
    }

    /// [`Straightening::own_peaks`] of `x`, then the highest within
    /// [`NEAR_REACH`] spans of each (as the guard's reference).
    fn near_peaks(&self, x: &[Vec3]) -> Vec<f64> {
        let own = self.own_peaks(x);
        let mut near = vec![0.0f64; x.len()];
        for s in nonempty_spans(&self.basis, x.len()) {
            let lo = s.saturating_sub(NEAR_REACH);
            let hi = (s + NEAR_REACH).min(x.len() - 1);
            near[s] = own[lo..=hi].iter().copied().fold(0.0, f64::max);
        }
        near
    }

    /// The samples of every non-empty span, with the caps `caps` (the
    /// original's peaks near each span and the start's) if any.
    fn samples(&self, x: &[Vec3], caps: Option<&(Vec<f64>, Vec<f64>)>) -> Vec<Sample> {
        let u = self.basis.knots;
        let mut out = Vec::new();
        for s in nonempty_spans(&self.basis, self.orig.len()) {
            let (a, b) = (u[s], u[s + 1]);
            let h = (b - a) / STRAIGHTEN_SAMPLES as f64;
            let floor = self.reference.map_or(0.0, |r| r.floor);
            let cap = caps.map_or(f64::INFINITY, |(orig, own)| {
                (orig[s] * (1.0 + CAP_TIE))
                    .min(own[s] * (1.0 + START_SLACK))
                    .max(floor)
            });
            for j in 0..STRAIGHTEN_SAMPLES {
                let t = a + h * (j as f64 + 0.5);
                let n = cubic_basis(u, s, t);
                let k_cap = caps.map_or(f64::INFINITY, |(_, own)| {
                    let (_, d1, d2) = at(x, s - 3, &n);
                    curvature_from(d1, d2) + START_SLACK * own[s] + floor
                });
                out.push(Sample {
                    span: s,
                    t,
                    w: h,
                    n,
                    cap,
                    k_cap,
                });
            }
        }
        out
    }

    /// The barrier objective at `x` with weight `mu` (0: the turning
    /// alone) and the tube at `room` times `R`, or `None` where a sample is
    /// not strictly inside. `v` holds the samples' parameters on the
    /// original (warm starts). The peak cap is weighed once per span, at
    /// its highest curvature (the highest sample, refined by golden-section
    /// search between its neighbours: a corner's peak is narrower than the
    /// samples' step, and at the maximum `dk/dt = 0`, so the gradient there
    /// is the one at a fixed parameter).
    fn eval(
        &self,
        o: &Original,
        samples: &[Sample],
        x: &[Vec3],
        v: &mut [f64],
        mu: f64,
        room: f64,
    ) -> Option<Eval> {
        let r = self.radius * room;
        let u = self.basis.knots;
        let mut f = 0.0;
        let mut turning = 0.0;
        let mut grad = vec![Vec3::ZERO; x.len()];
        for (i0, group) in spans_of(samples) {
            let s = group[0].span;
            let first = s - 3;
            let mut top = (0usize, -1.0f64);
            // The least sampled speed, where a near-cusp hides.
            let mut slow = (0usize, f64::INFINITY);
            for (j, smp) in group.iter().enumerate() {
                let i = i0 + j;
                let (p, d1, d2) = at(x, first, &smp.n);
                let sp = d1.norm();
                if sp.is_nan() || sp <= 0.0 {
                    return None;
                }
                let c = d1.cross(d2);
                let cn = c.norm();
                let s2 = sp * sp;
                let k = cn / (s2 * sp);
                if k > top.1 {
                    top = (j, k);
                }
                if sp < slow.1 {
                    slow = (j, sp);
                }
                let term = cn / s2;
                turning += smp.w * term;
                f += smp.w * term;
                // d(|c| / s^2) = d|c| / s^2 - 2 |c| / s^3 ds.
                let (gc1, gc2, ds) = parts(d1, d2, c, cn, sp);
                let mut per = [Vec3::ZERO; 4];
                for (a, g) in per.iter_mut().enumerate() {
                    let dc = gc1 * smp.n[1][a] + gc2 * smp.n[2][a];
                    let dsj = ds * smp.n[1][a];
                    *g = (dc * (1.0 / s2) - dsj * (2.0 * cn / (s2 * sp))) * smp.w;
                }
                // The tube.
                let q = match self.tube {
                    TubeMeasure::EqualParameter => o.derivs(smp.t).0,
                    TubeMeasure::Sliding => {
                        v[i] = o.project(p, v[i], self.resolution).0;
                        o.derivs(v[i]).0
                    }
                };
                let off = p - q;
                let d = off.norm();
                if d.is_nan() || d >= r {
                    return None;
                }
                if mu > 0.0 {
                    f -= mu * math::ln(r - d);
                    let dir = if d > 0.0 { off * (1.0 / d) } else { Vec3::ZERO };
                    let gd = dir * (mu / (r - d));
                    for (a, g) in per.iter_mut().enumerate() {
                        *g += gd * smp.n[0][a];
                    }
                    // The sample's own cap: the curvature may fall, not
                    // rise (but for the slack).
                    if smp.k_cap.is_finite() {
                        if k.is_nan() || k >= smp.k_cap {
                            return None;
                        }
                        f -= mu * math::ln(1.0 - k / smp.k_cap);
                        let s3 = s2 * sp;
                        let coef = mu / (smp.k_cap - k);
                        for (a, g) in per.iter_mut().enumerate() {
                            let dc = gc1 * smp.n[1][a] + gc2 * smp.n[2][a];
                            let dsj = ds * smp.n[1][a];
                            *g += (dc * (1.0 / s3) - dsj * (3.0 * cn / (s3 * sp))) * coef;
                        }
                    }
                }
                for (a, g) in per.iter().enumerate() {
                    grad[first + a] += *g;
                }
            }
            let cap = group[0].cap;
            if !(mu > 0.0 && cap.is_finite()) {
                continue; // (the turning alone: the sure check judges peaks)
            }
            // The span's peak, refined.
            let (lo, hi) = (u[s], u[s + 1]);
            let j = top.0;
            let left = if j == 0 { lo } else { group[j - 1].t };
            let right = if j + 1 == group.len() {
                hi
            } else {
                group[j + 1].t
            };
            let bez = bezier_of_span(u, x, s);
            let h = hi - lo;
            let k_at = |t: f64| {
                let (d1, d2) = bezier_derivatives(&bez, (t - lo) / h);
                curvature_from(d1, d2)
            };
            let mut t = golden_max(k_at, left, right);
            // A near-cusp between samples (the least sampled speed, with
            // a neighbour, or the span's end, more than `NARROW` times
            // faster): its spike is weighed where the speed is least (the
            // curvature's maximum is there to first order), as
            // [`Straightening::own_peaks`] judges it.
            let speed = |t: f64| bezier_derivatives(&bez, (t - lo) / h).0.norm();
            let j = slow.0;
            let left = if j == 0 { lo } else { group[j - 1].t };
            let right = if j + 1 == group.len() {
                hi
            } else {
                group[j + 1].t
            };
            if NARROW * slow.1 < speed(left).max(speed(right)) {
                let tm = golden_max(|t| -speed(t), left, right);
                if k_at(tm) > k_at(t) {
                    t = tm;
                }
            }
            let n = cubic_basis(u, s, t);
            let (_, d1, d2) = at(x, first, &n);
            let sp = d1.norm();
            let c = d1.cross(d2);
            let cn = c.norm();
            let s3 = sp * sp * sp;
            let k = (cn / s3).max(top.1);
            if k.is_nan() || k >= cap {
                return None;
            }
            if mu > 0.0 {
                f -= mu * math::ln(1.0 - k / cap);
                // dk/dP_j = d|c| / s^3 - 3 |c| / s^4 ds.
                let (gc1, gc2, ds) = parts(d1, d2, c, cn, sp);
                let coef = mu / (cap - k);
                for a in 0..4 {
                    let dc = gc1 * n[1][a] + gc2 * n[2][a];
                    let dsj = ds * n[1][a];
                    grad[first + a] += (dc * (1.0 / s3) - dsj * (3.0 * cn / (s3 * sp))) * coef;
                }
            }
        }
        for (g, &m) in grad.iter_mut().zip(&self.movable) {
            if !m {
                *g = Vec3::ZERO;
            }
        }
        Some(Eval { f, grad, turning })
    }

    /// One barrier round by L-BFGS from `x`; returns its iterations.
    fn minimise(
        &self,
        o: &Original,
        samples: &[Sample],
        x: &mut Vec<Vec3>,
        v: &mut [f64],
        mu: f64,
    ) -> usize {
        let room = 1.0 - SAMPLE_MARGIN;
        let Some(mut cur) = self.eval(o, samples, x, v, mu, room) else {
            return 0;
        };
        let dot = |a: &[Vec3], b: &[Vec3]| a.iter().zip(b).map(|(p, q)| p.dot(*q)).sum::<f64>();
        let mut memory: Vec<(Vec<Vec3>, Vec<Vec3>, f64)> = Vec::new();
        let mut iterations = 0;
        let mut window_start = cur.f;
        for _ in 0..round_iterations(samples.len()) {
            // The two-loop recursion: d = -H g.
            let mut q = cur.grad.clone();
            let mut alphas = Vec::with_capacity(memory.len());
            for (s, y, rho) in memory.iter().rev() {
                let a = rho * dot(s, &q);
                for (qi, yi) in q.iter_mut().zip(y) {
                    *qi -= *yi * a;
                }
                alphas.push(a);
            }
            let gamma = memory.last().map_or_else(
                || {
                    // First step: the largest point move a tenth of R.
                    let g = cur.grad.iter().map(|g| g.norm()).fold(0.0, f64::max);
                    if g > 0.0 {
                        0.1 * self.radius / g
                    } else {
                        0.0
                    }
                },
                |(s, y, _)| dot(s, y) / dot(y, y),
            );
            for qi in q.iter_mut() {
                *qi = *qi * gamma;
            }
            for ((s, y, rho), a) in memory.iter().zip(alphas.iter().rev()) {
                let b = rho * dot(y, &q);
                for (qi, si) in q.iter_mut().zip(s) {
                    *qi += *si * (a - b);
                }
            }
            let dir: Vec<Vec3> = q.iter().map(|d| -*d).collect();
            let slope = dot(&cur.grad, &dir);
            if slope.is_nan() || slope >= 0.0 {
                break;
            }
            // Backtracking: feasible and Armijo.
            let mut step = 1.0;
            let mut next = None;
            for _ in 0..HALVINGS {
                let trial: Vec<Vec3> = x.iter().zip(&dir).map(|(p, d)| *p + *d * step).collect();
                if let Some(e) = self.eval(o, samples, &trial, v, mu, room) {
                    if e.f <= cur.f + 1e-4 * step * slope {
                        next = Some((trial, e));
                        break;
                    }
                }
                step *= 0.5;
            }
            let Some((trial, e)) = next else { break };
            iterations += 1;
            let gain = cur.f - e.f;
            let s: Vec<Vec3> = trial.iter().zip(x.iter()).map(|(a, b)| *a - *b).collect();
            let y: Vec<Vec3> = e.grad.iter().zip(&cur.grad).map(|(a, b)| *a - *b).collect();
            let sy = dot(&s, &y);
            if sy > 0.0 {
                if memory.len() == MEMORY {
                    memory.remove(0);
                }
                memory.push((s, y, 1.0 / sy));
            }
            *x = trial;
            cur = e;
            if gain <= 0.0 {
                break;
            }
            // Progress over the last window of iterations.
            if iterations % STALL_WINDOW == 0 {
                if window_start - cur.f <= STALL * cur.f.abs() {
                    break;
                }
                window_start = cur.f;
            }
        }
        iterations
    }

    /// The sure bound of `x`'s distance from the original when every span
    /// is within `R` and, with the guard (`orig_near`: the original's
    /// peaks near each span), no span's peak rises above the original's
    /// near it, both measured as the barrier measures them (the guard's
    /// U-to-V rule, [`PeakReference::is_rise`], on these peaks).
    fn sure(&self, x: &[Vec3], orig_near: Option<&[f64]>) -> Option<f64> {
        let spans = nonempty_spans(&self.basis, self.orig.len());
        let diff = difference(x, self.orig);
        let own = orig_near.map(|_| self.own_peaks(x));
        let floor = self.reference.map_or(0.0, |r| r.floor);
        let mut bound: f64 = 0.0;
        for &s in &spans {
            let b = self
                .tube
                .bound_on(x, self.original, &diff, &self.basis, &[s], self.resolution);
            if b.is_nan() || b > self.radius {
                return None;
            }
            if let (Some(near), Some(own)) = (orig_near, &own) {
                let peak = own[s];
                if peak > floor && (peak.is_nan() || peak > near[s] * (1.0 + CAP_TIE)) {
                    return None;
                }
            }
            bound = bound.max(b);
        }
        Some(bound)
    }
}

/// The samples grouped by span: each group's first index and its samples.
fn spans_of(samples: &[Sample]) -> impl Iterator<Item = (usize, &[Sample])> {
    samples
        .chunk_by(|a, b| a.span == b.span)
        .scan(0, |start, group| {
            let i = *start;
            *start += group.len();
            Some((i, group))
        })
}

/// Point, first and second derivatives from the four control points from
/// `first` and their basis rows `n`.
fn at(x: &[Vec3], first: usize, n: &[[f64; 4]; 3]) -> (Vec3, Vec3, Vec3) {
    let (mut p, mut d1, mut d2) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    for a in 0..4 {
        let q = x[first + a];
        p += q * n[0][a];
        d1 += q * n[1][a];
        d2 += q * n[2][a];
    }
    (p, d1, d2)
}

/// The parts of the gradients: `d|c|/dP_j = N'_j g1 + N''_j g2` and
/// `ds/dP_j = N'_j ds` (with `c = d1 x d2`, `s = |d1|`; zero turning
/// where the curve is straight).
fn parts(d1: Vec3, d2: Vec3, c: Vec3, cn: f64, sp: f64) -> (Vec3, Vec3, Vec3) {
    let ch = if cn > 0.0 { c * (1.0 / cn) } else { Vec3::ZERO };
    (d2.cross(ch), ch.cross(d1), d1 * (1.0 / sp))
}

/// Golden-section steps of the peak refinement: the bracket, two sample
/// steps, shrinks to 0.618^24 of itself (about 1e-5).
const GOLDEN_STEPS: usize = 24;

/// The argument of the largest `g` on `[a, b]` by golden-section search
/// (one maximum assumed in the bracket; the larger end otherwise).
fn golden_max(g: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    const INV_PHI: f64 = 0.618_033_988_749_894_9;
    let (mut a, mut b) = (a, b);
    let mut c = b - (b - a) * INV_PHI;
    let mut d = a + (b - a) * INV_PHI;
    let (mut gc, mut gd) = (g(c), g(d));
    for _ in 0..GOLDEN_STEPS {
        if gc > gd {
            b = d;
            d = c;
            gd = gc;
            c = b - (b - a) * INV_PHI;
            gc = g(c);
        } else {
            a = c;
            c = d;
            gc = gd;
            d = a + (b - a) * INV_PHI;
            gd = g(d);
        }
    }
    if gc > gd {
        c
    } else {
        d
    }
}
