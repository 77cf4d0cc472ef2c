//! The targets of issue 16 where they are met, as regression guards (the
//! whole survey is `scripts/output-survey.py`, report in
//! `docs/output-survey.md`): with `simulate --override-feed`'s model on the
//! default machine at 0.05 mm, the program `smooth` writes by default
//! plans no slower than its input, at most 0.8 of it on the dense programs
//! below and at most 1.25 of the exact curves; G6.2 output within 2% of the
//! curves. Skipped without `../shared/paths`.

use fairpath_cli::compare::{compare, CompareOptions, Row};
use fairpath_cli::{Controller, Format};
use std::path::{Path, PathBuf};

fn shared(rel: &str) -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/paths")
        .join(rel);
    p.is_file().then_some(p)
}

/// The baseline and `auto`, with the written program in `formats`.
fn rows(path: &Path, formats: &[Format]) -> (Row, Row) {
    let opts = CompareOptions {
        tolerance: 0.05,
        machine: fairpath::feed::limits::MachineLimits::thesis(),
        methods: vec!["auto".into()],
        override_feed: true,
        formats: formats.to_vec(),
        controller: Controller::Generic,
    };
    let mut r = compare(path, &opts).unwrap();
    let auto = r.pop().unwrap();
    let original = r.pop().unwrap();
    for w in &auto.written {
        assert!(
            w.verified,
            "{}: {:?} not verified",
            path.display(),
            w.format
        );
    }
    (original, auto)
}

#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn the_default_output_of_dense_programs_keeps_the_gain() {
    for rel in [
        "synthetic/helix.ngc",
        "synthetic/surface-raster.ngc",
        "linuxcnc/performance/contour.ngc",
        "linuxcnc/XYtests/51MeanderAve.ngc",
    ] {
        let Some(p) = shared(rel) else {
            eprintln!("{rel} not found: skipped");
            continue;
        };
        let (original, auto) = rows(&p, &[Controller::Generic.default_format()]);
        let w = &auto.written[0];
        assert!(
            w.time <= 0.8 * original.time,
            "{rel}: written {} s, input {} s",
            w.time,
            original.time
        );
        assert!(
            w.time <= 1.25 * auto.time,
            "{rel}: written {} s, curves {} s",
            w.time,
            auto.time
        );
    }
}

#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn g6_2_output_plans_within_two_percent_of_the_curves() {
    for rel in [
        "synthetic/butterfly-80.ngc",
        "synthetic/helix.ngc",
        "synthetic/surface-raster.ngc",
        "linuxcnc/performance/line-contouring-xz.ngc",
    ] {
        let Some(p) = shared(rel) else {
            eprintln!("{rel} not found: skipped");
            continue;
        };
        let (original, auto) = rows(&p, &[Format::G6_2]);
        let w = &auto.written[0];
        assert!(
            w.time <= 1.02 * auto.time && w.time <= original.time,
            "{rel}: G6.2 {} s, curves {} s, input {} s",
            w.time,
            auto.time,
            original.time
        );
    }
}

#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn arcs_keep_the_gain_of_butterfly_80() {
    // butterfly-80: 80 G1 moves whose curves plan 0.39 of the input; the
    // arcs written for them within 10% of the curves (the issue asks 25%).
    // Within 5% while the planner held one curvature step per period; an
    // arc spline steps its curvature at every joint, and with the steps
    // closer than a period capped (`feed::junction::step_cap`) the arcs
    // plan 7.216 s against 6.762 s.
    let Some(p) = shared("synthetic/butterfly-80.ngc") else {
        return;
    };
    let (original, auto) = rows(&p, &[Format::Arcs]);
    let w = &auto.written[0];
    assert!(w.time <= 1.10 * auto.time, "{} vs {}", w.time, auto.time);
    assert!(w.time <= 0.45 * original.time);
}
