//! Where a job's written text goes as it is made ([`TextOut`]): appended a
//! megabyte or so at a time while it is written, read back from there for
//! the check, and cut back where a part is written again. A long written
//! program is then never held whole: on a one-run raster written as arcs
//! the text is many times the input (measurements: docs/tuning.md,
//! `text_out`; `docs/performance.md`).
//!
//! A file (the command line writes to a temporary file that becomes the
//! output only once every part verified) and a `Vec<u8>` (the library's
//! whole-program entry point, which returns the text) are outputs.

use std::io::{self, Read, Seek, SeekFrom, Write};

/// Text held by the writer before it goes to its [`TextOut`]: enough that
/// each append is a large write, little beside a long run's curves.
pub const SPILL_BYTES: usize = 1 << 20;

/// The output of a job's text: appended to at its end, read back, cut back.
pub trait TextOut {
    /// Appends `bytes` at the end of the text.
    fn append(&mut self, bytes: &[u8]) -> io::Result<()>;
    /// The text's length so far, in bytes.
    fn written(&mut self) -> io::Result<u64>;
    /// Cuts the text back to its first `len` bytes (a part written again).
    fn cut(&mut self, len: u64) -> io::Result<()>;
    /// A reader of the text from byte `from` to its end.
    fn read_from(&mut self, from: u64) -> io::Result<Box<dyn Read + '_>>;
}

impl TextOut for Vec<u8> {
    fn append(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.extend_from_slice(bytes);
        Ok(())
    }

    fn written(&mut self) -> io::Result<u64> {
        Ok(self.len() as u64)
    }

    fn cut(&mut self, len: u64) -> io::Result<()> {
        self.truncate(usize::try_from(len).unwrap_or(usize::MAX));
        Ok(())
    }

    fn read_from(&mut self, from: u64) -> io::Result<Box<dyn Read + '_>> {
        let from = usize::try_from(from).map_or(self.len(), |f| f.min(self.len()));
        Ok(Box::new(&self[from..]))
    }
}

/// A file written from its start: appends go to its end wherever a
/// reading left the file's position.
impl TextOut for std::fs::File {
    fn append(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.seek(SeekFrom::End(0))?;
        self.write_all(bytes)
    }

    fn written(&mut self) -> io::Result<u64> {
        self.seek(SeekFrom::End(0))
    }

    fn cut(&mut self, len: u64) -> io::Result<()> {
        self.set_len(len)?;
        self.seek(SeekFrom::End(0)).map(|_| ())
    }

    fn read_from(&mut self, from: u64) -> io::Result<Box<dyn Read + '_>> {
        self.seek(SeekFrom::Start(from))?;
        Ok(Box::new(self))
    }
}

/// What the writer hands its text to as it goes ([`Spill`]); a trait so
/// that the run writer need not name the output's lifetime.
pub(crate) trait Spiller {
    /// Hands `text`'s complete lines to the output, but the last line
    /// ending (the writer may take it back, at the end of a file without
    /// one), once `text` holds [`SPILL_BYTES`].
    fn spill(&mut self, text: &mut String) -> io::Result<()>;
}

/// The text written so far to a [`TextOut`], and how many lines it holds.
pub(crate) struct Spill<'o> {
    out: &'o mut dyn TextOut,
    newlines: usize,
    last: Option<u8>,
}

impl<'o> Spill<'o> {
    pub(crate) fn new(out: &'o mut dyn TextOut) -> Spill<'o> {
        Spill {
            out,
            newlines: 0,
            last: None,
        }
    }

    fn append(&mut self, bytes: &[u8]) -> io::Result<()> {
        if let Some(&b) = bytes.last() {
            self.newlines += bytes.iter().filter(|&&c| c == b'\n').count();
            self.last = Some(b);
            self.out.append(bytes)?;
        }
        Ok(())
    }

    /// Hands all of `text` to the output; returns the lines written
    /// through this spill, counted as `str::lines` counts them (a last line
    /// without a newline is a line).
    pub(crate) fn finish(mut self, text: &mut String) -> io::Result<usize> {
        self.append(text.as_bytes())?;
        text.clear();
        Ok(self.newlines + usize::from(self.last.is_some_and(|b| b != b'\n')))
    }
}

impl Spiller for Spill<'_> {
    fn spill(&mut self, text: &mut String) -> io::Result<()> {
        if text.len() < SPILL_BYTES {
            return Ok(());
        }
        let Some(nl) = text.rfind(['\n', '\r']) else {
            return Ok(());
        };
        // Keep the last line ending whole ("\r\n" too).
        let b = text.as_bytes();
        let keep = if nl > 0 && b[nl] == b'\n' && b[nl - 1] == b'\r' {
            nl - 1
        } else {
            nl
        };
        self.append(&text.as_bytes()[..keep])?;
        text.drain(..keep);
        Ok(())
    }
}

/// Reads `source` to its end and hands its complete lines to `lines` a
/// chunk at a time (each chunk ends just after a `'\n'`, the last one
/// where the text ends), so that no more than a chunk and a line are held.
/// A line ending is never cut (a `"\r\n"` ends with its `'\n'`; a lone
/// `'\r'` ends a line inside a chunk as in the whole text), so the lines
/// the chunks are cut into are the whole text's.
pub(crate) fn for_each_chunk<E>(
    source: &mut dyn Read,
    chunk: usize,
    mut lines: impl FnMut(&[u8], bool) -> Result<(), E>,
    io_error: impl Fn(io::Error) -> E,
) -> Result<(), E> {
    let mut buf: Vec<u8> = Vec::new();
    let mut first = true;
    loop {
        let start = buf.len();
        let n = (&mut *source)
            .take(chunk as u64)
            .read_to_end(&mut buf)
            .map_err(&io_error)?;
        if n == 0 {
            if !buf.is_empty() {
                lines(&buf, first)?;
            }
            return Ok(());
        }
        if let Some(nl) = buf[start..].iter().rposition(|&b| b == b'\n') {
            let end = start + nl + 1;
            lines(&buf[..end], first)?;
            first = false;
            buf.drain(..end);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With each line ending: the text handed out is the text, the last
    /// line ending always stays with the writer, and the lines are counted
    /// as `str::lines` counts them (a lone CR ends no line there).
    #[test]
    fn spilled_text_is_the_text_and_its_lines_are_counted() {
        for eol in ["\n", "\r\n", "\r"] {
            let line = format!("G1 X1.000 Y2.000{eol}");
            let mut out: Vec<u8> = Vec::new();
            let mut spill = Spill::new(&mut out);
            let mut text = String::new();
            let mut whole = String::new();
            for _ in 0..(3 * SPILL_BYTES / line.len()) {
                text.push_str(&line);
                whole.push_str(&line);
                spill.spill(&mut text).unwrap();
                assert!(text.ends_with(eol), "the last line ending stays");
            }
            text.push_str("M2");
            whole.push_str("M2");
            let lines = spill.finish(&mut text).unwrap();
            assert_eq!(out, whole.as_bytes(), "{eol:?}");
            assert_eq!(lines, whole.lines().count(), "{eol:?}");
        }
    }

    #[test]
    fn chunks_cut_after_line_feeds_hold_the_whole_text() {
        let text = b"a\r\nbb\rccc\n\ndddd\r\neeeee";
        for chunk in 1..text.len() + 2 {
            let mut got = Vec::new();
            let mut firsts = 0;
            for_each_chunk(
                &mut &text[..],
                chunk,
                |c: &[u8], first| -> Result<(), io::Error> {
                    assert!(c.ends_with(b"\n") || c.ends_with(b"eeeee"), "{c:?}");
                    firsts += usize::from(first);
                    got.extend_from_slice(c);
                    Ok(())
                },
                |e| e,
            )
            .unwrap();
            assert_eq!(got, text, "chunk {chunk}");
            assert_eq!(firsts, 1);
        }
    }

    #[test]
    fn a_file_is_appended_read_back_and_cut() {
        let mut f = tempfile::tempfile().unwrap();
        f.append(b"one\ntwo\n").unwrap();
        let mut s = String::new();
        f.read_from(4).unwrap().read_to_string(&mut s).unwrap();
        assert_eq!(s, "two\n");
        f.append(b"three\n").unwrap();
        assert_eq!(f.written().unwrap(), 14);
        f.cut(8).unwrap();
        f.append(b"four\n").unwrap();
        s.clear();
        f.read_from(0).unwrap().read_to_string(&mut s).unwrap();
        assert_eq!(s, "one\ntwo\nfour\n");
    }
}
