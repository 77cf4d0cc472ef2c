//! Method `none`: every run as it is. The pipeline around it still reads,
//! verifies, plans, writes, reads back and checks the program, so `smooth
//! --method none` expands a parameterised program (o-words, `#`
//! parameters, canned cycles read as moves) into plain moves through the
//! same verified path as every other method, and is the baseline the
//! other methods' cost is measured against (`scripts/scale.sh`).

use super::kept_joints::report_corners;
use super::{check_tolerance, SmoothError, SmoothedRun, Smoother};
use crate::geom::JointTolerances;
use crate::path::{Piece, Run};
use alloc::vec::Vec;

/// Consecutive pieces of a run count as meeting when their ends are within
/// this share of the tolerance (the same as the other methods' cleaning:
/// a thousandth of it, below any written decimal).
pub use crate::budget::CLEAN_SHARE as NONE_GAP_SHARE;

/// The method that changes nothing: each run's pieces as they are (no
/// zero-length moves dropped, no vertices merged). Every joint stays as the
/// program has it, and each that is not G2 is reported as a kept corner,
/// as the other methods report theirs: [`CornerReason::Reversal`](super::CornerReason::Reversal) where the
/// path turns back, [`CornerReason::NoRoom`](super::CornerReason::NoRoom) otherwise (as `arc-fit`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NoSmoothing;

impl Smoother for NoSmoothing {
    fn name(&self) -> &'static str {
        "none"
    }

    fn keeps_every_run(&self) -> bool {
        true
    }

    fn smooth_run(&self, run: &Run, tolerance: f64) -> Result<SmoothedRun, SmoothError> {
        check_tolerance(tolerance)?;
        let gap = NONE_GAP_SHARE * tolerance;
        let mut pieces: Vec<Piece> = Vec::with_capacity(run.pieces.len());
        for p in &run.pieces {
            let (s, e) = (p.start(), p.end());
            let line = p.source_lines.0;
            if !s.is_finite() || !e.is_finite() {
                return Err(SmoothError::NotFinite { line });
            }
            if pieces.last().is_some_and(|q| q.end().dist(s) > gap) {
                return Err(SmoothError::Discontinuous { line });
            }
            let mut p = p.clone();
            p.rapid = false;
            pieces.push(p);
        }
        let jt = JointTolerances::from_tolerance(tolerance);
        let mut kept_corners = Vec::new();
        report_corners(&pieces, 0, &jt, &mut kept_corners);
        Ok(SmoothedRun {
            pieces,
            kept_corners,
            ..SmoothedRun::default()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{Curve, Line, Vec3};
    use crate::smooth::CornerReason;
    use alloc::vec;

    fn line(a: Vec3, b: Vec3, l: usize) -> Piece {
        Piece {
            curve: Curve::Line(Line::new(a, b)),
            rapid: false,
            source_lines: (l, l),
            feed: Some(600.0),
        }
    }

    #[test]
    fn a_run_comes_back_as_it_is() {
        let a = Vec3::new(0.0, 0.0, 0.0);
        let b = Vec3::new(1.0, 0.0, 0.0);
        let c = Vec3::new(1.0, 1.0, 0.0);
        // A zero-length move and a corner stay.
        let run = Run::new(vec![line(a, b, 2), line(b, b, 3), line(b, c, 4)]);
        let out = NoSmoothing.smooth_run(&run, 0.05).unwrap();
        assert_eq!(out.pieces, run.pieces);
        assert_eq!(out.transitions, 0);
        // The corner at b is kept (the zero-length move's joints too).
        assert!(out.kept_corners.iter().any(|k| k.at == b));
        let back = Run::new(vec![line(a, b, 2), line(b, a, 3)]);
        let out = NoSmoothing.smooth_run(&back, 0.05).unwrap();
        assert_eq!(out.kept_corners.len(), 1);
        assert_eq!(out.kept_corners[0].reason, CornerReason::Reversal);
        assert_eq!(out.kept_corners[0].source_line, 2);
    }

    #[test]
    fn bad_runs_and_tolerances_are_errors() {
        let a = Vec3::new(0.0, 0.0, 0.0);
        let b = Vec3::new(1.0, 0.0, 0.0);
        let c = Vec3::new(2.0, 0.0, 0.0);
        let run = Run::new(vec![line(a, b, 2), line(c, a, 3)]);
        assert_eq!(
            NoSmoothing.smooth_run(&run, 0.05),
            Err(SmoothError::Discontinuous { line: 3 })
        );
        let nan = Vec3::new(f64::NAN, 0.0, 0.0);
        let run = Run::new(vec![line(a, nan, 7)]);
        assert_eq!(
            NoSmoothing.smooth_run(&run, 0.05),
            Err(SmoothError::NotFinite { line: 7 })
        );
        assert!(NoSmoothing.smooth_run(&Run::default(), -1.0).is_err());
    }
}
