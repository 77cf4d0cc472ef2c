//! JSON output (always mm) of every move of a program, with runs replaced by
//! their smoothed pieces, and the matching reader.
//!
//! ```json
//! {"units": "mm", "pieces": [
//!   {"type": "line", "p0": [x,y,z], "p1": [x,y,z], "rapid": false,
//!    "source_lines": [a, b], "feed": 1000.0},
//!   {"type": "nurbs", "degree": 3, "knots": [...], "points": [[x,y,z], ...],
//!    "weights": null, "rapid": false, "source_lines": [a, b], "feed": null}
//! ]}
//! ```
//!
//! Circular arcs are written as exact rational quadratic NURBS
//! ([`Nurbs::from_circular_arc`]); helical and spiral arcs as cubic
//! approximations within [`ARC_APPROX_MM`] ([`Nurbs::approximate`]). Numbers
//! use the shortest representation that reads back to the same f64.
//! `feed` (mm/min or null) is an addition to the minimal format.

use crate::error::{JsonError, WriteError};
use crate::program::Program;
use fairpath::geom::{Curve, Line, Nurbs, Vec3};
use fairpath::path::Piece;
use serde::{Deserialize, Serialize};

/// Accuracy (mm) of the cubic NURBS written for helical and spiral arcs.
pub const ARC_APPROX_MM: f64 = 1e-4;

/// Relative tolerance under which an arc counts as circular (no rise, equal
/// radii) and is written exactly.
const CIRCULAR_TOL_MM: f64 = 1e-12;

#[derive(Serialize, Deserialize)]
struct JsonProgram {
    units: String,
    pieces: Vec<JsonPiece>,
}

#[derive(Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase")]
enum JsonPiece {
    Line {
        p0: [f64; 3],
        p1: [f64; 3],
        rapid: bool,
        source_lines: [usize; 2],
        #[serde(default)]
        feed: Option<f64>,
    },
    Nurbs {
        degree: usize,
        knots: Vec<f64>,
        points: Vec<[f64; 3]>,
        weights: Option<Vec<f64>>,
        rapid: bool,
        source_lines: [usize; 2],
        #[serde(default)]
        feed: Option<f64>,
    },
}

fn to_json_piece(p: &Piece) -> Result<JsonPiece, WriteError> {
    let source_lines = [p.source_lines.0, p.source_lines.1];
    let nurbs = match &p.curve {
        Curve::Line(l) => {
            if !(l.p0.is_finite() && l.p1.is_finite()) {
                return Err(WriteError::NotFinite);
            }
            return Ok(JsonPiece::Line {
                p0: l.p0.to_array(),
                p1: l.p1.to_array(),
                rapid: p.rapid,
                source_lines,
                feed: p.feed,
            });
        }
        Curve::Arc(a) => {
            let tol = CIRCULAR_TOL_MM * a.r0.abs().max(1.0);
            if a.is_circular(tol) {
                Nurbs::from_circular_arc(a)
            } else {
                Nurbs::approximate(&**a, ARC_APPROX_MM)
            }
        }
        Curve::Nurbs(n) => (**n).clone(),
    };
    if nurbs.points.iter().any(|q| !q.is_finite()) || nurbs.knots.iter().any(|k| !k.is_finite()) {
        return Err(WriteError::NotFinite);
    }
    Ok(JsonPiece::Nurbs {
        degree: nurbs.degree,
        knots: nurbs.knots,
        points: nurbs.points.iter().map(|q| q.to_array()).collect(),
        weights: nurbs.weights,
        rapid: p.rapid,
        source_lines,
        feed: p.feed,
    })
}

/// Every move of the program in order, in mm: rapids (`"rapid": true`),
/// pinned moves and moves outside runs as they are, and each run's moves
/// replaced by `smoothed[k]` (same order as [`Program::runs`]).
pub fn write_json(program: &Program, smoothed: &[Vec<Piece>]) -> Result<String, WriteError> {
    let runs = program.run_spans();
    if smoothed.len() != runs.len() {
        return Err(WriteError::RunCount {
            expected: runs.len(),
            got: smoothed.len(),
        });
    }
    let moves = program.moves();
    let mut pieces = Vec::with_capacity(moves.len());
    let mut i = 0;
    let mut r = 0;
    while i < moves.len() {
        if r < runs.len() && runs[r].moves.start == i {
            for p in &smoothed[r] {
                pieces.push(to_json_piece(p)?);
            }
            i = runs[r].moves.end;
            r += 1;
        } else {
            pieces.push(to_json_piece(&moves[i].piece)?);
            i += 1;
        }
    }
    let doc = JsonProgram {
        units: "mm".into(),
        pieces,
    };
    serde_json::to_string(&doc).map_err(|_| WriteError::NotFinite)
}

/// Reads the pieces back from [`write_json`]'s output (lines and NURBS).
/// Every piece is checked as the library's constructors check curves
/// ([`Nurbs::new`]: degree 1 to [`Nurbs::MAX_DEGREE`], knot count and
/// order, finite values, positive weights): an invalid piece is a
/// [`JsonError::Piece`] naming its index (from 0) and the reason.
pub fn read_json(text: &str) -> Result<Vec<Piece>, JsonError> {
    let doc: JsonProgram = serde_json::from_str(text)?;
    if doc.units != "mm" {
        return Err(JsonError::Units(doc.units));
    }
    let mut out = Vec::with_capacity(doc.pieces.len());
    for (index, p) in doc.pieces.into_iter().enumerate() {
        let bad = |message: String| JsonError::Piece { index, message };
        let piece = match p {
            JsonPiece::Line {
                p0,
                p1,
                rapid,
                source_lines,
                feed,
            } => {
                let (a, b) = (Vec3::from_array(p0), Vec3::from_array(p1));
                // The difference too: every length and direction is taken
                // from it (1e308 and -1e308 are finite, their distance not).
                if !(a.is_finite() && b.is_finite() && (b - a).is_finite()) {
                    return Err(bad("non-finite coordinate".into()));
                }
                Piece {
                    curve: Curve::Line(Line::new(a, b)),
                    rapid,
                    source_lines: (source_lines[0], source_lines[1]),
                    feed,
                }
            }
            JsonPiece::Nurbs {
                degree,
                knots,
                points,
                weights,
                rapid,
                source_lines,
                feed,
            } => {
                let pts = points.into_iter().map(Vec3::from_array).collect();
                let n = Nurbs::new(degree, knots, pts, weights)
                    .map_err(|e| bad(format!("invalid NURBS: {e}")))?;
                Piece {
                    curve: Curve::from(n),
                    rapid,
                    source_lines: (source_lines[0], source_lines[1]),
                    feed,
                }
            }
        };
        if let Some(f) = piece.feed {
            if !(f.is_finite() && f >= 0.0) {
                return Err(JsonError::Piece {
                    index,
                    message: "feed must be finite and not negative".into(),
                });
            }
        }
        out.push(piece);
    }
    Ok(out)
}
