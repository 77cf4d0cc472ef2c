//! Line splitting and lexing: words with spans, comments, `%` lines, block
//! delete.
//!
//! Accepted syntax (LinuxCNC, Fanuc, Mach3, grbl, CAM post-processors):
//! * words are a letter (any case) and a number, with optional spaces between
//!   the letter, the sign and the digits (`G 1`, `X - 1.5`, `X  15.000`);
//!   numbers are `[+-]digits[.digits]` or `[+-].digits`; several words per
//!   line, with or without spaces between them (`G00G21G17`);
//! * comments `( ... )` (not nested, closed on the same line) and `;` to the
//!   end of the line;
//! * a line whose first non-blank character is `%` (program delimiters);
//! * an optional block-delete `/` at the start of a line;
//! * a Fanuc program number `O1234` alone on a line (passed through).
//!
//! Rejected with an error naming line and column: malformed numbers
//! (`X1.2.3`, `X`, `Xnan`, `Xinf`, numbers that overflow f64), exponent
//! notation (`X1e5` reads as `X1` followed by the word `E5`, which the
//! interpreter passes through),
//! any character that cannot start a word, LinuxCNC parameters `#`,
//! expressions `[...]`, o-word control flow (`o100 sub`, `o<name> call`),
//! and a word letter given twice on a line (except G and M; their modal
//! groups are checked by the interpreter). Every letter A-Z (but `O`) lexes
//! as a word: the interpreter passes the lines of words it does not
//! interpret (the 3D-printer extruder word `E`) through verbatim.

use crate::error::{ErrorKind, GcodeError};

/// One word: letter (upper case) and value, with the number's text as written
/// (spaces removed) and its 1-based column (of the letter).
#[derive(Clone, Debug, PartialEq)]
pub struct Word {
    pub letter: char,
    pub value: f64,
    pub text: String,
    pub column: usize,
}

/// What a line holds after lexing.
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

/// Splits `text` into lines: `(content, line ending)`; the line ending is
/// `"\r\n"`, `"\n"` or `""` (last line without a newline). A file ending in a
/// newline has no extra empty last line. Checks UTF-8 line by line.
pub fn split_lines(text: &[u8]) -> Result<Vec<(String, &'static str)>, GcodeError> {
    let mut out = Vec::new();
    let mut rest = text;
    let mut number = 0;
    while !rest.is_empty() {
        number += 1;
        let (line, ending, next) = match rest.iter().position(|&b| b == b'\n') {
            Some(i) => {
                if i > 0 && rest[i - 1] == b'\r' {
                    (&rest[..i - 1], "\r\n", &rest[i + 1..])
                } else {
                    (&rest[..i], "\n", &rest[i + 1..])
                }
            }
            None => (rest, "", &rest[rest.len()..]),
        };
        match std::str::from_utf8(line) {
            Ok(s) => out.push((s.to_string(), ending)),
            Err(e) => {
                let good = &line[..e.valid_up_to()];
                let column = std::str::from_utf8(good).map_or(1, |s| s.chars().count() + 1);
                return Err(GcodeError::new(number, column, ErrorKind::InvalidUtf8));
            }
        }
        rest = next;
    }
    Ok(out)
}

/// Lexes one line (without its line ending). `line_no` is 1-based.
pub fn lex_line(line: &str, line_no: usize) -> Result<LexedLine, GcodeError> {
    let chars: Vec<char> = line.chars().collect();
    let err = |col: usize, kind: ErrorKind| GcodeError::new(line_no, col + 1, kind);
    let is_blank = |c: char| c == ' ' || c == '\t' || c == '\r';
    let mut out = LexedLine::default();
    let mut i = 0;
    while i < chars.len() && is_blank(chars[i]) {
        i += 1;
    }
    if i < chars.len() && chars[i] == '%' {
        out.percent = true;
        return Ok(out);
    }
    if i < chars.len() && chars[i] == '/' {
        out.block_delete = true;
        i += 1;
    }
    while i < chars.len() {
        let c = chars[i];
        if is_blank(c) {
            i += 1;
            continue;
        }
        match c {
            '(' => {
                out.has_comment = true;
                let start = i;
                i += 1;
                loop {
                    if i >= chars.len() {
                        return Err(err(start, ErrorKind::UnclosedComment));
                    }
                    match chars[i] {
                        ')' => break,
                        '(' => return Err(err(i, ErrorKind::NestedComment)),
                        _ => i += 1,
                    }
                }
                i += 1;
            }
            ';' => {
                out.has_comment = true;
                break;
            }
            '#' => return Err(err(i, ErrorKind::Unsupported("LinuxCNC parameters (#)"))),
            '[' => return Err(err(i, ErrorKind::Unsupported("expressions ([...])"))),
            _ if c.is_ascii_alphabetic() => {
                let letter = c.to_ascii_uppercase();
                let col = i;
                if letter == 'O' {
                    i = lex_o_word(&chars, i, line_no, &mut out)?;
                    continue;
                }
                let (word, next) = lex_number(&chars, i + 1, letter, col, line_no)?;
                i = next;
                if letter != 'G' && letter != 'M' && out.words.iter().any(|w| w.letter == letter) {
                    return Err(err(col, ErrorKind::DuplicateWord(letter)));
                }
                out.words.push(word);
            }
            _ => return Err(err(i, ErrorKind::UnexpectedCharacter(c))),
        }
    }
    if out.program_number && !out.words.is_empty() {
        let w = &out.words[0];
        return Err(GcodeError::new(
            line_no,
            w.column,
            ErrorKind::Unsupported("words on a line with an O program number"),
        ));
    }
    Ok(out)
}

/// An `O` word: only a Fanuc program number (`O1234`) alone on its line is
/// accepted; anything else is an o-word subroutine or control-flow statement.
fn lex_o_word(
    chars: &[char],
    start: usize,
    line_no: usize,
    out: &mut LexedLine,
) -> Result<usize, GcodeError> {
    let unsupported = GcodeError::new(
        line_no,
        start + 1,
        ErrorKind::Unsupported("o-word subroutines and control flow"),
    );
    if !out.words.is_empty() || out.program_number || out.block_delete {
        return Err(unsupported);
    }
    let mut i = start + 1;
    let d0 = i;
    while i < chars.len() && chars[i].is_ascii_digit() {
        i += 1;
    }
    if i == d0 {
        return Err(unsupported);
    }
    // Only blanks or comments may follow.
    let mut j = i;
    while j < chars.len() && (chars[j] == ' ' || chars[j] == '\t' || chars[j] == '\r') {
        j += 1;
    }
    if j < chars.len() && chars[j] != '(' && chars[j] != ';' {
        return Err(unsupported);
    }
    out.program_number = true;
    Ok(i)
}

/// Lexes the number after a word letter at `chars[i..]`.
fn lex_number(
    chars: &[char],
    mut i: usize,
    letter: char,
    col: usize,
    line_no: usize,
) -> Result<(Word, usize), GcodeError> {
    let err = |kind: ErrorKind| GcodeError::new(line_no, col + 1, kind);
    let skip_blanks = |mut i: usize| {
        while i < chars.len() && (chars[i] == ' ' || chars[i] == '\t') {
            i += 1;
        }
        i
    };
    i = skip_blanks(i);
    let mut text = String::new();
    if i < chars.len() && (chars[i] == '+' || chars[i] == '-') {
        text.push(chars[i]);
        i = skip_blanks(i + 1);
    }
    let digits_start = i;
    let mut n_digits = 0;
    let mut n_points = 0;
    while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
        if chars[i] == '.' {
            n_points += 1;
        } else {
            n_digits += 1;
        }
        text.push(chars[i]);
        i += 1;
    }
    if i == digits_start {
        if i < chars.len() {
            match chars[i] {
                '#' => return Err(err(ErrorKind::Unsupported("LinuxCNC parameters (#)"))),
                '[' => return Err(err(ErrorKind::Unsupported("expressions ([...])"))),
                _ => {}
            }
        }
        if text.is_empty() {
            return Err(err(ErrorKind::MissingValue(letter)));
        }
        return Err(err(ErrorKind::MalformedNumber { letter, text }));
    }
    if n_digits == 0 || n_points > 1 {
        return Err(err(ErrorKind::MalformedNumber { letter, text }));
    }
    let value: f64 = text.parse().map_err(|_| {
        err(ErrorKind::MalformedNumber {
            letter,
            text: text.clone(),
        })
    })?;
    if !value.is_finite() {
        return Err(err(ErrorKind::NumberOutOfRange(letter)));
    }
    Ok((
        Word {
            letter,
            value,
            text,
            column: col + 1,
        },
        i,
    ))
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
        assert!(lex_line("o100 sub", 1).unwrap_err().is_unsupported());
        assert!(lex_line("O1000 (prog)", 1).unwrap().program_number);
        assert!(lex_line("#1=2", 1).unwrap_err().is_unsupported());
        assert!(lex_line("G00G21G17", 1).is_ok());
    }
}
