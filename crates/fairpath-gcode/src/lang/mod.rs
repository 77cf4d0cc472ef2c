//! LinuxCNC's G-code language as its interpreter (rs274ngc) reads it:
//! expressions ([`expr`]), parameters ([`params`]), o-word control flow
//! ([`flow`]) and polar coordinates ([`polar`]). [`crate::lexer`] reads the
//! syntax of a line; [`line`](mod@line) evaluates it into the plain words the
//! interpreter moves by.
//!
//! A program without o-words is read in place: one line per source line,
//! each line's words evaluated with the parameters as they are when the line
//! is reached. A program with o-words is expanded: the lines executed, in
//! execution order ([`flow`]).

pub mod error;
pub mod expr;
pub mod flow;
pub mod line;
pub mod params;
pub mod polar;

use crate::error::GcodeError;

/// The name of an o-word: `o100` (numbers compare as integers, `o0100` is
/// `o100`, as LinuxCNC prints them), `o<name>` (lower case, blanks removed),
/// or, for `call` only, a computed number (`o[#1+2] call`).
#[derive(Clone, Debug, PartialEq)]
pub enum OName {
    Number(u64),
    Named(String),
    Computed(expr::Expr),
}

impl std::fmt::Display for OName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OName::Number(n) => write!(f, "{n}"),
            OName::Named(s) => write!(f, "<{s}>"),
            OName::Computed(_) => write!(f, "[...]"),
        }
    }
}

/// An o-word command (LinuxCNC's `read_o`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OCommand {
    Sub,
    Endsub,
    Call,
    Return,
    Do,
    While,
    Endwhile,
    Repeat,
    Endrepeat,
    If,
    Elseif,
    Else,
    Endif,
    Break,
    Continue,
}

impl OCommand {
    /// The command of a keyword (lower case).
    pub fn from_keyword(k: &str) -> Option<OCommand> {
        Some(match k {
            "sub" => OCommand::Sub,
            "endsub" => OCommand::Endsub,
            "call" => OCommand::Call,
            "return" => OCommand::Return,
            "do" => OCommand::Do,
            "while" => OCommand::While,
            "endwhile" => OCommand::Endwhile,
            "repeat" => OCommand::Repeat,
            "endrepeat" => OCommand::Endrepeat,
            "if" => OCommand::If,
            "elseif" => OCommand::Elseif,
            "else" => OCommand::Else,
            "endif" => OCommand::Endif,
            "break" => OCommand::Break,
            "continue" => OCommand::Continue,
            _ => return None,
        })
    }

    /// The keyword.
    pub fn keyword(self) -> &'static str {
        match self {
            OCommand::Sub => "sub",
            OCommand::Endsub => "endsub",
            OCommand::Call => "call",
            OCommand::Return => "return",
            OCommand::Do => "do",
            OCommand::While => "while",
            OCommand::Endwhile => "endwhile",
            OCommand::Repeat => "repeat",
            OCommand::Endrepeat => "endrepeat",
            OCommand::If => "if",
            OCommand::Elseif => "elseif",
            OCommand::Else => "else",
            OCommand::Endif => "endif",
            OCommand::Break => "break",
            OCommand::Continue => "continue",
        }
    }

    /// Least and most bracketed arguments (a call takes up to 30, LinuxCNC's
    /// `INTERP_SUB_PARAMS`).
    pub fn arguments(self) -> (usize, usize) {
        match self {
            OCommand::Call => (0, params::SUB_PARAMS),
            OCommand::Return | OCommand::Endsub => (0, 1),
            OCommand::While | OCommand::Repeat | OCommand::If | OCommand::Elseif => (1, 1),
            _ => (0, 0),
        }
    }
}

/// An o-word statement: name, command, bracketed arguments (each with the
/// 1-based column of its `[`), and the column of the `o`.
#[derive(Clone, Debug, PartialEq)]
pub struct OWord {
    pub name: OName,
    pub command: OCommand,
    pub args: Vec<(expr::Expr, usize)>,
    pub column: usize,
}

/// The shortest decimal literal that reads back to exactly `v` (Rust's
/// round-trip formatting, which never uses exponent notation; G-code has
/// none): the text of a computed word.
pub fn literal(v: f64) -> String {
    let s = format!("{v}");
    if s == "-0" {
        "0".to_string()
    } else {
        s
    }
}

/// Evaluates one real value as LinuxCNC reads a word's value (`[1+2]`,
/// `-SIN[30]`, `2.5`) with no parameter set and the state at program start.
/// For tests and tools; errors name line 1 and the column in `text`.
pub fn evaluate_str(text: &str) -> Result<f64, GcodeError> {
    let src = crate::lexer::scan_line(&format!("#1={text}"), 1).map_err(|e| shift(e, 3))?;
    let p = params::Params::new();
    let view = params::SystemView::default();
    let scope = params::Scope {
        params: &p,
        view: &view,
        created: &[],
    };
    match src.items.as_slice() {
        [crate::lexer::Item {
            kind: crate::lexer::ItemKind::Assign { value, .. },
            ..
        }] => expr::eval(value, &scope, 1).map_err(|e| shift(e, 3)),
        _ => Err(GcodeError::new(
            1,
            1,
            crate::error::ErrorKind::Language(error::LangError::Syntax("not one value")),
        )),
    }
}

fn shift(mut e: GcodeError, by: usize) -> GcodeError {
    e.column = e.column.saturating_sub(by).max(1);
    e
}
