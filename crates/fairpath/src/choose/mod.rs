//! Choosing among the methods: `auto`, which smooths each run (and each
//! section of it) several ways and keeps the one its [`Objective`] ranks
//! cheapest, and the registry of every method by name.
//!
//! This layer sits above the methods ([`crate::smooth`]), the planner
//! ([`crate::feed`]) and the verifier ([`crate::verify`]); none of them
//! imports it.

mod auto;
mod auto_options;
mod candidate_set;
mod candidate_threads;
mod candidates;
mod judged_fair;
mod objective;
mod ranking;
mod registry;
mod reversals;
mod same_pieces;
mod sections;
#[cfg(test)]
mod test_support;
mod written_choice;

pub use auto::{sample_curves, Auto, ARC_SHARE};
pub use auto_options::AutoOptions;
pub use candidate_set::{candidate_names, CandidateSet};
pub use candidates::{
    keeps_arc_joints, through_corners_sections, CandidateRow, CornerMethod, Kind, Offered,
    SectionRule, CANDIDATES, CURVES_AS_WRITTEN, FAIR_CURVES_AS_WRITTEN, FAIR_MAX_PIECES,
    FAIR_STRAIGHTENED, JERK_FAIRNESS, OUTER_CORNERS, OUTER_MAX_TURN, OUTER_SHIFT_SHARES,
    OUTER_STRAIGHT_SHARE, OUTER_TRIES, THROUGH_JERK_FAIRNESS, THROUGH_MAX_PIECES, THROUGH_MAX_TURN,
    WIDE_WIGGLE_PER_TOL,
};
pub use judged_fair::JudgedFair;
pub use objective::{
    fair_on, peak_pass_for, rewrite_margin, Objective, PlannedTime, RenderObserver, WrittenTime,
    COST_PART_PIECES, FINER_KEEP_MARGIN, KEEP_MARGIN, RENDER_GAIN,
};
pub use registry::{by_name, method, Method, METHODS};
pub use reversals::{
    reversal_cuts, u_turn_cuts, REVERSAL_PIECES_PER_CUT, REVERSAL_TURN, REVERSAL_WALK_PIECES,
    U_TURN_CORNER, U_TURN_MAX_PIECES, U_TURN_WIDTH,
};
pub use same_pieces::{pieces_digest, same_pieces};
pub use sections::{split_at_long_lines, SECTION_LINES, SECTION_MAX_PIECES};
pub use written_choice::{
    WriterTries, FINAL_COST_CONTENDERS, FINAL_COST_MARGIN, FINAL_TIE_SHARE, SAME_COST_SHARE,
};
