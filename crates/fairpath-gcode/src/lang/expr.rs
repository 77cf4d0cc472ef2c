//! Expressions as LinuxCNC's rs274ngc reads and evaluates them
//! (`interp_read.cc`: `read_real_value`, `read_real_expression`,
//! `read_operation`, `read_unary`; `interp_execute.cc`: `execute_binary1`,
//! `execute_binary2`, `execute_unary`).
//!
//! * A *real value* is a number (`[+-]digits[.digits]`, no exponent), a
//!   parameter (`#1`, `##1`, `#[1+2]`, `#<name>`), a bracketed expression
//!   `[...]`, a function `NAME[...]` (`ABS ACOS ASIN COS EXP FIX FUP LN
//!   ROUND SIN SQRT TAN`, `ATAN[y]/[x]`, `EXISTS[#<name>]`), or `-`/`+`
//!   before a real value (unary minus binds tighter than any operator:
//!   `[-2**2]` is 4).
//! * Binary operators, by precedence (highest first), all left-associative
//!   (LinuxCNC's `precedence`): `**`; `* / MOD`; `+ -`; `EQ NE GT GE LT LE`;
//!   `AND OR XOR`. Inside brackets only; a word's value is one real value.
//! * Trigonometry in degrees. `MOD` is never negative (`fmod` plus the
//!   divisor's magnitude when negative); `EQ`, `NE`, `LE`, `GE` compare
//!   within [`TOLERANCE_EQUAL`]; logic operators give 1 or 0, any nonzero
//!   value being true; `ROUND` rounds halves away from zero; `FIX` is floor,
//!   `FUP` ceiling.
//! * Errors as LinuxCNC's: division by zero, a negative number to a
//!   non-integer power, `ACOS`/`ASIN` outside [-1, 1], `LN` of a value <= 0,
//!   `SQRT` of a negative value, any result that is not finite.

use super::error::LangError;
use super::params::Scope;
use crate::error::{ErrorKind, GcodeError};

/// Two values compare equal (`EQ`, and the equality part of `NE`, `LE`,
/// `GE`) when they differ by less than this: LinuxCNC 2.9's
/// `TOLERANCE_EQUAL` (`interp_internal.hh`; master has 1e-6).
pub const TOLERANCE_EQUAL: f64 = 0.0001;

/// How far from an integer a value may be where an integer is needed
/// (parameter numbers): LinuxCNC's `read_integer_value` accepts
/// `n + 0.9999 < v` as `n + 1` and `v < n + 0.0001` as `n`.
pub const INTEGER_TOLERANCE: f64 = 0.0001;

/// One character of a line as the reader sees it: lower case, blanks and
/// comments removed (a comment stays as one `(`), with its 0-based
/// character index in the line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tok {
    pub c: char,
    pub idx: usize,
}

/// Binary operators.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Power,
    Times,
    Divide,
    Mod,
    Plus,
    Minus,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
    Xor,
}

impl Op {
    /// LinuxCNC's precedence levels (`interp_internal.cc`).
    fn precedence(self) -> u8 {
        match self {
            Op::Power => 6,
            Op::Times | Op::Divide | Op::Mod => 5,
            Op::Plus | Op::Minus => 4,
            Op::Eq | Op::Ne | Op::Gt | Op::Ge | Op::Lt | Op::Le => 3,
            Op::And | Op::Or | Op::Xor => 2,
        }
    }
}

/// Unary functions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    Abs,
    Acos,
    Asin,
    Cos,
    Exp,
    Fix,
    Fup,
    Ln,
    Round,
    Sin,
    Sqrt,
    Tan,
}

/// An expression tree. `col` fields are 1-based columns for errors.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    Num(f64),
    /// `#index`.
    Param {
        index: Box<Expr>,
        col: usize,
    },
    /// `#<name>` (lower case, blanks removed).
    Named {
        name: String,
        col: usize,
    },
    Neg(Box<Expr>),
    Func {
        f: Func,
        arg: Box<Expr>,
        col: usize,
    },
    /// `ATAN[y]/[x]`, degrees.
    Atan {
        y: Box<Expr>,
        x: Box<Expr>,
        col: usize,
    },
    /// `EXISTS[#<name>]` (or `EXISTS[#n]`: 1 when n is a parameter number).
    Exists {
        target: Box<Expr>,
    },
    Binary {
        op: Op,
        l: Box<Expr>,
        r: Box<Expr>,
        col: usize,
    },
}

/// Reads values and expressions from a line's tokens.
pub struct Parser<'a> {
    toks: &'a [Tok],
    i: usize,
    ln: usize,
    line_len: usize,
}

impl<'a> Parser<'a> {
    pub fn new(toks: &'a [Tok], ln: usize, line_len: usize) -> Parser<'a> {
        Parser {
            toks,
            i: 0,
            ln,
            line_len,
        }
    }

    pub fn peek(&self) -> Option<char> {
        self.toks.get(self.i).map(|t| t.c)
    }

    pub fn peek_tok(&self) -> Option<Tok> {
        self.toks.get(self.i).copied()
    }

    fn peek_at(&self, k: usize) -> Option<char> {
        self.toks.get(self.i + k).map(|t| t.c)
    }

    pub fn bump(&mut self) {
        self.i += 1;
    }

    /// Character index just after the last token read.
    pub fn end_idx(&self) -> usize {
        self.i
            .checked_sub(1)
            .and_then(|k| self.toks.get(k))
            .map_or(0, |t| t.idx + 1)
    }

    /// 1-based column of the next token (or just past the line's end).
    fn col(&self) -> usize {
        self.peek_tok().map_or(self.line_len + 1, |t| t.idx + 1)
    }

    pub fn error_here(&self, e: LangError) -> GcodeError {
        GcodeError::new(self.ln, self.col(), ErrorKind::Language(e))
    }

    /// True when only comments are left.
    pub fn rest_is_comments(&self) -> bool {
        self.toks[self.i..].iter().all(|t| t.c == '(')
    }

    /// `<name>` (the `<` is next): the name, lower case, blanks removed.
    pub fn name(&mut self) -> Result<String, GcodeError> {
        let open = self.col();
        self.bump();
        let mut name = String::new();
        loop {
            match self.peek() {
                Some('>') => {
                    self.bump();
                    break;
                }
                Some('(') | None => {
                    return Err(GcodeError::new(
                        self.ln,
                        open,
                        ErrorKind::Language(LangError::Syntax(
                            "named parameter or o-word not closed with '>'",
                        )),
                    ))
                }
                Some(c) => {
                    name.push(c);
                    self.bump();
                }
            }
        }
        if name.is_empty() {
            return Err(GcodeError::new(
                self.ln,
                open,
                ErrorKind::Language(LangError::Syntax("empty name <>")),
            ));
        }
        Ok(name)
    }

    /// The value of a word whose letter (at `letter_idx`) was just read.
    /// Keeps the lexer's errors for plain values: no value at all is
    /// [`ErrorKind::MissingValue`], a malformed number
    /// [`ErrorKind::MalformedNumber`], both at the letter.
    pub fn word_value(
        &mut self,
        letter: char,
        letter_idx: usize,
    ) -> Result<(Expr, Option<String>), GcodeError> {
        let ln = self.ln;
        let at_letter = |kind| GcodeError::new(ln, letter_idx + 1, kind);
        let starts_value = |c: Option<char>| matches!(c, Some(c) if c.is_ascii_digit() || matches!(c, '.' | '+' | '-' | '[' | '#'));
        match self.peek() {
            c if starts_value(c) => {}
            Some(c) if c.is_ascii_alphabetic() && self.function_ahead() => {}
            _ => return Err(at_letter(ErrorKind::MissingValue(letter))),
        }
        let number_start = self.i;
        match self.real_value() {
            Ok(v) => Ok(v),
            Err(e) => {
                // A plain (signed) number that does not parse: the lexer's
                // error, at the letter.
                let mut k = number_start;
                let mut text = String::new();
                while let Some(t) = self.toks.get(k) {
                    if t.c.is_ascii_digit() || t.c == '.' || t.c == '+' || t.c == '-' {
                        text.push(t.c);
                        k += 1;
                    } else {
                        break;
                    }
                }
                let plain = !text.is_empty()
                    && !matches!(
                        self.toks.get(number_start + 1).map(|t| t.c),
                        Some('[' | '#')
                    );
                match e.kind {
                    ErrorKind::Language(LangError::Syntax("bad number format")) if plain => {
                        Err(at_letter(ErrorKind::MalformedNumber { letter, text }))
                    }
                    ErrorKind::Language(LangError::NotFinite(_)) if plain => {
                        Err(at_letter(ErrorKind::NumberOutOfRange(letter)))
                    }
                    _ => Err(e),
                }
            }
        }
    }

    /// A run of letters then `[`: a function name.
    fn function_ahead(&self) -> bool {
        let mut k = self.i;
        while self.toks.get(k).is_some_and(|t| t.c.is_ascii_alphabetic()) {
            k += 1;
        }
        k > self.i && self.toks.get(k).is_some_and(|t| t.c == '[')
    }

    /// A real value (LinuxCNC's `read_real_value`), with the number's text
    /// when it is a plain number.
    pub fn real_value(&mut self) -> Result<(Expr, Option<String>), GcodeError> {
        let Some(t) = self.peek_tok() else {
            return Err(self.error_here(LangError::Syntax("value missing at the end of the line")));
        };
        // As LinuxCNC: a sign before anything but a digit or '.' is a unary
        // operator; before those, or at the end, part of a number.
        let unary = matches!(self.peek_at(1), Some(c) if !c.is_ascii_digit() && c != '.');
        match t.c {
            '[' => Ok((self.bracketed()?, None)),
            '#' => Ok((self.parameter()?, None)),
            '+' | '-' if unary => {
                self.bump();
                let (v, _) = self.real_value()?;
                Ok((
                    if t.c == '-' {
                        Expr::Neg(Box::new(v))
                    } else {
                        v
                    },
                    None,
                ))
            }
            c if c.is_ascii_alphabetic() => Ok((self.function()?, None)),
            _ => {
                let (v, text) = self.number()?;
                Ok((Expr::Num(v), Some(text)))
            }
        }
    }

    /// `[+-]digits[.digits]` as LinuxCNC's `read_real_number`.
    fn number(&mut self) -> Result<(f64, String), GcodeError> {
        let col = self.col();
        let mut text = String::new();
        if let Some(c @ ('+' | '-')) = self.peek() {
            text.push(c);
            self.bump();
        }
        let (mut digits, mut points) = (0, 0);
        while let Some(c) = self.peek().filter(|c| c.is_ascii_digit() || *c == '.') {
            if c == '.' {
                points += 1;
            } else {
                digits += 1;
            }
            text.push(c);
            self.bump();
        }
        let bad = || {
            GcodeError::new(
                self.ln,
                col,
                ErrorKind::Language(LangError::Syntax("bad number format")),
            )
        };
        if digits == 0 || points > 1 {
            return Err(bad());
        }
        let v: f64 = text.parse().map_err(|_| bad())?;
        if !v.is_finite() {
            return Err(GcodeError::new(
                self.ln,
                col,
                ErrorKind::Language(LangError::NotFinite("infinity")),
            ));
        }
        Ok((v, text))
    }

    /// `#...` (the `#` is next).
    fn parameter(&mut self) -> Result<Expr, GcodeError> {
        let col = self.col();
        self.bump();
        if self.peek() == Some('<') {
            let name = self.name()?;
            return Ok(Expr::Named { name, col });
        }
        let (index, _) = self.real_value()?;
        Ok(Expr::Param {
            index: Box::new(index),
            col,
        })
    }

    /// `[ ... ]` (the `[` is next).
    pub fn bracketed(&mut self) -> Result<Expr, GcodeError> {
        self.bump();
        let e = self.binary(0)?;
        match self.peek() {
            Some(']') => {
                self.bump();
                Ok(e)
            }
            _ => Err(self.op_error()),
        }
    }

    fn op_error(&self) -> GcodeError {
        match self.peek() {
            None => self.error_here(LangError::Syntax("expression not closed with ']'")),
            Some('(') => self.error_here(LangError::Syntax("comment inside an expression")),
            Some(_) => self.error_here(LangError::Syntax("unknown operation")),
        }
    }

    /// Left-associative precedence climbing: operators of precedence at
    /// least `min`.
    fn binary(&mut self, min: u8) -> Result<Expr, GcodeError> {
        let (mut left, _) = self.real_value()?;
        loop {
            if self.peek() == Some(']') {
                return Ok(left);
            }
            let col = self.col();
            let save = self.i;
            let op = self.operator()?;
            if op.precedence() < min {
                self.i = save;
                return Ok(left);
            }
            let right = self.binary(op.precedence() + 1)?;
            left = Expr::Binary {
                op,
                l: Box::new(left),
                r: Box::new(right),
                col,
            };
        }
    }

    /// A binary operator (LinuxCNC's `read_operation`).
    fn operator(&mut self) -> Result<Op, GcodeError> {
        let c = self.peek();
        let two = |p: &Parser, a: char, b: char| p.peek_at(1) == Some(a) && p.peek_at(2) == Some(b);
        let (op, len) = match c {
            Some('+') => (Op::Plus, 1),
            Some('-') => (Op::Minus, 1),
            Some('/') => (Op::Divide, 1),
            Some('*') if self.peek_at(1) == Some('*') => (Op::Power, 2),
            Some('*') => (Op::Times, 1),
            Some('a') if two(self, 'n', 'd') => (Op::And, 3),
            Some('m') if two(self, 'o', 'd') => (Op::Mod, 3),
            Some('o') if self.peek_at(1) == Some('r') => (Op::Or, 2),
            Some('x') if two(self, 'o', 'r') => (Op::Xor, 3),
            Some('e') if self.peek_at(1) == Some('q') => (Op::Eq, 2),
            Some('n') if self.peek_at(1) == Some('e') => (Op::Ne, 2),
            Some('g') if self.peek_at(1) == Some('e') => (Op::Ge, 2),
            Some('g') if self.peek_at(1) == Some('t') => (Op::Gt, 2),
            Some('l') if self.peek_at(1) == Some('e') => (Op::Le, 2),
            Some('l') if self.peek_at(1) == Some('t') => (Op::Lt, 2),
            _ => return Err(self.op_error()),
        };
        self.i += len;
        Ok(op)
    }

    /// `NAME[...]` (a letter is next).
    fn function(&mut self) -> Result<Expr, GcodeError> {
        let col = self.col();
        let mut name = String::new();
        while let Some(c) = self.peek().filter(|c| c.is_ascii_alphabetic()) {
            name.push(c);
            self.bump();
        }
        let f = match name.as_str() {
            "abs" => Some(Func::Abs),
            "acos" => Some(Func::Acos),
            "asin" => Some(Func::Asin),
            "cos" => Some(Func::Cos),
            "exp" => Some(Func::Exp),
            "fix" => Some(Func::Fix),
            "fup" => Some(Func::Fup),
            "ln" => Some(Func::Ln),
            "round" => Some(Func::Round),
            "sin" => Some(Func::Sin),
            "sqrt" => Some(Func::Sqrt),
            "tan" => Some(Func::Tan),
            "atan" | "exists" => None,
            _ => {
                return Err(GcodeError::new(
                    self.ln,
                    col,
                    ErrorKind::Language(LangError::Syntax("unknown function name")),
                ))
            }
        };
        if self.peek() != Some('[') {
            return Err(self.error_here(LangError::Syntax("'[' missing after a function name")));
        }
        if name == "exists" {
            self.bump();
            if self.peek() != Some('#') {
                return Err(self.error_here(LangError::Syntax(
                    "EXISTS needs a parameter: EXISTS[#<name>]",
                )));
            }
            let target = self.parameter()?;
            if self.peek() != Some(']') {
                return Err(self.error_here(LangError::Syntax("']' missing after EXISTS[#...")));
            }
            self.bump();
            return Ok(Expr::Exists {
                target: Box::new(target),
            });
        }
        let arg = self.bracketed()?;
        match f {
            Some(f) => Ok(Expr::Func {
                f,
                arg: Box::new(arg),
                col,
            }),
            None => {
                if self.peek() != Some('/') {
                    return Err(
                        self.error_here(LangError::Syntax("ATAN needs the form ATAN[y]/[x]"))
                    );
                }
                self.bump();
                if self.peek() != Some('[') {
                    return Err(
                        self.error_here(LangError::Syntax("ATAN needs the form ATAN[y]/[x]"))
                    );
                }
                let x = self.bracketed()?;
                Ok(Expr::Atan {
                    y: Box::new(arg),
                    x: Box::new(x),
                    col,
                })
            }
        }
    }
}

/// Evaluates `e` with the parameters of `scope`; errors name line `ln`.
pub fn eval(e: &Expr, scope: &Scope, ln: usize) -> Result<f64, GcodeError> {
    let fail = |col: usize, e: LangError| GcodeError::new(ln, col, ErrorKind::Language(e));
    let finite = |v: f64, col: usize| -> Result<f64, GcodeError> {
        if v.is_nan() {
            Err(fail(col, LangError::NotFinite("not a number")))
        } else if v.is_infinite() {
            Err(fail(col, LangError::NotFinite("infinity")))
        } else {
            Ok(v)
        }
    };
    Ok(match e {
        Expr::Num(v) => *v,
        Expr::Param { index, col } => {
            let i = eval(index, scope, ln)?;
            let n = to_integer(i).ok_or_else(|| fail(*col, LangError::NotInteger(i)))?;
            scope.numbered(n, ln, *col)?
        }
        Expr::Named { name, col } => scope.named(name, ln, *col)?,
        Expr::Neg(v) => -eval(v, scope, ln)?,
        Expr::Exists { target } => match &**target {
            Expr::Named { name, .. } => f64::from(u8::from(scope.exists(name))),
            Expr::Param { index, col } => {
                let i = eval(index, scope, ln)?;
                let n = to_integer(i).ok_or_else(|| fail(*col, LangError::NotInteger(i)))?;
                f64::from(u8::from(
                    (1..super::params::MAX_PARAMETERS as i64).contains(&n),
                ))
            }
            _ => 0.0,
        },
        Expr::Func { f, arg, col } => {
            let v = eval(arg, scope, ln)?;
            let r = match f {
                Func::Abs => v.abs(),
                Func::Acos | Func::Asin if !(-1.0..=1.0).contains(&v) => {
                    let name = if *f == Func::Acos { "ACOS" } else { "ASIN" };
                    return Err(fail(*col, LangError::Domain(name)));
                }
                Func::Acos => v.acos().to_degrees(),
                Func::Asin => v.asin().to_degrees(),
                Func::Cos => v.to_radians().cos(),
                Func::Exp => v.exp(),
                Func::Fix => v.floor(),
                Func::Fup => v.ceil(),
                Func::Ln if v <= 0.0 => return Err(fail(*col, LangError::Domain("LN"))),
                Func::Ln => v.ln(),
                Func::Round => (v + if v < 0.0 { -0.5 } else { 0.5 }).trunc(),
                Func::Sin => v.to_radians().sin(),
                Func::Sqrt if v < 0.0 => return Err(fail(*col, LangError::Domain("SQRT"))),
                Func::Sqrt => v.sqrt(),
                Func::Tan => v.to_radians().tan(),
            };
            finite(r, *col)?
        }
        Expr::Atan { y, x, col } => {
            let (y, x) = (eval(y, scope, ln)?, eval(x, scope, ln)?);
            finite(y.atan2(x).to_degrees(), *col)?
        }
        Expr::Binary { op, l, r, col } => {
            let (a, b) = (eval(l, scope, ln)?, eval(r, scope, ln)?);
            let truth = |t: bool| if t { 1.0 } else { 0.0 };
            let close = (a - b).abs() < TOLERANCE_EQUAL;
            let v = match op {
                Op::Power => {
                    if a < 0.0 && b.floor() != b {
                        return Err(fail(*col, LangError::NegativePower));
                    }
                    a.powf(b)
                }
                Op::Times => a * b,
                Op::Divide => {
                    if b == 0.0 {
                        return Err(fail(*col, LangError::DivideByZero));
                    }
                    a / b
                }
                Op::Mod => {
                    let m = a % b;
                    if m < 0.0 {
                        m + b.abs()
                    } else {
                        m
                    }
                }
                Op::Plus => a + b,
                Op::Minus => a - b,
                Op::Eq => truth(close),
                Op::Ne => truth(!close),
                Op::Gt => truth(a > b),
                Op::Ge => truth(close || a >= b),
                Op::Lt => truth(a < b),
                Op::Le => truth(close || a <= b),
                Op::And => truth(a != 0.0 && b != 0.0),
                Op::Or => truth(a != 0.0 || b != 0.0),
                Op::Xor => truth((a != 0.0) != (b != 0.0)),
            };
            finite(v, *col)?
        }
    })
}

/// An integer as LinuxCNC's `read_integer_value` reads one: within
/// [`INTEGER_TOLERANCE`] of an integer, or `None`.
pub fn to_integer(v: f64) -> Option<i64> {
    let f = v.floor();
    if !f.is_finite() || f.abs() > 1e15 {
        return None;
    }
    if v - f > 1.0 - INTEGER_TOLERANCE {
        Some(f as i64 + 1)
    } else if v - f > INTEGER_TOLERANCE {
        None
    } else {
        Some(f as i64)
    }
}
