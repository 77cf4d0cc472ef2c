//! LinuxCNC's interpreter as a client of the tests: run `rs274 -g` on a
//! file and compare the motion calls it prints with fairpath's moves.

use std::path::{Path, PathBuf};
use std::process::Command;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Canon {
    Traverse([f64; 3]),
    Feed([f64; 3]),
    Arc([f64; 3]),
}

/// One rs274 at a time (they share `rs274ngc.var` in the working
/// directory, and 2.9's dies when two run at once).
static RS274: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Motion calls printed by `bin -g path` (run by `bash -c` in the file's
/// directory), or the error it reports.
pub fn rs274_of(bin: &str, path: &Path) -> Result<Vec<Canon>, String> {
    let _one = RS274.lock().unwrap_or_else(|e| e.into_inner());
    let out = Command::new("bash")
        .arg("-c")
        .arg(format!("{bin} -g \"$1\""))
        .arg("_")
        .arg(path)
        .current_dir(path.parent().unwrap_or(Path::new(".")))
        .output()
        .map_err(|e| e.to_string())?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        return Err(format!(
            "{}{}",
            stderr.trim(),
            stdout.lines().last().unwrap_or("")
        ));
    }
    let mut v = Vec::new();
    // In-plane axes (first, second) and the normal axis of ARC_FEED.
    let mut plane = (0, 1, 2);
    for line in stdout.lines() {
        let args = |l: &str| -> Vec<f64> {
            let inner = &l[l.find('(').unwrap() + 1..l.rfind(')').unwrap()];
            inner
                .split(',')
                .map(|x| x.trim().parse().unwrap_or(f64::NAN))
                .collect()
        };
        if line.contains("SELECT_PLANE(") {
            plane = if line.contains("CANON_PLANE_XZ") {
                (2, 0, 1)
            } else if line.contains("CANON_PLANE_YZ") {
                (1, 2, 0)
            } else {
                (0, 1, 2)
            };
        } else if line.contains("STRAIGHT_TRAVERSE(") {
            let n = args(line);
            v.push(Canon::Traverse([n[0], n[1], n[2]]));
        } else if line.contains("STRAIGHT_FEED(") {
            let n = args(line);
            v.push(Canon::Feed([n[0], n[1], n[2]]));
        } else if line.contains("ARC_FEED(") {
            let n = args(line);
            let mut e = [0.0; 3];
            e[plane.0] = n[0];
            e[plane.1] = n[1];
            e[plane.2] = n[5];
            v.push(Canon::Arc(e));
        }
    }
    Ok(v)
}

pub fn close(p: &[f64; 3], q: &[f64; 3]) -> bool {
    p.iter().zip(q).all(|(u, v)| (u - v).abs() <= 1.5e-4)
}

/// Walks both lists of motion calls together: matching calls advance both;
/// a straight move that ends within print resolution (1e-4) of the last
/// matched position is a zero-length move on that side only (rs274 emits one
/// for a bare `G0`; moves below its %.4f print resolution vanish) and is
/// skipped; anything else is a disagreement.
pub fn same(a: &[Canon], b: &[Canon]) -> Result<(), String> {
    let (mut i, mut j) = (0, 0);
    let mut last = [0.0f64; 3];
    let end = |c: &Canon| match c {
        Canon::Traverse(p) | Canon::Feed(p) => Some(*p),
        Canon::Arc(_) => None,
    };
    while i < a.len() && j < b.len() {
        let (x, y) = (&a[i], &b[j]);
        let matched = match (x, y) {
            (Canon::Traverse(p), Canon::Traverse(q))
            | (Canon::Feed(p), Canon::Feed(q))
            | (Canon::Arc(p), Canon::Arc(q)) => close(p, q),
            _ => false,
        };
        if matched {
            last = match y {
                Canon::Traverse(p) | Canon::Feed(p) | Canon::Arc(p) => *p,
            };
            i += 1;
            j += 1;
        } else if end(x).is_some_and(|p| close(&p, &last)) {
            i += 1;
        } else if end(y).is_some_and(|p| close(&p, &last)) {
            j += 1;
        } else {
            return Err(format!(
                "motion {i} / {j} of {} / {}: {x:?} vs {y:?} (after {last:?})",
                a.len(),
                b.len()
            ));
        }
    }
    let rest = |v: &[Canon]| v.iter().all(|c| end(c).is_some_and(|p| close(&p, &last)));
    if rest(&a[i..]) && rest(&b[j..]) {
        Ok(())
    } else {
        Err(format!(
            "{} motion calls vs {} (stopped at {i} / {j})",
            a.len(),
            b.len()
        ))
    }
}

pub fn have_rs274() -> bool {
    let _one = RS274.lock().unwrap_or_else(|e| e.into_inner());
    Command::new("rs274")
        .arg("-g")
        .arg("/dev/null")
        .output()
        .is_ok()
}

/// LinuxCNC master's run-in-place interpreter, if built.
pub fn master() -> Option<String> {
    let dir = std::env::var_os("FAIRPATH_LCNC_MASTER")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/root/lcnc-master"));
    dir.join("bin/rs274").exists().then(|| {
        format!(
            "set +u; . '{}' >/dev/null 2>&1; rs274",
            dir.join("scripts/rip-environment").display()
        )
    })
}
