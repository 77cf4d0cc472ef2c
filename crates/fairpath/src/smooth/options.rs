//! Errors of method options: which method, which option, which value, and
//! what is allowed. Every method validates its options once, before any
//! work ([`crate::choose::Method::validate`] at the front door; again in
//! `smooth_run` for callers that build a method by hand).

use alloc::format;
use alloc::string::String;

/// An option of a method out of its range.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("method {method}: option {option} = {value}: {expected}")]
pub struct OptionError {
    /// The method's command-line name.
    pub method: &'static str,
    /// The option's name (as in a TOML file of options).
    pub option: &'static str,
    /// The value given.
    pub value: String,
    /// What is allowed, e.g. "must be in [0, 1)".
    pub expected: &'static str,
}

/// `Ok` when `ok`, else the [`OptionError`] for `option = value`.
pub(crate) fn require(
    ok: bool,
    method: &'static str,
    option: &'static str,
    value: impl core::fmt::Debug,
    expected: &'static str,
) -> Result<(), OptionError> {
    if ok {
        Ok(())
    } else {
        Err(OptionError {
            method,
            option,
            value: format!("{value:?}"),
            expected,
        })
    }
}
