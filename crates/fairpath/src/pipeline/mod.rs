//! The library's entry point: every run of a program smoothed by one
//! method within the smoothing share of a [`ToleranceBudget`], and the
//! curves verified independently ([`crate::verify`]) before anything is
//! returned.

mod parallel;

pub use parallel::{par_map, verify_runs};
