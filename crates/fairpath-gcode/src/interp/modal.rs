//! The state changes of a line, in LinuxCNC's order of execution: M codes
//! (the spindle), the feed mode, F (before units: `G21 F100` in an inch
//! program is 100 in/min), then the modal G codes (plane, units, distance
//! modes, compensation, coordinate system, path control, motion mode).

use super::codes::G;
use super::line::Words;
use super::{err, State};
use crate::cycles::Spindle;
use crate::error::{ErrorKind, GcodeError};
use crate::program::{Feed, MotionMode};

/// What a line's state changes amount to.
pub(super) struct Changes {
    /// The line changes modal state (or holds words that do, or a `/`):
    /// it ends runs and pins its moves.
    pub(super) state: bool,
    /// The line changes the plane, which alone does not end a run.
    pub(super) plane: bool,
    /// The line holds a motion G word (or G5.3).
    pub(super) sets_motion: bool,
}

/// Applies the state changes of line `w` to `st`.
pub(super) fn apply(w: &Words, st: &mut State) -> Result<Changes, GcodeError> {
    let (lx, ln) = (w.lx, w.ln);
    let word = |l: char| lx.word(l);
    let mut changes = lx.block_delete || !w.codes.ms.is_empty();
    for (c, _) in &w.codes.ms {
        match c {
            3 => st.cycle.spindle = Spindle::Clockwise,
            4 => st.cycle.spindle = Spindle::CounterClockwise,
            5 => st.cycle.spindle = Spindle::Stopped,
            _ => {}
        }
    }
    for l in ['S', 'T', 'H', 'D', 'L', 'Q', 'E'] {
        // L and Q are spline words on spline lines.
        if word(l).is_some() && !(w.spline && (l == 'L' || l == 'Q')) {
            changes = true;
        }
    }
    for (g, _) in &w.codes.gs {
        if let G::FeedMode(m) = g {
            changes |= *m != st.feed_mode;
            st.feed_mode = *m;
        }
    }
    if let Some(f) = word('F') {
        if f.value < 0.0 {
            return Err(err(ln, f.column, ErrorKind::BadValue('F')));
        }
        st.feed = Some(Feed {
            mm_per_min: f.value * st.units.mm_per_unit(),
            text: f.text.as_str().into(),
            units: st.units,
        });
    }
    // A plane change alone does not end a run: the plane shapes only arcs
    // (resolved to 3D here) and canned cycles (always pinned), so a `G18`
    // line between two feed moves is written back in place and the joint
    // across it is smoothed like any other (CAM posts emit one before every
    // XZ arc: LinuxCNC's test_12mmflat.ngc kept a 3-degree corner there on
    // every pass). On a move line it pins the move, whose text must stay.
    let mut plane_changed = false;
    let mut sets_motion = false;
    for (g, gw) in &w.codes.gs {
        match *g {
            G::Plane(p) => {
                plane_changed |= p != st.plane;
                st.plane = p;
            }
            G::Units(u) => {
                if u != st.units {
                    changes = true;
                    st.units = u;
                    st.axis_text = [None, None, None];
                }
            }
            G::Incremental(inc) => {
                changes |= inc != st.incremental;
                st.incremental = inc;
            }
            G::ArcIncremental(inc) => {
                changes |= inc != st.arc_incremental;
                st.arc_incremental = inc;
            }
            G::FeedMode(_) => {}
            G::CutterComp(on) => {
                changes |= on || st.comp;
                st.comp = on;
            }
            G::ToolLength(on) => {
                if on || st.tlo {
                    changes = true;
                    st.forget([false, false, true]);
                }
                st.tlo = on;
            }
            G::CoordSystem(c) => {
                if c != st.coord {
                    changes = true;
                    st.forget([true; 3]);
                }
                st.coord = c;
            }
            G::PathControl(c) => {
                changes |= c != st.path || word('P').is_some() || word('Q').is_some();
                st.path = c;
                let mut text = format!("G{}", gw.text);
                if c == 640 {
                    for l in ['P', 'Q'] {
                        if let Some(v) = word(l) {
                            text.push_str(&format!(" {l}{}", v.text));
                        }
                    }
                }
                st.path_words = Some(text);
            }
            G::ReturnMode(to_r) => st.cycle.retract_to_r = to_r,
            G::LatheRadius => {}
            G::SpindleMode(c) => {
                changes |= c != st.spindle_mode;
                st.spindle_mode = c;
            }
            G::Cancel(_) => changes = true,
            G::NonModal(_) => changes = true,
            G::SplineEnd => sets_motion = true,
            G::Motion(m) => {
                sets_motion = true;
                // A spline G word without axes opens or continues a block.
                if !w.has_axes && m != st.motion && !w.spline {
                    changes = true;
                }
            }
        }
    }
    if let Some((m, _)) = w.motion {
        st.motion = m;
    }
    // A line outside block delete that sets F or the motion mode ends
    // their dependence on `/` lines.
    if !lx.block_delete {
        if word('F').is_some() {
            st.after_delete.feed = false;
        }
        if w.motion.is_some() {
            st.after_delete.motion = false;
        }
    }
    // A motion other than a canned cycle makes the next cycle take a new
    // initial level (LinuxCNC's convert_motion).
    match w.runs_motion() {
        Some(MotionMode::Cycle(_)) | None => {}
        Some(_) => st.cycle.other_motion(),
    }
    Ok(Changes {
        state: changes,
        plane: plane_changed,
        sets_motion,
    })
}
