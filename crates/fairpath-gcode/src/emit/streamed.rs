//! A long run's written text checked as it is read back, part after part
//! ([`RunStream`]): its deviation from the original run, its end points
//! and its planned times at each feed, measured as the pieces come and
//! then dropped, so that the reading never holds the run (millions of
//! blocks on a one-run raster written as arcs; measurements:
//! docs/tuning.md, `emit::streamed`).
//!
//! The figures are those of the check that reads the run whole
//! ([`crate::pipeline::compare_runs`] and [`Emitter::time`]), to the bit:
//! the deviation is measured in the verifier's chunks from the run's start
//! ([`VERIFY_CHUNK`]) and merged in order, as it merges a long run's, and
//! the times are planned in the windows [`Emitter::time`] plans in
//! ([`WindowedTimer`]). Where two windows do not stitch (a plan that must
//! be made whole), or the runs read do not pair as they were taken to,
//! the caller reads the text again whole.
//!
//! The reading ([`StreamFront`], on the caller's thread) and the measuring
//! ([`StreamCheck`], on a thread beside it) overlap: the reader hands a
//! group of pieces over and reads on while the group is measured.

use super::emitter::{Choice, Emitter};
use super::EmitError;
use crate::interp::{MotionReader, RunStream};
use crate::program::MotionOutline;
use fairpath::feed::plan::{Corners, PlanOptions};
use fairpath::feed::windowed::{PlanWindows, WindowedTimer};
use fairpath::feed::FeedError;
use fairpath::path::{Piece, Run};
use fairpath::pipeline::{par_map, VERIFY_CHUNK};
use fairpath::verify::{report_measuring, Deviation, Measures, RunReport, Verifier, VerifyOptions};
use std::sync::mpsc::{sync_channel, SyncSender};
use std::sync::Mutex;

/// Verifier chunks measured side by side (with the windows they complete
/// planned beside them): the group being measured, the two handed over
/// behind it and the one being read are all the check holds of a run
/// (measurements: docs/tuning.md, `GROUP_CHUNKS`).
const GROUP_CHUNKS: usize = 8;

/// A run checked as it was read.
pub(super) struct StreamedRun {
    /// Its index among the part's runs read back, and the original's it
    /// was paired with.
    pub(super) candidate: usize,
    pub(super) original: usize,
    pub(super) report: RunReport,
    /// Its time at each of [`Emitter::feeds`] as the choice is judged,
    /// then at the user's feed as `fairpath simulate` plans it where that
    /// is another plan (see [`StreamCheck::new`]); `None` where the
    /// windows did not stitch.
    pub(super) times: Vec<Option<f64>>,
}

/// The run being read.
struct Current<'a> {
    candidate: usize,
    original: usize,
    verifier: Verifier,
    deviation: Option<Deviation>,
    first: Option<Piece>,
    last: Option<Piece>,
    timers: Vec<Mutex<WindowedTimer>>,
    original_pieces: &'a [Piece],
}

/// What the reading hands over to the measuring.
enum Handed {
    /// Run `candidate` of the text, paired with the original's run
    /// `original`, starts.
    Start { candidate: usize, original: usize },
    /// Its next pieces.
    Pieces(Vec<Piece>),
    /// It ends.
    End,
}

/// The reading's side: which runs are taken (those whose choice is
/// rendered part after part), and their pieces handed over a group at a
/// time.
struct StreamFront {
    /// Per original run, whether its rendering is taken as it is read.
    taken: Vec<bool>,
    /// The original runs that move, in order (how runs pair).
    moving: Vec<usize>,
    /// The run being taken, and its pieces not yet handed over.
    run: Option<usize>,
    held: Vec<Piece>,
    to_check: SyncSender<Handed>,
}

impl RunStream for StreamFront {
    fn wants(&mut self, run: usize, moving: usize) -> bool {
        let Some(&o) = self.moving.get(moving) else {
            return false;
        };
        if !self.taken[o] || self.run.is_some() {
            return false;
        }
        self.run = Some(run);
        let start = Handed::Start {
            candidate: run,
            original: o,
        };
        // (A measuring that stopped has its reason, which the caller reads.)
        self.to_check.send(start).is_ok()
    }

    fn pieces(&mut self, run: usize, pieces: &[Piece], end: bool) {
        if self.run != Some(run) {
            return;
        }
        self.held.extend_from_slice(pieces);
        if end || self.held.len() >= GROUP_CHUNKS * VERIFY_CHUNK {
            let held = core::mem::take(&mut self.held);
            let _ = self.to_check.send(Handed::Pieces(held));
        }
        if end {
            let _ = self.to_check.send(Handed::End);
            self.run = None;
        }
    }
}

/// The measuring's side: each run taken, checked and timed as its pieces
/// come.
pub(super) struct StreamCheck<'a> {
    original: &'a [Run],
    verify: VerifyOptions,
    /// The plans each run is timed by: the feed (`true`: the machine's
    /// maximum) and how corners are judged.
    plans: Vec<(PlanOptions, Corners)>,
    current: Option<Current<'a>>,
    pub(super) done: Vec<StreamedRun>,
    pub(super) error: Option<FeedError>,
}

/// Whether any of `choices` is rendered part after part (and so may be
/// read back that way, [`read_checking`]).
pub(super) fn takes_any(choices: &[Choice]) -> bool {
    choices.iter().any(|c| c.streamed)
}

/// What [`read_checking`] gives: the reading after the text, its
/// motions, its runs (those taken hold no pieces), and the runs taken,
/// checked.
pub(super) type Checked = (MotionReader, Vec<MotionOutline>, Vec<Run>, Vec<StreamedRun>);

/// Reads `text` (a part written with `choices`) from `reading`, the runs
/// rendered part after part taken as they are read and checked against
/// `original` on a thread beside the reading (see the module docs).
pub(super) fn read_checking(
    em: &Emitter,
    reading: &MotionReader,
    text: &mut dyn std::io::Read,
    original: &[Run],
    choices: &[Choice],
    tolerance: f64,
) -> Result<Checked, EmitError> {
    let check = StreamCheck::new(em, original, tolerance);
    let moving = (0..original.len())
        .filter(|&i| original[i].pieces.iter().any(moves))
        .collect();
    std::thread::scope(|s| {
        // Two groups in flight: the reader runs ahead of the measuring by
        // at most that much.
        let (to_check, handed) = sync_channel(2);
        let measuring = s.spawn(move || {
            let mut check = check;
            for h in handed {
                check.take(h);
            }
            check
        });
        let mut front = StreamFront {
            taken: choices.iter().map(|c| c.streamed).collect(),
            moving,
            run: None,
            held: Vec::new(),
            to_check,
        };
        let read = reading.read_part_streaming_from(text, VERIFY_CHUNK, &mut front);
        drop(front);
        let check = measuring
            .join()
            .unwrap_or_else(|p| std::panic::resume_unwind(p));
        let (after, outline, runs) = read?;
        if let Some(e) = check.error {
            return Err(EmitError::Plan(e));
        }
        Ok((after, outline, runs, check.done))
    })
}

impl<'a> StreamCheck<'a> {
    /// For the runs of `em`'s part, `original` the program's own;
    /// `tolerance` what the written text must keep. Each run is timed at
    /// every feed of [`Emitter::feeds`] as `em` judges it, and where that
    /// is not as `fairpath simulate` plans it (corners other than
    /// blended), also at the user's feed as it does, for the written
    /// program's time.
    fn new(em: &Emitter, original: &'a [Run], tolerance: f64) -> StreamCheck<'a> {
        let opts = &em.opts;
        let plan = |override_feed: bool| em.plan_options(override_feed);
        let mut plans: Vec<(PlanOptions, Corners)> = em
            .feeds
            .iter()
            .map(|&f| (plan(f), opts.judged_by))
            .collect();
        if opts.judged_by != Corners::Blended {
            plans.push((plan(opts.override_feed), Corners::Blended));
        }
        StreamCheck {
            original,
            verify: VerifyOptions::new(tolerance),
            plans,
            current: None,
            done: Vec::new(),
            error: None,
        }
    }

    /// What the reading handed over.
    fn take(&mut self, h: Handed) {
        match h {
            Handed::Start {
                candidate,
                original,
            } => self.start(candidate, original),
            Handed::Pieces(p) => self.measure(p),
            Handed::End => self.end(),
        }
    }

    /// Run `candidate` of the text starts, paired with `original`.
    fn start(&mut self, candidate: usize, original: usize) {
        let windows = PlanWindows::DEFAULT;
        let timers: Option<Vec<_>> = self
            .plans
            .iter()
            .map(|(po, corners)| WindowedTimer::new(po, *corners, windows).map(Mutex::new))
            .collect();
        // (Windows apply to every plan here: rest to rest, whole look-ahead.)
        let timers = timers.unwrap_or_default();
        let original_pieces = self.original[original].pieces.as_slice();
        self.current = Some(Current {
            candidate,
            original,
            verifier: Verifier::new(original_pieces, &self.verify),
            deviation: None,
            first: None,
            last: None,
            timers,
            original_pieces,
        });
    }

    /// Measures and plans `held`, the next pieces of the run being read.
    fn measure(&mut self, held: Vec<Piece>) {
        let Some(cur) = self.current.as_mut() else {
            return;
        };
        if held.is_empty() {
            return;
        }
        if cur.first.is_none() {
            cur.first = held.first().cloned();
        }
        cur.last = held.last().cloned();
        let chunks = held.len().div_ceil(VERIFY_CHUNK);
        let timers = cur.timers.len();
        enum Job {
            Deviation(Deviation),
            Planned(Result<(), FeedError>),
        }
        let (verifier, timer) = (&cur.verifier, &cur.timers);
        let jobs = par_map(chunks + timers, |j| {
            if j < chunks {
                let end = ((j + 1) * VERIFY_CHUNK).min(held.len());
                Job::Deviation(verifier.deviation(&held[j * VERIFY_CHUNK..end]))
            } else {
                let mut t = timer[j - chunks].lock().unwrap_or_else(|e| e.into_inner());
                Job::Planned(t.push(&held))
            }
        });
        for job in jobs {
            match job {
                Job::Deviation(d) => {
                    cur.deviation = Some(match cur.deviation {
                        Some(acc) => acc.merge(d),
                        None => d,
                    });
                }
                Job::Planned(Err(e)) => {
                    self.error.get_or_insert(e);
                }
                Job::Planned(Ok(())) => {}
            }
        }
    }

    /// The run being read ends.
    fn end(&mut self) {
        let Some(cur) = self.current.take() else {
            return;
        };
        let mut times = Vec::with_capacity(self.plans.len());
        if cur.timers.len() != self.plans.len() {
            // (No timers: the run is to be read whole.)
            times.resize(self.plans.len(), None);
        }
        for t in cur.timers {
            let t = t.into_inner().unwrap_or_else(|e| e.into_inner());
            match t.finish() {
                Ok(t) => times.push(t),
                Err(e) => {
                    self.error.get_or_insert(e);
                    times.push(None);
                }
            }
        }
        // The report the verifier makes of the run whole: its ends from
        // the first and last pieces (all that `Measures::Ends` reads of
        // them), its deviation from the chunks.
        let ends: Vec<Piece> = cur.first.into_iter().chain(cur.last).collect();
        let (mut report, measure) =
            report_measuring(cur.original_pieces, &ends, &self.verify, Measures::Ends);
        if let (true, Some(d)) = (measure, cur.deviation) {
            report.set_deviation(d);
        }
        self.done.push(StreamedRun {
            candidate: cur.candidate,
            original: cur.original,
            report,
            times,
        });
    }
}

/// Whether a piece moves (as `pair_runs` pairs runs: a run moves unless
/// every piece is a line from a point to itself).
fn moves(p: &Piece) -> bool {
    !matches!(&p.curve, fairpath::geom::Curve::Line(l) if l.p0 == l.p1)
}
