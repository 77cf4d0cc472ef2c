//! `fairpath check` on a hand-edited JSON document: invalid pieces are an
//! error naming the file and the piece, never a panic.

use crate::common;
use common::{bin, example, shared};
use std::process::Output;

fn run(args: &[&str]) -> Output {
    bin().args(args).output().unwrap()
}

/// Issue 17's known bug: a JSON NURBS piece of degree 9 made
/// `fairpath check` panic in `ders_basis`. It is an error (exit status 1,
/// not a panic's 101) that names the piece and the degree.
#[test]
fn check_of_degree_9_json_nurbs_is_an_error_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let input = example("zigzag.ngc");
    let json = dir.path().join("zigzag.json");
    let o = run(&[
        "smooth",
        input.to_str().unwrap(),
        "-o",
        json.to_str().unwrap(),
        "--tolerance",
        "0.05mm",
        "--format",
        "json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let pieces = doc["pieces"].as_array_mut().unwrap();
    let index = pieces
        .iter()
        .position(|q| q["type"] == "nurbs")
        .expect("the smoothed zigzag has a NURBS piece");
    let q = &mut pieces[index];
    let first = q["points"][0].clone();
    q["degree"] = serde_json::json!(9);
    q["points"] = serde_json::json!(vec![first; 10]);
    let mut knots = vec![0.0; 10];
    knots.extend([1.0; 10]);
    q["knots"] = serde_json::json!(knots);
    q["weights"] = serde_json::Value::Null;
    let edited = dir.path().join("degree9.json");
    std::fs::write(&edited, doc.to_string()).unwrap();
    let o = run(&[
        "check",
        input.to_str().unwrap(),
        edited.to_str().unwrap(),
        "--tolerance",
        "0.05mm",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        err.contains("degree9.json") && err.contains(&format!("piece {index}")),
        "{err}"
    );
    assert!(err.contains("degree 9"), "{err}");
}

/// Fuzz input `hang-1717-17309`: a JSON output of
/// `linuxcnc/arc-feed/simple_arc2.ngc` with one piece's source lines
/// mutated, so its half circle (radius 10 mm, XZ plane) is checked against
/// the run along Y, 10 mm from it everywhere. The verifier's bisection
/// never closed its bound on that constant distance and `fairpath check`
/// ran for hours; the bisection of each span is bounded now
/// (`MAX_SPLITS_PER_SPAN`) and the check fails with the distance.
#[test]
fn hang_1717_17309_check_of_a_misplaced_arc_finishes_and_fails() {
    let Some(original) = shared("linuxcnc/arc-feed/simple_arc2.ngc") else {
        eprintln!("shared programs not found: skipped");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("hang-1717-17309.json");
    std::fs::write(&json, HANG_1717_17309).unwrap();
    let o = run(&[
        "check",
        original.to_str().unwrap(),
        json.to_str().unwrap(),
        "--tolerance",
        "0.05mm",
    ]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(3), "{out}");
    let dev: f64 = out
        .lines()
        .find_map(|l| l.trim().strip_prefix("max deviation:"))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|x| x.parse().ok())
        .unwrap_or_else(|| panic!("{out}"));
    assert!(dev >= 10.0, "{out}");
}

const HANG_1717_17309: &str = r#"{"pieces":[{"feed":null,"p0":[0.0,0.0,0.0],"p1":[0.0,0.0,0.0],"rapid":true,"source_lines":[3,3],"type":"line"},{"feed":1000.0,"p0":[0.0,0.0,0.0],"p1":[10.0,0.0,0.0],"rapid":false,"source_lines":[4,4],"type":"line"},{"degree":2,"feed":1000.0,"knots":[0.0,0.0,0.0,0.5,0.5,1.0,1.0,1.0],"points":[[10.0,0.0,0.0],[10.0,0.0,-9.999999999999998],[6.123233995736766e-16,0.0,-10.0],[-9.999999999999998,0.0,-10.0],[-10.0,0.0,0.0]],"rapid":false,"source_lines":[38,3],"type":"nurbs","weights":[1.0,0.7071067811865476,1.0,0.7071067811865476,1.0]},{"feed":null,"p0":[-10.0,0.0,0.0],"p1":[0.0,0.0,0.0],"rapid":true,"source_lines":[7,7],"type":"line"},{"feed":1000.0,"p0":[0.0,0.0,0.0],"p1":[0.0,10.0,0.0],"rapid":false,"source_lines":[9,9],"type":"line"},{"degree":2,"feed":1000.0,"knots":[0.0,0.0,0.0,0.5,0.5,1.0,1.0,1.0],"p1":[5e-324,0.0,1e+308],"points":[[0.0,10.0,0.0],[0.0,4.028324592902732,6.771243444677051],[0.0,-5.000000000000002,6.771243444677051],[0.0,-14.028324592902731,6.771243444677051],[0.0,-20.0,0.0]],"rapid":false,"source_lines":[11,11],"type":"nurbs","weights":[1.0,0.9114378277661477,1.0,0.9114378277661477,1.0]},{"feed":null,"p0":[0.0,-20.0,0.0],"p1":[0.0,0.0,0.0],"rapid":true,"source_lines":[12,12],"type":"line"}],"units":"mm"}"#;
