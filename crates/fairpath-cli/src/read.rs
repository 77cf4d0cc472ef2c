//! Reading programs from files: errors read `file:line:column: message`.

use anyhow::{anyhow, bail, Context, Result};
use fairpath_gcode::{ParseOptions, Program};
use std::path::Path;

/// Reads and parses a program; errors read `file:line:column: message`.
pub fn read_program(path: &Path) -> Result<Program> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
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
        bail!("{}: empty program", path.display());
    }
    fairpath_gcode::parse_with(bytes, opts).map_err(|e| anyhow!("{}:{e}", path.display()))
}
