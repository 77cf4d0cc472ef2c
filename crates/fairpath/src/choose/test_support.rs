//! What the tests of `choose` share: small runs and candidates, and the
//! renderings of a G-code writer on the thesis' machine.

use crate::feed::limits::MachineLimits;
use crate::geom::{Curve, Line, ParamCurve, Vec3};
use crate::path::{Piece, Run};
use crate::render::{CurveForm, RenderOptions};
use crate::smooth::{BsplineCorner, SmoothedRun, Smoother};
use alloc::vec::Vec;

/// A wavy raster of `points` points, its corners replaced by
/// `bspline-corner`'s transitions.
pub(super) fn corner_curves(points: usize) -> Vec<Piece> {
    let pts: Vec<Vec3> = (0..points)
        .map(|k| {
            let x = 0.5 * k as f64;
            Vec3::new(x, 0.3 * (0.7 * x).sin(), 0.02 * (1.3 * x).cos())
        })
        .collect();
    let run = Run::polyline(&pts, Some(6000.0));
    BsplineCorner::default()
        .smooth_run(&run, 0.045)
        .unwrap()
        .pieces
}

/// A candidate of one line whose end `x` is `r`: the result it stands for
/// ([`result`]).
pub(super) fn line_candidate(r: usize) -> SmoothedRun {
    SmoothedRun {
        pieces: alloc::vec![Piece {
            curve: Curve::Line(Line::new(Vec3::ZERO, Vec3::new(r as f64, 1.0, 0.0))),
            rapid: false,
            source_lines: (1, 1),
            feed: None,
        }],
        ..SmoothedRun::default()
    }
}

/// The result a [`line_candidate`] stands for.
pub(super) fn result(pieces: &[Piece]) -> usize {
    pieces[0].curve.end().x as usize
}

/// A G-code writer's rendering in `form` on the thesis' machine.
pub(super) fn render_options(form: CurveForm) -> RenderOptions {
    RenderOptions {
        form,
        chord: 0.005,
        limits: MachineLimits::thesis(),
        min_block_periods: 1.02,
        min_radius: 0.00254,
        step_share: crate::render::arcs::STEP_SHARE,
        min_arc_length: 4e-6,
    }
}
