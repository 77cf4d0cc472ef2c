//! G-code reader and writers for fairpath.
pub mod error;
pub mod interp;
pub mod lexer;
pub mod program;

pub use error::{ErrorKind, GcodeError};
pub use interp::parse;
pub use program::{Program, Units};
