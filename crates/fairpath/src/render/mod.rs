//! What a controller will run: the smoothed curves of a run turned into
//! the pieces an output format can say (G1 lines, G2/G3 arcs, NURBS),
//! within a chord share of the tolerance, shaped so that the machine keeps
//! the speed planned for the exact curves.
//!
//! A written program only keeps the gain of smoothing if the controller
//! can run it as fast as the curves. Two things take it away: short
//! blocks (a controller spends at least one interpolation period on each,
//! LinuxCNC 1.02: [`RenderOptions::min_block_periods`]), and curvature
//! steps where written pieces meet (a jerk-limited controller passes a
//! step `dk` at most at `sqrt(J Ts / dk)`). The renderer therefore reads
//! the plan of the exact curves ([`PlannedSpeed`]) and puts pieces as long
//! as that speed allows and as short as the curvature change asks:
//! [`arcs`] for arcs (biarcs), [`lines`] for G1.
//!
//! Lines of the run stay lines; arcs of the input stay arcs (except in
//! [`CurveForm::Lines`]); NURBS stay NURBS in [`CurveForm::Nurbs`].

pub mod absorb;
pub mod arcs;
mod chain_arcs;
mod even_arcs;
pub mod flat_arcs;
pub mod lines;
pub mod speed;

pub use absorb::absorb_short_lines;
pub use speed::PlannedSpeed;

use crate::feed::limits::MachineLimits;
use crate::geom::{BezierSpline, Curve, ParamCurve};
use crate::path::Piece;
use alloc::vec::Vec;

/// Most pieces of a run written as one chain of arcs, a cell per corner
/// (`chain_arcs`); chains start at multiples of it in the run's piece
/// numbers, so that [`render_range`]s whose bounds are multiples of it,
/// concatenated, are the rendering of the whole.
pub const CHAIN_PIECES: usize = 512;

/// What the output format can say for a curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CurveForm {
    /// G1 lines only.
    Lines,
    /// G2/G3 arcs (helical where a curve is not in a principal plane) and
    /// G1 lines.
    Arcs,
    /// NURBS as they are where the format can say them (G6.2, G5.2), arcs
    /// for the others; arcs as arcs, lines as lines.
    Nurbs(NurbsLimits),
}

/// Which NURBS a spline format can say.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NurbsLimits {
    /// Highest degree (Fanuc G6.2: 3; LinuxCNC: 7).
    pub max_degree: usize,
    /// The curve must lie in a principal plane: its coordinate along the
    /// normal may vary by at most this (mm). `None`: 3D.
    pub planar_mm: Option<f64>,
    /// Only the XY plane (G17): LinuxCNC 2.9 refuses G5.x in other planes.
    pub xy_only: bool,
    /// LinuxCNC's G5.2: what LinuxCNC runs for each block (its biarcs,
    /// four per control point, with no tolerance of their own,
    /// [`crate::controller::linuxcnc::g5_2_motion_of`]) must also lie
    /// within the chord share of the curve.
    pub linuxcnc_g5_2: bool,
}

/// How to render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    pub form: CurveForm,
    /// Largest distance (mm) of the rendered pieces from the curves they
    /// replace (the rounding of written coordinates is not in it: the
    /// caller takes it out first).
    pub chord: f64,
    /// The machine the speed was planned for.
    pub limits: MachineLimits,
    /// Shortest block, in interpolation periods of travel at the planned
    /// speed (LinuxCNC: 1.02; 0 for none).
    pub min_block_periods: f64,
    /// Smallest arc radius the controller accepts (mm): LinuxCNC refuses
    /// radii below 0.00127 mm (`RADIUS_TOLERANCE_MM`, interp_internal.hh).
    pub min_radius: f64,
    /// Share of the speed-safe curvature step `J Ts / v^2` that each end
    /// of a written piece may differ from the curve by (so neighbours
    /// differ by at most twice it): [`arcs::STEP_SHARE`] keeps every joint
    /// at or above the planned speed; larger values write fewer, longer
    /// pieces that slow the machine at their joints; `f64::INFINITY`
    /// leaves only the chord tolerance.
    pub step_share: f64,
    /// Shortest arc or line (mm) worth a block: a few units of the last
    /// written decimal, so that rounded ends of an arc never coincide (an
    /// IJK arc back to its start is a full circle).
    pub min_arc_length: f64,
}

/// Why rendering cannot be done.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum RenderError {
    #[error("render option {name} must be a positive number, got {value}")]
    BadOption { name: &'static str, value: f64 },
}

impl RenderOptions {
    /// The shortest block (mm) worth writing where the planned speed is
    /// `v` (mm/s): what the machine covers in `min_block_periods` periods
    /// or in its block time ([`MachineLimits::block_time`]), the longer.
    pub fn block_length(&self, v: f64) -> f64 {
        (self.min_block_periods * self.limits.period).max(self.limits.block_time) * v
    }

    /// How far the curvature of a written piece may step, at each side of
    /// a joint the machine is planned to pass at `v` mm/s, from the
    /// curve's: `step_share J Ts / v^2` (a jerk-limited controller passes
    /// a step `dk` at most at `sqrt(J Ts / dk)`); unbounded at rest.
    pub fn step_room(&self, v: f64) -> f64 {
        let m = &self.limits;
        if v > 0.0 {
            self.step_share * m.jerk * m.period / (v * v)
        } else {
            f64::INFINITY
        }
    }

    /// Checks every option, naming the first bad one.
    pub fn validate(&self) -> Result<(), RenderError> {
        let positive = [("chord", self.chord)];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(RenderError::BadOption { name, value });
            }
        }
        let non_negative = [
            ("step_share", self.step_share),
            ("min_block_periods", self.min_block_periods),
            ("min_radius", self.min_radius),
            ("min_arc_length", self.min_arc_length),
        ];
        for (name, value) in non_negative {
            if value.is_nan() || value < 0.0 || (value.is_infinite() && name != "step_share") {
                return Err(RenderError::BadOption { name, value });
            }
        }
        self.limits.validate().map_err(|e| RenderError::BadOption {
            name: e.name,
            value: e.value,
        })
    }
}

/// Counts of what was rendered.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Arcs written (helical ones included).
    pub arcs: usize,
    /// Helical arcs among them.
    pub helical: usize,
    /// Lines written (the run's own and those of curves).
    pub lines: usize,
    /// Lines written for stretches of curves that arcs could not follow
    /// (too steep to every plane, or too sharp for the smallest arc).
    pub fallback_lines: usize,
    /// Pieces (curves of the run) some stretch of which arcs could not
    /// follow: those `fallback_lines` were written for.
    pub fallback_pieces: usize,
    /// NURBS pieces written as they are.
    pub nurbs: usize,
    /// NURBS pieces a spline format could not say (degree, not in a
    /// plane, LinuxCNC's G5.2 biarcs off the curve), written as arcs.
    pub nurbs_as_arcs: usize,
    /// Short lines merged into the piece before them ([`absorb`]; not in
    /// `lines`).
    pub absorbed_lines: usize,
    /// Pieces written as chains of arcs, a cell per corner (`chain_arcs`).
    pub chained: usize,
}

impl RenderStats {
    /// Both counts together.
    pub fn add(&mut self, o: &RenderStats) {
        self.arcs += o.arcs;
        self.helical += o.helical;
        self.lines += o.lines;
        self.fallback_lines += o.fallback_lines;
        self.fallback_pieces += o.fallback_pieces;
        self.nurbs += o.nurbs;
        self.nurbs_as_arcs += o.nurbs_as_arcs;
        self.absorbed_lines += o.absorbed_lines;
        self.chained += o.chained;
    }
}

/// A rendered run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Rendered {
    /// Continuous pieces from the run's start to its end; each keeps the
    /// source lines and feed of the piece it renders.
    pub pieces: Vec<Piece>,
    pub stats: RenderStats,
    /// For each piece, the highest planned speed (mm/s) over the stretch of
    /// the curve it stands for: a writer gives a piece shorter than a few
    /// interpolation periods of travel at it more decimals (rounding bends
    /// a short piece more than the curve turns it: `fairpath-gcode`'s
    /// `GcodeWriteOptions::period_s`). Empty where unknown.
    pub speeds: Vec<f64>,
}

/// Rendered curves of one piece, each with its [`Rendered::speeds`] entry.
#[derive(Default)]
pub(crate) struct Emitted {
    pub(crate) curves: Vec<Curve>,
    pub(crate) speeds: Vec<f64>,
}

impl Emitted {
    pub(crate) fn push(&mut self, curve: Curve, speed: f64) {
        self.curves.push(curve);
        self.speeds.push(speed);
    }

    fn clear(&mut self) {
        self.curves.clear();
        self.speeds.clear();
    }
}

/// Whether `n` can be written as a spline block under `lim`, within
/// `chord` of itself as the controller runs it.
pub fn nurbs_fits(n: &crate::geom::Nurbs, lim: &NurbsLimits, chord: f64) -> bool {
    if n.degree > lim.max_degree {
        return false;
    }
    let plane = match lim.planar_mm {
        Some(tol) => match crate::geom::Plane::of_points(&n.points, tol) {
            Some(p) => p,
            None => return false,
        },
        None => crate::geom::Plane::Xy,
    };
    if lim.xy_only && plane != crate::geom::Plane::Xy {
        return false;
    }
    if !lim.linuxcnc_g5_2 {
        return true;
    }
    let Ok(motion) = crate::controller::linuxcnc::g5_2_motion_of(n, plane) else {
        return false;
    };
    // LinuxCNC's biarcs against a fine polyline of the curve, its segments
    // in a grid of radius `lim`: both counts grow as the chord shrinks, so
    // a scan of the polyline per sample would cost their product.
    let c = Curve::from(n.clone());
    let ts = crate::geom::flatten_params(&c, 0.01 * chord);
    let poly: Vec<crate::geom::Vec3> = ts.iter().map(|&t| c.eval(t)).collect();
    let lim = arcs::DEVIATION_USE * chord;
    // `flatten_params` returns both ends, so there is a segment; any
    // segment within `lim` of a point is listed in the point's cell.
    let segs = poly.windows(2).map(|w| (w[0], w[1])).collect();
    let grid = crate::geom::SegmentGrid::new(segs, lim);
    motion.iter().all(|m| {
        (0..=8).all(|k| {
            let (t0, t1) = m.domain();
            let q = m.eval(t0 + (t1 - t0) * k as f64 / 8.0);
            grid.nearest_within(q).is_some_and(|d| d.0 <= lim)
        })
    })
}

/// Renders the pieces of one smoothed run, whose planned speed is `speed`
/// (from the plan of exactly these pieces), as `opts.form` can say them.
pub fn render_run(
    pieces: &[Piece],
    speed: &PlannedSpeed,
    opts: &RenderOptions,
) -> Result<Rendered, RenderError> {
    let mut r = render_range(pieces, 0..pieces.len(), speed, opts)?;
    absorb_lines(&mut r, opts);
    Ok(r)
}

/// Merges the short lines of a whole rendered run into the pieces before
/// them ([`absorb`], [`SHORT_LINE_SHARE`], [`ABSORB_SHIFT_SHARE`] of the
/// chord): [`render_run`] does it; a caller that joins [`render_range`]s
/// does it once they are joined.
///
/// [`SHORT_LINE_SHARE`]: crate::budget::SHORT_LINE_SHARE
/// [`ABSORB_SHIFT_SHARE`]: crate::budget::ABSORB_SHIFT_SHARE
pub fn absorb_lines(r: &mut Rendered, opts: &RenderOptions) {
    let merged = absorb::absorb_with_speeds(
        &mut r.pieces,
        &mut r.speeds,
        crate::budget::SHORT_LINE_SHARE * opts.chord,
        crate::budget::ABSORB_SHIFT_SHARE * opts.chord,
    );
    r.stats.lines -= merged;
    r.stats.absorbed_lines += merged;
}

/// [`absorb_lines`] of a long run rendered part after part
/// ([`render_range`]s of consecutive ranges, in order), so that the run's
/// rendering is never held whole: each part comes out with its short
/// lines merged, but for its last piece kept, which a short line at the
/// start of the next part may still merge into (it comes out with that
/// part, or from [`LineAbsorber::finish`]). The parts' pieces, speeds and
/// stats, concatenated and added, are [`absorb_lines`]' of the whole.
pub struct LineAbsorber {
    max_len: f64,
    max_shift: f64,
    /// The last piece kept, its speed (if the parts have speeds) and what
    /// the merges into it have moved the path by.
    held: Option<(Piece, Option<f64>, f64)>,
}

impl LineAbsorber {
    /// For a run rendered with `opts`.
    pub fn new(opts: &RenderOptions) -> LineAbsorber {
        LineAbsorber {
            max_len: crate::budget::SHORT_LINE_SHARE * opts.chord,
            max_shift: crate::budget::ABSORB_SHIFT_SHARE * opts.chord,
            held: None,
        }
    }

    /// The next part of the run: what of it, and of the piece held from
    /// the part before, no later part can change.
    pub fn push(&mut self, mut r: Rendered) -> Rendered {
        let mut used = 0.0;
        if let Some((piece, speed, u)) = self.held.take() {
            r.pieces.insert(0, piece);
            if let Some(v) = speed {
                if r.speeds.len() + 1 == r.pieces.len() {
                    r.speeds.insert(0, v);
                }
            }
            used = u;
        }
        let (merged, used) = absorb::absorb_from(
            &mut r.pieces,
            &mut r.speeds,
            self.max_len,
            self.max_shift,
            used,
        );
        // (The lines merged are the part's: the held piece is never one.)
        r.stats.lines -= merged;
        r.stats.absorbed_lines += merged;
        let with_speeds = r.speeds.len() == r.pieces.len();
        if let Some(piece) = r.pieces.pop() {
            let speed = if with_speeds { r.speeds.pop() } else { None };
            self.held = Some((piece, speed, used));
        }
        r
    }

    /// The last piece of the run (no stats: they came with its part).
    pub fn finish(self) -> Rendered {
        let mut r = Rendered::default();
        if let Some((piece, speed, _)) = self.held {
            r.pieces.push(piece);
            r.speeds.extend(speed);
        }
        r
    }
}

/// `c` as its Bezier spans where it is a polynomial cubic B-spline: the
/// same curve up to rounding, with its own end points, which the
/// renderers sample hundreds of times a piece at a fraction of the cost
/// ([`BezierSpline`]); `None` for any other curve (rendered as it is).
fn bezier_spline_of(c: &Curve) -> Option<BezierSpline> {
    match c {
        Curve::Nurbs(n) => BezierSpline::of(n),
        _ => None,
    }
}

/// The spacing piece `i` of `pieces` needs as lines ([`lines::Spacing`]);
/// `None` for a straight line, a curve of no length or past the run's end.
fn spacing_of(
    pieces: &[Piece],
    i: usize,
    speed: &PlannedSpeed,
    opts: &RenderOptions,
) -> Option<lines::Spacing> {
    match &pieces.get(i)?.curve {
        Curve::Line(_) => None,
        c => match bezier_spline_of(c) {
            Some(spans) => lines::Spacing::of(&spans, i, speed, opts),
            None => lines::Spacing::of(c, i, speed, opts),
        },
    }
}

/// [`render_run`] of the pieces `range` of the run `pieces` only. Each
/// piece is rendered on its own (from its curve and the planned speed
/// along it), so the renderings of consecutive ranges, concatenated, are
/// the rendering of the whole run before its short lines are merged
/// ([`absorb_lines`]): a long run can be rendered in parts side by side.
pub fn render_range(
    pieces: &[Piece],
    range: core::ops::Range<usize>,
    speed: &PlannedSpeed,
    opts: &RenderOptions,
) -> Result<Rendered, RenderError> {
    opts.validate()?;
    let mut out = Rendered::default();
    let mut curves = Emitted::default();
    let start = range.start;
    // As lines: the spacing each curve needs, of the range and the pieces
    // next to it, whose spacings cap the moves at the joints
    // ([`lines::caps_between`]).
    let spaced_from = start.saturating_sub(1);
    let spacings: Vec<Option<lines::Spacing>> = if opts.form == CurveForm::Lines {
        (spaced_from..(range.end + 1).min(pieces.len()))
            .map(|i| spacing_of(pieces, i, speed, opts))
            .collect()
    } else {
        Vec::new()
    };
    let spacing = |i: usize| {
        i.checked_sub(spaced_from)
            .and_then(|k| spacings.get(k))
            .and_then(Option::as_ref)
    };
    // Chains of arcs found for the pieces up to `chained_to`, in order.
    let mut chained_to = start;
    let mut chains: alloc::collections::VecDeque<chain_arcs::Chained> = Default::default();
    let mut i = start;
    while i < range.end {
        if opts.form == CurveForm::Arcs && i >= chained_to {
            let j = chain_arcs::chain_end(pieces, i, range.end, opts.chord);
            if j > i {
                chains.extend(chain_arcs::cover(pieces, i..j, speed, opts));
                chained_to = j;
            }
        }
        if chains.front().is_some_and(|c| c.range.start == i) {
            let Some(c) = chains.pop_front() else { break };
            let feed = pieces[i].feed;
            for ((curve, v), source_lines) in c.arcs.into_iter().zip(c.speeds).zip(c.lines) {
                arcs::count_piece(&curve, &mut out.stats);
                out.speeds.push(v);
                out.pieces.push(Piece {
                    curve,
                    rapid: false,
                    source_lines,
                    feed,
                });
            }
            out.stats.chained += c.range.end - c.range.start;
            i = c.range.end;
            continue;
        }
        let p = &pieces[i];
        i += 1;
        let i = i - 1;
        curves.clear();
        let whole = || {
            let (t0, t1) = p.curve.domain();
            speed.max_over(i, t0, t1)
        };
        match (&p.curve, opts.form) {
            (Curve::Line(_), _) => {
                curves.push(p.curve.clone(), whole());
                out.stats.lines += 1;
            }
            (Curve::Arc(a), CurveForm::Arcs | CurveForm::Nurbs(_)) => {
                curves.push(p.curve.clone(), whole());
                out.stats.arcs += 1;
                if a.rise != 0.0 {
                    out.stats.helical += 1;
                }
            }
            (Curve::Nurbs(n), CurveForm::Nurbs(lim)) if nurbs_fits(n, &lim, opts.chord) => {
                curves.push(p.curve.clone(), whole());
                out.stats.nurbs += 1;
            }
            (c, CurveForm::Arcs | CurveForm::Nurbs(_)) => {
                if matches!(opts.form, CurveForm::Nurbs(_)) {
                    out.stats.nurbs_as_arcs += 1;
                }
                // A curve that arcs cannot follow is written as lines,
                // cut at joints passed fast as the curves next to it would
                // be cut as lines ([`lines::caps_between`]; arcs stay
                // arcs).
                let as_lines = |k: usize| match pieces.get(k).map(|p| &p.curve) {
                    Some(Curve::Arc(_)) => None,
                    _ => spacing_of(pieces, k, speed, opts),
                };
                let caps_of = |sp: &lines::Spacing| {
                    let before = i.checked_sub(1).and_then(as_lines);
                    lines::caps_between(before.as_ref(), sp, as_lines(i + 1).as_ref())
                };
                arcs::arcs_for_curve(c, i, speed, opts, &caps_of, &mut curves, &mut out.stats)
            }
            (c, CurveForm::Lines) => {
                if let Some(sp) = spacing(i) {
                    let before = i.checked_sub(1).and_then(spacing);
                    let caps = lines::caps_between(before, sp, spacing(i + 1));
                    let (curves, stats) = (&mut curves, &mut out.stats);
                    match bezier_spline_of(c) {
                        Some(spans) => {
                            lines::lines_with(&spans, i, sp, caps, speed, opts, curves, stats)
                        }
                        None => lines::lines_with(c, i, sp, caps, speed, opts, curves, stats),
                    }
                }
            }
        }
        out.speeds.append(&mut curves.speeds);
        out.pieces
            .extend(curves.curves.drain(..).map(|curve| Piece {
                curve,
                rapid: false,
                source_lines: p.source_lines,
                feed: p.feed,
            }));
    }
    // Before the short lines are merged: such a chord may be one.
    flat_arcs::flat_arcs_as_lines(&mut out.pieces, &mut out.stats);
    Ok(out)
}

/// `pieces` with each NURBS replaced by what LinuxCNC runs for it written
/// as G5.2 blocks ([`crate::controller::linuxcnc::g5_2_motion_of`]) in the
/// principal plane its control points lie in within `planar_mm` (XY when
/// none); a NURBS LinuxCNC cannot run stays as it is.
pub fn linuxcnc_g5_2_motion(pieces: &[Piece], planar_mm: f64) -> Vec<Piece> {
    let mut out = Vec::with_capacity(pieces.len());
    for p in pieces {
        match &p.curve {
            Curve::Nurbs(n) => {
                let plane = crate::geom::Plane::of_points(&n.points, planar_mm)
                    .unwrap_or(crate::geom::Plane::Xy);
                match crate::controller::linuxcnc::g5_2_motion_of(n, plane) {
                    Ok(curves) => {
                        out.extend(curves.into_iter().map(|curve| Piece { curve, ..p.clone() }))
                    }
                    Err(_) => out.push(p.clone()),
                }
            }
            _ => out.push(p.clone()),
        }
    }
    out
}
