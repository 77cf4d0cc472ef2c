//! Reading programs from files or standard input (`-`): errors read
//! `file:line:column: message`, then the line with a caret under the
//! column and a hint of what to do ([`crate::source_error`]).

use crate::source_error::SourceError;
use anyhow::{anyhow, bail, Context, Result};
use fairpath::path::Run;
use fairpath_gcode::program::MotionOutline;
use fairpath_gcode::{ParseOptions, Program};
use std::io::Read;
use std::path::Path;

/// Whether a path on the command line is `-`: standard input or output.
pub fn is_stdio(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// How a path is named in messages: `<stdin>` for `-`.
pub fn name(path: &Path) -> String {
    if is_stdio(path) {
        "<stdin>".to_string()
    } else {
        path.display().to_string()
    }
}

/// The bytes of a file, or of standard input for `-`.
pub fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    if is_stdio(path) {
        let mut bytes = Vec::new();
        std::io::stdin()
            .lock()
            .read_to_end(&mut bytes)
            .context("cannot read standard input")?;
        Ok(bytes)
    } else {
        std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))
    }
}

/// Reads and parses a program (standard input for `-`); errors read
/// `file:line:column: message` with the line and a caret.
pub fn read_program(path: &Path) -> Result<Program> {
    let bytes = read_bytes(path)?;
    parse_program(path, &bytes)
}

/// Parses a program read with the default [`ParseOptions`] (the
/// block-delete switch off). A program without moves (tool changes,
/// coolant ...) is a program: callers say what they make of it.
pub fn parse_program(path: &Path, bytes: &[u8]) -> Result<Program> {
    parse_program_with(path, bytes, &ParseOptions::default())
}

/// [`parse_program`] with `opts` (the block-delete switch).
pub fn parse_program_with(path: &Path, bytes: &[u8], opts: &ParseOptions) -> Result<Program> {
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        bail!("{}: empty program", name(path));
    }
    fairpath_gcode::parse_with(bytes, opts)
        .map_err(|e| anyhow!(SourceError::new(&name(path), bytes, &e)))
}

/// A program read for its motion only ([`fairpath_gcode::read_motion`]:
/// its motions in order and its runs, as [`Program::runs`] gives them with
/// the block-delete switch off, without holding its lines: a program of
/// 200 MB of comments is not held as 2 million lines); errors as
/// [`parse_program`]'s.
pub fn read_motion_of(path: &Path, bytes: &[u8]) -> Result<(Vec<MotionOutline>, Vec<Run>)> {
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        bail!("{}: empty program", name(path));
    }
    fairpath_gcode::read_motion(bytes)
        .map_err(|e| anyhow!(SourceError::new(&name(path), bytes, &e)))
}
