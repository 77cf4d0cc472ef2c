//! The blocks written for a run's pieces: G1 lines, G2/G3 arcs, spline
//! blocks ([`crate::write_spline`]), G1 chords of curves a format cannot
//! say; their coordinate words (incremental or absolute, the run's end as
//! the program wrote it) and F words.

use super::numbers::{decimals_within, fmt_fixed, rounding_mm, MAX_DECIMALS};
use super::run::RunWriter;
use super::{ArcWords, NurbsBlocks};
use crate::axes::{axis, set_axis, AXIS_LETTERS, CENTER_LETTERS};
use crate::error::WriteError;
use crate::program::MotionMode;
use fairpath::geom::{flatten_params, Arc, Curve, ParamCurve, Plane, Vec3};
use fairpath::path::Piece;
use fairpath::render::flat_arcs::FLAT_ARC_SWEEP;

/// Periods of travel at its planned speed below which a rendered piece
/// gets more decimals, its rounding scaled by the square of its length
/// over that travel ([`super::GcodeWriteOptions::period_s`]): rounding then
/// bends no such piece more than a ninth of what it bends a piece one
/// period long with the run's decimals. One period left `auto`'s
/// `butterfly-80.ngc` and LinuxCNC's `contour.ngc` slower than 12
/// decimals on every rendered piece; three plan as fast, for a text longer
/// than with one period and shorter than with ten (measurements:
/// docs/tuning.md, `FINE_PERIODS`).
pub const FINE_PERIODS: f64 = 3.0;

/// Distance (mm) within which a smoothed run end counts as the original
/// run end, so that the original coordinate text is written for it.
const SAME_POINT_MM: f64 = 1e-9;

/// Most decimals the last increment of an incremental run is written with
/// to land on the run's end: 15, where a value of a few units still has
/// f64 digits to spare ([`end_increment`]).
const MAX_END_DECIMALS: usize = 15;

/// The text of the increment (in units of `scale` mm) that takes the
/// written position `now` to a run's end `target` (mm) in an incremental
/// run: with `decimals` decimals, or more (up to [`MAX_END_DECIMALS`]),
/// the first that re-reads (`now + value * scale`, as the reader adds it)
/// to `target` exactly, else the closest. Run ends are kept exactly, but
/// in a G91 run whose moves the reader computed (polar `@ ^` words,
/// expressions) the end lies on no decimal grid: LinuxCNC's
/// `sam-circle_lines.ngc`, 370 polar moves in an o-word loop, ended 1.1e-8
/// mm from its end with 7 decimals, and every fitted rendering of it was
/// refused.
fn end_increment(now: f64, target: f64, scale: f64, decimals: usize) -> String {
    let mut best: Option<(f64, String)> = None;
    for d in decimals..=MAX_END_DECIMALS.max(decimals) {
        let t = fmt_fixed((target - now) / scale, d);
        let v: f64 = t.parse().unwrap_or(f64::NAN) * scale;
        let miss = (now + v - target).abs();
        if best.as_ref().is_none_or(|b| miss < b.0) {
            best = Some((miss, t));
        }
        if miss == 0.0 {
            break;
        }
    }
    best.map_or_else(|| fmt_fixed((target - now) / scale, decimals), |b| b.1)
}

impl RunWriter<'_> {
    /// A number in the run's units with `decimals` decimals.
    fn num(&self, v_mm: f64, decimals: usize) -> String {
        self.style.apply(fmt_fixed(v_mm / self.scale, decimals))
    }

    /// A feed (mm/min) as the program wrote it in the run's units, or as a
    /// number ([`RunWriter::feed_number`]).
    fn feed_text(&self, mm_per_min: f64) -> String {
        self.feed_texts
            .iter()
            .find(|f| f.mm_per_min == mm_per_min && f.units == self.run.units)
            .map_or_else(|| self.feed_number(mm_per_min), |f| f.text.to_string())
    }

    /// A feed (mm/min) as a number in the run's units (4 decimals).
    pub(super) fn feed_number(&self, mm_per_min: f64) -> String {
        self.style.apply(fmt_fixed(mm_per_min / self.scale, 4))
    }

    /// The text of F for a move at `feed` if one is due (on the run's first
    /// move, or when the feed changes): the feed is then the written one.
    fn due_feed(&mut self, feed: Option<f64>) -> Option<String> {
        match feed {
            Some(f) if self.first_move || self.cur_feed != Some(f) => {
                self.cur_feed = Some(f);
                Some(self.feed_text(f))
            }
            _ => None,
        }
    }

    /// The decimals of the piece being written, a G1 line `length` mm long
    /// (or an arc, see [`RunWriter::write_arc`]): the run's, more when it
    /// is shorter than [`FINE_PERIODS`] periods of travel at its speed
    /// ([`super::GcodeWriteOptions::period_s`]).
    fn piece_decimals(&self, length: f64) -> usize {
        self.finer_decimals(length, self.speed)
            .unwrap_or(self.decimals)
    }

    /// The decimals [`RunWriter::piece_decimals`] gives a piece `length`
    /// mm long passed at `speed` where that is more than the run's.
    fn finer_decimals(&self, length: f64, speed: Option<f64>) -> Option<usize> {
        let period = match (self.opts.period_s, speed) {
            (Some(ts), Some(v)) => FINE_PERIODS * v * ts,
            _ => return None,
        };
        (length > 0.0 && length < period).then(|| {
            let limit = rounding_mm(self.decimals, self.scale) * (length / period).powi(2);
            decimals_within(self.decimals, self.scale, limit)
        })
    }

    /// The decimals the piece before `next` (passed at `speed`) ends
    /// with, so that `next` starts where it should to the precision it is
    /// itself written with: a short move's direction turns by the rounding
    /// of its start over its length, as by that of its end. Between two
    /// corner transitions of `bspline-corner` that nearly meet, a G1 of
    /// 0.8 um followed a G6.2 block whose last control point had 7
    /// decimals: the move's own 12 decimals left it turned by 1e-4 rad
    /// against the blocks either side, a corner the planner passes at 11
    /// mm/s, and `examples/pocket-corners.ngc` written so read back 16%
    /// slower than its rendering on one run (measurements:
    /// docs/tuning.md, `RunWriter::start_decimals`).
    pub(super) fn start_decimals(&self, next: &Piece, speed: Option<f64>) -> usize {
        let length = match &next.curve {
            Curve::Line(l) => l.p0.dist(l.p1),
            Curve::Arc(a) => a.p0.dist(a.p1).min(a.r0.min(a.r1)),
            Curve::Nurbs(n) => shortest_leg(&n.points),
        };
        self.finer_decimals(length, speed.or(self.speed))
            .unwrap_or(0)
    }

    /// [`RunWriter::piece_decimals`] for a move, and in an incremental run
    /// at least the finest used before it on the run's last move: the
    /// written position is then on that finer grid, and only increments on
    /// it land on the run's end exactly.
    fn move_decimals(&mut self, length: f64, run_end: bool) -> usize {
        let mut d = self.piece_decimals(length).max(self.end_decimals);
        if self.run.incremental && run_end {
            d = d.max(self.finest);
        }
        self.finest = self.finest.max(d);
        d
    }

    /// The coordinate words, with `decimals` decimals, that take the
    /// written position to `target` (the original text of the run's end
    /// point when `run_end` and it is that point), and the position they
    /// re-read to.
    fn coord_words(&self, target: Vec3, run_end: bool, decimals: usize) -> (String, Vec3) {
        let moves = self.program.moves();
        let last_move = &moves[self.run.moves.end - 1];
        let orig_end = last_move.piece.end();
        let mut words = String::new();
        let mut next = self.cur;
        for a in 0..3 {
            let tv = axis(target, a);
            let now = axis(self.cur, a);
            let text = if self.run.incremental {
                let t = if run_end {
                    end_increment(now, tv, self.scale, decimals)
                } else {
                    fmt_fixed((tv - now) / self.scale, decimals)
                };
                if t == "0" {
                    continue;
                }
                t
            } else {
                let orig = if run_end && target.dist(orig_end) <= SAME_POINT_MM {
                    last_move.end_text[a].clone()
                } else {
                    None
                };
                match orig {
                    Some(t) => {
                        let v: f64 = t.parse().unwrap_or(f64::NAN) * self.scale;
                        if v == now {
                            continue;
                        }
                        t.to_string()
                    }
                    None => {
                        let t = fmt_fixed(tv / self.scale, decimals);
                        if t == fmt_fixed(now / self.scale, decimals) {
                            continue;
                        }
                        t
                    }
                }
            };
            let v: f64 = text.parse().unwrap_or(f64::NAN) * self.scale;
            let new = if self.run.incremental { now + v } else { v };
            set_axis(&mut next, a, new);
            words.push(' ');
            words.push(AXIS_LETTERS[a]);
            words.push_str(&self.style.apply(text));
        }
        (words, next)
    }

    /// The F word for a move at `feed`, if one is due.
    fn feed_word(&mut self, feed: Option<f64>) -> String {
        self.due_feed(feed)
            .map_or_else(String::new, |t| format!(" F{t}"))
    }

    pub(super) fn write_g1(
        &mut self,
        p: Vec3,
        run_end: bool,
        feed: Option<f64>,
    ) -> Result<(), WriteError> {
        if !p.is_finite() {
            return Err(WriteError::NotFinite);
        }
        let decimals = self.move_decimals(self.cur.dist(p), run_end);
        let (words, next) = self.coord_words(p, run_end, decimals);
        if words.is_empty() {
            return Ok(());
        }
        self.cur = next;
        let f = self.feed_word(feed);
        self.first_move = false;
        self.motion = Some(MotionMode::Linear);
        let line = format!("{}G1{words}{f}", self.take_n());
        self.push_line(&line);
        Ok(())
    }

    /// A curve as G1 chords within the chord the rounding leaves (the last
    /// one the run's end when `run_end`).
    pub(super) fn write_chords(
        &mut self,
        c: &Curve,
        run_end: bool,
        feed: Option<f64>,
    ) -> Result<(), WriteError> {
        let pts = piece_points(c, self.chord);
        let n = pts.len();
        for (k, p) in pts.into_iter().enumerate() {
            self.write_g1(p, run_end && k + 1 == n, feed)?;
        }
        Ok(())
    }

    /// A NURBS piece as a spline block ([`crate::write_spline`]); at the
    /// run's end a G1 to the program's own end text follows when the block's
    /// rounded last point is not it (run ends are kept exactly).
    pub(super) fn write_nurbs(
        &mut self,
        n: &fairpath::geom::Nurbs,
        run_end: bool,
        feed: Option<f64>,
    ) -> Result<(), WriteError> {
        use crate::write_spline::{g5_2_blocks, g6_2_block, G6Dialect, SplineWriteOptions};
        let kind = self.opts.nurbs.expect("called with NURBS blocks on");
        let feed_text = self.due_feed(feed);
        let decimals = match kind {
            NurbsBlocks::G6_2Fanuc { .. } => self.spline_decimals(&n.points).max(self.end_decimals),
            // In LinuxCNC's plane, within half a unit of the run's last
            // decimal (`write_spline`'s plane check).
            NurbsBlocks::G6_2Linuxcnc | NurbsBlocks::G5_2 => self.decimals,
        };
        // The block starts where the tool is: where a short move before it
        // was written finer than the run's decimals, the first control
        // point of a G6.2 block is that position with its decimals (it
        // moves by less than the rounding the module docs of
        // `write_spline` allow for). A G5.2 block starts at the current
        // position without writing it; LinuxCNC's G6.2 must stay in its
        // plane, so there the point moves only within it.
        let (start, start_decimals) = match kind {
            NurbsBlocks::G5_2 => (None, None),
            NurbsBlocks::G6_2Fanuc { .. } => self.start_of(n.points[0], decimals),
            NurbsBlocks::G6_2Linuxcnc => {
                let (s, d) = self.start_of(n.points[0], decimals);
                let tol = 0.5 * 10f64.powi(-(self.decimals as i32)) * self.scale;
                let in_plane = |p: Vec3| {
                    Plane::of_points(&n.points, tol)
                        .is_some_and(|pl| pl.off_plane(p) == pl.off_plane(n.points[0]))
                };
                match s {
                    Some(p) if in_plane(p) => (s, d),
                    _ => (None, None),
                }
            }
        };
        let moved;
        let n = match start {
            Some(p) => {
                let mut c = n.clone();
                c.points[0] = p;
                moved = c;
                &moved
            }
            None => n,
        };
        let so = SplineWriteOptions {
            mm_per_unit: self.scale,
            decimals,
            start_decimals,
            decimal_point: self.style.decimal_point,
            line_ending: self.eol,
            incremental: self.run.incremental,
            feed: feed_text,
            // A spline block is the curve itself: the chord the rounding
            // leaves is what its knots may move it by.
            knot_shift_mm: self.chord,
        };
        let plane = || {
            Plane::of_points(
                &n.points,
                0.5 * 10f64.powi(-(self.decimals as i32)) * self.scale,
            )
            .ok_or_else(|| WriteError::SplineCurve("the curve is in no principal plane".into()))
        };
        let text = match kind {
            NurbsBlocks::G6_2Fanuc { max_degree } => {
                g6_2_block(n, G6Dialect::Fanuc { max_degree }, &so)?
            }
            NurbsBlocks::G6_2Linuxcnc => {
                let plane = plane()?;
                self.select_plane(plane);
                g6_2_block(n, G6Dialect::Linuxcnc { plane, method: 1 }, &so)?
            }
            NurbsBlocks::G5_2 => {
                let plane = plane()?;
                self.select_plane(plane);
                g5_2_blocks(n, plane, &so)?
            }
        };
        let n_word = self.take_n();
        self.out.push_str(&n_word);
        self.out.push_str(&text);
        // Where the written text leaves the tool: the rounded last point.
        let end = n.points[n.points.len() - 1];
        let mut cur = end;
        for a in 0..3 {
            let t = fmt_fixed(axis(end, a) / self.scale, decimals);
            let v = t.parse::<f64>().unwrap_or(f64::NAN) * self.scale;
            set_axis(&mut cur, a, v);
        }
        self.cur = cur;
        self.finest = self.finest.max(decimals);
        self.first_move = false;
        self.motion = Some(match kind {
            NurbsBlocks::G6_2Fanuc { .. } => MotionMode::NurbsG6,
            NurbsBlocks::G6_2Linuxcnc => MotionMode::Linear,
            NurbsBlocks::G5_2 => MotionMode::Nurbs,
        });
        if run_end {
            // Only the axes whose written text differs get a word.
            self.write_g1(n.end(), true, None)?;
        }
        Ok(())
    }

    /// The decimals of a Fanuc G6.2 block with control points `pts`: those
    /// [`RunWriter::piece_decimals`] gives a line as long as its shortest
    /// leg. Rounding a control point by `rho` bends the curvature at the
    /// block's ends by about `4 rho / leg^2` (as it bends a short line's
    /// blend circles), where it must meet the next block's at their G2
    /// joint: a fit with legs of 0.03 mm written with 7 decimals (the
    /// run's) stepped the curvature by 1e-4 1/mm at every joint, and the
    /// thesis' design wave by `auto` read back slower than its curves
    /// (measurements: docs/tuning.md, `RunWriter::spline_decimals`).
    fn spline_decimals(&self, pts: &[Vec3]) -> usize {
        let leg = shortest_leg(pts);
        if leg.is_finite() {
            self.piece_decimals(leg)
        } else {
            self.decimals
        }
    }

    /// Where a spline block whose first control point is `p0`, written with
    /// `decimals`, starts: the current position and the decimals that
    /// write it exactly, when `p0` so written would not read back as it
    /// (the move before was written finer, [`RunWriter::piece_decimals`]);
    /// `(None, None)` when it does, or when the current position is farther
    /// from `p0` than that rounding (no move ends there).
    fn start_of(&self, p0: Vec3, decimals: usize) -> (Option<Vec3>, Option<usize>) {
        let read = |v: f64, d: usize| {
            fmt_fixed(v / self.scale, d)
                .parse::<f64>()
                .unwrap_or(f64::NAN)
                * self.scale
        };
        let same = |d: usize, p: Vec3| (0..3).all(|a| read(axis(p, a), d) == axis(self.cur, a));
        if same(decimals, p0) {
            return (None, None);
        }
        if self.cur.dist(p0) > rounding_mm(self.decimals.min(decimals), self.scale) {
            return (None, None);
        }
        // From `decimals` itself: a block written finer than the move
        // before it (its end is where a short move starts,
        // [`RunWriter::start_decimals`]) starts where that move left the
        // tool, which those decimals say exactly.
        match (decimals..=MAX_DECIMALS.max(decimals)).find(|&d| same(d, self.cur)) {
            Some(d) => (Some(self.cur), Some(d)),
            None => (None, None),
        }
    }

    /// A plane line when `plane` is not the written one.
    pub(super) fn select_plane(&mut self, plane: Plane) {
        if plane != self.plane {
            self.push_line(plane.gword());
            self.plane = plane;
        }
    }

    pub(super) fn write_arc(
        &mut self,
        a: &Arc,
        run_end: bool,
        feed: Option<f64>,
    ) -> Result<(), WriteError> {
        if !(a.p1.is_finite() && a.center.is_finite()) {
            return Err(WriteError::NotFinite);
        }
        let Some(plane) = Plane::of_normal(a.normal) else {
            // Not in a principal plane: chords.
            return self.write_chords(&Curve::from(*a), run_end, feed);
        };
        // Rounding turns an arc's end tangents by about `rho / r`, and the
        // ends' radii then differ by up to `2 rho`, which the reader takes
        // as a spiral whose tangents turn by about `2 rho / chord`: as a
        // line the shorter of the two long.
        let decimals = self.move_decimals(self.cur.dist(a.p1).min(a.r0.min(a.r1)), run_end);
        let (words, next) = self.coord_words(a.p1, run_end, decimals);
        let full_turn = a.sweep >= 2.0 * std::f64::consts::PI * (1.0 - 1e-12);
        let (s, e) = (plane.local(self.cur), plane.local(next));
        if !full_turn && s[0] == e[0] && s[1] == e[1] {
            // The rounded ends coincide in the plane: a G2/G3 would be a
            // full circle. The arc is shorter than the rounding: a line.
            return self.write_g1(a.p1, run_end, feed);
        }
        if !full_turn && controller_full_circle(a, self.scale) {
            // So short for its radius that a controller takes it for a
            // full circle: a line. (`r004_mixed.ngc` at 0.2 mm had a 2 nm
            // G2 on a radius of 4 km, a sweep of 5e-13 rad: LinuxCNC 2.8
            // runs it as a full circle, and so did the independent
            // check's flattening.)
            return self.write_g1(a.p1, run_end, feed);
        }
        let ccw = a.normal == plane.normal();
        // A plane change on a line of its own: on the move's line it would
        // make the move a state change, which readers keep out of runs.
        self.select_plane(plane);
        let mut line = self.take_n();
        line.push_str(if ccw { "G3" } else { "G2" });
        line.push_str(&words);
        let r = 0.5 * (a.r0 + a.r1);
        let half = std::f64::consts::PI;
        let use_r = self.opts.arcs == Some(ArcWords::R)
            && !full_turn
            && ((a.sweep - half).abs() > 0.1 * half);
        if use_r {
            let signed = if a.sweep > half { -r } else { r };
            line.push_str(" R");
            line.push_str(&self.num(signed, decimals));
        } else {
            let (ia, ib, _) = plane.axes();
            for ax in [ia, ib] {
                let c = axis(a.center, ax);
                let v = if self.arc_incremental {
                    c - axis(self.cur, ax)
                } else {
                    c
                };
                line.push(' ');
                line.push(CENTER_LETTERS[ax]);
                line.push_str(&self.num(v, decimals));
            }
        }
        let turns = ((a.sweep / (2.0 * half)) * (1.0 - 1e-12)).floor() as u64 + 1;
        if turns > 1 {
            line.push_str(&format!(" P{turns}"));
        }
        self.cur = next;
        let f = self.feed_word(feed);
        line.push_str(&f);
        self.first_move = false;
        self.motion = Some(if ccw {
            MotionMode::ArcCcw
        } else {
            MotionMode::ArcCw
        });
        self.push_line(&line);
        Ok(())
    }
}

/// LinuxCNC's `CART_FUZZ` (posemath.h, in the machine's units): since 2022
/// `pmCircleInit` runs an arc whose start and end are closer than it as a
/// full circle, and since 2024 one whose
/// `((start - centre) x (end - centre)) . normal`, about `r^2 sin(sweep)`,
/// is below it as a full circle less its sweep.
const CONTROLLER_CART_FUZZ: f64 = 1e-8;

/// Whether LinuxCNC (any of the versions of
/// [`fairpath::render::flat_arcs::CONTROLLER_CIRCLE_FUZZ`] and
/// [`CONTROLLER_CART_FUZZ`], each with a factor of two for the rounding of
/// the written words) would run `a`, an arc of less than a full turn, as a
/// full circle; `mm_per_unit` the program's unit, the machine's as far as
/// is known here. Such an arc is about a line: a sweep up to
/// [`FLAT_ARC_SWEEP`] (which the renderer writes as lines already, where
/// the short ones are merged into their neighbours), or a chord below 2e-8
/// units, or an `r^2 sin(sweep)` below 2e-8 units^2, which puts the arc
/// within `r (1 - cos(sweep / 2))` of its chord, at most 0.04 um in mm and
/// 1.05 um in inch (a quarter turn of radius 1.4e-4 units; the re-read
/// verification bounds it with the rest). Past a quarter turn such an arc
/// is left: read as a full circle less its sweep it would end at most its
/// diameter from its end (0.3 um in mm, 7 um in inch), and as a line it
/// would leave its chord by up to its radius.
fn controller_full_circle(a: &Arc, mm_per_unit: f64) -> bool {
    if a.sweep >= 0.5 * std::f64::consts::PI {
        return false;
    }
    let r = a.r0.min(a.r1) / mm_per_unit;
    a.sweep <= FLAT_ARC_SWEEP
        || r * a.sweep < 2.0 * CONTROLLER_CART_FUZZ
        || r * r * a.sweep.sin() < 2.0 * CONTROLLER_CART_FUZZ
}

/// The shortest leg of a control polygon `pts` that has a length (mm);
/// infinite where none has.
fn shortest_leg(pts: &[Vec3]) -> f64 {
    pts.windows(2)
        .map(|w| w[0].dist(w[1]))
        .filter(|&d| d > 0.0)
        .fold(f64::INFINITY, f64::min)
}

/// The points after the start of a curve at which G1 lines end.
fn piece_points(c: &Curve, chord: f64) -> Vec<Vec3> {
    match c {
        Curve::Line(l) => vec![l.p1],
        _ => {
            let ts = flatten_params(c, chord);
            let n = ts.len();
            ts.into_iter()
                .enumerate()
                .skip(1)
                .map(|(i, t)| if i + 1 == n { c.end() } else { c.eval(t) })
                .collect()
        }
    }
}
