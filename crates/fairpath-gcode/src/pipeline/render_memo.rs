//! The renderings `auto`'s objective made while it ranked its candidates
//! ([`fairpath::choose::WrittenTime`]), kept for the writer: the
//! candidate `auto` chooses for a run is mostly the one whose rendering
//! planned fastest, rendered with the options the writer renders with, so
//! the writer takes that rendering and its time instead of rendering and
//! planning the same pieces again ([`crate::emit`]). Where `auto` keeps
//! another, one the writer writes faster with its own tries
//! ([`fairpath::choose::FINAL_COST_MARGIN`]), the memo holds none of it
//! and the writer renders it.
//!
//! Per run (named by its first and last input lines and its end points)
//! and rendering options, only the fastest rendering seen is kept, with a
//! digest of the candidate's pieces ([`pieces_digest`]); the writer takes
//! it only for pieces with the same digest, so what it writes is what it
//! would have rendered itself, bit for bit. With each rendering kept, the
//! speed it was rendered by ([`PlannedSpeed`], the candidate's curves
//! planned at the machine's maximum feed) stays for the writer's other
//! renderings of the same pieces (another form, a finer chord), which
//! then need no plan of their own.
//!
//! Only renderings of the runs the writer will write are kept
//! ([`RenderMemo::expect_runs`]): `auto` also costs the sections it cuts a
//! run into, whose renderings no writer asks for (kept, they held every
//! section's fastest rendering at every cut length until the part was
//! written, many times the program itself on a plotter program of one
//! run; measurements: docs/tuning.md, `RenderMemo::expect_runs`).

use fairpath::choose::{pieces_digest, RenderObserver};
use fairpath::path::Piece;
use fairpath::path::Run;
use fairpath::render::{PlannedSpeed, Rendered};
use std::collections::{HashMap, HashSet};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::sync::Mutex;
use std::sync::OnceLock;

/// A run: its first and last input lines and its end points, bit for bit.
type RunKey = (usize, usize, [u64; 6]);

/// A candidate's digest and the speed its renderings were rendered by.
type DigestSpeed = ([u64; 2], Arc<PlannedSpeed>);

/// The fastest rendering seen of each run (see the module docs).
#[derive(Debug, Default)]
pub struct RenderMemo {
    kept: Mutex<HashMap<(RunKey, usize), Kept>>,
    /// The candidates' curves planned at the user's feeds, by digest.
    bounds: Mutex<HashMap<[u64; 2], f64>>,
    /// The speed each kept rendering was rendered by, by run and digest
    /// (not taken with the rendering).
    speeds: Mutex<HashMap<RunKey, Vec<DigestSpeed>>>,
    /// Renderings taken by the writer so far.
    taken: AtomicUsize,
    /// The runs whose renderings are kept, once told
    /// ([`RenderMemo::expect_runs`]); until then, every run's.
    expected: OnceLock<HashSet<RunKey>>,
}

#[derive(Debug)]
struct Kept {
    digest: [u64; 2],
    time: f64,
    rendering: Rendered,
}

fn run_key(pieces: &[Piece]) -> Option<RunKey> {
    let (first, last) = (pieces.first()?, pieces.last()?);
    let (a, b) = (first.start(), last.end());
    let bits = [a.x, a.y, a.z, b.x, b.y, b.z].map(f64::to_bits);
    Some((first.source_lines.0, last.source_lines.1, bits))
}

impl RenderObserver for RenderMemo {
    fn rendered(
        &self,
        pieces: &[Piece],
        render: usize,
        rendering: Rendered,
        time: f64,
        speed: &Arc<PlannedSpeed>,
    ) {
        let Some(key) = self.expected_key(pieces) else {
            return;
        };
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        if kept.get(&(key, render)).is_some_and(|k| k.time <= time) {
            return;
        }
        let digest = pieces_digest(pieces);
        {
            let mut speeds = self.speeds.lock().unwrap_or_else(|e| e.into_inner());
            let of_run = speeds.entry(key).or_default();
            if !of_run.iter().any(|(d, _)| *d == digest) {
                of_run.push((digest, speed.clone()));
            }
        }
        kept.insert(
            (key, render),
            Kept {
                digest,
                time,
                rendering,
            },
        );
    }

    fn bounded(&self, pieces: &[Piece], time: f64) {
        if self.expected_key(pieces).is_none() {
            return;
        }
        let digest = pieces_digest(pieces);
        let mut bounds = self.bounds.lock().unwrap_or_else(|e| e.into_inner());
        bounds.insert(digest, time);
    }
}

impl RenderMemo {
    /// Keeps from now on only the renderings (and bounds) of pieces that
    /// start and end where one of `runs` does, on its first and last
    /// input lines: the runs the writer will write (a method keeps a run's
    /// end points exactly). The first call counts; later ones are ignored.
    pub fn expect_runs(&self, runs: &[Run]) {
        let keys = runs.iter().filter_map(|r| run_key(&r.pieces)).collect();
        let _ = self.expected.set(keys);
    }

    /// The run key of `pieces` where their renderings are kept.
    fn expected_key(&self, pieces: &[Piece]) -> Option<RunKey> {
        let key = run_key(pieces)?;
        match self.expected.get() {
            Some(keys) if !keys.contains(&key) => None,
            _ => Some(key),
        }
    }

    /// The rendering of exactly `pieces` with the objective's rendering
    /// options `render` and its planned time, if it was kept; taken out.
    pub fn take(&self, pieces: &[Piece], render: usize) -> Option<(Rendered, f64)> {
        let key = (run_key(pieces)?, render);
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        if kept.get(&key)?.digest != pieces_digest(pieces) {
            return None;
        }
        self.taken.fetch_add(1, Ordering::Relaxed);
        kept.remove(&key).map(|k| (k.rendering, k.time))
    }

    /// Whether it holds the rendering of exactly `pieces` with the
    /// objective's rendering options `render` ([`RenderMemo::take`] would
    /// give it).
    pub fn holds(&self, pieces: &[Piece], render: usize) -> bool {
        let Some(key) = run_key(pieces) else {
            return false;
        };
        let kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        kept.get(&(key, render))
            .is_some_and(|k| k.digest == pieces_digest(pieces))
    }

    /// The time of exactly `pieces` planned at the user's feeds with
    /// blended corners, where the objective planned it (as the curves'
    /// time of a job is planned: `plan_input_and_curves_from` takes it).
    pub fn bound_of(&self, pieces: &[Piece]) -> Option<f64> {
        let bounds = self.bounds.lock().unwrap_or_else(|e| e.into_inner());
        bounds.get(&pieces_digest(pieces)).copied()
    }

    /// The speed a kept rendering of exactly `pieces` was rendered by, if
    /// one was kept (taken or not).
    pub fn speed_of(&self, pieces: &[Piece]) -> Option<Arc<PlannedSpeed>> {
        let key = run_key(pieces)?;
        let digest = pieces_digest(pieces);
        let speeds = self.speeds.lock().unwrap_or_else(|e| e.into_inner());
        speeds
            .get(&key)?
            .iter()
            .find(|(d, _)| *d == digest)
            .map(|(_, s)| s.clone())
    }

    /// How many renderings the writer took ([`RenderMemo::take`]).
    pub fn taken(&self) -> usize {
        self.taken.load(Ordering::Relaxed)
    }

    /// How many renderings it holds (not taken yet).
    pub fn held(&self) -> usize {
        self.kept.lock().unwrap_or_else(|e| e.into_inner()).len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fairpath::geom::{Curve, Line, Vec3};

    fn line(a: f64, b: f64, lines: (usize, usize)) -> Piece {
        Piece {
            curve: Curve::Line(Line::new(Vec3::new(a, 0.0, 0.0), Vec3::new(b, 0.0, 0.0))),
            rapid: false,
            source_lines: lines,
            feed: None,
        }
    }

    fn rendering(pieces: &[Piece]) -> Rendered {
        Rendered {
            pieces: pieces.to_vec(),
            ..Rendered::default()
        }
    }

    /// Once told the runs the writer will write, the memo keeps the
    /// renderings and bounds of those runs only: a section of a run (it
    /// starts inside the run's first line) is neither kept nor bounded;
    /// untold, it keeps every run's.
    #[test]
    fn only_the_runs_to_be_written_are_kept() {
        let run = vec![line(0.0, 1.0, (3, 3)), line(1.0, 2.0, (4, 4))];
        let section = vec![line(0.5, 1.0, (3, 3)), line(1.0, 2.0, (4, 4))];
        let speed = Arc::new(PlannedSpeed::default());
        for told in [true, false] {
            let memo = RenderMemo::default();
            if told {
                memo.expect_runs(&[Run::new(run.clone())]);
            }
            for pieces in [&run, &section] {
                memo.rendered(pieces, 0, rendering(pieces), 1.0, &speed);
                memo.bounded(pieces, 2.0);
            }
            assert!(memo.holds(&run, 0));
            assert_eq!(memo.bound_of(&run), Some(2.0));
            assert_eq!(memo.holds(&section, 0), !told);
            assert_eq!(memo.bound_of(&section).is_some(), !told);
            assert_eq!(memo.speed_of(&section).is_some(), !told);
            assert_eq!(memo.held(), if told { 1 } else { 2 });
            // The one the writer asks for is taken whole.
            let (r, t) = memo.take(&run, 0).expect("kept");
            assert_eq!((r.pieces, t), (run.clone(), 1.0));
        }
    }
}
