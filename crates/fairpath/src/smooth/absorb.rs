//! Absorbing moves far inside the tolerance into their neighbours before the
//! corner engine builds transitions on a chain of lines (issue 21, item 3):
//! `bspline-corner`, `ctm`, `lotm`, and the corner parts of `bspline-fit`,
//! `fair` and `auto`. Fits take dense moves as they are (a least-squares
//! fit rides over a jog), and `arc-fit` blends no corner.
//!
//! A CAM program's rounding leaves moves of a micrometre or less between
//! long moves: a jog (`X10 Y0` / `X10 Y0.00028` / `X20 Y0.00028`), a
//! spike out and back, a vertex split in two. A corner method sees two
//! corners there with no room between them: it keeps them as corners, or
//! squeezes transitions into the move's length, whose curvature then grows
//! as one over that length (5,657 1/mm for a 0.28 um jog where the band
//! allows a straight line). Such a move is merged into its neighbours
//! instead: the path goes from the move before it to the move after it
//! through one vertex, and the neighbouring corner gets a transition of
//! its own size.
//!
//! ## Which moves, and what it costs
//!
//! A move no longer than [`JogTolerances::max_len`] is a jog. Walking the
//! chain once, each jog `S = e -> v` between the move `A = p -> e` before
//! it and `T = v -> w` after it is collapsed into one vertex, the cheapest
//! of three ways:
//!
//! * the midpoint `m` of `S`: `A` becomes `p -> m` and `T` becomes `m -> w`.
//!   A point at parameter `t` of the new `A` is `t |m - e|` from the point
//!   at `t` of the old (linear interpolation), so `A` moves by at most
//!   `|m - e| = |S| / 2`, and `T` by `|m - v|`;
//! * skipping `v`: `S` and `T` become `e -> w`. Every point of `e -> w` lies
//!   within `d = dist(v, [e, w])` of the old path `e -> v -> w`: that path
//!   lies in the capsule of radius `d` around `[e, w]` and its projection
//!   on the line runs continuously from `e` to `w`, so it passes every point
//!   of `[e, w]` at distance at most `d`;
//! * skipping `e`: `A` and `S` become `p -> v`, within `dist(e, [p, v])`.
//!
//! The one vertex left is then skipped too where that is as cheap (the
//! same bound, from the segment before it to the one after): a jog on a
//! straight line leaves no vertex, which would take half of the line's
//! room from the corner at its end.
//!
//! What each new move may deviate from the original program adds up by the
//! triangle inequality: the bound of the move it replaces plus the move of
//! this step ([`LineChain::absorbed`] holds it per segment). A collapse is
//! made only when every changed segment stays within
//! [`JogTolerances::max_dev`], the chain's end vertices stay where they are
//! (run ends and joints with arcs are exact), no new segment is a
//! zero-length move, and the programmed feed is the same on every segment
//! involved (a feed keeps its stretch of path, as `merge_collinear` keeps
//! feed changes). The input lines of the absorbed move go to the neighbour
//! that takes its path, so every line stays in some piece's `source_lines`.
//!
//! ## Where the deviation comes from
//!
//! From the transitions' own band: the corner engine builds the transition
//! at vertex `k` within its band less the larger of `absorbed[k - 1]` and
//! `absorbed[k]`, and the lines it keeps are parts of the absorbed segments,
//! so its result stays within its band of the original program and
//! [`crate::budget::ToleranceBudget`]'s sum is unchanged. [`crate::budget::ABSORB_SHARE`] of the tolerance bounds what
//! absorbing may spend on one segment; where nothing is absorbed the bands
//! are as before.

use super::chains::LineChain;
use crate::geom::{point_segment_distance, Vec3};
use alloc::vec::Vec;
use core::f64::consts::PI;

/// Smallest turn (30 degrees) of a corner that a short move next to it
/// hides: a raster pass ending `X199.99` / `X200 Y0.0001` before a
/// 90-degree step-over leaves the step-over's transition 10 um of room.
/// Below it, vertices are the samples of a curve, whose moves the fits
/// and transitions take as they are.
pub(crate) const SHARP_TURN: f64 = PI / 6.0;

/// How far the direction turns at `v` from `a -> v` to `v -> b` (rad).
fn turn(a: Vec3, v: Vec3, b: Vec3) -> f64 {
    (v - a).angle_to(b - v)
}

/// What absorbing moves may do to a chain, in mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct JogTolerances {
    /// Moves no longer than this are jogs, to be absorbed.
    pub max_len: f64,
    /// Moves no longer than this, next to a vertex that turns by at least
    /// [`SHARP_TURN`], are short moves hiding that corner: absorbed by
    /// skipping their other end when that is cheap.
    pub short_len: f64,
    /// Largest deviation of an absorbed chain's segment from the original.
    pub max_dev: f64,
    /// New segments must be longer than this (the zero-length threshold).
    pub min_len: f64,
    /// Straight-on vertices a collapse leaves are merged within this
    /// (the cleaning's `collinear`).
    pub collinear: f64,
    /// The chain's first (last) segment keeps its direction: set where the
    /// chain starts (ends) at a fit, which leads into that segment along
    /// its line (a turned end segment would leave a corner at the joint).
    /// Elsewhere a chain ends at a run's end, where only the position
    /// counts, or at an arc of the input, a joint kept as a corner.
    pub keep_first_direction: bool,
    pub keep_last_direction: bool,
}

impl JogTolerances {
    /// Deviations up to `max_dev` mm: jogs are moves up to `2 max_dev`
    /// long (collapsed to their midpoint they move the path by at most
    /// `max_dev`), short moves up to `short_len`, new segments longer than
    /// `min_len`.
    pub fn new(max_dev: f64, short_len: f64, min_len: f64) -> Self {
        JogTolerances {
            max_len: 2.0 * max_dev,
            short_len,
            max_dev,
            min_len,
            collinear: 0.0,
            keep_first_direction: false,
            keep_last_direction: false,
        }
    }

    /// These, with straight-on vertices merged within `collinear` mm.
    pub fn merging(self, collinear: f64) -> Self {
        JogTolerances { collinear, ..self }
    }
}

/// One segment while the chain is rebuilt: its end vertex and attributes.
#[derive(Clone, Copy, Debug)]
struct Seg {
    to: Vec3,
    lines: (usize, usize),
    feed: Option<f64>,
    dev: f64,
}

/// How a jog is collapsed.
#[derive(Clone, Copy, Debug)]
enum Collapse {
    /// Into its midpoint: the move before ends there, the move after starts
    /// there.
    Midpoint { m: Vec3, dev_a: f64, dev_t: f64 },
    /// Its end vertex skipped: the move after starts at its start.
    SkipEnd { dev: f64 },
    /// Its start vertex skipped: the move before runs to its end.
    SkipStart { dev: f64 },
}

impl Collapse {
    fn cost(&self) -> f64 {
        match *self {
            Collapse::Midpoint { dev_a, dev_t, .. } => dev_a.max(dev_t),
            Collapse::SkipEnd { dev } | Collapse::SkipStart { dev } => dev,
        }
    }
}

/// The cheapest collapse of jog `s` (from `e`) between `a` (from `p`) and
/// `t`, within `jt`; `None` when none fits.
fn cheapest(
    p_a: Option<(Vec3, &Seg)>,
    e: Vec3,
    s: &Seg,
    t: Option<&Seg>,
    jt: &JogTolerances,
    allowed: impl Fn(&Collapse) -> bool,
) -> Option<Collapse> {
    let feed_ok = p_a.is_none_or(|(_, a)| a.feed == s.feed) && t.is_none_or(|t| t.feed == s.feed);
    if !feed_ok {
        return None;
    }
    let v = s.to;
    let long = |a: Vec3, b: Vec3| a.dist(b) > jt.min_len;
    let len = e.dist(v);
    // A jog collapses any way; a short move only by skipping its end away
    // from the sharp corner it hides.
    let jog = len <= jt.max_len;
    if !jog && len > jt.short_len {
        return None;
    }
    let sharp_at_e = p_a.is_some_and(|(p, _)| turn(p, e, v) >= SHARP_TURN);
    let sharp_at_v = t.is_some_and(|t| turn(e, v, t.to) >= SHARP_TURN);
    let mut options: [Option<Collapse>; 3] = [None; 3];
    if let (true, Some((p, a)), Some(t)) = (jog, p_a, t) {
        let m = e.lerp(v, 0.5);
        if long(p, m) && long(m, t.to) {
            options[0] = Some(Collapse::Midpoint {
                m,
                dev_a: a.dev + m.dist(e),
                dev_t: t.dev + m.dist(v),
            });
        }
    }
    if let (true, Some(t)) = (jog || sharp_at_e, t) {
        if long(e, t.to) {
            let dev = point_segment_distance(v, e, t.to) + s.dev.max(t.dev);
            options[1] = Some(Collapse::SkipEnd { dev });
        }
    }
    if let (true, Some((p, a))) = (jog || sharp_at_v, p_a) {
        if long(p, v) {
            let dev = point_segment_distance(e, p, v) + a.dev.max(s.dev);
            options[2] = Some(Collapse::SkipStart { dev });
        }
    }
    options
        .into_iter()
        .flatten()
        .filter(|c| c.cost() <= jt.max_dev && allowed(c))
        .min_by(|x, y| x.cost().total_cmp(&y.cost()))
}

/// The vertex a collapse leaves, where the last finished segment of `out`
/// ends and `t` starts, skipped too where that is cheap (a jog on a
/// straight line leaves no vertex): the segment from the last one's start to `t`'s end,
/// taken out of `out` to be the pending one, where it stays within
/// `jt.max_dev` of the original (the bound of skipping a vertex, module
/// docs), keeps the feed and is no zero-length move; `t` otherwise.
fn skip_left(out: &mut Vec<Seg>, start: Vec3, t: Seg, jt: &JogTolerances) -> Seg {
    let p = out.len().checked_sub(2).map_or(start, |j| out[j].to);
    if let Some(a) = out.last() {
        let dev = point_segment_distance(a.to, p, t.to) + a.dev.max(t.dev);
        if dev <= jt.max_dev && a.feed == t.feed && p.dist(t.to) > jt.min_len {
            if let Some(mut a) = out.pop() {
                a.to = t.to;
                a.dev = dev;
                a.lines.1 = t.lines.1;
                return a;
            }
        }
    }
    t
}

/// Absorbs the jogs of `chain` into their neighbours (module docs), its
/// end vertices kept exactly; every segment of the result lies within its
/// `absorbed` bound (at most `jt.max_dev`) of the original chain. Returns
/// the number of moves absorbed.
pub(crate) fn absorb_jogs(chain: &mut LineChain, jt: &JogTolerances) -> usize {
    let n = chain.segments();
    if n < 2 || jt.max_dev <= 0.0 {
        return 0;
    }
    let seg = |i: usize| Seg {
        to: chain.pts[i + 1],
        lines: chain.lines[i],
        feed: chain.feed[i],
        dev: chain.absorbed.get(i).copied().unwrap_or(0.0),
    };
    // Finished segments (`out[i]` from `start` or `out[i - 1].to`), then
    // the pending one `s` from `e`.
    let start = chain.pts[0];
    let mut out: Vec<Seg> = Vec::with_capacity(n);
    let mut s = seg(0);
    let mut absorbed = 0;
    for i in 1..=n {
        let t = (i < n).then(|| seg(i));
        let e = out.last().map_or(start, |a| a.to);
        let p_a = out
            .last()
            .map(|a| (out.len().checked_sub(2).map_or(start, |j| out[j].to), a));
        // No collapse turns a first or last segment whose direction is
        // kept: `A` is the first segment when it starts the chain, `s` when
        // nothing is finished; `t` is the last when `i == n - 1`, `s` when
        // there is no `t`.
        let a_first = jt.keep_first_direction && out.len() == 1;
        let s_first = jt.keep_first_direction && out.is_empty();
        let t_last = jt.keep_last_direction && i + 1 == n;
        let s_last = jt.keep_last_direction && t.is_none();
        let collapse = cheapest(p_a, e, &s, t.as_ref(), jt, |c| match c {
            Collapse::Midpoint { .. } => !a_first && !t_last,
            Collapse::SkipEnd { .. } => !s_first && !t_last,
            Collapse::SkipStart { .. } => !a_first && !s_last,
        });
        match (collapse, t) {
            (Some(Collapse::Midpoint { m, dev_a, dev_t }), Some(mut t)) => {
                let a = out.last_mut().unwrap();
                a.to = m;
                a.dev = dev_a;
                a.lines.1 = s.lines.1;
                t.dev = dev_t;
                // A jog on a straight line leaves no vertex: `m` itself is
                // skipped when that is cheap too (`p -> w`).
                s = skip_left(&mut out, start, t, jt);
            }
            (Some(Collapse::SkipEnd { dev }), Some(mut t)) => {
                t.lines.0 = s.lines.0;
                t.dev = dev;
                // The vertex left, `e`, skipped too where that is cheap.
                s = if !a_first && !t_last {
                    skip_left(&mut out, start, t, jt)
                } else {
                    t
                };
            }
            (Some(Collapse::SkipStart { dev }), t) => {
                let a = out.last_mut().unwrap();
                a.to = s.to;
                a.dev = dev;
                a.lines.1 = s.lines.1;
                match t {
                    // The vertex left, `v`, skipped too where that is cheap.
                    Some(t) if !a_first && !t_last => s = skip_left(&mut out, start, t, jt),
                    Some(t) => s = t,
                    None => {
                        absorbed += 1;
                        break;
                    }
                }
            }
            (_, Some(t)) => {
                out.push(s);
                s = t;
                continue;
            }
            (_, None) => {
                out.push(s);
                break;
            }
        }
        absorbed += 1;
    }
    if absorbed == 0 {
        return 0;
    }
    chain.pts = core::iter::once(start)
        .chain(out.iter().map(|s| s.to))
        .collect();
    chain.lines = out.iter().map(|s| s.lines).collect();
    chain.feed = out.iter().map(|s| s.feed).collect();
    chain.absorbed = out.iter().map(|s| s.dev).collect();
    absorbed
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::distance_to_polyline;
    use alloc::vec;
    use proptest::prelude::*;

    fn v(x: f64, y: f64) -> Vec3 {
        Vec3::new(x, y, 0.0)
    }

    fn chain(pts: Vec<Vec3>, feed: Vec<Option<f64>>) -> LineChain {
        let n = pts.len() - 1;
        LineChain {
            pts,
            lines: (1..=n).map(|i| (i, i)).collect(),
            feed,
            absorbed: vec![],
        }
    }

    const JT: JogTolerances = JogTolerances {
        max_len: 2e-3,
        short_len: 0.1,
        max_dev: 1e-3,
        min_len: 5e-5,
        collinear: 0.0,
        keep_first_direction: false,
        keep_last_direction: false,
    };

    /// Issue 21: `X10 Y0` / `X10 Y0.00028` / `X20 Y0.00028`: the jog
    /// collapses into its midpoint, which is skipped too; its lines go to
    /// the one move left.
    #[test]
    fn a_jog_of_0_28_um_between_straight_moves_leaves_no_vertex() {
        let mut c = chain(
            vec![
                v(0.0, 0.0),
                v(10.0, 0.0),
                v(10.0, 0.00028),
                v(20.0, 0.00028),
            ],
            vec![Some(1000.0); 3],
        );
        assert_eq!(absorb_jogs(&mut c, &JT), 1);
        // The midpoint is as cheap to skip: one straight move is left.
        assert_eq!(c.pts, vec![v(0.0, 0.0), v(20.0, 0.00028)]);
        assert_eq!(c.lines, vec![(1, 3)]);
        assert!(c.absorbed.iter().all(|&d| d <= 0.00028));
    }

    /// A jog that a skip collapses leaves no vertex on a straight leg
    /// either (regression: `tiny_jogs_are_absorbed` in fairpath-gcode,
    /// a jog of 0.2 um two thirds along a 1 mm leg before a corner of 118
    /// degrees; the vertex it left took half the leg, and the corner's
    /// transition peaked at 192 1/mm against 49 with the whole leg).
    #[test]
    fn a_skipped_jog_on_a_straight_leg_before_a_sharp_corner_leaves_no_vertex() {
        let (corner, end) = (
            v(0.7302134711428335, -0.6832190619131863),
            v(0.4796250, 0.2848747),
        );
        let e = v(0.0, 0.0).lerp(corner, 0.6566402895730279);
        let (az, len) = (-0.5018707247143419f64, 0.0002);
        let jog = e + v(az.cos(), az.sin()) * len;
        let mut c = chain(
            vec![v(0.0, 0.0), e, jog, corner, end],
            vec![Some(1000.0); 4],
        );
        assert_eq!(absorb_jogs(&mut c, &JT), 1);
        assert_eq!(c.pts, vec![v(0.0, 0.0), corner, end]);
        assert_eq!(c.lines, vec![(1, 3), (4, 4)]);
        assert!(c.absorbed.iter().all(|&d| d <= len));
    }

    /// A programmed feed keeps its stretch of path: a jog next to a feed
    /// change stays.
    #[test]
    fn a_jog_next_to_a_feed_change_stays() {
        let pts = vec![
            v(0.0, 0.0),
            v(10.0, 0.0),
            v(10.0, 0.00028),
            v(20.0, 0.00028),
        ];
        let mut c = chain(pts.clone(), vec![Some(1000.0), Some(10.0), Some(10.0)]);
        assert_eq!(absorb_jogs(&mut c, &JT), 0);
        assert_eq!(c.pts, pts);
    }

    /// The ends of a chain are exact: a jog at either end is merged into
    /// the move next to it, which keeps the end vertex.
    #[test]
    fn jogs_at_the_ends_keep_the_end_vertices() {
        let pts = vec![
            v(0.0, 0.0),
            v(0.0003, 0.0001),
            v(10.0, 0.0),
            v(10.0, 0.0002),
        ];
        let mut c = chain(pts, vec![None; 3]);
        assert_eq!(absorb_jogs(&mut c, &JT), 2);
        assert_eq!(c.pts, vec![v(0.0, 0.0), v(10.0, 0.0002)]);
        assert_eq!(c.lines, vec![(1, 3)]);
    }

    /// With `keep_first_direction` and `keep_last_direction` (a chain
    /// between fits) the end segments
    /// keep their direction: a jog at either end stays, and one next to
    /// them does not turn them (regression:
    /// `bspline_fit_props::mixed_dense_and_sparse`, where a fit led into a
    /// first move of 2 um that a collapse had turned, leaving a corner at
    /// the joint).
    #[test]
    fn between_fits_the_end_segments_keep_their_direction() {
        let jt = JogTolerances {
            keep_first_direction: true,
            keep_last_direction: true,
            ..JT
        };
        let pts = vec![
            v(0.0, 0.0),
            v(0.0003, 0.0001),
            v(10.0, 0.0),
            v(10.0, 0.0002),
        ];
        let mut c = chain(pts.clone(), vec![None; 3]);
        assert_eq!(absorb_jogs(&mut c, &jt), 0);
        assert_eq!(c.pts, pts);
        let pts = vec![
            v(-10.0, 0.0),
            v(0.0, 0.0),
            v(0.0003, 0.0001),
            v(10.0, 0.0),
            v(20.0, 0.0),
        ];
        let mut c = chain(pts, vec![None; 4]);
        assert_eq!(absorb_jogs(&mut c, &jt), 1);
        let d = |c: &LineChain, i: usize| (c.pts[i + 1] - c.pts[i]).normalized(0.0).unwrap();
        assert_eq!(d(&c, 0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(d(&c, c.segments() - 1), Vec3::new(1.0, 0.0, 0.0));
    }

    /// `X199.99` / `X200 Y0.0001` before a step-over: the short move's
    /// start is skipped, the step-over's corner keeps its vertex.
    #[test]
    fn a_short_move_before_a_step_over_is_skipped() {
        let mut c = chain(
            vec![
                v(-1.0, 0.0),
                v(0.0, 0.0),
                v(199.99, 0.0),
                v(200.0, 0.0001),
                v(200.0, 1.0),
                v(199.0, 1.0),
            ],
            vec![None; 5],
        );
        assert_eq!(absorb_jogs(&mut c, &JT), 1);
        assert_eq!(
            c.pts,
            vec![
                v(-1.0, 0.0),
                v(0.0, 0.0),
                v(200.0, 0.0001),
                v(200.0, 1.0),
                v(199.0, 1.0)
            ]
        );
        // A short move on a gentle curve (no sharp corner) stays.
        let mut arc = chain(
            vec![v(0.0, 0.0), v(0.05, 0.0), v(0.1, 0.001), v(0.15, 0.003)],
            vec![None; 3],
        );
        assert_eq!(absorb_jogs(&mut arc, &JT), 0);
    }

    proptest! {
        /// Every point of the absorbed chain lies within its segment's
        /// `absorbed` bound (at most `max_dev`) of the original chain; the
        /// ends are exact; every input line is still named, in order.
        #[test]
        fn absorbed_chains_stay_within_their_bounds(
            steps in prop::collection::vec((-1.0..1.0f64, -1.0..1.0f64, 0u8..4), 2..30),
        ) {
            // Long moves and jogs mixed: a quarter of the moves are tiny.
            let mut p = v(0.0, 0.0);
            let mut pts = vec![p];
            for (dx, dy, kind) in steps {
                let scale = if kind == 0 { 1.5e-3 } else { 1.0 };
                let d = v(dx, dy) * scale;
                if d.norm() > JT.min_len {
                    p += d;
                    pts.push(p);
                }
            }
            prop_assume!(pts.len() >= 3);
            let n = pts.len() - 1;
            let original = pts.clone();
            let mut c = chain(pts, vec![None; n]);
            absorb_jogs(&mut c, &JT);
            prop_assert_eq!(c.pts[0], original[0]);
            prop_assert_eq!(*c.pts.last().unwrap(), original[n]);
            let mut next = 1;
            for (j, &(a, b)) in c.lines.iter().enumerate() {
                prop_assert_eq!(a, next);
                next = b + 1;
                let dev = c.absorbed_at(j);
                prop_assert!(dev <= JT.max_dev);
                for s in 0..=16 {
                    let q = c.pts[j].lerp(c.pts[j + 1], s as f64 / 16.0);
                    let d = distance_to_polyline(q, &original).unwrap().0;
                    prop_assert!(d <= dev + 1e-12, "segment {} at {}: {} > {}", j, s, d, dev);
                }
            }
            prop_assert_eq!(next, n + 1);
        }
    }
}
