//! The progress line: on a terminal's standard error (a pseudo-terminal
//! made by util-linux `script`), never in a pipe, never with `--quiet`, and
//! erased when the job ends. `FAIRPATH_PROGRESS_DELAY_MS=0` shows it at
//! once (a second's delay by default). Skipped without `script`.

use std::path::Path;
use std::process::Command;

const ERASE: &str = "\r\x1b[2K";

fn have_script() -> bool {
    Command::new("script")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Runs `fairpath smooth` on a large enough program with `extra` flags,
/// under a pseudo-terminal when `tty`; returns everything it printed.
fn run(tty: bool, extra: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.ngc");
    let cmd = format!(
        "{} smooth {} -t 0.05mm -m bspline-corner -o {} {extra}",
        env!("CARGO_BIN_EXE_fairpath"),
        root.join("examples/zigzag.ngc").display(),
        out.display()
    );
    let o = if tty {
        Command::new("script")
            .args(["-qec", &cmd, "/dev/null"])
            .env("FAIRPATH_PROGRESS_DELAY_MS", "0")
            .output()
            .unwrap()
    } else {
        Command::new("sh")
            .args(["-c", &cmd])
            .env("FAIRPATH_PROGRESS_DELAY_MS", "0")
            .output()
            .unwrap()
    };
    assert!(o.status.success());
    String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr)
}

#[test]
fn progress_shows_on_a_terminal_only_and_not_when_quiet() {
    if !have_script() {
        eprintln!("script (util-linux) not installed: skipped");
        return;
    }
    // The step names come from the library's clock, so a slow step of a
    // small program may still pass unseen: retried a few times.
    let shown = (0..5).any(|_| {
        let t = run(true, "");
        t.contains(ERASE) && t.contains("fairpath smooth:")
    });
    assert!(shown, "no progress line on a terminal");
    assert!(!run(true, "--quiet").contains(ERASE));
    assert!(!run(false, "").contains(ERASE));
}
