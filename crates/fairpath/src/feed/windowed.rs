//! The planned time of a long run, planned window by window: the memory of
//! a plan grows with a window, not with the run.
//!
//! Why: the planner ([`super::plan`]) holds a few vectors per stretch of
//! the run. A one-run raster written as arcs (1.67 million blocks from
//! `surface-raster-large.ngc`) made 3.3 million stretches, and its time at
//! two feeds, planned side by side, held hundreds of megabytes (issue 19;
//! measurements: docs/tuning.md, `feed::windowed`).
//!
//! How: windows of [`PlanWindows::step`] pieces plus
//! [`PlanWindows::overlap`] on each side, each planned on its own from rest
//! to rest ([`super::plan::plan_run_shaped`]). A window's ends change its plan only
//! within the distance the machine needs to reach or leave its speed
//! there (tens of mm at most): further in, its segments are the whole
//! run's, because every step of the planner is local away from them
//! (caps of pieces and their joints; segment boundaries at local minima
//! of the cap; the look-ahead's passes, which forget a changed end speed
//! once the speed meets a cap; the splits where a profile passes a cap).
//! Two consecutive windows are therefore stitched at a segment boundary
//! inside their overlap (past the later one's anchor, where its sums of
//! lengths start from the earlier one's: a segment's length is a
//! difference of such sums, and sums begun elsewhere round otherwise)
//! where both plans hold the same
//! [`STITCH_SEGMENTS`] segments, to the bit (same place on the same
//! pieces, same boundary speeds, same duration): the first window's
//! segments up to it, the second's from it. The time is their durations
//! added in order, as the whole-run plan adds them, so it is the whole
//! plan's time to the bit wherever the windows agree with it (checked
//! on seeded random runs and on the written runs of the reference
//! programs: `tests/feed_windowed.rs`). Where two windows hold no such
//! segments (one segment across the whole overlap: a long run of G2
//! joints without a minimum of the cap), the run is planned whole.
//!
//! # Where windows are not the whole plan
//!
//! The locality above is not a theorem of this planner, and windows that
//! agree on [`STITCH_SEGMENTS`] segments can both differ from the whole
//! plan: the look-ahead drops a minimum of the cap that the speed does
//! not reach, and splits where a profile passes a cap, round by round,
//! so which boundaries a window keeps depends on the speeds its ends
//! allow, and fewer boundaries let a window's plan go faster than the
//! whole plan further in. It happens on runs of chords far shorter than
//! the overlap is long (G5.2 blocks read back as LinuxCNC runs them) and
//! where the feed changes from piece to piece; at one feed, chords of 10
//! um are stitched to the bit (`tests/feed_windowed.rs`). Stitching only
//! far from both windows' ends, or only between boundaries where the
//! speed is the cap in every round, did not make windows exact (cases,
//! figures and what was tried: docs/performance.md, "One set of windows
//! for every plan").
//!
//! So a long run's time is defined as its time in
//! [`PlanWindows::DEFAULT`] wherever fairpath plans it, `fairpath
//! simulate` included ([`crate::feed::program::run_time`]): the stitched
//! windows are a plan the machine can run (each window's plan is, and
//! they meet at segments alike), and every figure of a program is that
//! plan's. Windows of another size stitch elsewhere, so none is used.

use super::plan::{plan_time_shaped, plan_window, At, Corners, PlanOptions, RunEnds};
use super::shaping::Shaping;
use super::FeedError;
use crate::path::Piece;
use alloc::vec::Vec;

/// How a long run is cut into windows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlanWindows {
    /// Pieces from one window's start to the next's.
    pub step: usize,
    /// Pieces a window reaches past its step at its end, and the next
    /// window before its start: two consecutive windows share
    /// `2 * overlap` pieces.
    pub overlap: usize,
}

impl PlanWindows {
    /// 8,192 pieces a step, 4,096 of overlap (windows of 16,384): twice
    /// the planning of the run whole, which on `surface-raster-large.ngc`
    /// cost `auto` no CPU to speak of. The overlap is 200 mm of the
    /// shortest written arcs
    /// (0.05 mm), well past the 20 to 60 mm in which the machine reaches
    /// its feed (400 mm/s at 4000 mm/s^2 and 20000 mm/s^3: 20 mm for the
    /// acceleration, `v^2 / 2A`, plus the jerk phases), and lets
    /// `auto`'s written `surface-raster-large.ngc` stitch (a pass at the
    /// maximum feed is one segment over thousands of arcs; 2,048 did
    /// not). Every plan of a long run in fairpath is made in these
    /// windows, `simulate`'s included ([`crate::feed::program::run_time`]),
    /// and the plans carried across a program's parts hold three windows
    /// at a time: with a step of 16,384 the peak memory went over issue
    /// 19's target (measurements: docs/tuning.md, `PlanWindows::DEFAULT`).
    pub const DEFAULT: PlanWindows = PlanWindows {
        step: 1 << 13,
        overlap: 1 << 12,
    };

    /// Whether a run of `n` pieces is planned in windows (more than one
    /// window).
    pub fn windows(&self, n: usize) -> bool {
        n > self.step + 2 * self.overlap
    }
}

/// Consecutive segments two windows must hold alike to be stitched.
pub const STITCH_SEGMENTS: usize = 3;

/// A segment of a window's plan, placed on the run: where it starts and
/// ends (piece of the run, curve parameter) and its profile's boundary
/// speeds and duration, as bits (compared exactly).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Placed {
    start: (usize, u64),
    end: (usize, u64),
    v0: u64,
    v1: u64,
    duration: u64,
}

impl Placed {
    fn duration(&self) -> f64 {
        f64::from_bits(self.duration)
    }
    /// The start's place along the run, for ordering.
    fn at(&self) -> (usize, f64) {
        (self.start.0, f64::from_bits(self.start.1))
    }
}

/// The segments of the plan of the run's pieces `a..b` from rest to
/// rest, placed on the run, the start of piece `anchor` lying `s0` mm along
/// the run (as the run's plan adds the stretches' lengths); with that sum
/// at the start of piece `mark`. `pieces` are the run's pieces from
/// `base` on.
fn window_plan(
    pieces: &[Piece],
    base: usize,
    (a, b): (usize, usize),
    (anchor, s0, mark): (usize, f64, usize),
    opts: &PlanOptions,
    corners: Corners,
) -> Result<(Vec<Placed>, f64), FeedError> {
    let at = At {
        s0,
        anchor: anchor - a,
        mark: mark.min(b) - a,
    };
    let (plan, marked) = plan_window(&pieces[a - base..b - base], opts, corners, at)?;
    let placed = plan
        .segments
        .iter()
        .filter_map(|s| {
            let (first, last) = (s.parts.first()?, s.parts.last()?);
            Some(Placed {
                start: (a + first.piece, first.t0.to_bits()),
                end: (a + last.piece, last.t1.to_bits()),
                v0: s.profile.v0().to_bits(),
                v1: s.profile.v1().to_bits(),
                duration: s.profile.duration().to_bits(),
            })
        })
        .collect();
    Ok((placed, marked))
}

/// Where `next` (a later window's segments) first holds
/// [`STITCH_SEGMENTS`] segments alike with `held` (an earlier window's,
/// from its last stitch on): the index of the first of them in `held`
/// and in `next`.
fn stitch(held: &[Placed], next: &[Placed]) -> Option<(usize, usize)> {
    for (j, s) in next.iter().enumerate() {
        let Ok(i) = held.binary_search_by(|h| {
            let (p, q) = (h.at(), s.at());
            p.0.cmp(&q.0).then(p.1.total_cmp(&q.1))
        }) else {
            continue;
        };
        let k = STITCH_SEGMENTS;
        if i + k <= held.len() && j + k <= next.len() && held[i..i + k] == next[j..j + k] {
            return Some((i, j));
        }
    }
    None
}

/// [`plan_time_shaped`]'s time of `pieces` without shaping, planned in
/// the windows `w` where the run is longer than one (see the module docs):
/// the same to the bit wherever the windows agree with the whole plan.
/// Planned whole where two windows hold no segments alike, with a bounded
/// look-ahead ([`PlanOptions::window`]) or with other ends than rest.
pub fn plan_time_windowed(
    pieces: &[Piece],
    opts: &PlanOptions,
    corners: Corners,
    w: PlanWindows,
) -> Result<f64, FeedError> {
    match plan_time_in_windows(pieces, opts, corners, w)? {
        Some(t) => Ok(t),
        None => plan_time_shaped(pieces, opts, &Shaping::none(), corners),
    }
}

/// [`plan_time_windowed`]'s time where the run is planned in windows, and
/// `None` where it would be planned whole (one window, a bounded
/// look-ahead, ends other than rest, or two windows that hold no
/// segments alike).
pub fn plan_time_in_windows(
    pieces: &[Piece],
    opts: &PlanOptions,
    corners: Corners,
    w: PlanWindows,
) -> Result<Option<f64>, FeedError> {
    if !w.windows(pieces.len()) || !applies(opts, w) {
        return Ok(None);
    }
    let mut st = Stitcher::new(w);
    if !st.advance(pieces, 0, true, opts, corners)? {
        return Ok(None);
    }
    Ok(Some(st.time()))
}

/// Whether a run planned with `opts` can be planned in the windows `w`:
/// from rest to rest, with the whole look-ahead.
fn applies(opts: &PlanOptions, w: PlanWindows) -> bool {
    w.step > 0 && opts.window.is_none() && opts.ends == RunEnds::AtRest
}

/// Where the windows of a run stand: the last one planned and its
/// segments not yet added (see the module docs).
#[derive(Clone)]
struct Stitcher {
    w: PlanWindows,
    /// Pieces a window spans: its step and an overlap at each end.
    reach: usize,
    /// Start of the last window planned, once the first is.
    a: Option<usize>,
    /// The last window's segments from its stitch on.
    held: Vec<Placed>,
    /// The sum of lengths at the next window's anchor.
    s0: f64,
    /// The durations of the segments before `held`, added in order.
    time: f64,
}

impl Stitcher {
    fn new(w: PlanWindows) -> Stitcher {
        Stitcher {
            w,
            reach: w.step + 2 * w.overlap,
            a: None,
            held: Vec::new(),
            s0: 0.0,
            time: 0.0,
        }
    }

    /// Each window after the first takes its sums of lengths from the one
    /// before at its anchor, a half overlap in (inside both), and is
    /// stitched from there on only.
    fn anchor_of(&self, a: usize) -> usize {
        a + self.w.overlap / 2
    }

    /// The first of the run's pieces a window not yet planned needs.
    fn needed_from(&self) -> usize {
        self.a.map_or(0, |a| a + self.w.step)
    }

    /// Plans every window `pieces` holds whole: the run's pieces from
    /// `base` (at most [`Stitcher::needed_from`]) on, all of them if
    /// `done`. The first window is planned once the run is known to be
    /// longer than one. Returns false where two windows hold no segments
    /// alike (the run is then planned whole).
    fn advance(
        &mut self,
        pieces: &[Piece],
        base: usize,
        done: bool,
        opts: &PlanOptions,
        corners: Corners,
    ) -> Result<bool, FeedError> {
        let (w, reach) = (self.w, self.reach);
        let n = base + pieces.len();
        let mut a = match self.a {
            Some(a) => a,
            None if n > reach => {
                let first = (0, 0.0, self.anchor_of(w.step));
                let (held, s0) = window_plan(pieces, base, (0, reach), first, opts, corners)?;
                (self.held, self.s0) = (held, s0);
                self.a = Some(0);
                0
            }
            None => return Ok(true),
        };
        while a + reach < n {
            let next_a = a + w.step;
            let b = (next_a + reach).min(n);
            // The window's end is not known yet.
            if b < next_a + reach && !done {
                break;
            }
            let anchor = self.anchor_of(next_a);
            let at = (anchor, self.s0, self.anchor_of(next_a + w.step));
            let (mut next, s1) = window_plan(pieces, base, (next_a, b), at, opts, corners)?;
            next.retain(|s| s.start.0 >= anchor);
            let Some((i, j)) = stitch(&self.held, &next) else {
                return Ok(false);
            };
            // In order, as the whole plan adds them.
            for s in &self.held[..i] {
                self.time += s.duration();
            }
            next.drain(..j);
            self.held = next;
            self.s0 = s1;
            a = next_a;
            self.a = Some(a);
        }
        Ok(true)
    }

    /// The run's time once every window is planned.
    fn time(&self) -> f64 {
        let mut time = self.time;
        for s in &self.held {
            time += s.duration();
        }
        time
    }
}

/// [`plan_time_windowed`] of a run whose pieces come a part at a time (a
/// written run as it is read back): it holds the pieces of the window
/// being filled, not the run.
#[derive(Clone)]
pub struct WindowedTimer {
    opts: PlanOptions,
    corners: Corners,
    st: Stitcher,
    /// The run's pieces from `base` on, not yet planned.
    held: Vec<Piece>,
    base: usize,
    /// Two windows held no segments alike.
    unstitched: bool,
}

impl WindowedTimer {
    /// A timer for a run planned with `opts` and `corners` in the windows
    /// `w`; `None` where windows do not apply (a bounded look-ahead, ends
    /// other than rest).
    pub fn new(opts: &PlanOptions, corners: Corners, w: PlanWindows) -> Option<WindowedTimer> {
        applies(opts, w).then(|| WindowedTimer {
            opts: *opts,
            corners,
            st: Stitcher::new(w),
            held: Vec::new(),
            base: 0,
            unstitched: false,
        })
    }

    /// The run's next pieces, in order; the windows they complete are
    /// planned.
    pub fn push(&mut self, pieces: &[Piece]) -> Result<(), FeedError> {
        if self.unstitched {
            return Ok(());
        }
        // An overlap's pieces at a time, each chunk planned as soon as it
        // completes a window, in exactly the room it needs: the held
        // pieces stay within a window and an overlap (a megabyte
        // of read-back text is some 35,000 pieces; pushed whole they grew
        // the buffer to several windows on the large raster; measurements:
        // docs/tuning.md, `WindowedTimer::push`). The
        // windows and their plans are the same whatever the chunks.
        for chunk in pieces.chunks(self.st.w.overlap.max(1)) {
            if self.unstitched {
                return Ok(());
            }
            self.held.reserve_exact(chunk.len());
            self.held.extend_from_slice(chunk);
            self.plan(false)?;
        }
        Ok(())
    }

    fn plan(&mut self, done: bool) -> Result<(), FeedError> {
        let (opts, corners) = (&self.opts, self.corners);
        if !self
            .st
            .advance(&self.held, self.base, done, opts, corners)?
        {
            self.unstitched = true;
            self.held = Vec::new();
            return Ok(());
        }
        // (Past the run's end once its last window is planned.)
        let drop = (self.st.needed_from() - self.base).min(self.held.len());
        if drop > 0 {
            self.held.drain(..drop);
            self.base += drop;
        }
        Ok(())
    }

    /// The run's time: [`plan_time_windowed`]'s, to the bit; `None` where
    /// two windows held no segments alike (the run must be planned whole,
    /// which this timer cannot: it no longer holds the run).
    pub fn finish(mut self) -> Result<Option<f64>, FeedError> {
        if self.unstitched {
            return Ok(None);
        }
        if self.st.a.is_none() && !self.st.w.windows(self.held.len()) {
            // One window: planned whole, as `plan_time_windowed` plans it.
            let none = Shaping::none();
            return plan_time_shaped(&self.held, &self.opts, &none, self.corners).map(Some);
        }
        self.plan(true)?;
        if self.unstitched {
            return Ok(None);
        }
        Ok(Some(self.st.time()))
    }
}
