//! `compare`'s lower bound: never above the time of the original or of
//! any method's curves and written program, on the examples and on the
//! shared synthetic programs (read in place; skipped when absent); and the
//! bound of paths that follow the original in order, never above the time
//! of a path that passes its gates in order (the original always does,
//! and so does every method's written program on these).

use std::path::{Path, PathBuf};
use std::process::Command;

fn compare_json(input: &Path) -> serde_json::Value {
    let o = Command::new(env!("CARGO_BIN_EXE_fairpath"))
        .args(["compare", input.to_str().unwrap()])
        .args(["--tolerance", "0.05mm", "--format", "json"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

fn check(input: &Path) {
    let rows = compare_json(input);
    let rows = rows.as_array().unwrap();
    let bound = rows[0]["lower_bound_s"].as_f64().unwrap();
    assert!(bound > 0.0, "{}: bound {bound}", input.display());
    let ordered = rows[0]["lower_bound_in_order_s"].as_f64().unwrap();
    assert!(
        ordered > 0.0,
        "{}: in-order bound {ordered}",
        input.display()
    );
    assert_eq!(
        rows[0]["follows_in_order"],
        true,
        "{}: the original",
        input.display()
    );
    for r in rows {
        if r["follows_in_order"] == true {
            let t = r["time_s"].as_f64().unwrap();
            assert!(
                ordered <= t,
                "{} {}: in-order bound {ordered} > {t}",
                input.display(),
                r["method"]
            );
            let x = r["x_bound_in_order"].as_f64().unwrap();
            assert!((x - t / ordered).abs() <= 1e-9 * x);
        }
        let t = r["time_s"].as_f64().unwrap();
        let x = r["x_bound"].as_f64().unwrap();
        assert_eq!(r["lower_bound_s"].as_f64().unwrap(), bound);
        assert!(
            bound <= t,
            "{} {}: bound {bound} > {t}",
            input.display(),
            r["method"]
        );
        assert!((x - t / bound).abs() <= 1e-9 * x);
        for w in r["written"].as_array().unwrap() {
            let tw = w["time_s"].as_f64().unwrap();
            assert_eq!(
                w["follows_in_order"],
                true,
                "{} {} written",
                input.display(),
                r["method"]
            );
            assert!(
                ordered <= tw,
                "{} {} written: in-order bound {ordered} > {tw}",
                input.display(),
                r["method"]
            );
            assert!(
                bound <= tw,
                "{} {} written: bound {bound} > {tw}",
                input.display(),
                r["method"]
            );
        }
    }
}

#[test]
fn the_bound_is_below_every_method_on_the_examples() {
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    for name in ["pocket-corners.ngc", "rhombus.ngc", "zigzag.ngc"] {
        check(&examples.join(name));
    }
}

#[test]
fn the_bound_is_below_every_method_on_shared_synthetic_programs() {
    let dir = PathBuf::from("/work/shared/paths/synthetic");
    if !dir.is_dir() {
        eprintln!("skipped: {} is absent", dir.display());
        return;
    }
    for name in [
        "square-wave.ngc",
        "butterfly-80.ngc",
        "hexagon-3d.ngc",
        "surface-raster.ngc",
    ] {
        check(&dir.join(name));
    }
}
