//! A program as the motions the feed planner plans
//! ([`fairpath::feed::program`]): its runs of feed moves (its own, or
//! smoothed ones in their place), each pinned feed move on its own, and
//! its rapids, in order.

use crate::program::{MotionOutline, Program};
use fairpath::feed::program::{chain_motions, program_motions, Motion};
use fairpath::path::Run;

impl Program {
    /// The motions of the program with its runs replaced by `runs` (the
    /// program's own, or smoothed ones, in the order of [`Program::runs`]);
    /// pinned feed moves are motions of their own.
    pub fn motions(&self, runs: &[Run]) -> Vec<Motion> {
        self.motions_indexed(runs).0
    }

    /// [`Program::motions`], and the index of each run's motion.
    pub fn motions_indexed(&self, runs: &[Run]) -> (Vec<Motion>, Vec<usize>) {
        let spans: Vec<_> = self.run_spans().iter().map(|s| s.moves.clone()).collect();
        program_motions(self.moves(), |m| &m.piece, &spans, runs)
    }
}

/// The motions of fairpath's JSON (see [`crate::write_json()`]): consecutive
/// feed pieces that meet as one run, each rapid on its own.
pub fn json_motions(text: &str) -> Result<Vec<Motion>, crate::JsonError> {
    Ok(chain_motions(crate::read_json(text)?))
}

/// The motions of a program read for its motion only
/// ([`crate::read_motion`]): the same as [`Program::motions`] of its own
/// runs, without the program's lines (its runs are moved in, not copied).
pub fn outline_motions(outline: Vec<MotionOutline>, runs: Vec<Run>) -> Vec<Motion> {
    let mut runs: Vec<Option<Run>> = runs.into_iter().map(Some).collect();
    outline
        .into_iter()
        .filter_map(|m| match m {
            MotionOutline::Run(k) => runs.get_mut(k).and_then(Option::take).map(Motion::Feed),
            MotionOutline::Rapid(p) => Some(Motion::Rapid(p)),
            MotionOutline::Pinned(p) => Some(Motion::Feed(Run::new(vec![p]))),
        })
        .collect()
}
