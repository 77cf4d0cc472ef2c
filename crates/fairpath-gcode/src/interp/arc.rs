//! G2/G3 arcs: the centre (IJK) and radius (R) forms as LinuxCNC reads
//! them, helices and several turns (P).

use super::{err, finite, State};
use crate::axes::{axis, set_axis, AXIS_LETTERS, CENTER_LETTERS};
use crate::error::{ErrorKind, GcodeError};
use crate::lexer::{LexedLine, Word};
use crate::program::Units;
use fairpath::geom::{Arc, ArcError, Vec3};

/// Distance (mm) below which an arc's start and end coincide in the plane
/// (a full circle) or a point coincides with the centre: below G-code
/// resolution (1e-4 mm or 1e-5 in are the finest programs write).
pub const COINCIDENT_MM: f64 = 1e-7;

/// Largest difference between an IJK arc's start and end radius accepted
/// (a spiral arc within it is kept as a spiral, like LinuxCNC does); larger
/// is an error. LinuxCNC's defaults: 0.0005 in for inch programs, 0.01 mm for
/// mm programs (absolute, in program units). The same tolerance bounds how
/// much an R-form arc's radius may fall short of half the chord.
pub const ARC_RADIUS_TOLERANCE_INCH: f64 = 0.0005;
/// See [`ARC_RADIUS_TOLERANCE_INCH`].
pub const ARC_RADIUS_TOLERANCE_MM: f64 = 0.01;

/// Builds a G2/G3 arc from the current state.
pub(super) fn build_arc(
    lx: &LexedLine,
    ln: usize,
    st: &State,
    start: Vec3,
    end: Vec3,
    clockwise: bool,
    first_axis_col: usize,
) -> Result<Arc, GcodeError> {
    let (a1, a2, an) = st.plane.axes();
    let (l1, l2, loff) = (CENTER_LETTERS[a1], CENTER_LETTERS[a2], CENTER_LETTERS[an]);
    let mm = st.units.mm_per_unit();
    let tol = match st.units {
        Units::Inch => ARC_RADIUS_TOLERANCE_INCH,
        Units::Mm => ARC_RADIUS_TOLERANCE_MM,
    };
    let has_axis = lx.words.iter().any(|w| AXIS_LETTERS.contains(&w.letter));
    let has_center = CENTER_LETTERS.iter().any(|&l| lx.word(l).is_some());
    if !has_axis && (!has_center || lx.word('R').is_some()) {
        return Err(err(ln, first_axis_col, ErrorKind::ArcWithoutAxes));
    }
    let r_word = lx.word('R');
    let c1 = lx.word(l1);
    let c2 = lx.word(l2);
    if let Some(w) = lx.word(loff) {
        if w.value != 0.0 {
            return Err(err(ln, w.column, ErrorKind::ArcOffPlaneCenter(loff)));
        }
    }
    let turns = match lx.word('P') {
        None => 1,
        Some(w) => {
            if w.value.fract() != 0.0 || w.value < 1.0 || w.value > 1.0e6 {
                return Err(err(ln, w.column, ErrorKind::BadTurns(w.value)));
            }
            w.value as u32
        }
    };
    let (s1, s2) = (axis(start, a1), axis(start, a2));
    let (e1, e2) = (axis(end, a1), axis(end, a2));
    let mut center = start;
    match (r_word, c1.or(c2)) {
        (Some(r), Some(_)) => return Err(err(ln, r.column, ErrorKind::ArcRadiusAndCenter)),
        (None, None) => return Err(err(ln, first_axis_col, ErrorKind::ArcWithoutCenter)),
        (None, Some(_)) => {
            let off = |w: Option<&Word>, s: f64| -> Result<f64, GcodeError> {
                let v = w.map_or(0.0, |w| w.value) * mm;
                let c = if st.arc_incremental { s + v } else { v };
                match w {
                    Some(w) => finite(c, ln, w),
                    None => Ok(c),
                }
            };
            let cc1 = off(c1, s1)?;
            let cc2 = off(c2, s2)?;
            let r0 = (s1 - cc1).hypot(s2 - cc2) / mm;
            let r1 = (e1 - cc1).hypot(e2 - cc2) / mm;
            if (r1 - r0).abs() > tol {
                let w = c1.or(c2).map_or(first_axis_col, |w| w.column);
                return Err(err(
                    ln,
                    w,
                    ErrorKind::ArcRadiusMismatch {
                        r_start: r0,
                        r_end: r1,
                        tolerance: tol,
                    },
                ));
            }
            set_axis(&mut center, a1, cc1);
            set_axis(&mut center, a2, cc2);
        }
        (Some(rw), None) => {
            // LinuxCNC's arc_data_r.
            let radius = rw.value * mm;
            let abs_r = radius.abs();
            let (m1, m2) = (0.5 * (s1 + e1), 0.5 * (s2 + e2));
            let mut half = (m1 - e1).hypot(m2 - e2);
            if half <= COINCIDENT_MM {
                return Err(err(ln, rw.column, ErrorKind::ArcRadiusFullCircle));
            }
            if abs_r <= COINCIDENT_MM || half - abs_r > tol * mm {
                return Err(err(
                    ln,
                    rw.column,
                    ErrorKind::ArcRadiusTooSmall {
                        radius: rw.value.abs(),
                        half_chord: half / mm,
                    },
                ));
            }
            if half > abs_r {
                half = abs_r;
            }
            let chord_dir = (e2 - s2).atan2(e1 - s1);
            let theta = if clockwise == (radius > 0.0) {
                chord_dir - std::f64::consts::FRAC_PI_2
            } else {
                chord_dir + std::f64::consts::FRAC_PI_2
            };
            let offset = (abs_r * abs_r - half * half).max(0.0).sqrt();
            set_axis(&mut center, a1, m1 + offset * theta.cos());
            set_axis(&mut center, a2, m2 + offset * theta.sin());
        }
    }
    let arc = Arc::from_center(
        start,
        end,
        center,
        st.plane.normal(),
        clockwise,
        turns,
        COINCIDENT_MM,
    )
    .map_err(|e| match e {
        ArcError::ZeroRadius => err(ln, first_axis_col, ErrorKind::ArcZeroRadius),
        ArcError::NotFinite => err(ln, first_axis_col, ErrorKind::BadValue('R')),
    })?;
    Ok(arc)
}
