//! Tool paths as the rest of the library sees them: pieces of geometry with
//! the input lines they come from, grouped in runs of feed moves.

use crate::geom::{Curve, ParamCurve, Vec3};
use alloc::vec::Vec;

/// One move of a tool path, in mm.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    pub curve: Curve,
    /// A rapid (G0) move: never smoothed, never part of a run.
    pub rapid: bool,
    /// First and last input line (1-based) this piece replaces or comes from.
    pub source_lines: (usize, usize),
    /// Programmed feed in mm/min, if any.
    pub feed: Option<f64>,
}

impl Piece {
    pub fn start(&self) -> Vec3 {
        self.curve.start()
    }
    pub fn end(&self) -> Vec3 {
        self.curve.end()
    }
}

/// A run: consecutive feed moves with nothing between them that affects
/// motion, which a smoother may blend into one continuous path. Each piece
/// starts where the previous one ends.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Run {
    pub pieces: Vec<Piece>,
}

impl Run {
    pub fn new(pieces: Vec<Piece>) -> Run {
        Run { pieces }
    }
    pub fn start(&self) -> Option<Vec3> {
        self.pieces.first().map(|p| p.start())
    }
    pub fn end(&self) -> Option<Vec3> {
        self.pieces.last().map(|p| p.end())
    }
    /// Total length, accurate to `accuracy` mm.
    pub fn length(&self, accuracy: f64) -> f64 {
        let n = self.pieces.len().max(1) as f64;
        self.pieces
            .iter()
            .map(|p| p.curve.length(accuracy / n))
            .sum()
    }
}
