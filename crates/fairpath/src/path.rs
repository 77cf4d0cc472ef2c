//! Tool paths as the rest of the library sees them: pieces of geometry with
//! the input lines they come from, grouped in runs of feed moves.

use crate::geom::{flatten_params, Curve, Line, ParamCurve, Vec3};
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
    /// A run of feed moves along the lines through `pts` in order, every
    /// move at `feed` (mm/min), move `i` from input line `i + 1` (a CAM
    /// system's G1 program, as a caller without a reader builds it).
    pub fn polyline(pts: &[Vec3], feed: Option<f64>) -> Run {
        Run::new(
            pts.windows(2)
                .enumerate()
                .map(|(i, w)| Piece {
                    curve: Curve::Line(Line::new(w[0], w[1])),
                    rapid: false,
                    source_lines: (i + 1, i + 1),
                    feed,
                })
                .collect(),
        )
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

    /// The run with every piece whose curve `sample` picks replaced by
    /// chords within `chord` mm of it ([`flatten_params`]: measured at
    /// samples, so a caller that needs the bound verifies what it makes of
    /// them, as the pipeline does). End points are exact; each chord keeps
    /// the piece's input lines and feed. Lines are never sampled.
    pub fn sampled(&self, chord: f64, sample: impl Fn(&Curve) -> bool) -> Run {
        let mut out = Vec::with_capacity(self.pieces.len());
        for p in &self.pieces {
            let c = &p.curve;
            if matches!(c, Curve::Line(_)) || !sample(c) {
                out.push(p.clone());
                continue;
            }
            let ts = flatten_params(c, chord);
            let n = ts.len();
            let mut prev = c.start();
            for (i, &t) in ts.iter().enumerate().skip(1) {
                let q = if i + 1 == n { c.end() } else { c.eval(t) };
                out.push(Piece {
                    curve: Curve::Line(Line::new(prev, q)),
                    rapid: p.rapid,
                    source_lines: p.source_lines,
                    feed: p.feed,
                });
                prev = q;
            }
        }
        Run::new(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_polyline_run_joins_its_points_in_order() {
        let pts = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(3.0, 4.0, 0.0),
            Vec3::new(3.0, 4.0, 2.0),
        ];
        let run = Run::polyline(&pts, Some(600.0));
        assert_eq!(run.pieces.len(), 2);
        assert_eq!(run.start(), Some(pts[0]));
        assert_eq!(run.end(), Some(pts[2]));
        assert_eq!(run.pieces[0].end(), run.pieces[1].start());
        assert_eq!(run.pieces[1].source_lines, (2, 2));
        assert!(run.pieces.iter().all(|p| p.feed == Some(600.0) && !p.rapid));
        assert_eq!(run.length(1e-9), 7.0);
        assert!(Run::polyline(&pts[..1], None).pieces.is_empty());
    }
}
