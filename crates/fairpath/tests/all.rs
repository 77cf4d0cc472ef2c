//! The integration tests of this crate as one test binary: one build
//! and link instead of one per file, and the tests of every file
//! side by side on the cores (`cargo test -p fairpath --test integration FILE::`
//! runs one file's). Each file is a module; `common` holds their helpers.

mod absorb_props;
mod arc_chord_params;
mod arc_fit_props;
mod arc_joints_props;
mod arc_length_closed;
mod auto_props;
mod band_fit_props;
mod bezier_corner_props;
mod bspline_corner_props;
mod bspline_fit_props;
mod closed_forms;
mod common;
mod constructor_props;
mod corner_reach;
mod derivatives;
mod doc_diaries;
mod double_s;
mod fair_props;
mod feed_form;
mod feed_limits;
mod feed_plan;
mod feed_windowed;
mod fit_kernels_same_bits;
mod fit_planar;
mod judged_fair;
mod layers;
mod lower_bound;
mod memory_layout;
mod pipeline_parallel;
mod render_props;
mod straighten_props;
mod stream_props;
mod verify_detects;
