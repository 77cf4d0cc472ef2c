//! G5 (cubic) and G5.1 (quadratic): one line, one curve; I J (or the
//! previous G5's tangent) and P Q mapped to the plane's axes as LinuxCNC
//! master maps them.

use super::curves::{curves, emit};
use super::words::{check_words, coord, line_pin, state_pin};
use super::{spline_err, LineCtx};
use crate::axes::AXIS_LETTERS as AXES;
use crate::error::{ErrorKind, GcodeError, SplineError};
use crate::interp::{err, State};
use crate::program::Move;
use fairpath::controller::Plane;
use fairpath::geom::Vec3;

/// G5 (cubic, `quad` false) or G5.1 (quadratic): one line, one curve.
pub(super) fn g5(
    ctx: &LineCtx,
    st: &mut State,
    moves: &mut Vec<Move>,
    quad: bool,
) -> Result<bool, GcodeError> {
    let (lx, ln) = (ctx.lx, ctx.ln);
    let code = if quad { "G5.1" } else { "G5" };
    let col = ctx
        .code
        .map_or_else(|| lx.words.first().map_or(1, |w| w.column), |c| c.1.column);
    if st.comp {
        return Err(spline_err(ln, col, SplineError::CutterComp));
    }
    let extra = check_words(
        lx,
        ln,
        code,
        st.plane,
        if quad { "IJ" } else { "IJPQ" },
        false,
    )?;
    let plane = st.plane;
    let (a1, a2, _) = plane.axes();
    if lx.word(AXES[a1]).is_none() && lx.word(AXES[a2]).is_none() {
        let e = SplineError::MissingWord {
            code,
            letter: AXES[a1],
        };
        return Err(spline_err(ln, col, e));
    }
    let mm = st.units.mm_per_unit();
    let start = st.pos;
    let s = [start.x / mm, start.y / mm, start.z / mm];
    // The end, program units and mm (find_ends: omitted axes stay).
    let mut e_prog = s;
    let mut end = start.to_array();
    let mut words: [Option<String>; 3] = [None, None, None];
    for a in [a1, a2] {
        if let Some(w) = lx.word(AXES[a]) {
            (e_prog[a], end[a]) = coord(st, w, a, start, ln)?;
            words[a] = Some(w.text.to_string());
        }
    }
    let end = Vec3::from_array(end);
    let missing = |letter| spline_err(ln, col, SplineError::MissingWord { code, letter });
    let ij = match (lx.word('I'), lx.word('J')) {
        (Some(i), Some(j)) => [i.value, j.value],
        (None, None) if !quad => st
            .spline
            .g5_tangent
            .ok_or_else(|| spline_err(ln, col, SplineError::NoPreviousG5))?,
        (None, _) => return Err(missing('I')),
        (Some(_), None) => return Err(missing('J')),
    };
    // LinuxCNC master's mapping: I, J to the plane's (X|Y, Y|Z, X Z) in
    // G17, G19, G18; P, Q to its (first, second) in-plane axes.
    let p1 = match plane {
        Plane::Xy => [s[0] + ij[0], s[1] + ij[1]],
        Plane::Yz => [s[1] + ij[0], s[2] + ij[1]],
        Plane::Zx => [s[2] + ij[1], s[0] + ij[0]],
    };
    let e_in = plane.to_plane(Vec3::from_array(e_prog));
    let mut prog = vec![plane.to_plane(Vec3::from_array(s)), p1];
    let mut tangent = None;
    if !quad {
        let (p, q) = match (lx.word('P'), lx.word('Q')) {
            (Some(p), Some(q)) => (p.value, q.value),
            (None, _) => return Err(missing('P')),
            (_, None) => return Err(missing('Q')),
        };
        prog.push([e_in[0] + p, e_in[1] + q]);
        tangent = Some([-p, -q]);
    }
    prog.push(e_in);
    if prog.iter().flatten().any(|c| !c.is_finite()) {
        return Err(err(ln, col, ErrorKind::NumberOutOfRange('I')));
    }
    let off = plane.off_plane(start);
    let pts: Vec<Vec3> = prog
        .iter()
        .enumerate()
        .map(|(i, p)| match i {
            0 => start,
            _ if i + 1 == prog.len() => end,
            _ => plane.from_plane([p[0] * mm, p[1] * mm], off),
        })
        .collect();
    let weights = vec![1.0; prog.len()];
    let curves = curves(st, &prog, &pts, &weights, prog.len(), ln, col)?;
    let pin = line_pin(ctx, extra).or(state_pin(st, st.known.iter().all(|&k| k)));
    st.spline.g5_tangent = tangent;
    Ok(emit(st, moves, curves, ln, ln, pin, end, words))
}
