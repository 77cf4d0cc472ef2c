//! The path-control mode (G61, G61.1, G64) the input has in force at each
//! run, and whether the controller's blending under it could exceed the
//! blending share of the tolerance.

use crate::lexer::Word;
use crate::program::{Program, ProgramLine, Units};

/// A path-control command of the input.
#[derive(Clone, Debug, PartialEq)]
pub struct PathControl {
    /// The command's words as the input wrote them (`G64 P0.02 Q0.0`),
    /// without the other words of its line.
    pub text: String,
    /// G64 (blending); false for G61/G61.1 (exact path).
    pub blends: bool,
    /// G64's P in mm (converted with the units in force on its line, as
    /// LinuxCNC's `SET_MOTION_CONTROL_MODE` converts it with
    /// `FROM_PROG_LEN` when the line runs); `None` without P.
    pub p_mm: Option<f64>,
}

impl PathControl {
    /// Whether LinuxCNC's blending under this command may deviate more than
    /// `blend_mm` from the programmed path: a bare `G64` (or one with only
    /// Q) and `G64 P0` blend without a tolerance (a zero tolerance means
    /// none: `tcFindBlendTolerance`, tc.c, then allows a quarter of the
    /// segment), and a P above the share lets it deviate by P.
    pub fn exceeds(&self, blend_mm: f64) -> bool {
        self.blends && self.p_mm.is_none_or(|p| p <= 0.0 || p > blend_mm)
    }
}

/// Whether the line holds a path-control command (G61, G61.1, G64).
pub fn sets_path_control(line: &ProgramLine) -> bool {
    line.interpreted && has_path_control(&line.words)
}

/// Whether `words` (of an interpreted line) hold a path-control command.
pub(crate) fn has_path_control(words: &[Word]) -> bool {
    words
        .iter()
        .any(|w| w.letter == 'G' && matches!((w.value * 10.0).round() as i64, 610 | 611 | 640))
}

impl PathControl {
    /// The command in force after a line that holds one: `text` its words
    /// as the program wrote them ([`ProgramLine::path_control_after`]),
    /// `words` the line's words, `units` those in force on it.
    pub(crate) fn after_line(text: &str, words: &[Word], units: Units) -> PathControl {
        PathControl {
            text: text.to_string(),
            blends: text.starts_with("G64"),
            p_mm: text.starts_with("G64").then_some(()).and_then(|_| {
                words
                    .iter()
                    .find(|w| w.letter == 'P')
                    .map(|w| w.value * units.mm_per_unit())
            }),
        }
    }
}

/// What [`EmitOptions::budget_for`](crate::pipeline::EmitOptions::budget_for)
/// needs of the path controls in force at a program's runs: whether any
/// blends beyond a given share ([`PathControl::exceeds`]), gathered run by
/// run (`None` runs, without a command in force, count for nothing).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PathBlending {
    /// Some run has a G64 without a tolerance (no P, or P0).
    unbounded: bool,
    /// The largest positive P (mm) of a G64 in force at a run.
    max_p_mm: Option<f64>,
}

impl PathBlending {
    /// Adds the command in force at one run.
    pub fn add(&mut self, pc: &PathControl) {
        if !pc.blends {
            return;
        }
        match pc.p_mm {
            Some(p) if p > 0.0 => self.max_p_mm = Some(self.max_p_mm.map_or(p, |m| m.max(p))),
            _ => self.unbounded = true,
        }
    }

    /// Whether the command at some run blends beyond `blend_mm`: the same
    /// as [`PathControl::exceeds`] of any of them.
    pub fn exceeds(&self, blend_mm: f64) -> bool {
        self.unbounded || self.max_p_mm.is_some_and(|p| p > blend_mm)
    }

    /// Those of `program`'s runs ([`before_runs`]).
    pub fn of(program: &Program) -> PathBlending {
        let mut b = PathBlending::default();
        for pc in before_runs(program).iter().flatten() {
            b.add(pc);
        }
        b
    }
}

/// The path control in force before each run of `program` (same order as
/// [`Program::run_spans`]), `None` where the program has set none.
pub fn before_runs(program: &Program) -> Vec<Option<PathControl>> {
    before_runs_from(program, None).0
}

/// [`before_runs`] of a part of a program ([`Program::first_number`]),
/// `cur` being the command in force before its first line; also returns
/// the one in force after its last line (for the next part).
pub(crate) fn before_runs_from(
    program: &Program,
    mut cur: Option<PathControl>,
) -> (Vec<Option<PathControl>>, Option<PathControl>) {
    let lines = program.lines();
    let mut out = Vec::with_capacity(program.run_spans().len());
    let mut next = 0;
    let after = |l: &ProgramLine, cur: &mut Option<PathControl>| {
        if sets_path_control(l) {
            *cur = l
                .path_control_after
                .as_ref()
                .map(|text| PathControl::after_line(text, &l.words, l.units));
        }
    };
    for run in program.run_spans() {
        while next + program.first_number() < run.first_line {
            after(&lines[next], &mut cur);
            next += 1;
        }
        out.push(cur.clone());
    }
    for l in &lines[next..] {
        after(l, &mut cur);
    }
    (out, cur)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse;

    #[test]
    fn the_command_in_force_at_each_run_in_mm() {
        let text =
            "G20 G64 P0.001 Q0\nG0 X0 Y0\nG1 X1 F10\nG1 X2 Y1\nG21\nG61\nG1 X3\nG64\nG1 X4\nM30\n";
        let p = parse(text.as_bytes()).unwrap();
        let b = before_runs(&p);
        assert_eq!(b.len(), 3);
        let first = b[0].as_ref().unwrap();
        assert_eq!(first.text, "G64 P0.001 Q0");
        assert!((first.p_mm.unwrap() - 0.0254).abs() < 1e-12);
        assert!(first.exceeds(0.02) && !first.exceeds(0.03));
        let g61 = b[1].as_ref().unwrap();
        assert!(!g61.blends && !g61.exceeds(0.0));
        let bare = b[2].as_ref().unwrap();
        assert_eq!(bare.text, "G64");
        assert!(bare.exceeds(1000.0));
    }

    #[test]
    fn g64_p0_blends_without_a_tolerance() {
        let p = parse(b"G64 P0\nG0 X0\nG1 X1 F10\nM30\n").unwrap();
        assert!(before_runs(&p)[0].as_ref().unwrap().exceeds(1.0));
    }
}
