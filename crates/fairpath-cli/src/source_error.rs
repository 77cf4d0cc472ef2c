//! A reader error shown as compilers show theirs: `file:line:column:
//! message`, then the source line with a caret under the column, then a
//! hint of what to do.

use fairpath_gcode::lang::error::LangError;
use fairpath_gcode::{ErrorKind, GcodeError};
use std::fmt;

/// A reader error with the text of its line.
#[derive(Debug)]
pub struct SourceError {
    /// The file as named on the command line (`<stdin>` for `-`).
    pub file: String,
    pub error: GcodeError,
    /// The line's text (lossy UTF-8, without its line break); `None` when
    /// the line is past the end of the text.
    pub source_line: Option<String>,
    pub hint: &'static str,
}

impl SourceError {
    /// `error` in `bytes`, the text of the file `file`.
    pub fn new(file: &str, bytes: &[u8], error: &GcodeError) -> SourceError {
        SourceError {
            file: file.to_string(),
            error: error.clone(),
            source_line: line_text(bytes, error.line),
            hint: hint(error),
        }
    }
}

/// Line `n` (1-based) of `bytes`: lines end at LF, CR LF or a lone CR, as
/// the reader counts them; a byte-order mark at the start is not shown.
fn line_text(bytes: &[u8], n: usize) -> Option<String> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let mut line = 1;
    let mut start = 0;
    let mut i = 0;
    while i < bytes.len() {
        let end_here = match bytes[i] {
            b'\n' => Some(i + 1),
            b'\r' if bytes.get(i + 1) == Some(&b'\n') => Some(i + 2),
            b'\r' => Some(i + 1),
            _ => None,
        };
        if let Some(next) = end_here {
            if line == n {
                return Some(String::from_utf8_lossy(&bytes[start..i]).into_owned());
            }
            line += 1;
            start = next;
            i = next;
        } else {
            i += 1;
        }
    }
    (line == n && start < bytes.len())
        .then(|| String::from_utf8_lossy(&bytes[start..]).into_owned())
}

/// What to do about an error, in one line.
fn hint(e: &GcodeError) -> &'static str {
    match &e.kind {
        ErrorKind::InvalidUtf8 => "save the program as ASCII or UTF-8",
        ErrorKind::UnexpectedCharacter(_) => "remove the character or put it in a comment ( ... )",
        ErrorKind::UnclosedComment => "close the comment with ) on the same line",
        ErrorKind::NestedComment => "comments do not nest: remove the inner (",
        ErrorKind::MissingValue(_) => "give the word a number (e.g. X1.5) or remove it",
        ErrorKind::MalformedNumber { .. } => "write the number as digits with one decimal point",
        ErrorKind::DuplicateWord(_) => "keep one of the two words, or split the line",
        ErrorKind::ConflictingGCodes(_) | ErrorKind::ConflictingMCodes => {
            "split the line: one code of each modal group per line"
        }
        ErrorKind::NoMotionMode => "give a motion code (G0, G1, G2, G3) before the axis words",
        ErrorKind::ArcWithoutCenter => "give the centre as I/J/K or the radius as R",
        ErrorKind::ArcRadiusAndCenter => "give either I/J/K or R, not both",
        ErrorKind::ArcRadiusMismatch { .. } | ErrorKind::ArcRadiusTooSmall { .. } => {
            "check the arc's end point and centre (or radius): they do not make one circle"
        }
        ErrorKind::Language(LangError::EndlessLoop | LangError::TooManyLines(_)) => {
            "make each pass of the loop change what its condition reads (e.g. add 1 to its \
             counter); LinuxCNC would run it until stopped"
        }
        _ if e.is_unsupported() => {
            "fairpath does not read this: rewrite the line without it, or post the program \
             for plain RS274 (see docs/real-programs.md)"
        }
        _ => "correct the line as the message says; LinuxCNC would refuse it too",
    }
}

impl fmt::Display for SourceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.file, self.error)?;
        if let Some(text) = &self.source_line {
            let number = self.error.line.to_string();
            let pad = " ".repeat(number.len());
            // Tabs before the column stay tabs, so that the caret lines up.
            let under: String = text
                .chars()
                .take(self.error.column.saturating_sub(1))
                .map(|c| if c == '\t' { '\t' } else { ' ' })
                .collect();
            write!(
                f,
                "\n{pad} |\n{number} | {text}\n{pad} | {under}^\n{pad} = hint: {}",
                self.hint
            )?;
        } else {
            write!(f, "\n  = hint: {}", self.hint)?;
        }
        Ok(())
    }
}

impl std::error::Error for SourceError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_are_counted_as_the_reader_counts_them() {
        let text = b"\xEF\xBB\xBFa\r\nb\rc\nd";
        assert_eq!(line_text(text, 1).as_deref(), Some("a"));
        assert_eq!(line_text(text, 2).as_deref(), Some("b"));
        assert_eq!(line_text(text, 3).as_deref(), Some("c"));
        assert_eq!(line_text(text, 4).as_deref(), Some("d"));
        assert_eq!(line_text(text, 5), None);
    }

    /// An endless loop's hint says what to change, not that LinuxCNC
    /// would refuse the program (it runs it until stopped).
    #[test]
    fn an_endless_loop_is_told_how_to_end() {
        let text = b"G0 X0\no1 while [1]\nG1 X1 F100\no1 endwhile\n";
        let e = fairpath_gcode::parse(text).unwrap_err();
        let shown = SourceError::new("p.ngc", text, &e).to_string();
        assert!(shown.starts_with("p.ngc:2:1: endless loop"), "{shown}");
        assert!(
            shown.contains("hint: make each pass of the loop change"),
            "{shown}"
        );
        assert!(!shown.contains("would refuse"), "{shown}");
    }

    #[test]
    fn the_caret_is_under_the_column() {
        let text = b"G1 X1\n\tG1 X2 Q\n";
        let e = fairpath_gcode::parse(text).unwrap_err();
        let shown = SourceError::new("p.ngc", text, &e).to_string();
        let lines: Vec<&str> = shown.lines().collect();
        assert!(lines[0].starts_with("p.ngc:2:"), "{shown}");
        assert_eq!(lines[2], "2 | \tG1 X2 Q", "{shown}");
        let caret = lines[3].find('^').unwrap() - "  | ".len();
        let col = lines[2]["2 | ".len()..].find('Q').unwrap();
        assert_eq!(caret, col, "{shown}");
        assert!(lines[4].contains("hint:"), "{shown}");
    }
}
