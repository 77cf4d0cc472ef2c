//! G6.2 blocks (Fanuc NURBS syntax, LinuxCNC master's rules): the lines
//! that open a block and add control points and knots, and the block run,
//! as the exact NURBS, once LinuxCNC would find its knot vector complete.

use super::curves::emit;
use super::words::{
    check_words, coord, int_word, line_pin, plane_pair, state_pin, weight, NEAR_INT,
};
use super::{new_block, spline_err, Block, LineCtx, MAX_ORDER};
use crate::axes::AXIS_LETTERS as AXES;
use crate::error::{ErrorKind, GcodeError, SplineError};
use crate::interp::{err, finite, State};
use crate::lexer::Word;
use crate::program::{MotionMode, Move};
use fairpath::geom::{Curve, Line, Nurbs, NurbsError, Vec3};

/// A G6.2 line: opens the block, adds a control point or a knot, and runs
/// the block when its knot vector is complete.
pub(super) fn g6_2_line(
    ctx: &LineCtx,
    st: &mut State,
    moves: &mut Vec<Move>,
) -> Result<bool, GcodeError> {
    let (lx, ln) = (ctx.lx, ctx.ln);
    let code = "G6.2";
    let extra = check_words(lx, ln, code, st.plane, "PQRK", true)?;
    let pair = plane_pair(lx, ln, code, st.plane)?;
    if pair.is_none() {
        if let Some(w) = lx.word(AXES[st.plane.axes().2]) {
            let (a, b, _) = st.plane.axes();
            let e = SplineError::AxisPair {
                code,
                first: AXES[a],
                second: AXES[b],
            };
            return Err(spline_err(ln, w.column, e));
        }
    }
    let (p, q, r, k) = (lx.word('P'), lx.word('Q'), lx.word('R'), lx.word('K'));
    let col = ctx.code.map_or(1, |c| c.1.column);
    let missing =
        |letter, column| spline_err(ln, column, SplineError::MissingWord { code, letter });
    let mut block = match st.spline.open.take() {
        Some(b) => b,
        None => {
            let p = p.ok_or_else(|| missing('P', col))?;
            let order = int_word(p, ln, 2, MAX_ORDER)?;
            if pair.is_none() {
                let (a, b, _) = st.plane.axes();
                let e = SplineError::AxisPair {
                    code,
                    first: AXES[a],
                    second: AXES[b],
                };
                return Err(spline_err(ln, col, e));
            }
            new_block(st, true, ln, col, order)
        }
    };
    if let Some(p) = p {
        int_word(p, ln, block.order, block.order)?;
    }
    if let Some(q) = q {
        let r = q.value.round();
        if (q.value - r).abs() > NEAR_INT || !(1.0..=3.0).contains(&r) {
            return Err(spline_err(ln, q.column, SplineError::BadMethod(q.value)));
        }
    }
    let is_entry = pair.is_some()
        || k.is_some()
        || ctx.code.is_some()
        || p.is_some()
        || q.is_some()
        || r.is_some();
    if !is_entry {
        // F, M, comments inside the block.
        block.pin = block.pin.or(line_pin(ctx, extra));
        st.spline.open = Some(block);
        return Ok(false);
    }
    let k = k.ok_or_else(|| missing('K', lx.words.first().map_or(1, |w| w.column)))?;
    let knot = finite(k.value, ln, k)?;
    if let Some(&prev) = block.knots.last() {
        if knot < prev {
            let e = SplineError::KnotsDecreasing {
                previous: prev,
                knot,
            };
            return Err(spline_err(ln, k.column, e));
        }
    }
    if pair.is_some() {
        if block.knot_only > 0 {
            return Err(spline_err(
                ln,
                lx.words[0].column,
                SplineError::KnotVector("a control point after a knot-only line"),
            ));
        }
        let r = r.ok_or_else(|| missing('R', k.column))?;
        let w = weight(r, ln)?;
        let mut c = block.start.to_array();
        let mut words: [Option<String>; 3] = [None, None, None];
        for a in 0..3 {
            if let Some(wd) = lx.word(AXES[a]) {
                c[a] = coord(st, wd, a, block.start, ln)?.1;
                words[a] = Some(wd.text.to_string());
            }
        }
        block.pts.push(Vec3::from_array(c));
        block.weights.push(w);
        block.last_words = words;
    } else {
        block.knot_only += 1;
    }
    block.knots.push(knot);
    block.pin = block.pin.or(line_pin(ctx, extra));
    // LinuxCNC ends the block when the last `order` knots are equal.
    let (n, o) = (block.knots.len(), block.order);
    if n > o && block.knots[n - 1] == block.knots[n - o] {
        return run_g6_2(block, ctx, k, st, moves);
    }
    st.spline.open = Some(block);
    Ok(false)
}

/// Checks a complete G6.2 knot vector and makes its moves.
fn run_g6_2(
    block: Block,
    ctx: &LineCtx,
    k: &Word,
    st: &mut State,
    moves: &mut Vec<Move>,
) -> Result<bool, GcodeError> {
    let ln = ctx.ln;
    let o = block.order;
    let kv = |m: &'static str| spline_err(ln, k.column, SplineError::KnotVector(m));
    if block.knot_only != o {
        return Err(kv(
            "P equal knots in a row close the block: they must be the P knot-only lines at its end",
        ));
    }
    if block.pts.len() < o {
        let e = SplineError::TooFewPoints {
            points: block.pts.len(),
            order: o,
        };
        return Err(spline_err(ln, k.column, e));
    }
    if block.knots[..o].iter().any(|&x| x != block.knots[0]) {
        return Err(kv("the first knot must be given P times (clamped start)"));
    }
    let weights = if block.weights.iter().all(|&w| w == block.weights[0]) {
        None
    } else {
        Some(block.weights.clone())
    };
    let nurbs = Nurbs::new(o - 1, block.knots.clone(), block.pts.clone(), weights).map_err(
        |e| match e {
            NurbsError::EmptyDomain => kv("the knots span no parameter range"),
            NurbsError::NotFinite => err(ln, k.column, ErrorKind::NumberOutOfRange('X')),
            _ => kv("inconsistent"),
        },
    )?;
    let mut cs = Vec::with_capacity(2);
    if nurbs.points[0] != block.start {
        cs.push(Curve::Line(Line::new(block.start, nurbs.points[0])));
    }
    let end = nurbs.points[nurbs.points.len() - 1];
    cs.push(Curve::from(nurbs));
    let pin = block
        .pin
        .or(line_pin(ctx, false))
        .or(state_pin(st, block.start_known));
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
