//! Errors of LinuxCNC's language: expressions, parameters, o-words, polar
//! coordinates. They reach users as [`crate::ErrorKind::Language`] inside a
//! [`crate::GcodeError`] that names the line and column.

use thiserror::Error;

/// What went wrong in an expression, a parameter or an o-word.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum LangError {
    #[error("expression: {0}")]
    Syntax(&'static str),
    #[error("division by zero")]
    DivideByZero,
    #[error("negative number raised to a non-integer power")]
    NegativePower,
    #[error("argument of {0} out of range")]
    Domain(&'static str),
    #[error("calculation results in {0}")]
    NotFinite(&'static str),
    #[error("parameter number {0} out of range (1 to 5601)")]
    ParameterRange(f64),
    #[error("non-integer value {0} where an integer is needed")]
    NotInteger(f64),
    #[error("named parameter #<{0}> not defined")]
    UndefinedNamed(String),
    /// A parameter whose value lives in the machine (its parameter file,
    /// tool table, spindle, ...), which a reader of program coordinates
    /// cannot know.
    #[error("parameter {name}: {why}")]
    UnknownParameter { name: String, why: &'static str },
    #[error("cannot assign to read-only parameter {0}")]
    ReadOnly(String),
    /// Assigning a system parameter the reader cannot follow.
    #[error("assignment to {name}: {why}")]
    UnsupportedAssignment { name: String, why: &'static str },
    #[error("o-word: {0}")]
    OWordSyntax(&'static str),
    #[error("unknown o-word command {0:?}")]
    UnknownOCommand(String),
    #[error("o{name} {found} has no matching {expected}")]
    Unmatched {
        name: String,
        found: &'static str,
        expected: &'static str,
    },
    #[error("subroutine o{0} is not defined in this program (fairpath does not read external subroutine files)")]
    UndefinedSubroutine(String),
    #[error("subroutine o{0} is defined twice")]
    DuplicateSubroutine(String),
    #[error("subroutine calls nested deeper than {0} levels (LinuxCNC's limit)")]
    CallDepth(usize),
    #[error("more than {0} lines executed (endless loop or recursion?)")]
    TooManyLines(usize),
    #[error(
        "endless loop: its condition holds again after a pass that changed no parameter and no state of the machine the loop reads"
    )]
    EndlessLoop,
    #[error("polar coordinates: {0}")]
    Polar(&'static str),
}

impl LangError {
    /// True for valid LinuxCNC input the reader cannot follow (parameters
    /// of the machine, external subroutines), as opposed to errors
    /// LinuxCNC reports too.
    pub fn is_unsupported(&self) -> bool {
        matches!(
            self,
            LangError::UnknownParameter { .. }
                | LangError::UnsupportedAssignment { .. }
                | LangError::UndefinedSubroutine(_)
        )
    }
}
