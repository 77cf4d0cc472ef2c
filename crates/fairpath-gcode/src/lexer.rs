//! Line splitting and lexing: words with spans, comments, `%` lines, block
//! delete, and the syntax of LinuxCNC's language (parameters, expressions,
//! o-words), read as LinuxCNC's `interp_read.cc` reads it.
//!
//! Accepted syntax (LinuxCNC, Fanuc, Mach3, grbl, CAM post-processors):
//! * lines end with LF, CR LF or a lone CR (old Mac files); a UTF-8
//!   byte-order mark at the start of the file is skipped;
//! * blanks (space, tab) outside comments are ignored anywhere, as LinuxCNC
//!   strips them before reading: `G 1`, `X - 1.5`, `X 1 0.5` (= `X10.5`);
//!   letters are read in any case;
//! * words are a letter `A`..`Z` and a value; which letters mean something is
//!   the interpreter's business (it refuses `E`, for instance). A value is a
//!   number `[+-]digits[.digits]` or `[+-].digits`, a parameter (`#1`,
//!   `#<name>`, `##1`, `#[expr]`), an expression `[...]`, a function
//!   (`SIN[...]`, `ATAN[a]/[b]`, `EXISTS[#<name>]`, ...) or a value with a
//!   unary `-`/`+` (see [`crate::lang::expr`]);
//! * LinuxCNC's polar words `@` (radius) and `^` (angle);
//! * parameter assignments `#1 = value`, `#<name> = value`;
//! * o-word statements (`o100 sub`, `o<name> call [1] [2]`, `o1 while [..]`,
//!   ...) first on their line after an optional `/` and N word, followed by
//!   nothing but comments; a Fanuc program number `O1234` alone on a line
//!   (passed through);
//! * comments `( ... )` (not nested, closed on the same line) and `;` to the
//!   end of the line;
//! * a line whose first non-blank character is `%` (program delimiters);
//! * an optional block-delete `/` at the start of a line.
//!
//! Rejected with an error naming line and column: malformed numbers
//! (`X1.2.3`, `X`, `Xnan`, `Xinf`), exponent notation (`X1e5` reads as `X1`
//! followed by the word `E5`, which the interpreter passes through), a word
//! value whose magnitude exceeds [`MAX_WORD_MAGNITUDE`] (numbers of
//! hundreds of digits), any character that cannot start a word, malformed
//! expressions, and a word letter given twice on a line (except G and M;
//! their modal groups are checked by the interpreter). Every letter A-Z
//! lexes as a word: the interpreter passes the lines of words it does not
//! interpret (the 3D-printer extruder word `E`) through verbatim.

use crate::error::{ErrorKind, GcodeError};
use crate::lang::error::LangError;
use crate::lang::expr::{self, Expr, Tok};
use crate::lang::{self, OCommand, OName, OWord};
use crate::short_text::ShortText;
use std::ops::Range;

/// Largest magnitude of a word's value (program units, or whatever the
/// word counts), literal or computed: 1e9 is a million metres in mm and far
/// beyond any feed, speed or line number a program writes, while a value of
/// hundreds of digits is a corrupt file; refusing it at its column beats a
/// late failure (overflowing arithmetic, a dwell of centuries).
pub const MAX_WORD_MAGNITUDE: f64 = 1e9;

/// One word: letter (upper case) and value, with the number's text as written
/// (spaces removed) and its 1-based column (of the letter). A value computed
/// from an expression or parameters has as text the shortest literal that
/// reads back to exactly the same f64 ([`crate::lang::literal`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Word {
    pub letter: char,
    pub value: f64,
    pub text: ShortText,
    pub column: usize,
}

/// What a line holds after lexing and evaluation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LexedLine {
    /// Words in order of appearance.
    pub words: Vec<Word>,
    /// The line starts with `/` (block delete).
    pub block_delete: bool,
    /// The line is a `%` delimiter line.
    pub percent: bool,
    /// The line is a Fanuc program number (`O1234`), passed through.
    pub program_number: bool,
    /// The line has at least one comment.
    pub has_comment: bool,
}

impl LexedLine {
    pub fn word(&self, letter: char) -> Option<&Word> {
        self.words.iter().find(|w| w.letter == letter)
    }
}

/// What one item of a line is.
#[derive(Clone, Debug, PartialEq)]
pub enum ItemKind {
    /// A word: upper-case letter (or `@`, `^`), its value, and the number's
    /// text when the value is a plain number as written.
    Word {
        letter: char,
        value: Expr,
        literal: Option<String>,
    },
    /// `#target = value` (numbered: `index` is the parameter expression).
    Assign { target: ParamTarget, value: Expr },
}

/// The parameter an assignment sets.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamTarget {
    Numbered(Expr),
    Named(String),
}

/// One item of a line with where it sits.
#[derive(Clone, Debug, PartialEq)]
pub struct Item {
    pub kind: ItemKind,
    /// 1-based column of the letter or the `#`.
    pub column: usize,
    /// Character range of the value in the line (after the letter) for a
    /// word; of the whole assignment for an assignment.
    pub span: Range<usize>,
}

/// The syntax of one line: what [`scan_line`] reads before anything is
/// evaluated.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SourceLine {
    pub items: Vec<Item>,
    pub block_delete: bool,
    pub percent: bool,
    pub program_number: bool,
    pub has_comment: bool,
    /// The o-word statement of the line, if any (its N word, if any, is in
    /// `items`).
    pub oword: Option<OWord>,
}

impl SourceLine {
    /// True when the line holds a parameter assignment.
    pub fn assigns(&self) -> bool {
        self.items
            .iter()
            .any(|i| matches!(i.kind, ItemKind::Assign { .. }))
    }
}

/// Splits `text` into lines: `(content, line ending)`; the line ending is
/// `"\r\n"`, `"\n"`, `"\r"` (a lone CR, as old Mac files end lines) or `""`
/// (last line without a newline). A file ending in a newline has no extra
/// empty last line. A UTF-8 byte-order mark at the start is skipped. Checks
/// UTF-8 line by line.
pub fn split_lines(text: &[u8]) -> Result<Vec<(String, &'static str)>, GcodeError> {
    line_slices(text)
        .map(|l| l.map(|(t, e)| (t.to_string(), e)))
        .collect()
}

/// The lines of `text` as [`split_lines`] cuts them, borrowed from `text`
/// (no copy): a reader that keeps one `String` per line makes it from
/// these, so the program holds each line's text once.
pub fn line_slices(
    text: &[u8],
) -> impl Iterator<Item = Result<(&str, &'static str), GcodeError>> + '_ {
    line_slices_of(text.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(text))
}

/// [`line_slices`] of text that goes on from other text (a byte-order
/// mark there is a character of the line, not skipped).
pub(crate) fn line_slices_of(
    text: &[u8],
) -> impl Iterator<Item = Result<(&str, &'static str), GcodeError>> + '_ {
    let mut rest = text;
    let mut number = 0;
    core::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        number += 1;
        let (line, ending, next) = match rest.iter().position(|&b| b == b'\n' || b == b'\r') {
            Some(i) if rest[i] == b'\r' && rest.get(i + 1) == Some(&b'\n') => {
                (&rest[..i], "\r\n", &rest[i + 2..])
            }
            Some(i) if rest[i] == b'\r' => (&rest[..i], "\r", &rest[i + 1..]),
            Some(i) => (&rest[..i], "\n", &rest[i + 1..]),
            None => (rest, "", &rest[rest.len()..]),
        };
        rest = next;
        Some(match std::str::from_utf8(line) {
            Ok(s) => Ok((s, ending)),
            Err(e) => {
                // Nothing after an invalid line is read.
                rest = &[];
                let good = &line[..e.valid_up_to()];
                let column = std::str::from_utf8(good).map_or(1, |s| s.chars().count() + 1);
                Err(GcodeError::new(number, column, ErrorKind::InvalidUtf8))
            }
        })
    })
}

/// Lexes and evaluates one line (without its line ending) with no parameter
/// set and the position at the origin: for lines of plain G-code. `line_no`
/// is 1-based. [`crate::parse`] evaluates lines with the program's
/// parameters instead.
pub fn lex_line(line: &str, line_no: usize) -> Result<LexedLine, GcodeError> {
    let src = scan_line(line, line_no)?;
    if src.oword.is_some() {
        return Err(GcodeError::new(
            line_no,
            src.oword.as_ref().map_or(1, |o| o.column),
            ErrorKind::Unsupported("o-word statements outside a program"),
        ));
    }
    let mut params = lang::params::Params::new();
    let view = lang::params::SystemView::default();
    Ok(lang::line::evaluate(&src, line_no, &mut params, &view)?.lexed)
}

/// Reads the syntax of one line (without its line ending): items, o-word,
/// comments. Nothing is evaluated. `line_no` is 1-based.
pub fn scan_line(line: &str, line_no: usize) -> Result<SourceLine, GcodeError> {
    let err = |idx: usize, kind: ErrorKind| GcodeError::new(line_no, idx + 1, kind);
    let mut out = SourceLine::default();
    // Tokens: every non-blank character outside comments, lower case, with
    // its index; a comment is one '(' token. The characters are read once,
    // as they come: a line's memory is its tokens, not a copy of its text
    // (a comment of 200 MB costs nothing here).
    let mut toks: Vec<Tok> = Vec::new();
    let mut chars = line.chars().enumerate();
    // Index (in characters) of the first non-blank character, and the
    // number of characters read.
    let mut first_non_blank = None;
    let mut len = 0;
    while let Some((i, c)) = chars.next() {
        len = i + 1;
        if first_non_blank.is_none() && !matches!(c, ' ' | '\t' | '\r') {
            first_non_blank = Some(i);
        }
        match c {
            ' ' | '\t' | '\r' => {}
            '(' => {
                out.has_comment = true;
                loop {
                    match chars.next() {
                        None => return Err(err(i, ErrorKind::UnclosedComment)),
                        Some((j, ')')) => {
                            len = j + 1;
                            break;
                        }
                        Some((j, '(')) => return Err(err(j, ErrorKind::NestedComment)),
                        Some(_) => {}
                    }
                }
                toks.push(Tok { c: '(', idx: i });
            }
            ';' => {
                out.has_comment = true;
                len += chars.count();
                break;
            }
            _ => toks.push(Tok {
                c: c.to_ascii_lowercase(),
                idx: i,
            }),
        }
    }
    let first_non_blank = first_non_blank.unwrap_or(len);
    let mut p = expr::Parser::new(&toks, line_no, len);
    if p.peek() == Some('%') && toks[0].idx == first_non_blank {
        out.percent = true;
        return Ok(out);
    }
    if p.peek() == Some('/') {
        out.block_delete = true;
        p.bump();
    }
    while let Some(t) = p.peek_tok() {
        match t.c {
            '(' => {
                p.bump();
            }
            '#' => {
                let item = scan_assignment(&mut p)?;
                out.items.push(item);
            }
            'o' => {
                let only_n = out
                    .items
                    .iter()
                    .all(|it| matches!(it.kind, ItemKind::Word { letter: 'N', .. }));
                if !only_n || out.oword.is_some() || out.program_number {
                    return Err(err(
                        t.idx,
                        ErrorKind::Unsupported("o-word after other words"),
                    ));
                }
                scan_oword(&mut p, &mut out, line_no)?;
            }
            c if c.is_ascii_alphabetic() || c == '@' || c == '^' => {
                let letter = c.to_ascii_uppercase();
                p.bump();
                let (value, literal) = p.word_value(letter, t.idx)?;
                if letter != 'G'
                    && letter != 'M'
                    && out.items.iter().any(
                        |it| matches!(it.kind, ItemKind::Word { letter: l, .. } if l == letter),
                    )
                {
                    return Err(err(t.idx, ErrorKind::DuplicateWord(letter)));
                }
                out.items.push(Item {
                    kind: ItemKind::Word {
                        letter,
                        value,
                        literal,
                    },
                    column: t.idx + 1,
                    span: t.idx + 1..p.end_idx(),
                });
            }
            _ => {
                return Err(err(
                    t.idx,
                    ErrorKind::UnexpectedCharacter(line.chars().nth(t.idx).unwrap_or(t.c)),
                ))
            }
        }
    }
    if out.program_number {
        if let Some(it) = out.items.first() {
            return Err(GcodeError::new(
                line_no,
                it.column,
                ErrorKind::Unsupported("words on a line with an O program number"),
            ));
        }
    }
    Ok(out)
}

/// `#index = value` or `#<name> = value` (LinuxCNC's
/// `read_parameter_setting`: the value is one real value, not a bare
/// expression without brackets).
fn scan_assignment(p: &mut expr::Parser) -> Result<Item, GcodeError> {
    let hash = p.peek_tok().expect("caller saw '#'");
    p.bump();
    let target = if p.peek() == Some('<') {
        ParamTarget::Named(p.name()?)
    } else {
        ParamTarget::Numbered(p.real_value()?.0)
    };
    if p.peek() != Some('=') {
        return Err(p.error_here(LangError::Syntax(
            "'=' missing in parameter assignment (a parameter cannot start a word)",
        )));
    }
    p.bump();
    let (value, _) = p.real_value()?;
    Ok(Item {
        kind: ItemKind::Assign { target, value },
        column: hash.idx + 1,
        span: hash.idx..p.end_idx(),
    })
}

/// The o-word statement at the parser's position (`o`), as LinuxCNC's
/// `read_o` reads it: a number, `<name>` or (for `call` only) an
/// expression, a command, its bracketed arguments, then only comments. A
/// number with no command is a Fanuc program number.
fn scan_oword(
    p: &mut expr::Parser,
    out: &mut SourceLine,
    line_no: usize,
) -> Result<(), GcodeError> {
    let o = p.peek_tok().expect("caller saw 'o'");
    p.bump();
    let syntax = |msg| {
        GcodeError::new(
            line_no,
            o.idx + 1,
            ErrorKind::Language(LangError::OWordSyntax(msg)),
        )
    };
    let name = match p.peek() {
        Some('<') => OName::Named(p.name()?),
        Some(c) if c.is_ascii_digit() => {
            let mut n: u64 = 0;
            while let Some(d) = p.peek().and_then(|c| c.to_digit(10)) {
                n = n.saturating_mul(10).saturating_add(d as u64);
                p.bump();
            }
            OName::Number(n)
        }
        Some('[') | Some('#') => OName::Computed(p.real_value()?.0),
        _ => return Err(syntax("o-word without a number or <name>")),
    };
    let mut word = String::new();
    while let Some(c) = p.peek().filter(|c| c.is_ascii_alphabetic()) {
        word.push(c);
        p.bump();
    }
    if word.is_empty() {
        let rest_is_comment = p.rest_is_comments();
        if matches!(name, OName::Number(_))
            && rest_is_comment
            && !out.block_delete
            && out.items.is_empty()
        {
            out.program_number = true;
            return Ok(());
        }
        return Err(syntax(
            "o-word without a command (sub, call, while, if, ...)",
        ));
    }
    let command = match OCommand::from_keyword(&word) {
        Some(c) => c,
        None => {
            return Err(GcodeError::new(
                line_no,
                o.idx + 1,
                ErrorKind::Language(LangError::UnknownOCommand(word)),
            ))
        }
    };
    if matches!(name, OName::Computed(_)) && command != OCommand::Call {
        return Err(syntax("a computed o-word number is only read for call"));
    }
    let mut args = Vec::new();
    loop {
        match p.peek() {
            Some('(') => p.bump(),
            Some('[') => {
                let start = p.peek_tok().map_or(0, |t| t.idx);
                let e = p.bracketed()?;
                args.push((e, start + 1));
            }
            None => break,
            Some(_) => {
                return Err(p.error_here(LangError::OWordSyntax(
                    "unexpected character after the o-word command",
                )))
            }
        }
    }
    let need = command.arguments();
    if args.len() < need.0 || args.len() > need.1 {
        return Err(syntax(match need {
            (1, 1) => "this o-word command needs one [condition or count]",
            (0, 0) => "this o-word command takes no argument",
            (0, 1) => "return and endsub take at most one [value]",
            _ => "o-word call takes at most 30 arguments",
        }));
    }
    out.oword = Some(OWord {
        name,
        command,
        args,
        column: o.idx + 1,
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_and_spans() {
        let l = lex_line("N10 g1 X - 1.5 y2 (c) ; rest", 3).unwrap();
        let w: Vec<_> = l
            .words
            .iter()
            .map(|w| (w.letter, w.value, w.column))
            .collect();
        assert_eq!(
            w,
            vec![
                ('N', 10.0, 1),
                ('G', 1.0, 5),
                ('X', -1.5, 8),
                ('Y', 2.0, 16)
            ]
        );
        assert!(l.has_comment);
        assert_eq!(l.words[2].text, "-1.5");
    }

    #[test]
    fn errors() {
        let e = lex_line("G1 X1.2.3", 2).unwrap_err();
        assert_eq!((e.line, e.column), (2, 4));
        let e = lex_line("G1 Xnan", 1).unwrap_err();
        assert_eq!(e.kind, ErrorKind::MissingValue('X'));
        let l = lex_line("G1 X1e5", 1).unwrap();
        assert_eq!((l.words[2].letter, l.words[2].column), ('E', 6));
        let e = lex_line("G1 X1 X2", 1).unwrap_err();
        assert_eq!(e.kind, ErrorKind::DuplicateWord('X'));
        assert!(scan_line("o100 sub", 1).unwrap().oword.is_some());
        assert!(lex_line("O1000 (prog)", 1).unwrap().program_number);
        assert!(lex_line("G00G21G17", 1).is_ok());
    }

    #[test]
    fn line_endings() {
        let l = split_lines(b"\xEF\xBB\xBFG0 X1\rG1 X2\r\nG1 X3\nG1 X4").unwrap();
        let t: Vec<_> = l.iter().map(|(t, e)| (t.as_str(), *e)).collect();
        assert_eq!(
            t,
            vec![
                ("G0 X1", "\r"),
                ("G1 X2", "\r\n"),
                ("G1 X3", "\n"),
                ("G1 X4", "")
            ]
        );
        // Borrowed, the same cut; an invalid line ends the lines.
        let b: Vec<_> = line_slices(b"G0 X1\r\nG1 X2").map(Result::unwrap).collect();
        assert_eq!(b, vec![("G0 X1", "\r\n"), ("G1 X2", "")]);
        let e: Vec<_> = line_slices(b"G0\n(\xC3\xA9 \xFF)\nG1").collect();
        assert_eq!(e.len(), 2);
        let err = e[1].clone().unwrap_err();
        assert_eq!(
            (err.line, err.column, err.kind),
            (2, 4, ErrorKind::InvalidUtf8)
        );
    }

    /// The scanner reads characters as they come (no copy of the line):
    /// columns count characters, comments of any length are one token.
    #[test]
    fn columns_and_comments_without_a_copy_of_the_line() {
        let e = scan_line("(\u{e9}\u{e9}) G1 (a (b)", 4).unwrap_err();
        assert_eq!(
            (e.line, e.column, e.kind),
            (4, 12, ErrorKind::NestedComment)
        );
        let e = scan_line("G1 X1 (\u{e9}t\u{e9}", 1).unwrap_err();
        assert_eq!((e.column, e.kind), (7, ErrorKind::UnclosedComment));
        let e = scan_line("G1 \u{e9}", 1).unwrap_err();
        assert_eq!(
            (e.column, e.kind),
            (4, ErrorKind::UnexpectedCharacter('\u{e9}'))
        );
        let long = format!("G1 X2 ({})", "x".repeat(1 << 20));
        let l = lex_line(&long, 1).unwrap();
        assert!(l.has_comment);
        assert_eq!(l.words.len(), 2);
        assert!(scan_line("  % (x)", 1).unwrap().percent);
        assert!(!scan_line("G0 %", 1).is_ok_and(|l| l.percent));
        // A word at the end of a line with a `;` comment.
        let e = lex_line("G1 X ; \u{e9}\u{e9}", 1).unwrap_err();
        assert_eq!(e.kind, ErrorKind::MissingValue('X'));
    }
}
