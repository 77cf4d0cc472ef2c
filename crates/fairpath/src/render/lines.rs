//! A curve as G1 lines a controller can follow at speed.
//!
//! A blending controller passes a chain of short moves on the blend
//! circles at its vertices; where the moves are short the circles fill
//! them and meet, and the machine follows the piecewise-constant curvature
//! of those circles (`crate::feed::junction`). A vertex between moves of
//! lengths `l1 <= l2` turning by `phi ~ kappa (l1 + l2) / 2` gets a circle
//! of curvature `phi / l1 = kappa (1 + l2 / l1) / 2`: uneven moves misstate
//! the curvature, and the step between neighbouring circles slows the
//! machine as any curvature step does (`v <= sqrt(J Ts / dk)`); circles
//! only meet (and stand for the curve) when the moves are of equal length.
//! So the curve is cut into stretches over which the spacing needed varies
//! by at most [`SPACING_RATIO`], each into moves of equal length at the
//! smallest spacing needed in it.
//!
//! Where two stretches meet, the vertex between moves `l1 < l2` takes only
//! `l1 / 2` of the longer move, so its circle and the next one do not meet:
//! a straight gap is left between them, and the curvature steps by a whole
//! circle's, about the curve's `kappa` (by `kappa (1 + l2/l1) / 2` on the
//! shorter side). The machine passes that at the planned speed `v` only
//! where `kappa v^2` is below `J Ts`; so a stretch ends only at a sample
//! where `kappa v^2 <= step_share J Ts` (half the speed-safe step with
//! [`super::arcs::STEP_SHARE`], leaving room for the shorter side's
//! `(1 + l2/l1) / 2` up to a ratio of 3): the last such sample before the
//! spacing ratio is exceeded, or, where there is none, the first one after
//! it (the stretch goes on at its smallest spacing). In the middle of a
//! corner transition, where the machine is slow because the curvature is
//! high, no spacing changes then: on `surface-raster.ngc` at 0.05 mm the
//! step-overs' transitions, written as G1 (they are not in a principal
//! plane), were planned to a crawl at each change of spacing, and `auto`
//! wrote it slower (measurements: docs/tuning.md, "Where a stretch of
//! lines ends"; `docs/lower-bound.md`, made by `scripts/lower-bound.sh`,
//! has every surveyed program). Moves of one
//! stretch are placed at equal distances along the curve (`at_length`),
//! so that the spacing does not change inside a stretch either. The spacing needed is
//!
//! * at most `sqrt(8 e / kappa)`: the chord error `kappa h^2 / 8` within
//!   the share `e` (a hard limit);
//! * at most `J Ts / (v^2 |dk/ds|)` (`k` the curvature vector, whose turning
//!   a circle-to-circle step also carries), so that neighbouring circles
//!   differ by no more than the planned speed `v` can pass, but
//! * never below the length covered in `min_block_periods` interpolation
//!   periods at the planned speed (LinuxCNC spends at least 1.02 periods on
//!   a block, and caps the speed of shorter ones), or in the machine's
//!   block time, unless the chord error asks for it.
//!
//! With a block time (`MachineLimits::block_time`) the planner caps a
//! move of length `l` at `l / block_time`, so a stretch cut at the
//! spacing of its slow end would crawl through its fast end: where no
//! sample lets the spacing change and the moves would fall below the
//! block floor, the stretch ends at the sample where a change asks least
//! of the jerk, if the step left there passes faster
//! ([`FLOOR_CUT_SHARE`]).

use super::speed::PlannedSpeed;
use super::{Emitted, RenderOptions, RenderStats};
use crate::geom::{flatten_params_between, point_segment_distance, Curve, Line, ParamCurve, Vec3};
use alloc::vec::Vec;

/// Largest ratio of the spacings needed within one stretch of equal moves
/// (exceeded only where no sample lets the spacing change: module docs).
pub const SPACING_RATIO: f64 = 2.0;

pub use crate::budget::CHORD_USE;

/// The chord error's spacing never asks for moves shorter than this many
/// times the error aimed at (`e`): a move of arc length `2 e` lies within
/// `e` of its chord whatever the curve does inside (each of its points is
/// within half the arc length of an end), so a higher curvature needs no
/// shorter move. Without it a reversal inside a curve, where the path
/// stops and the curvature has no bound, asked for the shortest block: one
/// of `auto`'s fits of LinuxCNC's `test-active-states.ngc` went out 1.5 mm
/// and back, and its lines were cut at 1 nm, millions of them for a
/// program of 36 lines (measurements: docs/tuning.md,
/// `MIN_CHORD_SPACING_PER_E`). The moves are still checked at their
/// middles and halved where off, and the text is verified when read back.
pub const MIN_CHORD_SPACING_PER_E: f64 = 2.0;

/// With a block time, a stretch whose moves would fall below the block
/// floor where the machine is fast is ended early where the step it
/// leaves passes at least this share of the speed the floor allows
/// (`l / block_time`): the floor caps every move of the fast part, the
/// step one vertex. Chosen on four programs at 1 ms (docs/tuning.md,
/// "Block time").
pub const FLOOR_CUT_SHARE: f64 = 0.5;

/// Sampling of the curve that the spacing is computed on, as a share of
/// the chord tolerance.
pub(crate) const FINE_CHORD: f64 = 0.1;

/// Lines for curve `c` (piece `piece` of the run) appended to `out`, from
/// `c.start()` to `c.end()` exactly, the moves next to its ends no longer
/// than the caps `caps_of` gives for its spacing (from its neighbours,
/// [`caps_between`]).
pub(crate) fn lines_for_curve<C: ParamCurve + ?Sized>(
    c: &C,
    piece: usize,
    speed: &PlannedSpeed,
    opts: &RenderOptions,
    caps_of: &dyn Fn(&Spacing) -> Caps,
    out: &mut Emitted,
    stats: &mut RenderStats,
) {
    if let Some(sp) = Spacing::of(c, piece, speed, opts) {
        let caps = caps_of(&sp);
        lines_with(c, piece, &sp, caps, speed, opts, out, stats);
    }
}

/// The largest spacing allowed at a piece's start and end by the pieces
/// before and after it ([`caps_between`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Caps {
    pub start: f64,
    pub end: f64,
}

/// The spacing a curve needs, sample by sample (module docs), and where
/// it may change.
pub(crate) struct Spacing {
    ts: Vec<f64>,
    pts: Vec<Vec3>,
    /// Arc length to each sample along the fine polyline.
    s: Vec<f64>,
    /// Spacing needed at each sample.
    h: Vec<f64>,
    /// Whether the spacing may change at each sample.
    free: Vec<bool>,
    /// The curvature at each sample.
    kappa: Vec<f64>,
    /// The planned speed at each sample.
    v: Vec<f64>,
}

impl Spacing {
    /// The spacing curve `c` (piece `piece` of the run) needs; `None` for
    /// a curve of no length.
    pub(crate) fn of<C: ParamCurve + ?Sized>(
        c: &C,
        piece: usize,
        speed: &PlannedSpeed,
        opts: &RenderOptions,
    ) -> Option<Spacing> {
        let m = &opts.limits;
        let e = CHORD_USE * opts.chord;
        let (t0, t1) = c.domain();
        let ts = flatten_params_between(c, t0, t1, FINE_CHORD * opts.chord);
        let n = ts.len();
        if n < 2 {
            return None;
        }
        let pts: Vec<Vec3> = ts.iter().map(|&t| c.eval(t)).collect();
        let ks: Vec<Vec3> = ts.iter().map(|&t| c.curvature_vector(t)).collect();
        let mut s = alloc::vec![0.0f64; n];
        for i in 1..n {
            s[i] = s[i - 1] + pts[i - 1].dist(pts[i]);
        }
        let total = s[n - 1];
        if total.is_nan() || total <= 0.0 {
            return None;
        }
        let mut h = alloc::vec![total; n];
        let mut free = alloc::vec![false; n];
        let mut kappas = alloc::vec![0.0f64; n];
        let mut vs = alloc::vec![0.0f64; n];
        for i in 0..n {
            let kappa = ks[i].norm();
            // (At least `2 e`: a move of arc length `2 e` lies within `e`
            // of its chord whatever the curve does inside, and at a cusp
            // the curvature has no bound: see `MIN_CHORD_SPACING_PER_E`.)
            let chord_h = if kappa > 0.0 {
                crate::math::sqrt(8.0 * e / kappa).max(MIN_CHORD_SPACING_PER_E * e)
            } else {
                total
            };
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
            let ds = s[b] - s[a];
            let dk = if ds > 0.0 {
                (ks[b] - ks[a]).norm() / ds
            } else {
                0.0
            };
            let v = speed.at(piece, ts[i]);
            let step_h = if v > 0.0 && dk > 0.0 {
                2.0 * opts.step_share * m.jerk * m.period / (v * v * dk)
            } else {
                total
            };
            let block_h = opts.block_length(v);
            kappas[i] = kappa;
            vs[i] = v;
            // Whether the spacing may change here (module docs).
            free[i] = kappa * v * v <= opts.step_share * m.jerk * m.period;
            h[i] = chord_h
                .min(step_h.max(block_h))
                .min(total)
                .max(opts.min_arc_length);
        }
        Some(Spacing {
            ts,
            pts,
            s,
            h,
            free,
            kappa: kappas,
            v: vs,
        })
    }

    /// The smallest spacing needed from the start up to the first sample
    /// where the spacing may change (all of it when there is none): what
    /// the moves next to the start are cut at.
    fn lead(&self) -> f64 {
        let to = self
            .free
            .iter()
            .position(|&f| f)
            .unwrap_or(self.h.len() - 1);
        self.h[..=to].iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// [`Spacing::lead`] from the end backwards.
    fn trail(&self) -> f64 {
        let from = self.free.iter().rposition(|&f| f).unwrap_or(0);
        self.h[from..].iter().copied().fold(f64::INFINITY, f64::min)
    }
}

/// The caps of a piece rendered as lines between pieces whose spacings
/// are `before` and `after` (`None` for a straight line, a curve of no
/// length or the run's end, whose joints are free; [`Spacing::of`]): where
/// the spacing may change on neither side of a joint (the machine is fast
/// there and the curves bend), the moves next to it are cut at the
/// smaller of the two spacings, the neighbour's being the smallest it
/// needs up to where its own spacing may change.
///
/// Without it each piece was cut on its own and the spacing jumped at the
/// joints: `spiral_lines.ngc` by `bspline-fit` in G1 from 0.051 to 0.553
/// mm, where the circles of the blending controller no longer meet and
/// the curvature steps by the curve's whole `kappa` (the machine slowed to
/// `sqrt(J Ts / kappa)`, far below the planned speed; measurements:
/// docs/tuning.md, `caps_between`). Only the immediate
/// neighbours count, so that a run rendered in ranges is rendered as
/// whole ([`super::render_range`]): a neighbour cut finer than it needs by
/// its own other neighbour is not seen.
pub(crate) fn caps_between(
    before: Option<&Spacing>,
    this: &Spacing,
    after: Option<&Spacing>,
) -> Caps {
    let n = this.free.len();
    let start = match before {
        Some(b) if !b.free[b.free.len() - 1] && !this.free[0] => b.trail(),
        _ => f64::INFINITY,
    };
    let end = match after {
        Some(a) if !a.free[0] && !this.free[n - 1] => a.lead(),
        _ => f64::INFINITY,
    };
    Caps { start, end }
}

/// Lines for curve `c` (piece `piece`), whose spacing is `sp`, from
/// `c.start()` to `c.end()` exactly, the moves next to its ends no longer
/// than `caps` allow.
#[allow(clippy::too_many_arguments)]
pub(crate) fn lines_with<C: ParamCurve + ?Sized>(
    c: &C,
    piece: usize,
    sp: &Spacing,
    caps: Caps,
    speed: &PlannedSpeed,
    opts: &RenderOptions,
    out: &mut Emitted,
    stats: &mut RenderStats,
) {
    let e = CHORD_USE * opts.chord;
    let m = &opts.limits;
    let (ts, pts, s, free) = (&sp.ts, &sp.pts, &sp.s, &sp.free);
    let n = ts.len();
    let mut h = sp.h.clone();
    h[0] = h[0].min(caps.start);
    h[n - 1] = h[n - 1].min(caps.end);
    // Stretches over which the needed spacing varies by at most a factor
    // SPACING_RATIO, each cut into moves of equal length at its smallest
    // spacing, ending only where the spacing may change (`free`; `lo` is
    // the smallest spacing up to the last such sample; see the module docs).
    let mut params = Vec::new();
    params.push(ts[0]);
    let mut a = 0;
    while a + 1 < n {
        let mut b = a + 1;
        let mut lo = h[a].min(h[b]);
        let mut hi = h[a].max(h[b]);
        // The last sample of the stretch so far where the spacing may
        // change, with the smallest spacing up to it.
        let mut last_free: Option<(usize, f64)> = None;
        // With a block time: the sample where a change of spacing asks
        // least of the jerk (`kappa v^2`), with the smallest spacing up to
        // it; and the highest planned speed in the stretch, where the
        // block time asks for the longest moves.
        let mut softest: Option<(usize, f64)> = None;
        let mut fastest = sp.v[a].max(sp.v[b]);
        while b + 1 < n {
            if free[b] {
                last_free = Some((b, lo));
            }
            let stiff = |i: usize| sp.kappa[i] * sp.v[i] * sp.v[i];
            if m.block_time > 0.0 && softest.is_none_or(|(c, _)| stiff(b) < stiff(c)) {
                softest = Some((b, lo));
            }
            let (l2, h2) = (lo.min(h[b + 1]), hi.max(h[b + 1]));
            if h2 > SPACING_RATIO * l2 {
                if let Some((c, l)) = last_free {
                    b = c;
                    lo = l;
                    break;
                }
                // Moves at `l2` would take less than the block time where
                // the machine is fast, which caps the speed there at `l2 /
                // block_time`: end the stretch where a change of spacing
                // costs least, if the step it leaves (a circle's `kappa (1
                // + ratio) / 2` for the ratio of the spacings on its two
                // sides, module docs) passes faster than that.
                let floor = m.block_time * fastest.max(sp.v[b + 1]);
                if let Some((c, l)) = softest.filter(|_| l2 < floor) {
                    // The spacings on either side: the stretch's up to
                    // `c`, and at least the smallest needed after it.
                    let after = h[c + 1..=b + 1]
                        .iter()
                        .copied()
                        .fold(f64::INFINITY, f64::min);
                    let ratio = l.max(after) / l.min(after);
                    let step = 0.5 * sp.kappa[c] * (1.0 + ratio);
                    let passes = if step > 0.0 {
                        crate::math::sqrt(m.jerk * m.period / step)
                    } else {
                        f64::INFINITY
                    };
                    if passes.min(sp.v[c]) > FLOOR_CUT_SHARE * l2 / m.block_time {
                        b = c;
                        lo = l;
                        break;
                    }
                }
            }
            fastest = fastest.max(sp.v[b + 1]);
            lo = l2;
            hi = h2;
            b += 1;
        }
        let len = s[b] - s[a];
        let moves = crate::math::ceil(len / lo).max(1.0) as usize;
        let mut j = a;
        for k in 1..moves {
            let target = s[a] + len * k as f64 / moves as f64;
            while j + 1 < b && s[j + 1] < target {
                j += 1;
            }
            params.push(at_length(c, (ts[j], ts[j + 1]), pts[j], target - s[j]));
        }
        params.push(ts[b]);
        a = b;
    }
    // Emit, halving any move whose middle is off by more than the share.
    let mut prev_t = params[0];
    let mut prev = c.start();
    let last = params.len() - 1;
    for (i, &t) in params.iter().enumerate().skip(1) {
        let q = if i == last { c.end() } else { c.eval(t) };
        let fine = (&ts[..], &pts[..]);
        let v = speed.max_over(piece, prev_t, t);
        emit(
            c,
            fine,
            (prev_t, t),
            (prev, q),
            e / CHORD_USE,
            (out, v),
            stats,
            0,
        );
        prev_t = t;
        prev = q;
    }
}

/// The parameter in `t = (t0, t1)` (a fine segment, flat within
/// `FINE_CHORD` of the chord share) where the curve is `d` from its point
/// `p0 = c(t0)`, by Newton steps on `|c(t) - p0| = d` from the linear
/// guess. Moves of a stretch are then equal to a few parts per million;
/// the linear guess alone, where the parameter's speed varies along a
/// long flat segment, made them differ by about 1% from one to the next,
/// and every change of spacing is a curvature step (module docs).
fn at_length<C: ParamCurve + ?Sized>(c: &C, t: (f64, f64), p0: Vec3, d: f64) -> f64 {
    let (t0, t1) = t;
    let span = c.eval(t1).dist(p0);
    if span.is_nan() || span <= 0.0 {
        return t0;
    }
    let mut x = t0 + (t1 - t0) * (d / span).clamp(0.0, 1.0);
    for _ in 0..3 {
        let q = c.eval(x);
        let d1 = c.deriv1(x);
        let r = q - p0;
        let dist = r.norm();
        // d|c(t) - p0|/dt = (c(t) - p0) . c'(t) / |c(t) - p0|
        let slope = if dist > 0.0 {
            r.dot(d1) / dist
        } else {
            d1.norm()
        };
        if slope.is_nan() || slope <= 0.0 {
            break;
        }
        let next = (x - (dist - d) / slope).clamp(t0, t1);
        if next == x {
            break;
        }
        x = next;
    }
    x
}

#[allow(clippy::too_many_arguments)]
fn emit<C: ParamCurve + ?Sized>(
    c: &C,
    fine: (&[f64], &[Vec3]),
    (ta, tb): (f64, f64),
    (pa, pb): (Vec3, Vec3),
    chord: f64,
    (out, v): (&mut Emitted, f64),
    stats: &mut RenderStats,
    depth: u32,
) {
    let tm = 0.5 * (ta + tb);
    let pm = c.eval(tm);
    let off = [0.25, 0.5, 0.75]
        .iter()
        .map(|f| point_segment_distance(c.eval(ta + (tb - ta) * f), pa, pb))
        .fold(0.0, f64::max);
    // The samples of the curve inside the move too: spaced along the curve,
    // they see a bulge that a parameter far from arc length hides from the
    // three points above.
    let (fts, fpts) = fine;
    let from = fts.partition_point(|&t| t <= ta);
    let to = fts.partition_point(|&t| t < tb);
    let off = fpts[from..to.max(from)]
        .iter()
        .map(|&q| point_segment_distance(q, pa, pb))
        .fold(off, f64::max);
    // A move that ends where it starts writes nothing; the curve between
    // may still go somewhere (a closed piece: a fit through a spur's tip
    // and back, from a section's cut on one leg to the same point on the
    // other), and is then cut, as any move it leaves by more than the
    // share.
    if pa == pb && (off <= chord || depth >= 24) {
        return;
    }
    if off > chord && depth < 24 {
        emit(
            c,
            fine,
            (ta, tm),
            (pa, pm),
            chord,
            (out, v),
            stats,
            depth + 1,
        );
        emit(
            c,
            fine,
            (tm, tb),
            (pm, pb),
            chord,
            (out, v),
            stats,
            depth + 1,
        );
        return;
    }
    out.push(Curve::Line(Line::new(pa, pb)), v);
    stats.lines += 1;
}
