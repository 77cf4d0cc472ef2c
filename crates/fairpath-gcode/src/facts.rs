//! What writing any part of a program needs to know of the whole of it:
//! the number style of its words, whether its arcs are written with R,
//! the path control in force at its runs, its units. A program read whole
//! gives them ([`ProgramFacts::of`]); one processed part by part gives
//! them from a first streamed reading ([`crate::interp::read_facts`]) that
//! keeps no lines or moves, so that every part is written exactly as the
//! whole program would be.

use crate::program::{MoveKind, Passthrough, Program, Units};
use crate::write_gcode::{before_runs, ArcWords, NumberStyle, PathBlending, StyleCount};

/// What writing a program needs of all of it (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramFacts {
    /// The style of the program's own numbers ([`NumberStyle::of`]).
    pub style: NumberStyle,
    /// R when any of the program's arcs is written with R, IJK otherwise
    /// ([`crate::emit::arc_words_of`]).
    pub arc_words: ArcWords,
    /// The path controls in force at its runs
    /// ([`crate::write_gcode::path_control_before_runs`]).
    pub blending: PathBlending,
    /// Units of the first run, where there is one.
    pub first_run_units: Option<Units>,
    /// The program's units ([`Program::units`]).
    pub units: Units,
    /// The line ending the program's lines use (the first one written).
    pub eol: &'static str,
    /// Lines of the program (in place: of the source file).
    pub lines: usize,
    /// Its moves and, of them, its rapids.
    pub moves: usize,
    pub rapids: usize,
    /// Lines passed through verbatim ([`Program::passthrough`]).
    pub passthrough: Vec<Passthrough>,
    /// Some interpreted line starts with the block-delete `/`.
    pub block_delete: bool,
    /// Some feed move is a NURBS (a G6.2 block, read exactly): the program
    /// is for a controller that runs them.
    pub nurbs: bool,
    /// The highest degree of those NURBS (0 where there are none): a
    /// controller that runs the program runs NURBS of that degree.
    pub nurbs_degree: usize,
}

impl ProgramFacts {
    /// The facts of a program read whole.
    pub fn of(program: &Program) -> ProgramFacts {
        let mut count = StyleCount::default();
        let mut uses_r = false;
        for line in program.lines().iter().filter(|l| l.interpreted) {
            count.add(&line.words);
        }
        for m in program.moves() {
            uses_r |= m.kind == MoveKind::Arc
                && program.line(m.line).words.iter().any(|w| w.letter == 'R');
        }
        let mut blending = PathBlending::default();
        for pc in before_runs(program).iter().flatten() {
            blending.add(pc);
        }
        ProgramFacts {
            style: count.style(),
            arc_words: if uses_r { ArcWords::R } else { ArcWords::Ijk },
            blending,
            first_run_units: program.run_spans().first().map(|r| r.units),
            units: program.units(),
            eol: program
                .lines()
                .iter()
                .map(|l| l.ending)
                .find(|e| !e.is_empty())
                .unwrap_or("\n"),
            lines: program.lines().len(),
            moves: program.moves().len(),
            rapids: program.moves().iter().filter(|m| m.piece.rapid).count(),
            passthrough: program.passthrough().to_vec(),
            block_delete: program
                .lines()
                .iter()
                .any(|l| l.interpreted && is_block_delete(&l.text)),
            nurbs: program.moves().iter().any(is_nurbs_feed),
            nurbs_degree: program.moves().iter().map(nurbs_degree).max().unwrap_or(0),
        }
    }

    /// The units a program's render takes its decimals from: those of its
    /// first run, else the program's.
    pub fn render_units(&self) -> Units {
        self.first_run_units.unwrap_or(self.units)
    }
}

/// Whether a move is a feed move along a NURBS ([`ProgramFacts::nurbs`]).
pub(crate) fn is_nurbs_feed(m: &crate::Move) -> bool {
    !m.piece.rapid && matches!(m.piece.curve, fairpath::geom::Curve::Nurbs(_))
}

/// The degree of a feed move along a NURBS, 0 for any other move
/// ([`ProgramFacts::nurbs_degree`]).
pub(crate) fn nurbs_degree(m: &crate::Move) -> usize {
    match &m.piece.curve {
        fairpath::geom::Curve::Nurbs(n) if !m.piece.rapid => n.degree,
        _ => 0,
    }
}

/// Whether a line's text starts with the block-delete `/`.
pub(crate) fn is_block_delete(text: &str) -> bool {
    text.trim_start().starts_with('/')
}
