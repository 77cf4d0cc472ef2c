//! `fairpath report`: the page holds the three pictures for the program and
//! each method, the numbers of `simulate`, and loads in a real browser
//! (headless Chromium, Debian's `chromium`) without script errors.
//!
//! Without Chromium the browser test is skipped with a message, unless
//! `FAIRPATH_REQUIRE_CHROMIUM` is set (`.ci/run` sets it after installing
//! the package), in which case its absence is a failure.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Writes the report of `program` with `methods` and returns its HTML.
fn report(program: &Path, methods: &str, out: &Path) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_fairpath"))
        .args(["report", "-t", "0.05mm", "--methods", methods, "-o"])
        .arg(out)
        .arg(program)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read_to_string(out).unwrap()
}

fn count(html: &str, what: &str) -> usize {
    html.matches(what).count()
}

/// The planned time of a program as `fairpath simulate --format json`
/// gives it.
fn simulated_time(program: &Path) -> f64 {
    let o = Command::new(env!("CARGO_BIN_EXE_fairpath"))
        .args(["simulate", "--format", "json"])
        .arg(program)
        .output()
        .unwrap();
    assert!(o.status.success());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    v["time_s"].as_f64().unwrap()
}

#[test]
fn the_page_holds_the_three_pictures_for_each_method() {
    let dir = tempfile::tempdir().unwrap();
    let program = root().join("examples/pocket-corners.ngc");
    let html = report(&program, "auto,arc-fit", &dir.path().join("r.html"));
    // A 2.5D program: the XY view only.
    assert_eq!(count(&html, r#"<svg class="pathview""#), 1);
    // The band around each feed run of the original, and the original.
    let runs = count(&html, r#"<polyline class="band""#);
    assert!(runs > 0);
    assert_eq!(count(&html, r#"<polyline class="original""#), runs);
    assert!(count(&html, r#"<polyline class="written""#) >= 2);
    // Curvature, feed against time, feed against arc length for the
    // program and each method.
    assert_eq!(count(&html, r#"<svg class="chart""#), 2 + 3);
    for id in ["curvature", "feed-time", "feed-length-0", "feed-length-2"] {
        assert!(html.contains(&format!(r#"id="{id}""#)), "{id}");
    }
    // The summary: the program and one row per method, the program's time
    // as `simulate` plans it.
    assert_eq!(count(&html, "<tr><td>"), 3);
    let t = format!("{:.3}", simulated_time(&program));
    assert!(html.contains(&format!("<td>{t}</td><td>1.000</td>")), "{t}");
    // Self-contained: nothing to fetch.
    for fetch in ["src=\"http", "href=\"http", "<script src", "<link"] {
        assert!(!html.contains(fetch), "{fetch}");
    }
}

#[test]
fn a_3d_path_gets_a_view_per_plane() {
    let dir = tempfile::tempdir().unwrap();
    let program = root().join("../shared/paths/synthetic/helix.ngc");
    if !program.exists() {
        eprintln!("{} not found: skipped", program.display());
        return;
    }
    let html = report(&program, "bspline-corner", &dir.path().join("h.html"));
    for plane in ["XY", "XZ", "YZ"] {
        assert!(
            html.contains(&format!(r#"data-plane="{plane}""#)),
            "{plane}"
        );
    }
}

#[test]
fn a_method_that_does_not_exist_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.html");
    let o = Command::new(env!("CARGO_BIN_EXE_fairpath"))
        .args(["report", "-t", "0.05mm", "--methods", "smoothest", "-o"])
        .arg(&out)
        .arg(root().join("examples/zigzag.ngc"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(!out.exists(), "no partial file");
}

fn have_chromium() -> bool {
    Command::new("chromium")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

#[test]
fn the_page_loads_in_chromium_without_script_errors() {
    if !have_chromium() {
        assert!(
            std::env::var_os("FAIRPATH_REQUIRE_CHROMIUM").is_none(),
            "chromium is required (FAIRPATH_REQUIRE_CHROMIUM) but not installed"
        );
        eprintln!("chromium not installed: skipped");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("r.html");
    let html = report(
        &root().join("examples/pocket-corners.ngc"),
        "auto,bspline-corner",
        &page,
    );
    let o = Command::new("chromium")
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--enable-logging=stderr",
            "--v=0",
            "--virtual-time-budget=2000",
            "--dump-dom",
        ])
        .arg(format!("file://{}", page.display()))
        .output()
        .unwrap();
    let dom = String::from_utf8_lossy(&o.stdout);
    let log = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{log}");
    // The script ran to its end and caught no error.
    assert!(dom.contains(r#"data-ready="1""#), "{log}");
    assert!(dom.contains(r#"<pre id="errors"></pre>"#), "{dom}");
    assert!(!log.contains("Uncaught"), "{log}");
    // The browser built every drawn element of the file.
    for what in [
        "<polyline",
        r#"<svg class="pathview""#,
        r#"<svg class="chart""#,
        "<circle",
    ] {
        assert_eq!(count(&dom, what), count(&html, what), "{what}");
    }
}
