//! The modal state of the interpreter.

use crate::block_delete::{Dependence, Modal, Snapshot};
use crate::cycles::CycleState;
use crate::program::{Feed, MotionMode, MoveKind, Passthrough, Units};
use crate::spline::{ParseOptions, SplineState};
use fairpath::controller::Plane;
use fairpath::geom::Vec3;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FeedMode {
    InverseTime,
    PerMinute,
    PerRev,
}

/// The modal state of the interpreter.
#[derive(Clone)]
pub(crate) struct State {
    /// Current position, mm, program coordinates.
    pub(crate) pos: Vec3,
    /// Whether each axis of `pos` is known (see the crate docs).
    pub(crate) known: [bool; 3],
    /// Text of the absolute coordinate last written for each axis.
    pub(crate) axis_text: [Option<crate::short_text::ShortText>; 3],
    pub(crate) units: Units,
    pub(crate) incremental: bool,
    pub(super) arc_incremental: bool,
    pub(crate) plane: Plane,
    pub(crate) motion: MotionMode,
    pub(crate) feed: Option<Feed>,
    pub(crate) feed_mode: FeedMode,
    pub(crate) comp: bool,
    pub(super) tlo: bool,
    /// Canned cycle settings and the spindle direction they check.
    pub(crate) cycle: CycleState,
    /// Skip `/` lines (the block-delete switch on).
    pub(super) skip_block_delete: bool,
    /// What later lines depend on of `/` lines (switch off).
    pub(super) after_delete: Dependence,
    /// Lines passed through, and the last line holding a move that was
    /// not passed through (ranges of passed-through lines merge across
    /// lines without such moves).
    pub(super) passthrough: Vec<Passthrough>,
    pub(super) last_plain_move_line: usize,
    pub(super) coord: u16,
    pub(super) path: u16,
    /// The words of the path-control command in force (`G64 P0.01 Q0`),
    /// if the program set one.
    pub(super) path_words: Option<String>,
    pub(super) spindle_mode: u16,
    pub(super) ended: bool,
    pub(super) percent_lines: usize,
    /// Spline blocks being read, and how splines are read.
    pub(crate) spline: SplineState,
}

impl State {
    pub(super) fn new(opts: &ParseOptions) -> State {
        State {
            pos: Vec3::ZERO,
            known: [true; 3],
            axis_text: [None, None, None],
            units: Units::Mm,
            incremental: false,
            arc_incremental: true,
            plane: Plane::Xy,
            motion: MotionMode::None,
            feed: None,
            feed_mode: FeedMode::PerMinute,
            comp: false,
            tlo: false,
            coord: 540,
            path: 640,
            path_words: None,
            spindle_mode: 970,
            ended: false,
            percent_lines: 0,
            spline: SplineState::new(opts.splines),
            cycle: CycleState::new(),
            skip_block_delete: opts.block_delete,
            after_delete: Dependence::default(),
            passthrough: Vec::new(),
            last_plain_move_line: 0,
        }
    }

    /// What a `/` line may change ([`crate::block_delete`]).
    pub(super) fn snapshot(&self) -> Snapshot {
        Snapshot {
            pos: self.pos,
            known: self.known,
            feed: self.feed.as_ref().map(|f| f.mm_per_min),
            motion: self.motion,
            modal: Modal {
                units: self.units,
                incremental: self.incremental,
                arc_incremental: self.arc_incremental,
                plane: self.plane,
                feed_mode: self.feed_mode,
                comp: self.comp,
                tool_length: self.tlo,
                coord: self.coord,
                path_control: self.path_words.clone(),
                retract_to_r: self.cycle.retract_to_r,
            },
        }
    }

    /// Records that line `ln` is passed through because of `what`.
    pub(super) fn note_passthrough(&mut self, ln: usize, what: &'static str) {
        if let Some(last) = self.passthrough.last_mut() {
            if last.what == what && *last.lines.end() >= self.last_plain_move_line {
                last.lines = *last.lines.start()..=ln;
                return;
            }
        }
        self.passthrough.push(Passthrough {
            lines: ln..=ln,
            what,
        });
    }
    /// A `%` line: the second one ends the program.
    pub(super) fn percent_line(&mut self) {
        self.percent_lines += 1;
        if self.percent_lines >= 2 {
            self.ended = true;
        }
    }

    /// Whether a move of `kind` on a line outside block delete depends on an
    /// earlier `/` line ([`crate::block_delete`]): `modal_motion` is whether
    /// the line moves in the modal motion mode.
    pub(super) fn depends_on_deleted_line(&self, kind: MoveKind, modal_motion: bool) -> bool {
        let dep = &self.after_delete;
        let start = dep.axes.iter().any(|&a| a)
            && (!self.incremental || (kind == MoveKind::Arc && !self.arc_incremental));
        dep.state || (dep.feed && kind != MoveKind::Rapid) || (dep.motion && modal_motion) || start
    }

    pub(super) fn forget(&mut self, axes: [bool; 3]) {
        for a in 0..3 {
            if axes[a] {
                self.known[a] = false;
                self.axis_text[a] = None;
            }
        }
    }
}
