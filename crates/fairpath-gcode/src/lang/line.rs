//! Evaluating one line: its words' values, its parameter assignments, and
//! (for expanded programs) its text with every computed value written out.
//!
//! As LinuxCNC (`interp_read.cc` `read_parameter_setting`, and `execute`
//! in `rs274ngc_pre.cc`): every value of the line is computed with the
//! parameters as they were before the line; the assignments then apply in
//! order, numbered ones first, then named ones, before the line's words
//! act. A named parameter assigned on the line exists (with value 0) for
//! the reads after its assignment on the same line.

use super::error::LangError;
use super::expr::{eval, to_integer};
use super::literal;
use super::params::{Params, Scope, SystemView};
use crate::error::{ErrorKind, GcodeError};
use crate::lexer::{ItemKind, LexedLine, ParamTarget, SourceLine, Word, MAX_WORD_MAGNITUDE};
use std::ops::Range;

/// A line after evaluation.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluated {
    /// The words with their values (a computed word's text is its value's
    /// round-trip literal).
    pub lexed: LexedLine,
    /// The line held a parameter assignment.
    pub assigns: bool,
    /// Character range of each word of `lexed` (letter included) in the
    /// source line.
    pub spans: Vec<Range<usize>>,
    /// Text edits that write the line out with literal values: (character
    /// range of the source line, replacement), in order, disjoint.
    pub edits: Vec<(Range<usize>, String)>,
}

impl Evaluated {
    /// The source line with the edits applied: computed values written
    /// out, assignments removed.
    pub fn expanded_text(&self, source: &str) -> String {
        let chars: Vec<char> = source.chars().collect();
        let mut out = String::with_capacity(source.len());
        let mut at = 0;
        for (r, rep) in &self.edits {
            out.extend(&chars[at..r.start]);
            out.push_str(rep);
            at = r.end;
        }
        out.extend(&chars[at..]);
        out
    }
}

/// Evaluates `src` (the syntax of source line `ln`) with `params` and
/// `view`, and applies its assignments to `params`.
pub fn evaluate(
    src: &SourceLine,
    ln: usize,
    params: &mut Params,
    view: &SystemView,
) -> Result<Evaluated, GcodeError> {
    let mut out = Evaluated {
        lexed: LexedLine {
            words: Vec::with_capacity(src.items.len()),
            block_delete: src.block_delete,
            percent: src.percent,
            program_number: src.program_number,
            has_comment: src.has_comment,
        },
        assigns: false,
        spans: Vec::with_capacity(src.items.len()),
        edits: Vec::new(),
    };
    let mut created: Vec<String> = Vec::new();
    let mut numbered: Vec<(i64, f64, usize)> = Vec::new();
    let mut named: Vec<(String, f64, usize)> = Vec::new();
    for item in &src.items {
        let scope = Scope {
            params,
            view,
            created: &created,
        };
        match &item.kind {
            ItemKind::Word {
                letter,
                value,
                literal: lit,
            } => {
                let v = eval(value, &scope, ln)?;
                if v.abs() > MAX_WORD_MAGNITUDE {
                    return Err(GcodeError::new(
                        ln,
                        item.column,
                        ErrorKind::NumberOutOfRange(*letter),
                    ));
                }
                let text = match lit {
                    Some(t) => t.clone(),
                    None => {
                        let t = literal(v);
                        out.edits.push((item.span.clone(), t.clone()));
                        t
                    }
                };
                out.lexed.words.push(Word {
                    letter: *letter,
                    value: v,
                    text: text.into(),
                    column: item.column,
                });
                out.spans.push(item.column - 1..item.span.end);
            }
            ItemKind::Assign { target, value } => {
                out.assigns = true;
                let v = eval(value, &scope, ln)?;
                match target {
                    ParamTarget::Numbered(index) => {
                        let i = eval(index, &scope, ln)?;
                        let n = to_integer(i).ok_or_else(|| {
                            GcodeError::new(
                                ln,
                                item.column,
                                ErrorKind::Language(LangError::NotInteger(i)),
                            )
                        })?;
                        numbered.push((n, v, item.column));
                    }
                    ParamTarget::Named(name) => {
                        named.push((name.clone(), v, item.column));
                        created.push(name.clone());
                    }
                }
                out.edits.push((item.span.clone(), String::new()));
            }
        }
    }
    for (n, v, col) in numbered {
        params.set_numbered(n, v, ln, col)?;
    }
    for (name, v, col) in named {
        params.set_named(&name, v, ln, col)?;
    }
    Ok(out)
}
