//! `fairpath check` on a hand-edited JSON document: invalid pieces are an
//! error naming the file and the piece, never a panic.

mod common;
use common::{bin, example};
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
        "0.05",
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
        "0.05",
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
