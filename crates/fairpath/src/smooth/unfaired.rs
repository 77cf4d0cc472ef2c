//! Curves a method left as they are although it smooths their kind, and
//! why: what method `fair` reports for the curves the thesis' fairing
//! cannot take ([`crate::geom::tube_fair::as_fairable`]) where it keeps
//! them (see [`crate::smooth::OtherCurves`]).
//!
//! Such a curve is kept exactly as written (it is trivially within the
//! tolerance of itself) and the rest of the program is smoothed: refusing
//! the whole program for one rational arc among thousands of B-splines
//! would help no one, but a user must see that it was not faired, so the
//! report counts them by reason with the first input line
//! ([`crate::smooth::SmoothedRun::unfaired`]; the CLI prints it).

use crate::geom::tube_fair::TubeFairError;
use core::fmt;

/// Why a curve was left unfaired.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum UnfairedReason {
    /// A rational NURBS (weights differ): an exact conic, not faired.
    Rational,
    /// Degree 4 and above: no exact cubic of it.
    Degree(usize),
    /// The curve jumps at a knot.
    Discontinuous,
    /// Not a valid NURBS.
    Invalid,
}

impl fmt::Display for UnfairedReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UnfairedReason::Rational => f.write_str("rational (weights differ)"),
            UnfairedReason::Degree(d) => write!(f, "degree {d} (no exact cubic)"),
            UnfairedReason::Discontinuous => f.write_str("jumps at a knot"),
            UnfairedReason::Invalid => f.write_str("invalid curve"),
        }
    }
}

impl UnfairedReason {
    /// The reason for a fairing error, `None` for an option error (which is
    /// the caller's, not the curve's).
    pub fn from_error(e: &TubeFairError) -> Option<UnfairedReason> {
        Some(match e {
            TubeFairError::BadOption { .. } => return None,
            TubeFairError::Rational => UnfairedReason::Rational,
            TubeFairError::Degree(d) => UnfairedReason::Degree(*d),
            TubeFairError::Discontinuous(_) => UnfairedReason::Discontinuous,
            TubeFairError::NotClamped | TubeFairError::Invalid(_) => UnfairedReason::Invalid,
        })
    }
}

/// A curve left as it was.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Unfaired {
    /// Its input lines (first, last), as the piece has them.
    pub source_lines: (usize, usize),
    pub reason: UnfairedReason,
}
