//! The parameter store: numbered parameters, named local and global
//! parameters, and the system parameters the reader can know, as LinuxCNC
//! keeps them (`interp_namedparams.cc`, `interp_o_word.cc`).
//!
//! * Numbered parameters `#1` .. `#5000` are the program's: unset ones read
//!   0. `#1` .. `#30` are a subroutine's arguments: a call saves them, sets
//!   them from its arguments (0 for those not given) and restores them on
//!   return; the others are global.
//! * `#5420` .. `#5422` (and `#<_x>`, `#<_y>`, `#<_z>`) are the current
//!   position in program coordinates and units. The other system parameters
//!   (`#5001` and up: probe results, G28/G30 homes, work offsets, tool
//!   table, the A..W position) live in the machine's parameter file, which
//!   a reader of program coordinates does not know: reading or setting them
//!   is an unsupported-feature error naming the parameter.
//! * Named parameters: `#<_name>` is global; any other name is local to the
//!   subroutine call (the main program is level 0, its own scope). Reading
//!   a name never set is an error, as in LinuxCNC. Predefined read-only
//!   names give the modal state ([`SystemView`]); those of the machine
//!   (`#<_current_tool>`, `#<_rpm>`, ...) are unsupported-feature errors.

use super::error::LangError;
use crate::error::{ErrorKind, GcodeError};
use std::collections::HashMap;

/// LinuxCNC's `RS274NGC_MAX_PARAMETERS`: parameter numbers run from 1 to
/// this minus one.
pub const MAX_PARAMETERS: usize = 5602;
/// Highest numbered parameter that belongs to the program (LinuxCNC's
/// user parameters end at 5000; the system's start at 5001).
pub const USER_PARAMETERS: usize = 5000;
/// Parameters `#1` .. `#30` are a subroutine's arguments
/// (`INTERP_SUB_PARAMS`).
pub const SUB_PARAMS: usize = 30;
/// First parameter of the current position (`#5420` = X .. `#5428` = W).
pub const POSITION_PARAMETER: usize = 5420;

/// What the interpreter knows of its state, for system parameters: a small
/// read-only view built before each line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SystemView {
    /// Current X, Y, Z in program units, `None` when not known (after a
    /// coordinate-system change, G28, ...).
    pub position: [Option<f64>; 3],
    /// Millimetres per program unit (1 or 25.4).
    pub mm_per_unit: f64,
    pub incremental: bool,
    /// Plane as LinuxCNC's `_plane`: 170, 180 or 190.
    pub plane: u16,
    /// Motion mode as LinuxCNC's `_motion_mode`: the G code times 10 (0,
    /// 10, 20, 30, ...; 800 for none).
    pub motion: u16,
    /// Feed rate in program units per minute (0 when none set).
    pub feed: f64,
    /// 930, 940 or 950.
    pub feed_mode: u16,
    pub cutter_comp: bool,
    /// G90.1 in force.
    pub arc_absolute: bool,
    /// 540 .. 593.
    pub coord_system: u16,
    /// 960 (constant surface speed) or 970 (rpm).
    pub spindle_mode: u16,
    /// Source line being read (`#<_line>`).
    pub line: usize,
}

impl Default for SystemView {
    /// The state at program start: origin, mm, G90, G17, no motion mode.
    fn default() -> SystemView {
        SystemView {
            position: [Some(0.0); 3],
            mm_per_unit: 1.0,
            incremental: false,
            plane: 170,
            motion: 800,
            feed: 0.0,
            feed_mode: 940,
            cutter_comp: false,
            arc_absolute: false,
            coord_system: 540,
            spindle_mode: 970,
            line: 0,
        }
    }
}

/// Named parameters LinuxCNC predefines from the machine's state, which the
/// reader cannot know.
const MACHINE_NAMES: &[&str] = &[
    "_vmajor",
    "_vminor",
    "_metric_machine",
    "_tool_offset",
    "_retract_r_plane",
    "_retract_old_z",
    "_lathe_diameter_mode",
    "_lathe_radius_mode",
    "_spindle_on",
    "_spindle_cw",
    "_mist",
    "_flood",
    "_speed_override",
    "_feed_override",
    "_adaptive_feed",
    "_feed_hold",
    "_rpm",
    "_current_tool",
    "_current_pocket",
    "_selected_pocket",
    "_selected_tool",
    "_a",
    "_b",
    "_c",
    "_u",
    "_v",
    "_w",
    "_abs_x",
    "_abs_y",
    "_abs_z",
    "_abs_a",
    "_abs_b",
    "_abs_c",
    "_abs_u",
    "_abs_v",
    "_abs_w",
    "_task",
    "_remap_level",
];

const MACHINE_WHY: &str = "a value of the machine, not of the program (fairpath reads program coordinates and does not know the machine's state or parameter file)";

/// The program's parameters.
#[derive(Clone, Debug)]
pub struct Params {
    numbered: Vec<f64>,
    globals: HashMap<String, f64>,
    /// Local named parameters per call level (0 = main program).
    locals: Vec<HashMap<String, f64>>,
    /// `#1` .. `#30` of each caller, saved by a call.
    saved: Vec<[f64; SUB_PARAMS]>,
    value: f64,
    value_returned: bool,
    /// Changes so far: every call and return, and every assignment that
    /// changed a value (its bits; one that wrote the value the parameter
    /// held does not count): a loop whose pass changed nothing left the
    /// parameters as they were ([`Params::changes`]).
    changes: u64,
    /// Reads of the interpreter's state so far (the position, the modes,
    /// the line: [`Params::view_reads`]); a cell, since expressions read
    /// through a shared [`Scope`].
    view_reads: core::cell::Cell<u64>,
}

impl Default for Params {
    fn default() -> Params {
        Params::new()
    }
}

impl Params {
    pub fn new() -> Params {
        Params {
            numbered: vec![0.0; USER_PARAMETERS + 1],
            globals: HashMap::new(),
            locals: vec![HashMap::new()],
            saved: Vec::new(),
            value: 0.0,
            value_returned: false,
            changes: 0,
            view_reads: core::cell::Cell::new(0),
        }
    }

    /// Subroutine call depth (0 in the main program).
    pub fn call_level(&self) -> usize {
        self.locals.len() - 1
    }

    /// How many changes (calls, returns, assignments of another value)
    /// were made so far: where two readings are equal, every parameter
    /// holds what it held at the first (a pass that sets a counter to the
    /// value it had, `#1 = [#11]` with `#11` unset, changes nothing).
    pub fn changes(&self) -> u64 {
        self.changes
    }

    /// How many times an expression read the interpreter's state (the
    /// position, the modes, the line number: a [`SystemView`] value) so
    /// far: where two readings are equal, what ran between them read
    /// parameters only.
    pub fn view_reads(&self) -> u64 {
        self.view_reads.get()
    }

    fn note_view_read(&self) {
        self.view_reads.set(self.view_reads.get() + 1);
    }

    /// Enters a subroutine: saves `#1..#30`, sets them from `args` (0 for
    /// those not given), opens a new scope of local names.
    pub fn enter_call(&mut self, args: &[f64]) {
        self.changes += 1;
        let mut save = [0.0; SUB_PARAMS];
        save.copy_from_slice(&self.numbered[1..=SUB_PARAMS]);
        self.saved.push(save);
        for k in 0..SUB_PARAMS {
            self.numbered[k + 1] = args.get(k).copied().unwrap_or(0.0);
        }
        self.locals.push(HashMap::new());
    }

    /// Leaves a subroutine: restores `#1..#30`, drops its local names.
    pub fn leave_call(&mut self) {
        self.changes += 1;
        if let Some(save) = self.saved.pop() {
            self.numbered[1..=SUB_PARAMS].copy_from_slice(&save);
            self.locals.pop();
        }
    }

    /// Sets `#<_value>` and `#<_value_returned>` on `return`/`endsub`.
    pub fn set_return(&mut self, value: Option<f64>) {
        self.changes += 1;
        self.value = value.unwrap_or(0.0);
        self.value_returned = value.is_some();
    }

    /// Sets numbered parameter `n`.
    pub fn set_numbered(
        &mut self,
        n: i64,
        v: f64,
        ln: usize,
        col: usize,
    ) -> Result<(), GcodeError> {
        let fail = |e| GcodeError::new(ln, col, ErrorKind::Language(e));
        if n < 1 || n >= MAX_PARAMETERS as i64 {
            return Err(fail(LangError::ParameterRange(n as f64)));
        }
        let n = n as usize;
        if n > USER_PARAMETERS {
            return Err(fail(LangError::UnsupportedAssignment {
                name: format!("#{n}"),
                why: "a system parameter of the machine (fairpath reads program coordinates and does not know the machine's parameter file)",
            }));
        }
        self.count_change(Some(self.numbered[n]), v);
        self.numbered[n] = v;
        Ok(())
    }

    /// Sets named parameter `name` (global when it starts with `_`).
    pub fn set_named(
        &mut self,
        name: &str,
        v: f64,
        ln: usize,
        col: usize,
    ) -> Result<(), GcodeError> {
        if is_predefined(name) {
            return Err(GcodeError::new(
                ln,
                col,
                ErrorKind::Language(LangError::ReadOnly(format!("#<{name}>"))),
            ));
        }
        let old = if name.starts_with('_') {
            self.globals.insert(name.to_string(), v)
        } else if let Some(l) = self.locals.last_mut() {
            l.insert(name.to_string(), v)
        } else {
            None
        };
        self.count_change(old, v);
        Ok(())
    }

    /// Counts an assignment of `v` to a parameter that held `old` (`None`:
    /// did not exist) where it changes the value's bits ([`Params::changes`]).
    fn count_change(&mut self, old: Option<f64>, v: f64) {
        if old.is_none_or(|o| o.to_bits() != v.to_bits()) {
            self.changes += 1;
        }
    }

    fn user_named(&self, name: &str) -> Option<f64> {
        if name.starts_with('_') {
            self.globals.get(name).copied()
        } else {
            self.locals.last().and_then(|l| l.get(name).copied())
        }
    }
}

fn is_predefined(name: &str) -> bool {
    matches!(
        name,
        "_x" | "_y"
            | "_z"
            | "_metric"
            | "_imperial"
            | "_absolute"
            | "_incremental"
            | "_feed"
            | "_motion_mode"
            | "_plane"
            | "_value"
            | "_value_returned"
            | "_call_level"
            | "_line"
            | "_ccomp"
            | "_inverse_time"
            | "_units_per_minute"
            | "_units_per_rev"
            | "_coord_system"
            | "_spindle_rpm_mode"
            | "_spindle_css_mode"
            | "_ijk_absolute_mode"
    ) || MACHINE_NAMES.contains(&name)
        || name.starts_with("_ini[")
        || name.starts_with("_hal[")
}

/// What an expression reads: the parameters, the interpreter's state, and
/// the named parameters an assignment earlier on the same line created
/// (LinuxCNC creates them, with value 0, while reading the line).
pub struct Scope<'a> {
    pub params: &'a Params,
    pub view: &'a SystemView,
    pub created: &'a [String],
}

impl Scope<'_> {
    fn position(
        &self,
        axis: usize,
        name: String,
        ln: usize,
        col: usize,
    ) -> Result<f64, GcodeError> {
        let fail = |why| {
            GcodeError::new(
                ln,
                col,
                ErrorKind::Language(LangError::UnknownParameter {
                    name: name.clone(),
                    why,
                }),
            )
        };
        self.params.note_view_read();
        if self.view.cutter_comp {
            return Err(fail("the position cannot be read with cutter radius compensation on (LinuxCNC refuses it too)"));
        }
        self.view.position[axis].ok_or_else(|| {
            fail("the position is not known here (after a change of coordinate system, offsets, G28/G30 or probing, which fairpath does not follow)")
        })
    }

    /// Numbered parameter `n`.
    pub fn numbered(&self, n: i64, ln: usize, col: usize) -> Result<f64, GcodeError> {
        let fail = |e| GcodeError::new(ln, col, ErrorKind::Language(e));
        if n < 1 || n >= MAX_PARAMETERS as i64 {
            return Err(fail(LangError::ParameterRange(n as f64)));
        }
        let n = n as usize;
        if n <= USER_PARAMETERS {
            return Ok(self.params.numbered[n]);
        }
        if (POSITION_PARAMETER..POSITION_PARAMETER + 3).contains(&n) {
            return self.position(n - POSITION_PARAMETER, format!("#{n}"), ln, col);
        }
        let why = match n {
            5061..=5070 => "a probe result, known only to the machine",
            5161..=5189 => "a G28/G30 home position from the machine's parameter file",
            5210..=5390 => "a work offset (G92, G54..G59.3) from the machine's parameter file",
            5400..=5413 => "a value of the machine's tool table",
            5423..=5428 => "the position of an axis other than X, Y, Z, which fairpath does not track",
            _ => "a system parameter of the machine (fairpath reads program coordinates and does not know the machine's parameter file)",
        };
        Err(fail(LangError::UnknownParameter {
            name: format!("#{n}"),
            why,
        }))
    }

    /// Named parameter `name`.
    pub fn named(&self, name: &str, ln: usize, col: usize) -> Result<f64, GcodeError> {
        let v = self.view;
        if is_predefined(name) && !matches!(name, "_value" | "_value_returned" | "_call_level") {
            self.params.note_view_read();
        }
        let truth = |t: bool| if t { 1.0 } else { 0.0 };
        let axis = |a: usize| self.position(a, format!("#<{name}>"), ln, col);
        Ok(match name {
            "_x" => axis(0)?,
            "_y" => axis(1)?,
            "_z" => axis(2)?,
            "_metric" => truth(v.mm_per_unit == 1.0),
            "_imperial" => truth(v.mm_per_unit != 1.0),
            "_absolute" => truth(!v.incremental),
            "_incremental" => truth(v.incremental),
            "_feed" => v.feed,
            "_motion_mode" => f64::from(v.motion),
            "_plane" => f64::from(v.plane),
            "_value" => self.params.value,
            "_value_returned" => truth(self.params.value_returned),
            "_call_level" => self.params.call_level() as f64,
            "_line" => v.line as f64,
            "_ccomp" if !v.cutter_comp => 400.0,
            "_inverse_time" => truth(v.feed_mode == 930),
            "_units_per_minute" => truth(v.feed_mode == 940),
            "_units_per_rev" => truth(v.feed_mode == 950),
            "_coord_system" => f64::from(v.coord_system),
            "_spindle_rpm_mode" => truth(v.spindle_mode == 970),
            "_spindle_css_mode" => truth(v.spindle_mode == 960),
            "_ijk_absolute_mode" => truth(v.arc_absolute),
            _ if name == "_ccomp"
                || MACHINE_NAMES.contains(&name)
                || name.starts_with("_ini[")
                || name.starts_with("_hal[") =>
            {
                return Err(GcodeError::new(
                    ln,
                    col,
                    ErrorKind::Language(LangError::UnknownParameter {
                        name: format!("#<{name}>"),
                        why: if name == "_ccomp" {
                            "the side of cutter compensation is not tracked"
                        } else {
                            MACHINE_WHY
                        },
                    }),
                ))
            }
            _ => match self.params.user_named(name) {
                Some(x) => x,
                None if self.created.iter().any(|c| c == name) => 0.0,
                None => {
                    return Err(GcodeError::new(
                        ln,
                        col,
                        ErrorKind::Language(LangError::UndefinedNamed(name.to_string())),
                    ))
                }
            },
        })
    }

    /// `EXISTS[#<name>]`.
    pub fn exists(&self, name: &str) -> bool {
        is_predefined(name)
            || self.params.user_named(name).is_some()
            || self.created.iter().any(|c| c == name)
    }
}
