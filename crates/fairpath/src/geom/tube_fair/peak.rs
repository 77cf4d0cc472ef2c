//! The peak pass (ours, beyond the thesis): after the thesis' iterations
//! stop, the highest curvature peaks are lowered one at a time with the
//! room the tube still has around them.
//!
//! Why: the thesis' iterations move every point by one global allowance
//! (eq. 3-39) and stop as soon as the curve touches the tube anywhere; and
//! they move the points of a smooth group nearly as one (the 9.0 weight
//! of eq. 3-31 sends each along its apex's direction), which lowers the
//! curvature where groups meet but carries the top of a wide bend along
//! unchanged. On a smooth design curve (the thesis' case 1) that leaves
//! the peak curvature, which caps the feed at `sqrt(A / k)`, where it was:
//! our design wave kept its 0.0570 1/mm at every radius, and planned
//! slower under fairpath's full model. A machinist's fairing lowers the
//! tightest bend first.
//!
//! One move: take the span with the highest sampled peak
//! ([`PeakPass::span_shape`]; of peaks equal within [`TRIAL_TIE`], the
//! first span's); for each of its control points (four on a cubic) that may move, try
//! moving it towards the chord of its neighbours (its bisector, as the
//! thesis moves a ripple point, eqs. 3-23 to 3-25) by [`TRIAL_STEPS`]
//! distances, halving from [`RIPPLE_REACH_SHARE`] of the way to that chord
//! (at most the radius); also try laying two to five consecutive points
//! near the span on the chord of the points outside them (ours:
//! `Lowering::chord_trials`, for bends made over short legs), the whole
//! way first, then halving; keep the trial whose four spans' highest peak is
//! lowest, if it is below the peak being lowered, the spans are inside the
//! tube on the sure bound ([`TubeMeasure::bound_on`], within `accuracy * R`;
//! nothing is asked of the control points' own moves, which the thesis'
//! iterations may already have taken past `R` where the difference
//! spline's points alternate in sign and its curve stays inside),
//! and (with the guard) no span rises over the original's peaks near it
//! ([`PeakReference::is_rise`]). A span whose peak no trial lowers is
//! left, and the next highest is taken. Each kept move lowers the highest
//! peak of the spans it touches below the peak it was made for and changes
//! no other span, so the curve's highest peak never rises, and falls
//! wherever a move lowers the top one. The pass stops when no span is
//! left above the floor (`accuracy` times the original's highest peak) or
//! after [`MOVES_PER_POINT`] moves per control point.

use super::directions::RIPPLE_REACH_SHARE;
use super::guard::{PeakReference, PEAK_ACCURACY, PEAK_SAMPLES};
use super::slide::{Original, TubeMeasure};
use super::spans::{nonempty_spans, Basis, Span};
use crate::geom::{curvature_candidates, curvature_from, refined_peak, Extrema, Vec3, NARROW};
use crate::math;
use alloc::collections::BinaryHeap;
use alloc::vec;
use alloc::vec::Vec;

/// Trial distances per candidate point: the largest, then halved (ours:
/// four halvings reach a sixteenth of the way, enough to settle two
/// neighbouring points against each other).
pub const TRIAL_STEPS: usize = 5;

/// How many consecutive points a chord trial of the peak pass lays on the
/// chord of the points outside them (ours; see the module docs). Up to
/// three straightened our sharp line; up to five also the line whose
/// spline interpolates the displaced points (to the straight line's time)
/// at about the same computing time over the B-spline programs of
/// `docs/fair-outputs.md` (`docs/methods.md`; measurements:
/// docs/tuning.md, `CHORD_TRIAL_POINTS`).
pub const CHORD_TRIAL_POINTS: core::ops::RangeInclusive<usize> = 2..=5;

/// Relative margin of the comparisons that choose a move (ours): a trial
/// must beat the best so far by more than this share of its demand
/// (closer is a tie, kept by the trials' order), and may add at most this
/// share to the turning of the spans it changes, so that which move is
/// kept does not depend on rounding. Trials that lay points on a chord
/// often leave the turning as it was (a monotone bend spread over other
/// legs turns as much) and the same demand (a span made straight has the
/// floor's); a path tilted into 3D chose another move than in its plane
/// on rounding alone. A billionth is far above the rounding of these sums
/// and far below any gain worth a move.
pub const TRIAL_TIE: f64 = 1e-9;

/// Most moves per control point (ours): bounds the work by the size of
/// the curve, whatever the radius.
pub const MOVES_PER_POINT: usize = 4;

/// Whether the peak pass runs, and what it lowers, span by span: the
/// highest value of a demand sampled at [`PEAK_SAMPLES`] equal steps of
/// each knot span.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "kebab-case", deny_unknown_fields)
)]
pub enum PeakPass {
    /// No peak pass: the thesis' iterations alone.
    Off,
    /// The curvature `k` (1/mm): the thesis' time model caps the speed at
    /// `sqrt(A / k)` only (its section 4.5), so lowering the highest `k`
    /// raises the lowest cap of that model, whatever the machine.
    Curvature,
    /// The inverse of the lowest speed cap that the curve's shape sets
    /// under a jerk-limited planner (fairpath's full model,
    /// `docs/planning.md`): `v <= sqrt(A / k)` (normal acceleration),
    /// `v <= cbrt(J / k^2)` (normal jerk: `k^2 v^3 <= J` at a constant
    /// speed) and `v <= cbrt(J / |dk/ds|)` (the jerk of a turning
    /// curvature: `|dk/ds| v^3 <= J`), and `max_feed` above them all.
    /// Lowering curvature alone can steepen `dk/ds` where it spreads a
    /// bend, and slow such a planner; this measure weighs both.
    SpeedCaps {
        /// Largest feed (mm/s): where the shape allows more, it is not
        /// the limit and the span is left alone.
        max_feed: f64,
        /// Normal acceleration limit `A` (mm/s^2).
        normal_acc: f64,
        /// Jerk limit `J` (mm/s^3).
        jerk: f64,
        /// Interpolation period `Ts` (s): where two pieces meet with a
        /// step `dk` of the curvature vector (arcs that meet G1), the
        /// planner passes at most `sqrt(J Ts / dk)`
        /// (`feed::junction::jump_cap`); [`PeakPass::jump_demand`]. The
        /// fairing itself moves one curve, whose spans meet C2.
        #[cfg_attr(feature = "serde", serde(default = "default_period"))]
        period: f64,
    },
}

/// The default machine's interpolation period, 1 ms (also what a TOML
/// file that leaves `period` out gets).
pub const DEFAULT_PERIOD: f64 = 0.001;

#[cfg(feature = "serde")]
fn default_period() -> f64 {
    DEFAULT_PERIOD
}

impl PeakPass {
    /// The speed caps of fairpath's default machine (the thesis' own:
    /// 400 mm/s, 4000 mm/s^2, 20000 mm/s^3, its section 4.5), which
    /// `feed::limits::MachineLimits::thesis()`, the CLI's default, also holds.
    pub const DEFAULT_MACHINE: PeakPass = PeakPass::SpeedCaps {
        max_feed: 400.0,
        normal_acc: 4000.0,
        jerk: 20000.0,
        period: DEFAULT_PERIOD,
    };

    /// The pass for a curve programmed at `feed` (mm/s, if any): the speed
    /// caps' `max_feed` lowered to that feed. Where the program asks for
    /// less speed than the shape allows, lowering the shape's demand buys
    /// nothing, and the moves (which may widen a bend) would only add
    /// length, which costs time at such a feed.
    pub fn at_feed(self, feed: Option<f64>) -> PeakPass {
        match (self, feed) {
            (
                PeakPass::SpeedCaps {
                    max_feed,
                    normal_acc,
                    jerk,
                    period,
                },
                Some(f),
            ) if f > 0.0 && f < max_feed => PeakPass::SpeedCaps {
                max_feed: f,
                normal_acc,
                jerk,
                period,
            },
            (pass, _) => pass,
        }
    }

    /// Whether every number is finite and positive.
    pub fn is_valid(&self) -> bool {
        match *self {
            PeakPass::Off | PeakPass::Curvature => true,
            PeakPass::SpeedCaps {
                max_feed,
                normal_acc,
                jerk,
                period,
            } => [max_feed, normal_acc, jerk, period]
                .iter()
                .all(|x| x.is_finite() && *x > 0.0),
        }
    }

    /// The demand of a span from its largest sampled curvature `k` (1/mm)
    /// and largest `max(k^2, |dk/ds|)` (1/mm^2): the maximum over samples
    /// of a maximum of increasing functions of these is that maximum of
    /// the samples' maxima, so a span needs one square root and one cube
    /// root, not two per sample.
    pub fn demand(&self, k: f64, jerk_term: f64) -> f64 {
        match *self {
            PeakPass::Off | PeakPass::Curvature => k,
            PeakPass::SpeedCaps {
                max_feed,
                normal_acc,
                jerk,
                ..
            } => (1.0 / max_feed)
                .max(math::sqrt(k / normal_acc))
                .max(math::cbrt(jerk_term / jerk)),
        }
    }

    /// The demand of a step `dk` (1/mm) of the curvature vector where two
    /// pieces meet: the inverse of `sqrt(J Ts / dk)`, the planner's cap
    /// across it (`feed::junction::jump_cap`); 0 for the curvature alone
    /// (the thesis' model has no jerk).
    pub fn jump_demand(&self, dk: f64) -> f64 {
        match *self {
            PeakPass::Off | PeakPass::Curvature => 0.0,
            PeakPass::SpeedCaps { jerk, period, .. } => math::sqrt(dk / (jerk * period)),
        }
    }

    /// The demand's floor: below it nothing is gained (the feed, not the
    /// shape, is the limit; or, for curvature, `floor`).
    fn floor(&self, curvature_floor: f64) -> f64 {
        match *self {
            PeakPass::Off | PeakPass::Curvature => curvature_floor,
            PeakPass::SpeedCaps { max_feed, .. } => 1.0 / max_feed,
        }
    }

    /// What the pass weighs on the non-empty span `s` of the clamped
    /// B-spline (`basis`, `pts`), sampled as [`super::guard::span_peak`]
    /// samples curvature.
    pub fn span_shape(&self, basis: &Basis, pts: &[Vec3], s: usize) -> SpanShape {
        self.span_shape_below(basis, pts, s, f64::INFINITY)
            .unwrap_or_default()
    }

    /// [`PeakPass::span_shape`], or `None` as soon as a sample's demand is
    /// not below `bar` (a trial that fails there needs no more samples).
    fn span_shape_below(
        &self,
        basis: &Basis,
        pts: &[Vec3],
        s: usize,
        bar: f64,
    ) -> Option<SpanShape> {
        let b = Span::of(basis, pts, s);
        // What each sample is compared with instead of `bar`: `k < bar`,
        // or `k / A < bar^2` and `max(k^2, |dk/ds|) / J < bar^3`.
        let (k_bar, jerk_bar, rate) = match *self {
            PeakPass::Off | PeakPass::Curvature => (bar, f64::INFINITY, false),
            PeakPass::SpeedCaps {
                normal_acc, jerk, ..
            } => (bar * bar * normal_acc, bar * bar * bar * jerk, true),
        };
        let mut shape = SpanShape::default();
        // Curvature and the jerk cap's term at `tau`.
        let at = |tau: f64| {
            let (d1, d2, d3) = b.derivs3(tau);
            let k = curvature_from(d1, d2);
            let jerk_term = if rate {
                (k * k).max(math::abs(curvature_rate(d1, d2, d3)))
            } else {
                0.0
            };
            (k, jerk_term, d1)
        };
        let h = 1.0 / PEAK_SAMPLES as f64;
        let taus: [f64; PEAK_SAMPLES + 1] = core::array::from_fn(|j| j as f64 * h);
        let mut ks = [0.0f64; PEAK_SAMPLES + 1];
        let mut jerks = [0.0f64; PEAK_SAMPLES + 1];
        let mut speeds = [0.0f64; PEAK_SAMPLES + 1];
        for (j, &tau) in taus.iter().enumerate() {
            let (k, jerk_term, d1) = at(tau);
            // (A NaN is never below.)
            if !(k < k_bar && jerk_term < jerk_bar) {
                return None;
            }
            (ks[j], jerks[j]) = (k, jerk_term);
            speeds[j] = d1.norm();
            // Simpson's rule over the samples (an even number of steps).
            let w = if j == 0 || j == PEAK_SAMPLES {
                1.0
            } else if j % 2 == 1 {
                4.0
            } else {
                2.0
            };
            shape.turning += w * h / 3.0 * k * d1.norm();
        }
        // Refined between the samples where they show a peak narrower
        // than their step, as `span_peak` refines the guard's (at the
        // sampled local maxima of the curvature and minima of the speed,
        // and of the jerk cap's term), so that a spike between samples is
        // weighed at its height.
        let between = curvature_candidates(
            |t| b.derivs12(t),
            &taus,
            (&ks, &speeds),
            PEAK_ACCURACY,
            Extrema::Narrow,
        );
        let k_max = between
            .iter()
            .map(|&t| at(t).0)
            .fold(ks.iter().copied().fold(0.0, f64::max), f64::max);
        let jerk_max = if rate {
            // Its narrow maxima only, as the curvature's.
            let narrow = |j: usize| {
                let (lo, hi) = (j.saturating_sub(1), (j + 1).min(PEAK_SAMPLES));
                jerks[j] > NARROW * jerks[lo].max(jerks[hi])
            };
            let sampled = jerks.iter().copied().fold(0.0, f64::max);
            let refined = if (0..=PEAK_SAMPLES).any(narrow) {
                refined_peak(|t| at(t).1, &taus, &jerks, PEAK_ACCURACY, narrow)
            } else {
                sampled
            };
            between.iter().map(|&t| at(t).1).fold(refined, f64::max)
        } else {
            0.0
        };
        shape.peak = k_max;
        shape.demand = self.demand(k_max, jerk_max);
        // (The floor 1/F may be the demand; a bar at or below it fails.)
        (shape.demand < bar).then_some(shape)
    }
}

/// What the peak pass weighs on one knot span.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SpanShape {
    /// Highest demand ([`PeakPass`]), sampled and each sampled peak refined.
    pub demand: f64,
    /// Highest curvature (1/mm), sampled and refined: what the guard
    /// compares.
    pub peak: f64,
    /// Turning `integral |k| ds` (radians, Simpson's rule on the samples):
    /// a move may not add to the turning of the spans it changes, so the
    /// pass never buys a lower peak with new wiggles (a bend widened
    /// outwards turns as much as before; a ripple added turns more).
    pub turning: f64,
}

/// `dk/ds` (1/mm^2) of a curve with derivatives `d1`, `d2`, `d3` in any
/// parameter: with `c = d1 x d2`, `k = |c| / |d1|^3` and
/// `dk/dt = (c . (d1 x d3)) / (|c| |d1|^3) - 3 |c| (d1 . d2) / |d1|^5`,
/// divided by `|d1|` (the chain rule); at an inflection (`c = 0`) the
/// one-sided `|d1 x d3| / |d1|^4`. 0 where the curve stops (`d1 = 0`).
pub fn curvature_rate(d1: Vec3, d2: Vec3, d3: Vec3) -> f64 {
    let s = d1.norm();
    if s == 0.0 {
        return 0.0;
    }
    let c = d1.cross(d2);
    let cn = c.norm();
    let s3 = s * s * s;
    if cn == 0.0 {
        return d1.cross(d3).norm() / (s3 * s);
    }
    (c.dot(d1.cross(d3)) / (cn * s3) - 3.0 * cn * d1.dot(d2) / (s3 * s * s)) / s
}

/// What the peak pass did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PeakPassRecord {
    /// Moves kept.
    pub moves: usize,
    /// Highest span demand ([`PeakPass`]) before and after.
    pub peak_before: f64,
    pub peak_after: f64,
    /// Sure bound of the result's distance from the original (mm, at
    /// most the radius): the largest of the spans' bounds.
    pub deviation_bound: f64,
}

/// The curve the pass works on and what bounds it.
pub(super) struct Lowering<'a> {
    pub basis: Basis<'a>,
    pub orig: &'a [Vec3],
    /// Control points the pass may move.
    pub movable: Vec<bool>,
    pub radius: f64,
    /// `accuracy * R`: the tightness of the sure bound.
    pub resolution: f64,
    /// The guard's reference, when the guard is on.
    pub reference: Option<&'a PeakReference>,
    /// What is lowered (not [`PeakPass::Off`]).
    pub measure: PeakPass,
    /// `accuracy` times the original's highest curvature peak: with
    /// [`PeakPass::Curvature`], spans at or below it are left alone.
    pub floor: f64,
    /// Sure bound of the starting curve's distance from the original (mm).
    pub bound: f64,
    /// How the distance from the original is measured.
    pub tube: TubeMeasure,
    /// The original's spans, for the sliding tube (`None`: equal
    /// parameters, or a curve the sliding tube does not measure).
    pub original: Option<&'a Original<'a>>,
}

/// A span peak in the heap, ordered by its bits (peaks are finite and not
/// negative, and such floats order as their bits do).
type Entry = (u64, usize);

impl Lowering<'_> {
    /// A sure bound of span `t`'s distance from the original, as the tube
    /// is measured (`cur` and its difference `diff` from the original).
    fn span_bound(&self, cur: &[Vec3], diff: &[Vec3], t: usize) -> f64 {
        self.tube
            .bound_on(cur, self.original, diff, &self.basis, &[t], self.resolution)
    }

    /// The non-empty spans control point `j` belongs to.
    fn spans_of(&self, j: usize) -> impl Iterator<Item = usize> + '_ {
        let (m, p, u) = (self.orig.len(), self.basis.degree, self.basis.knots);
        (j.max(p)..=(j + p).min(m - 1)).filter(move |&s| u[s] < u[s + 1])
    }

    /// Lowers the peaks of `cur` (see the module documentation).
    pub fn run(&self, cur: &mut [Vec3]) -> PeakPassRecord {
        let (basis, m) = (&self.basis, self.orig.len());
        let spans = nonempty_spans(basis, m);
        let floor = self.measure.floor(self.floor);
        let mut peak = vec![0.0f64; m];
        let mut turning = vec![0.0f64; m];
        let mut heap: BinaryHeap<Entry> = BinaryHeap::with_capacity(spans.len());
        for &s in &spans {
            let shape = self.measure.span_shape(basis, cur, s);
            (peak[s], turning[s]) = (shape.demand, shape.turning);
            if peak[s].is_finite() && peak[s] > floor {
                heap.push((peak[s].to_bits(), s));
            }
        }
        let top = |peak: &[f64]| spans.iter().map(|&s| peak[s]).fold(0.0, f64::max);
        let mut record = PeakPassRecord {
            peak_before: top(&peak),
            ..PeakPassRecord::default()
        };
        let mut diff: Vec<Vec3> = cur.iter().zip(self.orig).map(|(p, q)| *p - *q).collect();
        // The sure bound of each span's distance: the curve's own to start
        // with (each span is at most that), then the one that admitted the
        // last move there.
        let mut bound = vec![self.bound; m];
        let max_moves = MOVES_PER_POINT * m;
        while let Some((bits, s)) = heap.pop() {
            if bits != peak[s].to_bits() {
                continue; // stale: the span changed since it was pushed
            }
            if record.moves >= max_moves {
                break;
            }
            let s = first_of_tie(&mut heap, &peak, s);
            let Some(mv) = self.best_move(cur, &mut diff, &turning, s, peak[s]) else {
                continue; // this peak cannot be lowered: leave it
            };
            for &(j, p) in &mv.moved {
                cur[j] = p;
                diff[j] = p - self.orig[j];
            }
            record.moves += 1;
            for (t, shape, d) in mv.peaks {
                bound[t] = d;
                (peak[t], turning[t]) = (shape.demand, shape.turning);
                let k = shape.demand;
                if k > floor {
                    heap.push((k.to_bits(), t));
                }
            }
        }
        record.peak_after = top(&peak);
        record.deviation_bound = spans.iter().map(|&s| bound[s]).fold(0.0, f64::max);
        record
    }

    /// The bisector of control point `j` of `cur` towards the chord of its
    /// neighbours and [`RIPPLE_REACH_SHARE`] of the way to that chord (as
    /// `directions::bisector`, eqs. 3-23 to 3-25); `None` where it may not
    /// move or lies on the line of its neighbours.
    fn bisector(&self, cur: &[Vec3], j: usize) -> Option<(Vec3, f64)> {
        if !self.movable[j] || j == 0 || j + 1 >= cur.len() {
            return None;
        }
        let (a, p, b) = (cur[j - 1], cur[j], cur[j + 1]);
        let dv = ((a - p).normalized(0.0)? + (b - p).normalized(0.0)?).normalized(0.0)?;
        let (la, lb) = (a.dist(p), b.dist(p));
        let q = a + (b - a) * (la / (la + lb));
        Some((dv, RIPPLE_REACH_SHARE * q.dist(p)))
    }

    /// Trials that lay two to five consecutive movable points of span
    /// `s`'s neighbourhood on the chord of the points outside them, each
    /// at its share of the polygon's length between them (the whole way
    /// at the first step, at most the radius).
    ///
    /// Why (ours): a bend that the polygon makes over a few short legs
    /// between long ones (where the program's own points were close
    /// together) stays sharp however little it turns, and its curvature
    /// rate caps the speed; each of those points lies almost on the chord
    /// of its own neighbours, so the bisector trials, which reach a share
    /// of the way to that chord, barely move it. Laid on the chord of the
    /// long legs' far ends, the points leave the turn to those ends, where
    /// it spreads over the long spans (`line-two-points-sharp` at R = 0.25
    /// mm: a bend of 0.0025 rad over 0.25 mm, 0.0123 1/mm).
    fn chord_trials(&self, cur: &[Vec3], s: usize) -> Vec<Vec<(usize, Vec3)>> {
        let m = cur.len();
        let mut trials = Vec::new();
        for len in CHORD_TRIAL_POINTS {
            // Windows [a, a + len) meeting the span's points s - p..=s,
            // with a point on each side.
            let first = (s + 1).saturating_sub(self.basis.degree + len).max(1);
            for a in first..=s {
                let b = a + len; // the point after the window
                if b >= m || !(a..b).all(|j| self.movable[j]) {
                    continue;
                }
                let (p, q) = (cur[a - 1], cur[b]);
                let legs: Vec<f64> = (a..=b).map(|j| cur[j].dist(cur[j - 1])).collect();
                let total: f64 = legs.iter().sum();
                if total.is_nan() || total <= 0.0 {
                    continue;
                }
                let mut along = 0.0;
                let mut trial: Vec<(usize, Vec3)> = (a..b)
                    .zip(&legs)
                    .map(|(j, leg)| {
                        along += leg;
                        (j, p + (q - p) * (along / total) - cur[j])
                    })
                    .collect();
                let largest = trial.iter().map(|d| d.1.norm()).fold(0.0, f64::max);
                if largest.is_nan() || largest <= self.resolution {
                    continue;
                }
                if largest > self.radius {
                    let f = self.radius / largest;
                    trial.iter_mut().for_each(|d| d.1 = d.1 * f);
                }
                trials.push(trial);
            }
        }
        trials
    }

    /// The best trial move for span `s` of peak `target`: the points
    /// moved, their new places and the new peaks of the spans they touch;
    /// `None` if no trial lowers the peak within the tube (and the guard).
    ///
    /// The trials move one of the span's control points (four on a cubic), two
    /// neighbouring ones, or all that may move, along their bisectors by
    /// one distance (each at most its own reach), inwards (flattening the
    /// points' own turns) or outwards (widening a bend whose top already
    /// touches the tube, which flattens the turn next to them): a peak
    /// shared by two points (the middle of a symmetric bend) falls only
    /// when both move.
    /// Then the chord trials ([`Lowering::chord_trials`]). A trial is kept
    /// over the best so far only when its highest peak is lower by more
    /// than [`TRIAL_TIE`].
    fn best_move(
        &self,
        cur: &mut [Vec3],
        diff: &mut [Vec3],
        turning: &[f64],
        s: usize,
        target: f64,
    ) -> Option<Move> {
        let dirs: Vec<(usize, Vec3, f64)> = (s - self.basis.degree..=s)
            .filter_map(|j| self.bisector(cur, j).map(|(dv, reach)| (j, dv, reach)))
            .collect();
        let mut sets: Vec<&[(usize, Vec3, f64)]> = Vec::new();
        for k in 0..dirs.len() {
            sets.push(&dirs[k..=k]);
            if k + 1 < dirs.len() && dirs[k + 1].0 == dirs[k].0 + 1 {
                sets.push(&dirs[k..=k + 1]);
            }
        }
        if dirs.len() > 2 {
            sets.push(&dirs[..]);
        }
        // Each trial: the points it moves and their displacements at its
        // first (largest) step; later steps halve them.
        let mut trials: Vec<Vec<(usize, Vec3)>> = Vec::new();
        for set in &sets {
            // One distance for the set, at most each point's reach.
            let step = set.iter().map(|d| d.2).fold(self.radius, f64::min);
            for sign in [1.0, -1.0] {
                trials.push(
                    set.iter()
                        .map(|&(j, dv, _)| (j, dv * (sign * step)))
                        .collect(),
                );
            }
        }
        trials.extend(self.chord_trials(cur, s));
        let mut best: Option<(f64, Move)> = None;
        for trial in &trials {
            let mut spans: Vec<usize> = trial.iter().flat_map(|&(j, _)| self.spans_of(j)).collect();
            spans.sort_unstable();
            spans.dedup();
            // The span being lowered first: most trials fail there, and
            // need not shape the others.
            if let Some(i) = spans.iter().position(|&t| t == s) {
                spans.swap(0, i);
            }
            let turning_before: f64 = spans.iter().map(|&t| turning[t]).sum();
            let largest = trial.iter().map(|d| d.1.norm()).fold(0.0, f64::max);
            let mut scale = 1.0;
            for _ in 0..TRIAL_STEPS {
                if largest * scale <= self.resolution {
                    break;
                }
                let moved: Vec<(usize, Vec3)> = trial
                    .iter()
                    .map(|&(j, d)| (j, cur[j] + d * scale))
                    .collect();
                scale *= 0.5;
                let old: Vec<Vec3> = moved.iter().map(|&(j, _)| cur[j]).collect();
                for &(j, p) in &moved {
                    cur[j] = p;
                }
                // (A NaN demand never passes.)
                let bar = best
                    .as_ref()
                    .map_or(target, |b| (b.0 * (1.0 - TRIAL_TIE)).min(target));
                let mut both: Vec<(usize, SpanShape)> = Vec::with_capacity(spans.len());
                let mut lower = true;
                for &t in &spans {
                    match self.measure.span_shape_below(&self.basis, cur, t, bar) {
                        Some(shape) => both.push((t, shape)),
                        None => {
                            lower = false;
                            break;
                        }
                    }
                }
                if !lower {
                    for (&(j, _), &p) in moved.iter().zip(&old) {
                        cur[j] = p;
                    }
                    continue;
                }
                let high = both.iter().map(|(_, b)| b.demand).fold(0.0, f64::max);
                // (Laid on a chord, points often leave the turning as it
                // was: equal within TRIAL_TIE is not more.)
                let turning_after: f64 = both.iter().map(|(_, b)| b.turning).sum();
                let rejected = turning_after > turning_before * (1.0 + TRIAL_TIE)
                    || self
                        .reference
                        .is_some_and(|r| both.iter().any(|&(t, b)| r.is_rise(t, b.peak)));
                let bounds: Vec<f64> = if rejected {
                    Vec::new()
                } else {
                    for &(j, p) in &moved {
                        diff[j] = p - self.orig[j];
                    }
                    // Span by span, so each span keeps the bound that
                    // admitted it (the curve's bound is their largest).
                    let bounds = spans
                        .iter()
                        .map(|&t| self.span_bound(cur, diff, t))
                        .collect();
                    for (&(j, _), &p) in moved.iter().zip(&old) {
                        diff[j] = p - self.orig[j];
                    }
                    bounds
                };
                for (&(j, _), &p) in moved.iter().zip(&old) {
                    cur[j] = p;
                }
                if rejected {
                    continue;
                }
                if bounds.iter().all(|&b| b <= self.radius) {
                    let peaks = both
                        .iter()
                        .zip(bounds)
                        .map(|(&(t, b), d)| (t, b, d))
                        .collect();
                    best = Some((high, Move { moved, peaks }));
                }
            }
        }
        best.map(|b| b.1)
    }
}

/// Of span `s`, just popped from `heap`, and the spans whose peaks tie
/// with it (within [`TRIAL_TIE`]), the first: the others go back. The
/// peaks of a symmetric curve are equal but for rounding, and where the
/// moves they get reach each other, the order they are lowered in shapes
/// the result: it goes by place, not by rounding.
fn first_of_tie(heap: &mut BinaryHeap<Entry>, peak: &[f64], s: usize) -> usize {
    let low = peak[s] * (1.0 - TRIAL_TIE);
    let mut tied = vec![s];
    while let Some(&(bits, t)) = heap.peek() {
        if bits != peak[t].to_bits() {
            heap.pop(); // stale
            continue;
        }
        if peak[t] < low {
            break;
        }
        heap.pop();
        tied.push(t);
    }
    let first = tied.iter().copied().fold(usize::MAX, usize::min);
    for t in tied {
        if t != first {
            heap.push((peak[t].to_bits(), t));
        }
    }
    first
}

/// A move the pass keeps: the points and their new places, and the new
/// shapes and deviation bounds of the spans they touch.
struct Move {
    moved: Vec<(usize, Vec3)>,
    peaks: Vec<(usize, SpanShape, f64)>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::tube_fair::tube::{deviation_bound, difference};

    /// A step `dk` of the curvature vector demands the inverse of the
    /// planner's cap across it, `sqrt(J Ts / dk)`: 0.2 1/mm on the default
    /// machine (20000 mm/s^3, 1 ms) caps at 10 mm/s. The thesis' model has
    /// no jerk, so no such demand; a period that is not a positive number
    /// makes the pass invalid.
    #[test]
    fn a_curvature_step_demands_the_inverse_of_the_planners_cap() {
        let pass = PeakPass::DEFAULT_MACHINE;
        assert!((pass.jump_demand(0.2) - 0.1).abs() < 1e-15);
        assert_eq!(pass.jump_demand(0.0), 0.0);
        assert_eq!(PeakPass::Curvature.jump_demand(0.2), 0.0);
        let PeakPass::SpeedCaps {
            max_feed,
            normal_acc,
            jerk,
            ..
        } = pass
        else {
            unreachable!()
        };
        for period in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
            let bad = PeakPass::SpeedCaps {
                max_feed,
                normal_acc,
                jerk,
                period,
            };
            assert!(!bad.is_valid(), "{period}");
        }
        assert!(pass.is_valid());
    }

    fn knots(m: usize) -> Vec<f64> {
        let spans = m - 3;
        let mut u = vec![0.0; 4];
        u.extend((1..spans).map(|i| i as f64));
        u.extend([spans as f64; 4]);
        u
    }

    /// A bump on a line: its highest peak never rises, the curve stays in
    /// the tube, its turning does not grow, the ends stay, and some move is
    /// kept.
    #[test]
    fn a_bump_is_lowered_inside_the_tube() {
        let orig: Vec<Vec3> = (0..12)
            .map(|i| {
                let x = i as f64;
                Vec3::new(x, 3.0 * (-(x - 5.5) * (x - 5.5) / 4.0).exp(), 0.0)
            })
            .collect();
        let knots_u = knots(orig.len());
        let u = Basis::cubic(&knots_u);
        let m = orig.len();
        let turning = |pts: &[Vec3]| -> f64 {
            nonempty_spans(&u, m)
                .into_iter()
                .map(|s| PeakPass::Curvature.span_shape(&u, pts, s).turning)
                .sum()
        };
        let mut moved = 0;
        for (measure, r) in [
            (PeakPass::Curvature, 0.1),
            (PeakPass::Curvature, 0.5),
            (PeakPass::DEFAULT_MACHINE, 0.5),
        ] {
            let mut movable = vec![true; m];
            movable[0] = false;
            movable[m - 1] = false;
            let reference = PeakReference::new(&u, &orig, 0.01);
            let pass = Lowering {
                basis: u,
                orig: &orig,
                movable,
                radius: r,
                resolution: 0.01 * r,
                reference: Some(&reference),
                measure,
                floor: reference.floor,
                bound: 0.0,
                tube: TubeMeasure::EqualParameter,
                original: None,
            };
            let mut cur = orig.clone();
            let rec = pass.run(&mut cur);
            assert!(
                rec.peak_after <= rec.peak_before,
                "{measure:?} {r}: {rec:?}"
            );
            assert!(turning(&cur) <= turning(&orig), "{measure:?} {r}");
            let dense = deviation_bound(&difference(&cur, &orig), &u, 1e-9);
            assert!(dense <= rec.deviation_bound + 1e-9 && rec.deviation_bound <= r);
            assert_eq!((cur[0], cur[m - 1]), (orig[0], orig[m - 1]));
            moved += rec.moves;
        }
        assert!(moved > 0);
    }

    /// `dk/ds` in closed form against a central difference of the
    /// curvature along a cubic.
    #[test]
    fn the_curvature_rate_is_the_derivative_of_the_curvature() {
        let b = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 2.0, 0.3),
            Vec3::new(3.0, -1.0, 0.5),
            Vec3::new(4.0, 1.0, -0.2),
        ];
        let d3 = (b[3] - b[2] * 3.0 + b[1] * 3.0 - b[0]) * 6.0;
        let k = |t: f64| {
            let (d1, d2) = super::super::spans::bezier_derivatives(&b, t);
            curvature_from(d1, d2)
        };
        let h = 1e-6;
        for t in [0.1, 0.3, 0.5, 0.8] {
            let (d1, d2) = super::super::spans::bezier_derivatives(&b, t);
            let numeric = (k(t + h) - k(t - h)) / (2.0 * h) / d1.norm();
            let exact = curvature_rate(d1, d2, d3);
            assert!(
                (numeric - exact).abs() <= 1e-6 * (1.0 + exact.abs()),
                "{t}: {numeric} {exact}"
            );
        }
    }
}
