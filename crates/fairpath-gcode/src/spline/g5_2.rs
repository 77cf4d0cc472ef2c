//! G5.2 ... G5.3 blocks: the G5.2 lines that open a block and add its
//! control points (weights `P`, order `L`), and the G5.3 that checks and
//! runs it.

use super::curves::{curves, emit};
use super::words::{check_words, coord, int_word, line_pin, plane_pair, state_pin, weight};
use super::{new_block, spline_err, LineCtx, SplineReading, MAX_ORDER};
use crate::axes::AXIS_LETTERS as AXES;
use crate::error::{GcodeError, SplineError};
use crate::interp::State;
use crate::lexer::Word;
use crate::program::{MotionMode, Move};

/// Highest `L` taken on G5.2 lines (LinuxCNC has no limit; the block
/// needs that many points anyway).
const MAX_L: usize = 64;

/// A G5.2 line: opens the block or adds a control point.
pub(super) fn g5_2_point(ctx: &LineCtx, st: &mut State) -> Result<(), GcodeError> {
    let (lx, ln) = (ctx.lx, ctx.ln);
    let extra = check_words(lx, ln, "G5.2", st.plane, "PL", false)?;
    let pair = plane_pair(lx, ln, "G5.2", st.plane)?;
    let (p, l) = (lx.word('P'), lx.word('L'));
    let mut block = match st.spline.open.take() {
        Some(b) => b,
        None => {
            let col = ctx.code.map_or(1, |c| c.1.column);
            let mut b = new_block(st, false, ln, col, 3);
            let mm = st.units.mm_per_unit();
            b.prog.push(st.plane.to_plane(st.pos / mm));
            b.pts.push(st.pos);
            b.weights.push(match (pair, p) {
                (None, Some(p)) => weight(p, ln)?,
                _ => 1.0,
            });
            b
        }
    };
    let opening = block.first_line == ln;
    if let Some(l) = l {
        let order = int_word(l, ln, 0, MAX_L)?;
        if order > 3 {
            block.order = order;
        }
    }
    match pair {
        Some([a, b]) => {
            let p = p.ok_or_else(|| {
                let e = SplineError::MissingWord {
                    code: "G5.2",
                    letter: 'P',
                };
                spline_err(ln, b.column, e)
            })?;
            let w = weight(p, ln)?;
            let (i1, i2, _) = st.plane.axes();
            let (pa, ma) = coord(st, a, i1, block.start, ln)?;
            let (pb, mb) = coord(st, b, i2, block.start, ln)?;
            block.prog.push([pa, pb]);
            block.pts.push(
                st.plane
                    .from_plane([ma, mb], st.plane.off_plane(block.start)),
            );
            block.weights.push(w);
            block.last_words = [None, None, None];
            block.last_words[i1] = Some(a.text.to_string());
            block.last_words[i2] = Some(b.text.to_string());
        }
        None if !opening && (ctx.code.is_some() || p.is_some() || l.is_some()) => {
            let (a, b, _) = st.plane.axes();
            let col = ctx.code.map(|c| c.1).or(p).or(l).map_or(1, |w| w.column);
            let e = SplineError::AxisPair {
                code: "G5.2",
                first: AXES[a],
                second: AXES[b],
            };
            return Err(spline_err(ln, col, e));
        }
        None => {}
    }
    block.pin = block.pin.or(line_pin(ctx, extra));
    st.spline.open = Some(block);
    Ok(())
}

/// G5.3: runs the open G5.2 block.
pub(super) fn close_g5_2(
    ctx: &LineCtx,
    w: &Word,
    st: &mut State,
    moves: &mut Vec<Move>,
) -> Result<bool, GcodeError> {
    let ln = ctx.ln;
    let block = match st.spline.open.take() {
        Some(b) if !b.g6 => b,
        _ => return Err(spline_err(ln, w.column, SplineError::EndWithoutBlock)),
    };
    let extra = check_words(ctx.lx, ln, "G5.3", st.plane, "", false)?;
    if let Some(a) = ctx.lx.words.iter().find(|w| AXES.contains(&w.letter)) {
        let e = SplineError::WordNotAllowed {
            code: "G5.3",
            letter: a.letter,
        };
        return Err(spline_err(ln, a.column, e));
    }
    if block.pts.len() < block.order {
        let e = SplineError::TooFewPoints {
            points: block.pts.len(),
            order: block.order,
        };
        return Err(spline_err(ln, w.column, e));
    }
    if st.spline.reading == SplineReading::Exact && block.order > MAX_ORDER {
        let e = SplineError::BadOrder {
            value: block.order as f64,
            min: 3,
            max: MAX_ORDER,
        };
        return Err(spline_err(block.first_line, block.column, e));
    }
    let pin = block
        .pin
        .or(line_pin(ctx, extra))
        .or(state_pin(st, block.start_known));
    let cs = curves(
        st,
        &block.prog,
        &block.pts,
        &block.weights,
        block.order,
        ln,
        w.column,
    )?;
    let end = block.pts[block.pts.len() - 1];
    st.motion = MotionMode::None;
    st.spline.moved_otherwise();
    Ok(emit(
        st,
        moves,
        cs,
        block.first_line,
        ln,
        pin,
        end,
        block.last_words,
    ))
}
