//! Typed errors of the reader and writers. Every reader error names the
//! 1-based line and column of the offending text.

use thiserror::Error;

/// A reader error at a position of the input. Displays as
/// `line:column: message`.
#[derive(Clone, Debug, PartialEq, Error)]
#[error("{line}:{column}: {kind}")]
pub struct GcodeError {
    /// 1-based line number.
    pub line: usize,
    /// 1-based column (in characters; bytes for invalid UTF-8).
    pub column: usize,
    pub kind: ErrorKind,
}

impl GcodeError {
    pub fn new(line: usize, column: usize, kind: ErrorKind) -> GcodeError {
        GcodeError { line, column, kind }
    }

    /// True for input that is valid G-code of some dialect but uses a feature
    /// this reader does not support (parameters, expressions, o-words,
    /// splines, canned cycles, ...), as opposed to malformed input.
    pub fn is_unsupported(&self) -> bool {
        matches!(
            self.kind,
            ErrorKind::Unsupported(_)
                | ErrorKind::UnsupportedGCode(_)
                | ErrorKind::UnsupportedWord(_)
        ) || matches!(&self.kind, ErrorKind::Language(l) if l.is_unsupported())
    }
}

/// What went wrong.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum ErrorKind {
    // ---- lexical ----
    #[error("invalid UTF-8")]
    InvalidUtf8,
    #[error("unexpected character {0:?}")]
    UnexpectedCharacter(char),
    #[error("comment not closed before the end of the line")]
    UnclosedComment,
    #[error("nested '(' inside a comment")]
    NestedComment,
    #[error("word {0} has no number")]
    MissingValue(char),
    #[error("malformed number for word {letter}: {text:?}")]
    MalformedNumber { letter: char, text: String },
    #[error("number for word {0} is out of range")]
    NumberOutOfRange(char),
    #[error("word {0} appears twice on one line")]
    DuplicateWord(char),
    // ---- unsupported features ----
    #[error("unsupported: {0}")]
    Unsupported(&'static str),
    #[error("unsupported G code G{0}")]
    UnsupportedGCode(String),
    #[error("unsupported word {0}")]
    UnsupportedWord(char),
    // ---- semantic ----
    #[error("unknown G code G{0}")]
    UnknownGCode(String),
    #[error("two G codes of the same modal group ({0}) on one line")]
    ConflictingGCodes(&'static str),
    #[error("two M codes of the same modal group on one line")]
    ConflictingMCodes,
    #[error("two commands on one line use the axis words")]
    ConflictingAxisUsers,
    #[error("axis words without a motion mode (after G80 or at program start)")]
    NoMotionMode,
    #[error("G2/G3 without any axis word")]
    ArcWithoutAxes,
    #[error("G2/G3 needs either a centre (I/J/K) or a radius R")]
    ArcWithoutCenter,
    #[error("G2/G3 has both a radius R and centre words")]
    ArcRadiusAndCenter,
    #[error("centre word {0} is not in the selected plane")]
    ArcOffPlaneCenter(char),
    #[error("R-form arc with the end point equal to the start point")]
    ArcRadiusFullCircle,
    #[error("arc radius {radius} is too small to reach the end point (half chord {half_chord})")]
    ArcRadiusTooSmall { radius: f64, half_chord: f64 },
    #[error("arc radius differs between start ({r_start}) and end ({r_end}) by more than {tolerance} (program units)")]
    ArcRadiusMismatch {
        r_start: f64,
        r_end: f64,
        tolerance: f64,
    },
    #[error("degenerate arc: start or end coincides with the centre")]
    ArcZeroRadius,
    #[error("P (number of turns) must be a positive integer, got {0}")]
    BadTurns(f64),
    #[error("value of {0} is out of range")]
    BadValue(char),
    #[error(transparent)]
    Spline(#[from] SplineError),
    /// Expressions, parameters, o-words, polar coordinates.
    #[error(transparent)]
    Language(#[from] crate::lang::error::LangError),
    #[error(transparent)]
    Cycle(#[from] CycleError),
}

/// Canned cycles LinuxCNC refuses (its messages, from interp_cycles.cc).
#[derive(Clone, Debug, PartialEq, Error)]
pub enum CycleError {
    #[error("{code} needs the word {letter} (the first cycle after another motion mode)")]
    MissingWord { code: &'static str, letter: char },
    #[error("canned cycle with zero feed rate")]
    ZeroFeed,
    #[error("canned cycles cannot run in inverse time feed mode (G93)")]
    InverseTime,
    #[error("canned cycles cannot run with cutter radius compensation on")]
    CutterComp,
    #[error("L (repeats) must be a positive integer, got {0}")]
    BadRepeats(f64),
    #[error("R plane ({r}) below the bottom of the cycle ({bottom})")]
    RBelowBottom { r: f64, bottom: f64 },
    #[error("Q (peck depth) must be positive, got {0}")]
    BadPeck(f64),
    #[error("canned cycles take no {0} word (LinuxCNC moves no rotary or UVW axis in them)")]
    AxisWord(char),
    #[error("{code} needs the spindle turning {turning}")]
    Spindle {
        code: &'static str,
        turning: &'static str,
    },
}

/// Malformed spline blocks (G5, G5.1, G5.2/G5.3, G6.2).
#[derive(Clone, Debug, PartialEq, Error)]
pub enum SplineError {
    #[error("{0} block is not closed")]
    NotClosed(&'static str),
    #[error("G5.3 without an open G5.2 block")]
    EndWithoutBlock,
    #[error("{code} needs the word {letter}")]
    MissingWord { code: &'static str, letter: char },
    #[error("{code}: a control point needs both {first} and {second}")]
    AxisPair {
        code: &'static str,
        first: char,
        second: char,
    },
    #[error("{code} does not take the word {letter} (in this plane)")]
    WordNotAllowed { code: &'static str, letter: char },
    #[error("weight must be positive, got {0}")]
    BadWeight(f64),
    #[error("order must be an integer from {min} to {max}, got {value}")]
    BadOrder { value: f64, min: usize, max: usize },
    #[error("{points} control points, fewer than the order {order}")]
    TooFewPoints { points: usize, order: usize },
    #[error("knot {knot} is below the knot before it ({previous})")]
    KnotsDecreasing { previous: f64, knot: f64 },
    #[error("G6.2 knot vector: {0}")]
    KnotVector(&'static str),
    #[error("inside a spline block: {0}")]
    InBlock(&'static str),
    #[error("G5 without I and J must follow another G5")]
    NoPreviousG5,
    #[error("Q must be 1, 2 or 3 (LinuxCNC's G6.2 method), got {0}")]
    BadMethod(f64),
    #[error("G5/G5.1 with cutter radius compensation (LinuxCNC refuses it)")]
    CutterComp,
}

/// Errors of the writers and of [`crate::read_json`].
#[derive(Debug, Error)]
pub enum WriteError {
    #[error("{expected} smoothed runs expected, {got} given")]
    RunCount { expected: usize, got: usize },
    #[error("chord tolerance must be positive and finite, got {0}")]
    BadChord(f64),
    /// The chord tolerance is smaller than the rounding of coordinates
    /// written with the most decimals the writer uses.
    #[error(
        "chord tolerance {chord_mm} mm is below the rounding of {decimals} decimals ({rounding_mm:e} mm)"
    )]
    ChordBelowRounding {
        chord_mm: f64,
        decimals: usize,
        rounding_mm: f64,
    },
    #[error("a smoothed piece has a non-finite coordinate")]
    NotFinite,
    /// A spline block writer was given options it cannot honour.
    #[error("spline writer: {0}")]
    SplineOptions(&'static str),
    /// The curve is not one the asked block can describe.
    #[error("spline writer: {0}")]
    SplineCurve(String),
    /// A G5.2 curve (or a G6.2 curve for LinuxCNC) leaves its plane.
    #[error("the curve leaves the {plane} plane by {deviation_mm} mm (more than the {allowed_mm} mm the written coordinates resolve)")]
    NotPlanar {
        plane: &'static str,
        deviation_mm: f64,
        allowed_mm: f64,
    },
    /// The output ([`crate::text_out::TextOut`]) refused the text.
    #[error("writing the output")]
    Output(#[source] std::io::Error),
}

/// Errors of [`crate::read_json`].
#[derive(Debug, Error)]
pub enum JsonError {
    #[error("JSON: {0}")]
    Syntax(#[from] serde_json::Error),
    #[error("piece {index}: {message}")]
    Piece { index: usize, message: String },
    #[error("units {0:?} not supported (only \"mm\")")]
    Units(String),
}
