//! Run detection for `bspline-fit`: which parts of a chain of segments are
//! dense samples of a smooth curve (to be fitted) and which are sparse
//! (long lines and real corners, to be kept and blended).
//!
//! **Rule.** Vertex `i` between segments of lengths `s_in`, `s_out` with
//! turning angle `phi` (angle between the two directions) is *dense* when
//!
//! 1. `s_in <= max_segment` and `s_out <= max_segment`: longer moves are
//!    programmed lines, not samples. Default 10 mm: CAM output sampled at
//!    chord error `c` has segments `s = sqrt(8 R c)`, under 10 mm for radii
//!    up to 1250 mm at `c = 0.01 mm` (Siemens' compressor, `COMPCAD`,
//!    likewise only takes blocks below a length limit). Rule 3 still makes
//!    a long move's vertex a corner unless it turns very little. 5 mm
//!    planned the issue-5 survey slower (measurements: docs/tuning.md,
//!    `SectionOptions::max_segment`);
//! 2. `phi <= max_turn` (default 0.5 rad, about 29 degrees): sharper turns
//!    are corners, whatever the segment lengths, unless the vertex is a
//!    wiggle inside the band: its height over the chord of its two
//!    neighbours is at most `wiggle_per_tol * tolerance` (default 1), so
//!    that chord is within the tolerance of the two segments and a fit may
//!    cut the vertex (noise, or a zigzag finer than the tolerance such as
//!    LinuxCNC's `zigzag_0.002_0.0005.ngc`; added here, the seed has no
//!    angle rule). The height is measured from the chord's line: a
//!    near-reversal with one short leg (an arc's last chord, then a line
//!    straight back) lies on that line beyond the chord and counts as
//!    dense too. The fit then turns through it within the band (it is
//!    verified like any fit), as a near-cusp where the machine nearly
//!    stops, as it must at a reversal. Measured from the chord segment
//!    instead, such vertices went to corner transitions, which planned
//!    the issue-5 survey slower, nothing faster (measurements:
//!    docs/tuning.md, `SectionOptions::wiggle_per_tol`);
//! 3. `phi (s_in + s_out) / 16 <= chord_error_per_tol * tolerance`: a circle
//!    through a vertex turning by `phi` between chords of mean length `s`
//!    has sagitta `c = s^2 / (8 R) = phi s / 8` over each chord, so this says
//!    the vertex looks like the sample of a curve taken at a chord error no
//!    larger than twice the tolerance (default factor 2): the curve moved
//!    inwards by half that sagitta, which a fit inside the band can follow,
//!    is within the tolerance of the vertices and of the chords' middles.
//!    It scales the rule with the tolerance: a 3 mm move turning by 10
//!    degrees is a sample at 0.05 mm but a corner at 0.005 mm. (Factor 1,
//!    the curve through the vertices within the tolerance, left LinuxCNC's
//!    `spiral_lines.ngc`, 3.8 mm moves turning by 5.7 degrees, sagitta 0.048
//!    mm, to corner transitions at 0.05 mm, which planned far slower than
//!    the fit; on the rest of the issue-5 survey factor 2 planned the same
//!    or faster. Measurements: docs/tuning.md,
//!    `SectionOptions::chord_error_per_tol`.)
//!
//! The end vertices of a chain (run ends, or next to an arc) have one
//! segment; they are dense when it satisfies rule 1. A *dense section* is a
//! maximal range of consecutive dense vertices; it is fitted when it has at
//! least `min_points` vertices (default 4, the seed's smallest fit of 4
//! control points; 8 planned the issue-5 survey slower: docs/tuning.md,
//! `SectionOptions::min_points`).

use crate::geom::Vec3;
use crate::smooth::{require, OptionError};
use alloc::vec::Vec;

/// Thresholds of the run detection (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct SectionOptions {
    /// Longest segment (mm) next to a dense vertex.
    pub max_segment: f64,
    /// Largest turning angle (rad) at a dense vertex.
    pub max_turn: f64,
    /// Largest implied chord error at a dense vertex, as a multiple of the
    /// tolerance.
    pub chord_error_per_tol: f64,
    /// Largest height of a vertex over the chord of its neighbours, as a
    /// multiple of the tolerance, for it to be dense whatever its turn.
    pub wiggle_per_tol: f64,
    /// Fewest vertices of a fitted section.
    pub min_points: usize,
}

impl Default for SectionOptions {
    fn default() -> Self {
        SectionOptions {
            max_segment: 10.0,
            max_turn: 0.5,
            chord_error_per_tol: 2.0,
            wiggle_per_tol: 1.0,
            min_points: 4,
        }
    }
}

/// Sharpest turn (rad, about 143 degrees) that the through-corners
/// candidate fits across; sharper vertices (reversals) stay corners.
///
/// A corner transition (seed 000) ends with zero curvature on its lines.
/// Next to a sampled arc, the fit of the arc must then ramp its curvature
/// from zero to `1/R` after the corner and back before the next one: on
/// short arcs between corners (LinuxCNC's `line-arc-burnin.ngc`,
/// `linearc.ngc`) the ramps slowed `auto` below the program as it is. The
/// through-corners candidate makes every vertex of the sampled run up to
/// this turn dense, whatever its segment lengths, so one fit runs through
/// the corner (knots are added where it misses the band) and each arc's
/// curvature runs into the next piece's. Where such a fit fails, the
/// section is split around its sharpest vertex as usual.
pub const THROUGH_MAX_TURN: f64 = 2.5;

/// The run detection of the through-corners candidates: every vertex up
/// to [`THROUGH_MAX_TURN`] is dense, whatever its segment lengths.
pub fn through_corners_sections() -> SectionOptions {
    SectionOptions {
        max_segment: 1e6,
        max_turn: THROUGH_MAX_TURN,
        chord_error_per_tol: 1e6,
        ..SectionOptions::default()
    }
}

impl SectionOptions {
    /// Checks the ranges of the options, naming `method` in the error.
    pub fn validate_for(&self, method: &'static str) -> Result<(), OptionError> {
        let m = method;
        let s = self.max_segment;
        require(
            s > 0.0 && s.is_finite(),
            m,
            "sections.max_segment",
            s,
            "must be a positive length (mm)",
        )?;
        let t = self.max_turn;
        require(
            (0.0..core::f64::consts::PI).contains(&t),
            m,
            "sections.max_turn",
            t,
            "must be in [0, pi) rad",
        )?;
        let c = self.chord_error_per_tol;
        require(
            c >= 0.0 && c.is_finite(),
            m,
            "sections.chord_error_per_tol",
            c,
            "must be >= 0 and finite",
        )?;
        let w = self.wiggle_per_tol;
        require(
            w >= 0.0 && w.is_finite(),
            m,
            "sections.wiggle_per_tol",
            w,
            "must be >= 0 and finite",
        )?;
        let n = self.min_points;
        require(n >= 3, m, "sections.min_points", n, "must be at least 3")
    }

    /// Whether vertex `i` of the chain `pts` is dense at `tolerance` mm.
    pub fn is_dense(&self, pts: &[Vec3], i: usize, tolerance: f64) -> bool {
        let n = pts.len();
        if n < 2 {
            return false;
        }
        let seg = |k: usize| pts[k + 1] - pts[k];
        if i == 0 {
            return seg(0).norm() <= self.max_segment;
        }
        if i == n - 1 {
            return seg(n - 2).norm() <= self.max_segment;
        }
        let (a, b) = (seg(i - 1), seg(i));
        let (sa, sb) = (a.norm(), b.norm());
        if sa > self.max_segment || sb > self.max_segment || sa == 0.0 || sb == 0.0 {
            return false;
        }
        let phi = a.angle_to(b);
        let sample = phi * (sa + sb) / 16.0 <= self.chord_error_per_tol * tolerance;
        if phi <= self.max_turn {
            return sample;
        }
        // Height of the vertex over the chord of its neighbours.
        let chord = a + b;
        let c = chord.norm();
        let height = if c > 0.0 {
            chord.cross(a).norm() / c
        } else {
            sa
        };
        height <= self.wiggle_per_tol * tolerance
    }
}

/// The dense sections of the chain `pts`: inclusive vertex ranges `(k, m)`,
/// in order, not overlapping, each with at least `min_points` vertices.
pub fn dense_sections(pts: &[Vec3], tolerance: f64, o: &SectionOptions) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start: Option<usize> = None;
    for i in 0..=pts.len() {
        let dense = i < pts.len() && o.is_dense(pts, i, tolerance);
        match (dense, start) {
            (true, None) => start = Some(i),
            (false, Some(k)) => {
                if i - k >= o.min_points {
                    out.push((k, i - 1));
                }
                start = None;
            }
            _ => {}
        }
    }
    out
}
