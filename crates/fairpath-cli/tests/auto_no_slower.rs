//! Issue 21: `auto` writes a program no slower than the best single
//! curvature-continuous method's, on the shared programs where it once
//! was slower (read in place; skipped without `../shared/paths`).
//!
//! Regressions: `surface-raster.ngc`, where the curves' time pruned
//! `bspline-fit` although its arcs plan faster than its curves (auto
//! 59.597 s against `fair` 59.489 s and `bspline-fit` 59.497 s), and where
//! `fair` was no candidate on a run of 2,979 lines; `square-wave.ngc`,
//! where `auto` writes `bspline-corner`'s program and `ctm` the same
//! transitions, rounded differently in the seventh decimal (a tie).

use fairpath_cli::compare::{compare, CompareOptions};
use fairpath_cli::{Controller, Format};
use std::path::{Path, PathBuf};

fn shared(rel: &str) -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/paths")
        .join(rel);
    p.is_file().then_some(p)
}

/// Two times of written programs count as equal within this share: the
/// same geometry, its coordinates rounded differently.
const TIE: f64 = 1e-6;

fn check(rel: &str) {
    let Some(p) = shared(rel) else {
        eprintln!("{rel} not found: skipped");
        return;
    };
    let methods = [
        "auto",
        "bspline-corner",
        "ctm",
        "lotm",
        "bspline-fit",
        "fair",
    ];
    let opts = CompareOptions {
        tolerance: 0.05,
        machine: fairpath::feed::limits::MachineLimits::thesis(),
        methods: methods.iter().map(|m| m.to_string()).collect(),
        override_feed: false,
        formats: vec![Format::Arcs],
        controller: Controller::Generic,
    };
    let rows = compare(&p, &opts).unwrap();
    let written = |m: &str| {
        let r = rows.iter().find(|r| r.method == m).unwrap();
        let w = &r.written[0];
        assert!(w.verified, "{rel} {m}: not verified");
        w.time
    };
    let auto = written("auto");
    for m in &methods[1..] {
        let t = written(m);
        assert!(
            auto <= t * (1.0 + TIE),
            "{rel}: auto {auto:.4} s, slower than {m} {t:.4} s"
        );
    }
}

#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn surface_raster_auto_is_no_slower_than_fair_or_bspline_fit() {
    check("synthetic/surface-raster.ngc");
}

#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn square_wave_auto_ties_ctm() {
    check("synthetic/square-wave.ngc");
}
