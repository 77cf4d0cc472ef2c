//! Usage errors and the exit codes: a value on the command line that is
//! wrong exits 2 as clap's own parse errors do, whether clap or a check
//! after parsing finds it; a program that does not verify exits 3 where a
//! command documents it; every other error exits 1.

use std::fmt;

/// Exit status of a usage error: a flag or value the command line got
/// wrong (clap's own status for the errors it finds).
pub const EXIT_USAGE: u8 = 2;
/// Exit status of `check` and `compare` when a program fails to verify.
pub const EXIT_NOT_VERIFIED: u8 = 3;
/// Exit status of any other error (unreadable or malformed input, a
/// `smooth` result that failed its check and was not written, I/O).
pub const EXIT_ERROR: u8 = 1;

/// The exit codes as `--help` prints them.
pub const EXIT_CODES_HELP: &str = "\
Exit status:
  0  success
  1  error: input unreadable or not G-code we read, a smoothed result that
     failed its own check (nothing written), a file that cannot be written
  2  usage: an unknown flag or a bad value (negative tolerance, unknown
     method, -o naming the input without --in-place, ...)
  3  check, compare: a program that does not stay within the tolerance";

/// A value on the command line that is wrong, found after parsing: the
/// binary exits [`EXIT_USAGE`] for it. The message names the flag and the
/// value and says what to give instead.
#[derive(Debug)]
pub struct UsageError(pub String);

impl fmt::Display for UsageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// A [`UsageError`] as an `anyhow::Error`.
pub fn usage(message: impl fmt::Display) -> anyhow::Error {
    anyhow::Error::new(UsageError(message.to_string()))
}

/// The exit status for an error: [`EXIT_USAGE`] when a [`UsageError`] is
/// anywhere in its chain, else [`EXIT_ERROR`].
pub fn exit_status(e: &anyhow::Error) -> u8 {
    if is_usage(e) {
        EXIT_USAGE
    } else {
        EXIT_ERROR
    }
}

/// Whether `e` is (or wraps) a [`UsageError`].
pub fn is_usage(e: &anyhow::Error) -> bool {
    e.chain().any(|c| c.is::<UsageError>())
}
