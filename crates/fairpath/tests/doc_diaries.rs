//! Doc comments say what and why; the measurements that chose a value or
//! a design (planned and computing times, memory, dates of runs) go to
//! `docs/tuning.md` and `docs/performance.md`, where the doc comment points
//! (issue 19: diaries in doc comments go stale). This test keeps them out
//! of the doc comments (`///`, `//!`) of the three crates: a date, or a
//! before-and-after figure (`12.64 -> 12.91 s`, `59.864 s against 59.497
//! s`, `627 -> 504 MB`), fails it. A source's worked example (a textbook's
//! "Example 3.12") is a citation, not a diary, and may stay.

use std::path::Path;

/// Whether `s` holds a date `20YY-MM-DD`.
fn has_date(s: &str) -> bool {
    let b = s.as_bytes();
    (0..b.len().saturating_sub(9)).any(|i| {
        let d = |k: usize| b[i + k].is_ascii_digit();
        b[i] == b'2'
            && b[i + 1] == b'0'
            && d(2)
            && d(3)
            && b[i + 4] == b'-'
            && d(5)
            && d(6)
            && b[i + 7] == b'-'
            && d(8)
            && d(9)
    })
}

/// Whether `s` holds a number, then `between`, then a number, then one of
/// `units` (` s`, ` MB`, ...): a before-and-after figure.
fn has_figure_pair(s: &str, between: &str, units: &[&str]) -> bool {
    let mut rest = s;
    while let Some(k) = rest.find(between) {
        let (before, after) = (&rest[..k], &rest[k + between.len()..]);
        let ends_in_number = before
            .trim_end_matches(" s")
            .ends_with(|c: char| c.is_ascii_digit());
        let number: String = after
            .chars()
            .take_while(|c| c.is_ascii_digit() || *c == '.' || *c == ',')
            .collect();
        if ends_in_number
            && number.starts_with(|c: char| c.is_ascii_digit())
            && units.iter().any(|u| after[number.len()..].starts_with(u))
        {
            return true;
        }
        rest = after;
    }
    false
}

/// The diary found on a doc-comment line, if any.
fn diary(comment: &str) -> Option<&'static str> {
    if comment.contains("Example") {
        return None; // a source's worked example
    }
    if has_date(comment) {
        return Some("a date");
    }
    let units = [" s", " MB", " GB"];
    for between in [" -> ", " against ", " instead of "] {
        if has_figure_pair(comment, between, &units) {
            return Some("a before-and-after figure");
        }
    }
    None
}

#[test]
fn doc_comments_carry_no_measurement_diaries() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for krate in ["fairpath", "fairpath-gcode", "fairpath-cli"] {
        crate::common::rust_files(&root.join(krate).join("src"), &mut files);
    }
    assert!(files.len() > 100, "{} source files found", files.len());
    let mut found = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for (i, line) in text.lines().enumerate() {
            let t = line.trim_start();
            if let Some(c) = t.strip_prefix("///").or_else(|| t.strip_prefix("//!")) {
                if let Some(what) = diary(c) {
                    found.push(format!("{}:{}: {what}: {}", f.display(), i + 1, c.trim()));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "measurements in doc comments (move them to docs/tuning.md and point there):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_diary_patterns_catch_what_they_should() {
    assert_eq!(diary(" measured 2026-11-28 on the raster"), Some("a date"));
    assert_eq!(
        diary(" (`line-contouring-xz.ngc` 12.64 -> 12.91 s, nothing faster)"),
        Some("a before-and-after figure")
    );
    assert_eq!(
        diary(" curves plan 59.864 s against 59.497 s"),
        Some("a before-and-after figure")
    );
    assert_eq!(
        diary(" peak RSS 627 -> 504 MB"),
        Some("a before-and-after figure")
    );
    assert_eq!(
        diary(" took 68 s instead of 5 s"),
        Some("a before-and-after figure")
    );
    // What and why, units, derivations and sources stay.
    assert_eq!(diary(" the speed `v -> 0` at a corner; 1 ms periods"), None);
    assert_eq!(
        diary(" (the book's Example 3.12: 1.76 s instead of 2.67 s)"),
        None
    );
    assert_eq!(diary(" a cap of 5 mm against 3 mm of travel"), None);
}
