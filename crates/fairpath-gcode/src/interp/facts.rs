//! [`ProgramFacts`] of a program read as a stream: each line adds to the
//! counts and is dropped ([`read_facts`]), so a program processed part by
//! part knows what writing any part needs of the whole before it reads
//! the first part.

use super::reader::Reader;
use super::State;
use crate::error::GcodeError;
use crate::facts::ProgramFacts;
use crate::lexer::{line_slices, Word};
use crate::program::{Move, MoveKind, Units};
use crate::spline::ParseOptions;
use crate::write_gcode::{has_path_control, ArcWords, PathBlending, PathControl, StyleCount};

/// What [`read_facts`] gathers, line by line.
#[derive(Clone, Debug, Default)]
pub(super) struct FactsAcc {
    count: StyleCount,
    uses_r: bool,
    blending: PathBlending,
    /// The path control in force after the lines read.
    path: Option<PathControl>,
    first_run_units: Option<Units>,
    /// The feed of the last move of the run being read, if one is.
    run_feed: Option<Option<f64>>,
    eol: Option<&'static str>,
    lines: usize,
    moves: usize,
    rapids: usize,
    block_delete: bool,
    nurbs: bool,
    nurbs_degree: usize,
}

impl FactsAcc {
    /// Any line (interpreted or passed through unread).
    pub(super) fn ending(&mut self, ending: &'static str) {
        self.lines += 1;
        if self.eol.is_none() && !ending.is_empty() {
            self.eol = Some(ending);
        }
    }

    /// An interpreted line: its words, its moves, whether it breaks runs,
    /// and the state after it. Runs are told as `group_runs` groups them
    /// (a feed change starts one).
    pub(super) fn line(
        &mut self,
        text: &str,
        words: &[Word],
        moves: &[Move],
        breaks_run: bool,
        st: &State,
    ) {
        self.block_delete |= crate::facts::is_block_delete(text);
        self.count.add(words);
        self.moves += moves.len();
        self.rapids += moves.iter().filter(|m| m.piece.rapid).count();
        self.nurbs |= moves.iter().any(crate::facts::is_nurbs_feed);
        let degree = moves.iter().map(crate::facts::nurbs_degree).max();
        self.nurbs_degree = self.nurbs_degree.max(degree.unwrap_or(0));
        self.uses_r |=
            moves.iter().any(|m| m.kind == MoveKind::Arc) && words.iter().any(|w| w.letter == 'R');
        if breaks_run {
            self.run_feed = None;
        } else {
            for m in moves {
                if self.run_feed != Some(m.piece.feed) {
                    // A run starts: the path control in force before its
                    // line (a line that sets one breaks runs).
                    if self.first_run_units.is_none() {
                        self.first_run_units = Some(st.units);
                    }
                    if let Some(pc) = &self.path {
                        self.blending.add(pc);
                    }
                }
                self.run_feed = Some(m.piece.feed);
            }
        }
        if has_path_control(words) {
            self.path = st
                .path_words
                .as_ref()
                .map(|text| PathControl::after_line(text, words, st.units));
        }
    }
}

/// The facts of a program without o-words ([`ProgramFacts::of`] of its
/// reading, the same), read as a stream: no line or move is kept. `None`
/// for a program with o-words (which is read whole, expanded).
pub fn read_facts(text: &[u8], opts: &ParseOptions) -> Result<Option<ProgramFacts>, GcodeError> {
    let mut oword = false;
    for l in line_slices(text) {
        oword |= crate::lang::flow::looks_like_oword(l?.0);
    }
    if oword {
        return Ok(None);
    }
    let mut r = Reader::new(opts);
    r.facts = Some(Box::default());
    for (i, line) in line_slices(text).enumerate() {
        let (t, ending) = line?;
        r.step_in_place(i + 1, t, ending)?;
    }
    r.first_number = r.facts.as_ref().map_or(1, |f| f.lines + 1);
    r.check_closed()?;
    let f = r.facts.take().unwrap_or_default();
    Ok(Some(ProgramFacts {
        style: f.count.style(),
        arc_words: if f.uses_r { ArcWords::R } else { ArcWords::Ijk },
        blending: f.blending,
        first_run_units: f.first_run_units,
        units: r.start_units.unwrap_or(r.st.units),
        eol: f.eol.unwrap_or("\n"),
        lines: f.lines,
        moves: f.moves,
        rapids: f.rapids,
        passthrough: core::mem::take(&mut r.st.passthrough),
        block_delete: f.block_delete,
        nurbs: f.nurbs,
        nurbs_degree: f.nurbs_degree,
    }))
}
