//! # fairpath
//!
//! Tolerance-bounded, curvature-continuous (G2) smoothing of CNC tool paths.
//!
//! Data flows one way:
//!
//! ```text
//! G-code text --(fairpath-gcode reader)--> Program --> Runs of feed moves (path::Run)
//!     --> method (smooth::Smoother: ArcFit, BsplineCorner, BsplineFit, Ctm, Lotm;
//!                 or choose::Auto, ranking them by an injected Objective)
//!     --> smoothed pieces
//!     --> verify (independent: deviation, joint continuity, endpoints)
//!     --> feed::plan (jerk-limited look-ahead: machining time, profiles)
//!     --> writers (fairpath-gcode: G-code, JSON)
//! ```
//!
//! * [`geom`]: vectors, lines, arcs, B-spline/NURBS curves; derivatives,
//!   curvature, arc length, distances to polylines; the continuity class of
//!   a joint.
//! * [`path`]: pieces of geometry tied to the input lines they replace,
//!   grouped in runs.
//! * [`smooth`]: the smoothing methods behind one trait (methods only).
//! * [`verify`]: the independent check of a smoothed run (imports only
//!   [`geom`] and [`path`]).
//! * [`choose`] holds `auto` (candidates ranked by an injected
//!   [`choose::Objective`], e.g. the planned time on the user's machine)
//!   and the registry of methods by name.
//! * [`controller`]: what controllers do with the codes fairpath reads and
//!   writes: LinuxCNC's G5/G5.1/G5.2 spline arithmetic, replicated.
//! * [`feed`]: machine limits, speed caps, jerk-limited (double-S)
//!   profiles, the look-ahead planner and the interpolator.
//!
//! The crate has no I/O and builds without `std` (`default-features = false`)
//! for `core + alloc` targets such as a controller's firmware. Coordinates are
//! f64 millimetres throughout.
#![cfg_attr(not(feature = "std"), no_std)]

extern crate alloc;

pub mod budget;
pub mod choose;
pub mod controller;
pub mod feed;
pub mod geom;
mod math;
pub mod path;
pub mod pipeline;
pub mod render;
#[cfg(test)]
mod seeded;
pub mod smooth;
pub mod verify;

pub use geom::{Curve, ParamCurve, Vec3};
pub use path::{Piece, Run};
