//! The options of method `auto` ([`super::Auto`]), checked once at the
//! front door.

use super::auto::ARC_SHARE;
use super::candidate_set::CandidateSet;
use super::reversals::{REVERSAL_TURN, U_TURN_WIDTH};
use super::sections::SECTION_LINES;
use super::written_choice::FINAL_COST_MARGIN;
use crate::smooth::{require, OptionError};

/// Options of [`Auto`](super::Auto).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct AutoOptions {
    /// Share of the tolerance for the chords of sampled arcs, in `(0, 0.5]`.
    pub arc_share: f64,
    /// For each of these lengths (mm), the lines longer than it cut the
    /// run into sections, each smoothed by its own fastest candidate; the
    /// fastest of these mixes and the best candidate for the whole run is
    /// kept ([`SECTION_LINES`]; an infinite length cuts nothing, all
    /// infinite: one choice per run).
    pub section_lines: [f64; 3],
    /// Offer the corner methods on the curves as written
    /// ([`super::CURVES_AS_WRITTEN`]), which keep the corners next to arcs,
    /// beside the G2 candidates on every run with an arc or curve. False
    /// by default: `auto` makes every joint G2 but reversals (issue 5), and
    /// offers them only where every G2 candidate would leave the run as the
    /// program wrote it (see the module documentation).
    pub curves_as_written: bool,
    /// Turn (rad, in `(0, pi]`, or infinite) at and above which a vertex
    /// is a near-reversal: the run is also smoothed as the runs between
    /// such vertices, each kept as a corner (reported as a reversal), and
    /// that is kept where it plans faster ([`REVERSAL_TURN`] by default,
    /// about 160 degrees; infinite: every joint but exact reversals G2, as
    /// before this option).
    pub reversal_turn: f64,
    /// Widest U-turn (mm, at least 0, or infinite) whose two corners are
    /// kept the same way where that plans faster: two sharp corners this
    /// close that together turn by `reversal_turn` or more, such as the
    /// step-over between the passes of a zigzag ([`U_TURN_WIDTH`] by
    /// default, 3 mm; 0: none; see [`super::u_turn_cuts`]).
    pub u_turn_width: f64,
    /// Candidates not offered on any run, by the names the summary gives
    /// them (none by default): fewer candidates, less computing time, and
    /// a written program that may plan slower (what each costs and gains:
    /// `docs/auto-ablation.md`). At least one of those offered on every
    /// run must stay.
    pub leave_out: CandidateSet,
    /// Share of the best cost within which the other candidates of a run
    /// are judged again as the writer finally writes them, the cheapest
    /// [`FINAL_COST_CONTENDERS`](super::FINAL_COST_CONTENDERS) of them
    /// ([`FINAL_COST_MARGIN`] by default, 0.1; at least 0: none).
    pub final_cost_margin: f64,
}

impl AutoOptions {
    /// Checks the ranges of the options.
    pub fn validate(&self) -> Result<(), OptionError> {
        let s = self.arc_share;
        require(
            s > 0.0 && s <= 0.5,
            "auto",
            "arc_share",
            s,
            "must be in (0, 0.5]",
        )?;
        let l = self.section_lines;
        require(
            l.iter().all(|&x| x > 0.0),
            "auto",
            "section_lines",
            l,
            "must be positive lengths (mm) or infinite",
        )?;
        let r = self.reversal_turn;
        require(
            r > 0.0 && (r <= core::f64::consts::PI || r == f64::INFINITY),
            "auto",
            "reversal_turn",
            r,
            "must be an angle (rad) in (0, pi], or infinite (no cut)",
        )?;
        let w = self.u_turn_width;
        require(
            w >= 0.0,
            "auto",
            "u_turn_width",
            w,
            "must be a width (mm) of 0 or more, or infinite",
        )?;
        let m = self.final_cost_margin;
        require(
            m >= 0.0 && m.is_finite(),
            "auto",
            "final_cost_margin",
            m,
            "must be a share of 0 or more",
        )?;
        require(
            !self.leave_out.holds_every_one_always_offered(),
            "auto",
            "leave_out",
            self.leave_out,
            "must keep one of the candidates offered on every run \
             (bspline-fit, bspline-corner, lotm)",
        )
    }
}

impl Default for AutoOptions {
    fn default() -> Self {
        AutoOptions {
            arc_share: ARC_SHARE,
            section_lines: SECTION_LINES,
            curves_as_written: false,
            reversal_turn: REVERSAL_TURN,
            u_turn_width: U_TURN_WIDTH,
            leave_out: CandidateSet::EMPTY,
            final_cost_margin: FINAL_COST_MARGIN,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A margin is a share of 0 or more: a negative, infinite or NaN one
    /// is refused at the front door; 0 (no contender judged) is taken.
    #[test]
    fn final_cost_margin_is_a_finite_share_of_0_or_more() {
        let with = |m: f64| AutoOptions {
            final_cost_margin: m,
            ..AutoOptions::default()
        };
        for bad in [-0.01, f64::INFINITY, f64::NAN] {
            assert!(with(bad).validate().is_err(), "{bad}");
        }
        for good in [0.0, FINAL_COST_MARGIN, 0.5] {
            assert!(with(good).validate().is_ok(), "{good}");
        }
    }
}
