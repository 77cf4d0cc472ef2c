//! Helpers shared by the integration tests.
#![allow(dead_code)]

use fairpath::geom::{Curve, Line, Vec3};
use fairpath::path::{Piece, Run};

/// A run of G1 moves through `pts` at 1000 mm/min, input lines numbered
/// from 1.
pub fn polyline_run(pts: &[Vec3]) -> Run {
    polyline_run_with_feeds(pts, &[1000.0])
}

/// A run of G1 moves through `pts`, move `i` at `feeds[i % feeds.len()]`
/// mm/min.
pub fn polyline_run_with_feeds(pts: &[Vec3], feeds: &[f64]) -> Run {
    Run::new(
        pts.windows(2)
            .enumerate()
            .map(|(i, w)| Piece {
                curve: Curve::Line(Line::new(w[0], w[1])),
                rapid: false,
                source_lines: (i + 1, i + 1),
                feed: Some(feeds[i % feeds.len()]),
            })
            .collect(),
    )
}

pub fn v(x: f64, y: f64, z: f64) -> Vec3 {
    Vec3::new(x, y, z)
}
