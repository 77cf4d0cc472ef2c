//! o-word control flow: subroutines (`sub`, `endsub`, `call`, `return`),
//! loops (`while`/`endwhile`, `do`/`while`, `repeat`/`endrepeat`, `break`,
//! `continue`) and conditionals (`if`/`elseif`/`else`/`endif`), executed as
//! LinuxCNC's `interp_o_word.cc` does for well-formed programs.
//!
//! [`Structure::of`] matches the statements of the whole program first
//! (by name: `o100 if` ... `o100 endif`), so that an unmatched statement is
//! an error at its line before anything runs. [`Executor`] then runs the
//! program line by line and hands each executed non-o-word line to its
//! caller, which evaluates and interprets it.
//!
//! Rules (LinuxCNC's):
//! * a `sub` ... `endsub` definition is skipped where it stands and runs
//!   only when called, from anywhere in the file; definitions do not nest;
//!   a call of a subroutine not defined in the program is an
//!   unsupported-feature error (LinuxCNC would look for a file of that name
//!   in its subroutine path, which a reader of one file does not have);
//! * `call [a] [b] ...` binds `#1`, `#2`, ... (up to 30, the rest 0) in the
//!   subroutine; the caller's `#1..#30` and local named parameters come back
//!   on `endsub`/`return`; `return [v]`/`endsub [v]` set `#<_value>` (and
//!   `#<_value_returned>` = 1; without a value both are 0);
//! * calls nest at most [`MAX_CALL_LEVEL`] deep (LinuxCNC's
//!   `INTERP_SUB_ROUTINE_LEVELS` - 1);
//! * `repeat [n]` runs its body `n` times (rounded to the nearest integer,
//!   ties to even, as `nearbyint`; 0 or fewer: not at all); the count is
//!   taken once per entry;
//! * `break` and `continue` name an enclosing `while` or `do` loop (LinuxCNC
//!   refuses them in `repeat`); `continue` re-tests the loop's condition;
//! * at most [`MAX_EXECUTED_LINES`] lines run (o-word lines included),
//!   beyond which the program is taken for an endless loop;
//! * a `while` or `do` loop whose condition holds again after a pass that
//!   changed no parameter (no call or return, and no assignment of a value
//!   the parameter did not hold: [`Params::changes`]) and either left the
//!   state conditions read (`SystemView`: position, modes, feed) as it was
//!   or never read it ([`Params::view_reads`]; an incremental move in a
//!   loop on a counter that is never counted) is endless, and an error at
//!   once (ours: LinuxCNC runs it until it is stopped; a loop whose
//!   counter's increment was left out, or whose counter was set to an
//!   unset parameter's 0 on every pass, took seconds and gigabytes to reach
//!   the line limit; measurements: docs/tuning.md, `lang::flow`): the
//!   interpreter is deterministic, so the pass and every one after it
//!   would repeat the same.

use super::error::LangError;
use super::expr::{eval, to_integer};
use super::params::{Params, Scope, SystemView};
use super::{OCommand, OName};
use crate::error::{ErrorKind, GcodeError};
use crate::lexer::SourceLine;
use std::collections::HashMap;

/// Most lines executed (o-word lines included) before the reader gives up
/// on a program as an endless loop: ten million is far beyond what a real
/// program expands to (and what the expanded program's memory allows),
/// and takes seconds to reach.
pub const MAX_EXECUTED_LINES: usize = 10_000_000;

/// Deepest subroutine nesting: LinuxCNC's `INTERP_SUB_ROUTINE_LEVELS` is
/// 10 and a call that reaches level 10 is refused.
pub const MAX_CALL_LEVEL: usize = 9;

/// What an o-word line is linked to (indices of lines, 0-based).
#[derive(Clone, Debug, PartialEq)]
enum Link {
    Sub { end: usize },
    Leave,
    Call,
    If { branches: Vec<usize>, endif: usize },
    Branch { endif: usize },
    Endif,
    While { end: usize },
    Endwhile { start: usize },
    Do,
    DoWhile { start: usize },
    Repeat { end: usize },
    Endrepeat { start: usize },
    Jump { to: usize },
}

/// The matched o-word statements of a program.
#[derive(Clone, Debug, Default)]
pub struct Structure {
    /// Subroutine name -> (line of `sub`, line of `endsub`).
    subs: HashMap<String, (usize, usize)>,
    links: HashMap<usize, Link>,
}

/// The key LinuxCNC compares o-word names by.
fn key(name: &OName) -> String {
    match name {
        OName::Number(n) => n.to_string(),
        OName::Named(s) => s.clone(),
        OName::Computed(_) => String::new(),
    }
}

/// An open statement while matching.
struct Open {
    command: OCommand,
    key: String,
    line: usize,
    column: usize,
    branches: Vec<usize>,
    has_else: bool,
    /// `break` lines (jump past the end) and `continue` lines (jump to the
    /// re-test) waiting for the loop's end.
    breaks: Vec<usize>,
    continues: Vec<usize>,
}

/// True when the program has o-word statements (other than a Fanuc program
/// number), so that it is read by expansion.
pub fn uses_control_flow(lines: &[Result<SourceLine, GcodeError>], texts: &[String]) -> bool {
    lines.iter().zip(texts).any(|(l, t)| match l {
        Ok(s) => s.oword.is_some(),
        Err(_) => looks_like_oword(t),
    })
}

/// A line whose first word (after `/` and an N word) is `o` followed by
/// `<` or digits then a letter: an o-word statement that did not scan.
pub fn looks_like_oword(text: &str) -> bool {
    // The line without blanks, lower case, read as far as the decision
    // needs (a long comment after the first word is never copied).
    let mut t = text
        .chars()
        .filter(|c| !c.is_whitespace())
        .map(|c| c.to_ascii_lowercase())
        .peekable();
    // Comments before the statement (LinuxCNC refuses them there; the
    // scanner reports it); an unclosed one leaves nothing.
    while t.next_if_eq(&'(').is_some() {
        if !t.by_ref().any(|c| c == ')') {
            return false;
        }
    }
    t.next_if_eq(&'/');
    if t.next_if_eq(&'n').is_some() {
        while t.next_if(|&c| c.is_ascii_digit() || c == '.').is_some() {}
    }
    if t.next_if_eq(&'o').is_none() {
        return false;
    }
    if t.next_if(|c| matches!(c, '<' | '[' | '#')).is_some() {
        return true;
    }
    let mut digits = false;
    while t.next_if(|c| c.is_ascii_digit()).is_some() {
        digits = true;
    }
    digits && t.next().is_some_and(|c| c.is_ascii_alphabetic())
}

impl Structure {
    /// Matches the o-word statements of `lines` (source line `i + 1` is
    /// `lines[i]`). A line that does not scan and looks like an o-word
    /// statement is reported here; other lines' errors wait until they run.
    pub fn of(
        lines: &[Result<SourceLine, GcodeError>],
        texts: &[String],
    ) -> Result<Structure, GcodeError> {
        let mut s = Structure::default();
        let mut stack: Vec<Open> = Vec::new();
        for (i, l) in lines.iter().enumerate() {
            let o = match l {
                Ok(src) => match &src.oword {
                    Some(o) => o,
                    None => continue,
                },
                Err(e) if looks_like_oword(&texts[i]) => return Err(e.clone()),
                Err(_) => continue,
            };
            let k = key(&o.name);
            let at = |e: LangError| GcodeError::new(i + 1, o.column, ErrorKind::Language(e));
            let unmatched = |found: &'static str, expected: &'static str| {
                at(LangError::Unmatched {
                    name: o.name.to_string(),
                    found,
                    expected,
                })
            };
            let open = |command| Open {
                command,
                key: k.clone(),
                line: i,
                column: o.column,
                branches: Vec::new(),
                has_else: false,
                breaks: Vec::new(),
                continues: Vec::new(),
            };
            let top_is = |stack: &Vec<Open>, c: OCommand| {
                stack.last().is_some_and(|t| t.command == c && t.key == k)
            };
            match o.command {
                OCommand::Sub => {
                    if !stack.is_empty() {
                        return Err(at(LangError::OWordSyntax(
                            "a subroutine definition inside another statement (definitions do not nest)",
                        )));
                    }
                    stack.push(open(OCommand::Sub));
                }
                OCommand::Endsub => {
                    if !top_is(&stack, OCommand::Sub) {
                        return Err(unmatched("endsub", "sub"));
                    }
                    let t = stack.pop().expect("checked");
                    if s.subs.insert(k.clone(), (t.line, i)).is_some() {
                        return Err(GcodeError::new(
                            t.line + 1,
                            t.column,
                            ErrorKind::Language(LangError::DuplicateSubroutine(o.name.to_string())),
                        ));
                    }
                    s.links.insert(t.line, Link::Sub { end: i });
                    s.links.insert(i, Link::Leave);
                }
                OCommand::Return => {
                    if !stack
                        .first()
                        .is_some_and(|t| t.command == OCommand::Sub && t.key == k)
                    {
                        return Err(unmatched("return", "sub"));
                    }
                    s.links.insert(i, Link::Leave);
                }
                OCommand::Call => {
                    s.links.insert(i, Link::Call);
                }
                OCommand::Do | OCommand::Repeat | OCommand::If => stack.push(open(o.command)),
                OCommand::While => {
                    if top_is(&stack, OCommand::Do) {
                        let t = stack.pop().expect("checked");
                        s.links.insert(t.line, Link::Do);
                        s.links.insert(i, Link::DoWhile { start: t.line });
                        for b in t.breaks {
                            s.links.insert(b, Link::Jump { to: i + 1 });
                        }
                        for c in t.continues {
                            s.links.insert(c, Link::Jump { to: i });
                        }
                    } else {
                        stack.push(open(OCommand::While));
                    }
                }
                OCommand::Endwhile | OCommand::Endrepeat | OCommand::Endif => {
                    let (opener, name) = match o.command {
                        OCommand::Endwhile => (OCommand::While, "while"),
                        OCommand::Endrepeat => (OCommand::Repeat, "repeat"),
                        _ => (OCommand::If, "if"),
                    };
                    if !top_is(&stack, opener) {
                        return Err(unmatched(o.command.keyword(), name));
                    }
                    let t = stack.pop().expect("checked");
                    match o.command {
                        OCommand::Endwhile => {
                            s.links.insert(t.line, Link::While { end: i });
                            s.links.insert(i, Link::Endwhile { start: t.line });
                            for b in t.breaks {
                                s.links.insert(b, Link::Jump { to: i + 1 });
                            }
                            for c in t.continues {
                                s.links.insert(c, Link::Jump { to: t.line });
                            }
                        }
                        OCommand::Endrepeat => {
                            s.links.insert(t.line, Link::Repeat { end: i });
                            s.links.insert(i, Link::Endrepeat { start: t.line });
                        }
                        _ => {
                            for &b in &t.branches {
                                s.links.insert(b, Link::Branch { endif: i });
                            }
                            s.links.insert(
                                t.line,
                                Link::If {
                                    branches: t.branches,
                                    endif: i,
                                },
                            );
                            s.links.insert(i, Link::Endif);
                        }
                    }
                }
                OCommand::Elseif | OCommand::Else => {
                    if !top_is(&stack, OCommand::If) {
                        return Err(unmatched(o.command.keyword(), "if"));
                    }
                    let t = stack.last_mut().expect("checked");
                    if t.has_else {
                        return Err(at(LangError::OWordSyntax("elseif or else after else")));
                    }
                    t.has_else = o.command == OCommand::Else;
                    t.branches.push(i);
                }
                OCommand::Break | OCommand::Continue => {
                    let Some(t) = stack.iter_mut().rev().find(|t| {
                        matches!(t.command, OCommand::While | OCommand::Do) && t.key == k
                    }) else {
                        return Err(unmatched(o.command.keyword(), "while or do loop"));
                    };
                    if o.command == OCommand::Break {
                        t.breaks.push(i);
                    } else {
                        t.continues.push(i);
                    }
                }
            }
        }
        if let Some(t) = stack.pop() {
            let expected = match t.command {
                OCommand::Sub => "endsub",
                OCommand::Do => "while",
                OCommand::While => "endwhile",
                OCommand::Repeat => "endrepeat",
                _ => "endif",
            };
            let name = match &lines[t.line] {
                Ok(src) => src
                    .oword
                    .as_ref()
                    .map(|o| o.name.to_string())
                    .unwrap_or_default(),
                Err(_) => String::new(),
            };
            return Err(GcodeError::new(
                t.line + 1,
                t.column,
                ErrorKind::Language(LangError::Unmatched {
                    name,
                    found: t.command.keyword(),
                    expected,
                }),
            ));
        }
        Ok(s)
    }
}

/// A subroutine call being run.
struct Frame {
    return_to: usize,
    /// Remaining passes of each `repeat` entered in this frame, by line.
    repeats: HashMap<usize, i64>,
    /// Per `while` loop (by its `while` line) and `do` loop (by its `do`
    /// line) entered in this frame: the parameters' changes, the reads of
    /// the interpreter's state and the state when its condition last held.
    passes: HashMap<usize, Pass>,
}

impl Frame {
    fn new(return_to: usize) -> Frame {
        Frame {
            return_to,
            repeats: HashMap::new(),
            passes: HashMap::new(),
        }
    }

    /// The condition of loop `key` held with `now`; `again`: after a pass
    /// of the loop (not on entering it). False where the pass before saw
    /// the same ([`Pass::repeats`]): an endless loop.
    fn pass(&mut self, key: usize, now: Pass, again: bool) -> bool {
        let endless = again && self.passes.get(&key).is_some_and(|b| now.repeats(b));
        self.passes.insert(key, now);
        !endless
    }
}

/// What a loop's condition held with: [`Params::changes`],
/// [`Params::view_reads`] and the interpreter's state.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pass {
    changes: u64,
    view_reads: u64,
    view: SystemView,
}

impl Pass {
    /// The pass that ended here will be run again, the same, forever
    /// (ours; the interpreter is deterministic): it changed no parameter,
    /// and it either left the interpreter's state as it was or never read
    /// it (then its control flow, which reads parameters only, repeats
    /// whatever its moves do to the position: `G91 X1` in a loop on a
    /// counter that is never counted).
    fn repeats(&self, before: &Pass) -> bool {
        self.changes == before.changes
            && (self.view == before.view || self.view_reads == before.view_reads)
    }
}

/// Runs a program's control flow.
pub struct Executor<'a> {
    lines: &'a [Result<SourceLine, GcodeError>],
    structure: Structure,
    pc: usize,
    frames: Vec<Frame>,
    executed: usize,
    /// The `while` line an `endwhile` or `continue` just went back to.
    back_edge: Option<usize>,
}

impl<'a> Executor<'a> {
    /// Matches the statements of `lines` (see [`Structure::of`]).
    pub fn new(
        lines: &'a [Result<SourceLine, GcodeError>],
        texts: &[String],
    ) -> Result<Executor<'a>, GcodeError> {
        Ok(Executor {
            lines,
            structure: Structure::of(lines, texts)?,
            pc: 0,
            frames: vec![Frame::new(lines.len())],
            executed: 0,
            back_edge: None,
        })
    }

    /// Lines executed so far (o-word lines included).
    pub fn executed(&self) -> usize {
        self.executed
    }

    /// Subroutine depth (0 in the main program).
    pub fn call_level(&self) -> usize {
        self.frames.len() - 1
    }

    /// Index of the next source line to run.
    pub fn position(&self) -> usize {
        self.pc
    }

    /// The condition of loop `key` (of the current frame) held with
    /// `params` and `view`; `again`: after a pass ([`Frame::pass`]).
    fn pass(
        &mut self,
        key: usize,
        (params, view): (&Params, &SystemView),
        again: bool,
    ) -> Result<(), LangError> {
        let frame = self.frames.last_mut().expect("main frame");
        let now = Pass {
            changes: params.changes(),
            view_reads: params.view_reads(),
            view: *view,
        };
        if frame.pass(key, now, again) {
            Ok(())
        } else {
            Err(LangError::EndlessLoop)
        }
    }

    /// Runs o-word lines until the next line to interpret, and returns its
    /// index (0-based), or `None` at the end of the file. `view` is the
    /// interpreter's state for conditions that read it.
    pub fn next(
        &mut self,
        params: &mut Params,
        view: &SystemView,
    ) -> Result<Option<usize>, GcodeError> {
        loop {
            let i = self.pc;
            let Some(line) = self.lines.get(i) else {
                return Ok(None);
            };
            self.executed += 1;
            if self.executed > MAX_EXECUTED_LINES {
                return Err(GcodeError::new(
                    i + 1,
                    1,
                    ErrorKind::Language(LangError::TooManyLines(MAX_EXECUTED_LINES)),
                ));
            }
            let src = line.as_ref().map_err(Clone::clone)?;
            let Some(o) = &src.oword else {
                self.pc += 1;
                return Ok(Some(i));
            };
            let here = SystemView {
                line: i + 1,
                ..*view
            };
            let ln = i + 1;
            let arg = |params: &Params, k: usize| -> Result<Option<f64>, GcodeError> {
                match o.args.get(k) {
                    None => Ok(None),
                    Some((e, _)) => {
                        let scope = Scope {
                            params,
                            view: &here,
                            created: &[],
                        };
                        eval(e, &scope, ln).map(Some)
                    }
                }
            };
            let cond = |params: &Params| -> Result<bool, GcodeError> {
                Ok(arg(params, 0)?.unwrap_or(0.0) != 0.0)
            };
            let fail = |e: LangError| GcodeError::new(ln, o.column, ErrorKind::Language(e));
            let link = self.structure.links.get(&i).cloned();
            match (o.command, link) {
                (OCommand::Sub, Some(Link::Sub { end })) => self.pc = end + 1,
                (OCommand::Endsub | OCommand::Return, _) => {
                    let v = arg(params, 0)?;
                    params.set_return(v);
                    if self.frames.len() < 2 {
                        return Err(fail(LangError::OWordSyntax(
                            "endsub or return outside a called subroutine",
                        )));
                    }
                    params.leave_call();
                    let f = self.frames.pop().expect("checked");
                    self.pc = f.return_to;
                }
                (OCommand::Call, _) => {
                    let name = match &o.name {
                        OName::Computed(e) => {
                            let scope = Scope {
                                params,
                                view: &here,
                                created: &[],
                            };
                            let v = eval(e, &scope, ln)?;
                            let n = to_integer(v).ok_or_else(|| fail(LangError::NotInteger(v)))?;
                            n.to_string()
                        }
                        n => key(n),
                    };
                    let Some(&(def, _)) = self.structure.subs.get(&name) else {
                        let shown = match &o.name {
                            OName::Named(s) => format!("<{s}>"),
                            _ => name,
                        };
                        return Err(fail(LangError::UndefinedSubroutine(shown)));
                    };
                    if self.call_level() + 1 > MAX_CALL_LEVEL {
                        return Err(fail(LangError::CallDepth(MAX_CALL_LEVEL)));
                    }
                    let mut args = Vec::with_capacity(o.args.len());
                    for k in 0..o.args.len() {
                        args.push(arg(params, k)?.unwrap_or(0.0));
                    }
                    params.enter_call(&args);
                    self.frames.push(Frame::new(i + 1));
                    self.pc = def + 1;
                }
                (OCommand::While, Some(Link::While { end })) => {
                    // (Come back from its `endwhile` or a `continue`, or
                    // entered from above.)
                    let again = self.back_edge.take() == Some(i);
                    self.pc = if cond(params)? {
                        self.pass(i, (params, view), again).map_err(fail)?;
                        i + 1
                    } else {
                        end + 1
                    };
                }
                (OCommand::Endwhile, Some(Link::Endwhile { start })) => {
                    self.pc = start;
                    self.back_edge = Some(start);
                }
                (OCommand::Do, _) => {
                    // Entered from above (a pass goes back past it).
                    let frame = self.frames.last_mut().expect("main frame");
                    frame.passes.remove(&i);
                    self.pc = i + 1;
                }
                (OCommand::While, Some(Link::DoWhile { start })) => {
                    self.pc = if cond(params)? {
                        self.pass(start, (params, view), true).map_err(fail)?;
                        start + 1
                    } else {
                        i + 1
                    };
                }
                (OCommand::If, Some(Link::If { branches, endif })) => {
                    self.pc = endif + 1;
                    if cond(params)? {
                        self.pc = i + 1;
                    } else {
                        for b in branches {
                            let Ok(bsrc) = &self.lines[b] else { continue };
                            let Some(bo) = &bsrc.oword else { continue };
                            if bo.command == OCommand::Else {
                                self.pc = b + 1;
                                break;
                            }
                            self.executed += 1;
                            let scope = Scope {
                                params,
                                view: &SystemView {
                                    line: b + 1,
                                    ..*view
                                },
                                created: &[],
                            };
                            let c = match bo.args.first() {
                                Some((e, _)) => eval(e, &scope, b + 1)?,
                                None => 0.0,
                            };
                            if c != 0.0 {
                                self.pc = b + 1;
                                break;
                            }
                        }
                    }
                }
                (OCommand::Elseif | OCommand::Else, Some(Link::Branch { endif })) => {
                    self.pc = endif + 1
                }
                (OCommand::Endif, _) => self.pc = i + 1,
                (OCommand::Repeat, Some(Link::Repeat { end })) => {
                    let frame = self.frames.last_mut().expect("main frame");
                    let left = match frame.repeats.get(&i) {
                        Some(&n) => n,
                        None => {
                            let n = arg(params, 0)?.unwrap_or(0.0).round_ties_even();
                            n.clamp(i64::MIN as f64, i64::MAX as f64) as i64
                        }
                    };
                    if left > 0 {
                        frame.repeats.insert(i, left - 1);
                        self.pc = i + 1;
                    } else {
                        frame.repeats.remove(&i);
                        self.pc = end + 1;
                    }
                }
                (OCommand::Endrepeat, Some(Link::Endrepeat { start })) => self.pc = start,
                (OCommand::Break, Some(Link::Jump { to })) => self.pc = to,
                (OCommand::Continue, Some(Link::Jump { to })) => {
                    self.pc = to;
                    self.back_edge = Some(to);
                }
                _ => {
                    return Err(fail(LangError::OWordSyntax("statement without its match")));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::looks_like_oword;

    /// The rule as it was written first, on a copy of the whole line.
    fn on_a_copy(text: &str) -> bool {
        let t: String = text
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect::<String>()
            .to_ascii_lowercase();
        let mut t = t.as_str();
        while let Some(r) = t.strip_prefix('(') {
            t = r.split_once(')').map_or("", |(_, rest)| rest);
        }
        let t = t.strip_prefix('/').unwrap_or(t);
        let t = match t.strip_prefix('n') {
            Some(r) => r.trim_start_matches(|c: char| c.is_ascii_digit() || c == '.'),
            None => t,
        };
        let Some(r) = t.strip_prefix('o') else {
            return false;
        };
        r.starts_with(['<', '[', '#']) || {
            let d = r.trim_start_matches(|c: char| c.is_ascii_digit());
            d.len() < r.len() && d.starts_with(|c: char| c.is_ascii_alphabetic())
        }
    }

    #[test]
    fn oword_lines_read_as_far_as_needed() {
        let parts = [
            "", " ", "o", "O", "1", "0", "<", "[", "#", "(", ")", "/", "n", "N", ".", "sub", "x",
            "é", ";", "\t", "(c)", "o100", "n10", "2.5",
        ];
        // Every line of up to three parts.
        let mut n = 0;
        for a in parts {
            for b in parts {
                for c in parts {
                    let line = format!("{a}{b}{c}");
                    assert_eq!(looks_like_oword(&line), on_a_copy(&line), "{line:?}");
                    n += 1;
                }
            }
        }
        assert_eq!(n, parts.len().pow(3));
        for line in [
            "o100 sub",
            "/ N20 O<name> call",
            "(c) o1 if",
            "o1 (x",
            "N1.5o2endsub",
        ] {
            assert_eq!(looks_like_oword(line), on_a_copy(line), "{line:?}");
        }
    }
}
