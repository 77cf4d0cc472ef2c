//! Block delete (`/` lines) read with the switch off: what the lines after
//! a `/` line depend on, so that the moves whose meaning differs with the
//! switch on are pinned and the written program runs as the original with
//! the switch either way.
//!
//! With the switch off the `/` line runs; with it on (LinuxCNC skips the
//! line) the machine is elsewhere afterwards, or in another modal state.
//! The rules (applied by [`crate::interp`]):
//! * a `/` line that moves taints the axes whose position it changed: a
//!   later move that starts with a tainted axis is pinned
//!   ([`PinReason::AfterBlockDelete`](crate::PinReason::AfterBlockDelete))
//!   in G90; an absolute word for an axis clears its taint. In G91 the
//!   increments do not depend on the start and the writer writes G91 runs
//!   as increments, so only arcs with absolute centres (G90.1) are pinned;
//! * a `/` line that changes the feed taints the feed: every later feed
//!   move is pinned until a line outside block delete sets F;
//! * a `/` line that changes the motion mode taints it: every later line
//!   moving in the modal motion mode is pinned until a motion G word, and
//!   all axes are tainted after such a line (its end point may differ);
//! * a `/` line that changes any other modal state the path or the writer
//!   depends on (units, distance modes, plane, feed mode, cutter
//!   compensation, tool length offset, coordinate system, path control,
//!   canned-cycle retract mode) or holds a group-0 code (G10, G28, G30,
//!   G52, G53, G92 ...; not G4) taints everything: every later move is
//!   pinned, to the end of the program. This is the safe rule: the written
//!   program is then the original from there on;
//! * a `/` line with any motion makes later canned cycles depend on it
//!   (their initial level): after a cycle line the axes are tainted.

use crate::axes::axis;
use crate::interp::FeedMode;
use crate::program::{MotionMode, Units};
use fairpath::controller::Plane;
use fairpath::geom::Vec3;

/// What later lines depend on.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Dependence {
    /// Axes whose position depends on a `/` line.
    pub axes: [bool; 3],
    /// The modal feed was last set on a `/` line.
    pub feed: bool,
    /// The modal motion mode was last set on a `/` line.
    pub motion: bool,
    /// A `/` line ran a motion: canned cycles' initial level depends on it.
    pub cycles: bool,
    /// A `/` line changed other modal state: every later move is pinned.
    pub state: bool,
}

impl Dependence {
    /// Nothing depends on a `/` line.
    pub fn is_clear(&self) -> bool {
        *self == Dependence::default()
    }
}

/// The part of the modal state a `/` line can change, compared before and
/// after it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Snapshot {
    pub pos: Vec3,
    pub known: [bool; 3],
    pub feed: Option<f64>,
    pub motion: MotionMode,
    /// Everything else that makes [`Dependence::state`] when it changes.
    pub modal: Modal,
}

/// Modal settings a `/` line must not change without pinning the rest of
/// the program.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Modal {
    pub units: Units,
    pub incremental: bool,
    pub arc_incremental: bool,
    pub plane: Plane,
    pub feed_mode: FeedMode,
    pub comp: bool,
    pub tool_length: bool,
    pub coord: u16,
    pub path_control: Option<String>,
    pub retract_to_r: bool,
}

impl Dependence {
    /// Records what the `/` line that took the state from `before` to
    /// `after` changed. `group0` is whether it held a group-0 code other
    /// than G4, `moved` whether it ran any motion.
    pub fn after_deleted_line(
        &mut self,
        before: &Snapshot,
        after: &Snapshot,
        group0: bool,
        moved: bool,
    ) {
        for a in 0..3 {
            if axis(before.pos, a) != axis(after.pos, a) || before.known[a] != after.known[a] {
                self.axes[a] = true;
            }
        }
        self.feed |= before.feed != after.feed;
        self.motion |= before.motion != after.motion;
        self.cycles |= moved;
        self.state |= group0 || before.modal != after.modal;
    }
}
