//! Every method by the name the command line uses.

use super::auto::{Auto, AutoOptions};
use super::objective::Objective;
use crate::smooth::{ArcFit, BsplineCorner, BsplineFit, Ctm, Lotm, NoSmoothing, Smoother};
use alloc::boxed::Box;
use alloc::sync::Arc;

/// Names of the methods [`by_name`] knows.
pub const METHODS: &[&str] = &[
    "arc-fit",
    "auto",
    "bspline-corner",
    "bspline-fit",
    "ctm",
    "lotm",
    "none",
];

/// The method called `name` on the command line, with default options
/// (`auto` ranking by [`super::PlannedTime::default`]: use [`method`] to
/// give it the user's machine).
pub fn by_name(name: &str) -> Option<Box<dyn Smoother>> {
    match name {
        "auto" => Some(Box::new(Auto::default())),
        _ => others(name),
    }
}

/// The method called `name` with default options, `auto` ranking its
/// candidates by `objective`.
pub fn method(name: &str, objective: Arc<dyn Objective>) -> Option<Box<dyn Smoother>> {
    match name {
        "auto" => Some(Box::new(Auto::new(AutoOptions::default(), objective))),
        _ => others(name),
    }
}

/// Every method but `auto` (`none`: the runs as they are).
fn others(name: &str) -> Option<Box<dyn Smoother>> {
    match name {
        "arc-fit" => Some(Box::new(ArcFit::default())),
        "bspline-corner" => Some(Box::new(BsplineCorner::default())),
        "bspline-fit" => Some(Box::new(BsplineFit::default())),
        "ctm" => Some(Box::new(Ctm::default())),
        "lotm" => Some(Box::new(Lotm::default())),
        "none" => Some(Box::new(NoSmoothing)),
        _ => None,
    }
}
