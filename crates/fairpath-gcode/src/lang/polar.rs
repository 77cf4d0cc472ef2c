//! LinuxCNC's polar coordinates: `@` (radius) and `^` (angle, degrees) in
//! the XY plane, turned into X and Y words before the interpreter moves, as
//! LinuxCNC's `find_ends` (`interp_find.cc`) computes them:
//!
//! * G90: `@r ^a` is the point at radius r and angle a from the origin; `@r`
//!   alone keeps the current angle, `^a` alone the current radius (both
//!   need a current point other than the origin for `@` alone).
//! * G91: `@r` moves the current point r further from the origin along its
//!   angle; `^a` turns it by a about the origin (both refused at the
//!   origin).
//!
//! As in LinuxCNC, polar words are refused outside the G17 plane, beside X
//! or Y words, and on lines whose axis words do not move (G10, G28, G30,
//! G52, G53, G92).

use super::error::LangError;
use super::line::Evaluated;
use super::literal;
use super::params::SystemView;
use crate::error::{ErrorKind, GcodeError};
use crate::lexer::Word;

/// Replaces the line's `@`/`^` words by X and Y words (text: round-trip
/// literals, column: the first polar word's) and records the text edit that
/// writes them out. Does nothing on a line without polar words.
pub fn resolve(ev: &mut Evaluated, view: &SystemView, ln: usize) -> Result<(), GcodeError> {
    let words = &ev.lexed.words;
    let r = words.iter().position(|w| w.letter == '@');
    let a = words.iter().position(|w| w.letter == '^');
    let Some(first) = [r, a].into_iter().flatten().min() else {
        return Ok(());
    };
    let col = words[first].column;
    let fail = |msg| GcodeError::new(ln, col, ErrorKind::Language(LangError::Polar(msg)));
    let g_on_line = |codes: &[i64]| {
        words.iter().find_map(|w| {
            let c = (w.value * 10.0).round() as i64;
            (w.letter == 'G' && codes.contains(&c)).then_some(c)
        })
    };
    if words.iter().any(|w| w.letter == 'X' || w.letter == 'Y') {
        return Err(fail("cannot be given with X or Y words"));
    }
    if g_on_line(&[100, 280, 300, 520, 530, 920]).is_some() {
        return Err(fail(
            "only for motion (not with G10, G28, G30, G52, G53, G92)",
        ));
    }
    let plane = g_on_line(&[170, 180, 190]).unwrap_or(i64::from(view.plane));
    if plane != 170 {
        return Err(fail("only in the G17 (XY) plane"));
    }
    let mpu = match g_on_line(&[200, 210]) {
        Some(200) => 25.4,
        Some(_) => 1.0,
        None => view.mm_per_unit,
    };
    let incremental = match g_on_line(&[900, 910]) {
        Some(c) => c == 910,
        None => view.incremental,
    };
    let radius = r.map(|k| words[k].value);
    let angle = a.map(|k| words[k].value);
    let current = || -> Result<(f64, f64), GcodeError> {
        match (view.position[0], view.position[1]) {
            (Some(x), Some(y)) => Ok((x * view.mm_per_unit / mpu, y * view.mm_per_unit / mpu)),
            _ => Err(GcodeError::new(
                ln,
                col,
                ErrorKind::Language(LangError::UnknownParameter {
                    name: "the current X/Y position (for @ or ^)".into(),
                    why: "not known here (after a change of coordinate system, offsets, G28/G30 or probing, which fairpath does not follow)",
                }),
            )),
        }
    };
    let (x, y) = if !incremental {
        match (radius, angle) {
            (Some(r), Some(a)) => (r * a.to_radians().cos(), r * a.to_radians().sin()),
            (Some(r), None) => {
                let (cx, cy) = current()?;
                if cx == 0.0 && cy == 0.0 {
                    return Err(fail("an angle ^ is needed at the origin"));
                }
                let t = cy.atan2(cx);
                (r * t.cos(), r * t.sin())
            }
            (None, Some(a)) => {
                let (cx, cy) = current()?;
                let r = cy.hypot(cx);
                (r * a.to_radians().cos(), r * a.to_radians().sin())
            }
            (None, None) => unreachable!("a polar word was found"),
        }
    } else {
        let (cx, cy) = current()?;
        let (mut px, mut py) = (cx, cy);
        if let Some(r) = radius {
            if px == 0.0 && py == 0.0 {
                return Err(fail("G91 polar motion is indeterminate at the origin"));
            }
            let t = py.atan2(px);
            let rr = py.hypot(px) + r;
            (px, py) = (rr * t.cos(), rr * t.sin());
        }
        if let Some(a) = angle {
            if px == 0.0 && py == 0.0 {
                return Err(fail("G91 polar motion is indeterminate at the origin"));
            }
            let t = py.atan2(px) + a.to_radians();
            let rr = py.hypot(px);
            (px, py) = (rr * t.cos(), rr * t.sin());
        }
        (px - cx, py - cy)
    };
    for (v, letter) in [(x, 'X'), (y, 'Y')] {
        if !v.is_finite() {
            return Err(GcodeError::new(
                ln,
                col,
                ErrorKind::NumberOutOfRange(letter),
            ));
        }
    }
    let (xt, yt) = (literal(x), literal(y));
    // The polar words' text becomes "X.. Y.." at the first one.
    let polar_spans: Vec<_> = [r, a]
        .into_iter()
        .flatten()
        .map(|k| ev.spans[k].clone())
        .collect();
    ev.edits.retain(|(e, _)| {
        !polar_spans
            .iter()
            .any(|s| s.start <= e.start && e.end <= s.end)
    });
    for s in &polar_spans {
        let rep = if s.start == ev.spans[first].start {
            format!("X{xt} Y{yt}")
        } else {
            String::new()
        };
        ev.edits.push((s.clone(), rep));
    }
    ev.edits.sort_by_key(|(e, _)| e.start);
    let span = ev.spans[first].clone();
    let mut k = 0;
    while k < ev.lexed.words.len() {
        if matches!(ev.lexed.words[k].letter, '@' | '^') {
            ev.lexed.words.remove(k);
            ev.spans.remove(k);
        } else {
            k += 1;
        }
    }
    let at = ev
        .spans
        .iter()
        .position(|s| s.start > span.start)
        .unwrap_or(ev.spans.len());
    for (i, (letter, value, text)) in [('X', x, xt), ('Y', y, yt)].into_iter().enumerate() {
        ev.lexed.words.insert(
            at + i,
            Word {
                letter,
                value,
                text: text.into(),
                column: col,
            },
        );
        ev.spans.insert(at + i, span.clone());
    }
    Ok(())
}
