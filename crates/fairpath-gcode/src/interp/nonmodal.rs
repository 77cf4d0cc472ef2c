//! The group-0 codes that use a line's axis words: G92 sets the position,
//! G52, G10 and G92.1/G92.2/G92.3 make axes unknown, G28/G30 move through
//! the intermediate point to home (see the crate docs).

use super::codes::NonModal;
use super::line::Words;
use super::motion::target_point;
use super::{finite, State};
use crate::axes::set_axis;
use crate::error::GcodeError;
use crate::lexer::Word;
use crate::program::{Move, MoveKind, PinReason};
use fairpath::geom::{Curve, Line};
use fairpath::path::Piece;

/// Applies the line's group-0 code (if any) to `st`, appending the rapid
/// of a G28/G30 with axis words.
pub(super) fn apply(w: &Words, st: &mut State, moves: &mut Vec<Move>) -> Result<(), GcodeError> {
    let Some((n, _)) = w.nonmodal else {
        return Ok(());
    };
    let (lx, ln) = (w.lx, w.ln);
    let mm = st.units.mm_per_unit();
    let given: [Option<&Word>; 3] = w.axis_words();
    let given_mask = given.map(|g| g.is_some());
    match n {
        NonModal::G92 => {
            for a in 0..3 {
                if let Some(w) = given[a] {
                    let v = finite(w.value * mm, ln, w)?;
                    set_axis(&mut st.pos, a, v);
                    st.known[a] = true;
                    st.axis_text[a] = Some(w.text.clone());
                }
            }
        }
        NonModal::G52 => st.forget(given_mask),
        NonModal::G10 | NonModal::G92_1 | NonModal::G92_2 | NonModal::G92_3 => st.forget([true; 3]),
        NonModal::G28 | NonModal::G30 => {
            // Rapid to the intermediate point (if any), then home: the
            // position is unknown afterwards.
            if w.has_axes {
                st.spline.moved_otherwise();
                let target = target_point(st, &given, ln)?;
                let start = st.pos;
                moves.push(Move {
                    piece: Piece {
                        curve: Curve::Line(Line::new(start, target)),
                        rapid: true,
                        source_lines: (ln, ln),
                        feed: None,
                    },
                    line: ln,
                    kind: MoveKind::Rapid,
                    pinned: Some(PinReason::SpecialMotion),
                    end_text: [None, None, None],
                });
                st.pos = target;
            }
            st.forget([true; 3]);
        }
        NonModal::G28_1 | NonModal::G30_1 | NonModal::Dwell | NonModal::G53 => {}
    }
    if !lx.block_delete {
        // Home and G92 set the position the same way with the switch on.
        match n {
            NonModal::G28 | NonModal::G30 => st.after_delete.axes = [false; 3],
            NonModal::G92 => {
                for a in 0..3 {
                    st.after_delete.axes[a] &= !given_mask[a];
                }
            }
            _ => {}
        }
    }
    Ok(())
}
