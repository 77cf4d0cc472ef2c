//! Spline programs against LinuxCNC's own interpreter, `rs274 -g`: Debian's
//! LinuxCNC 2.9 (`rs274` on the PATH, package `linuxcnc-uspace`) and, when
//! present, a run-in-place build of master (`/root/lcnc-master`, or the
//! directory in `FAIRPATH_LCNC_MASTER`).
//!
//! `rs274` prints a spline as one canon call with its number of control
//! points (`NURBS_FEED(n, ...)` in 2.9, `NURBS_G5_FEED` / `NURBS_G6_FEED_`
//! in master), not the biarcs the real canon layer makes of it; so the
//! comparison is: the same sequence of motion calls (straight moves with
//! their end points, arcs, splines with their number of control points),
//! and the same position after every line (a `(DEBUG,...)` line printing
//! `#<_x> #<_y> #<_z>` is added after each line of a copy of the program
//! in a temporary directory). The biarcs themselves are checked against
//! LinuxCNC's code in `fairpath::controller::linuxcnc`'s tests.
//!
//! Without 2.9's `rs274` the tests are skipped with a message, unless
//! `FAIRPATH_REQUIRE_RS274` is set; without master, its parts are skipped.

use crate::common;

use fairpath::controller::Plane;
use fairpath::geom::{Curve, Nurbs, Vec3};
use fairpath_gcode::{
    g5_2_blocks, g6_2_block, parse_with, G6Dialect, MoveKind, ParseOptions, Program, SplineReading,
    SplineWriteOptions,
};
use std::path::{Path, PathBuf};
use std::process::Command;

#[derive(Debug, Clone, PartialEq)]
enum Call {
    Traverse([f64; 3]),
    Feed([f64; 3]),
    Arc,
    Spline(usize),
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Lcnc {
    V29,
    Master,
}

fn master_dir() -> PathBuf {
    std::env::var_os("FAIRPATH_LCNC_MASTER")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/root/lcnc-master"))
}

/// The command running `rs274 -g file` in the file's directory (rs274
/// reads and writes its parameter file `rs274ngc.var` in the current
/// directory: parallel runs in one directory disturb each other).
fn command(which: Lcnc, file: &Path) -> Command {
    let mut c = command_in_cwd(which, file);
    if let Some(dir) = file.parent().filter(|d| d.is_dir()) {
        c.current_dir(dir);
    }
    c
}

fn command_in_cwd(which: Lcnc, file: &Path) -> Command {
    match which {
        Lcnc::V29 => {
            let mut c = Command::new("rs274");
            c.arg("-g").arg(file);
            c
        }
        Lcnc::Master => {
            let env = master_dir().join("scripts/rip-environment");
            let mut c = Command::new("bash");
            c.arg("-c")
                .arg("set +u; source \"$1\" >/dev/null 2>&1; exec rs274 -g \"$2\"")
                .arg("_")
                .arg(env)
                .arg(file);
            c
        }
    }
}

fn available(which: Lcnc) -> bool {
    match which {
        Lcnc::V29 => {
            let _guard = common::RS274.lock().unwrap_or_else(|e| e.into_inner());
            command(which, Path::new("/dev/null")).output().is_ok()
        }
        Lcnc::Master => master_dir().join("bin/rs274").exists(),
    }
}

/// 2.9 must be there when `FAIRPATH_REQUIRE_RS274` is set.
fn have_29() -> bool {
    if available(Lcnc::V29) {
        return true;
    }
    assert!(
        std::env::var_os("FAIRPATH_REQUIRE_RS274").is_none(),
        "rs274 is required (FAIRPATH_REQUIRE_RS274) but not installed"
    );
    eprintln!("rs274 (linuxcnc-uspace) not installed: skipped");
    false
}

fn nums(l: &str, open: &str) -> Vec<f64> {
    let start = l.find(open).unwrap() + open.len();
    let inner = &l[start..l[start..].find(')').map_or(l.len(), |i| start + i)];
    inner
        .split([',', ' '])
        .filter_map(|x| x.trim().trim_matches('"').parse().ok())
        .collect()
}

/// The motion calls rs274 prints, and the positions `(line, xyz)` the
/// inserted DEBUG lines report; or its error.
#[allow(clippy::type_complexity)]
fn run(which: Lcnc, file: &Path) -> Result<(Vec<Call>, Vec<(usize, [f64; 3])>), String> {
    // One at a time (see `common::RS274`).
    let out = {
        let _guard = common::RS274.lock().unwrap_or_else(|e| e.into_inner());
        command(which, file).output().map_err(|e| e.to_string())?
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() {
        let stderr = String::from_utf8_lossy(&out.stderr);
        return Err(format!(
            "{} ({})",
            stderr.replace("executing", "").trim(),
            out.status
        ));
    }
    let (mut calls, mut pos) = (Vec::new(), Vec::new());
    for l in stdout.lines() {
        if l.contains("STRAIGHT_TRAVERSE(") || l.contains("STRAIGHT_FEED(") {
            let n = nums(l, "(");
            let p = [n[0], n[1], n[2]];
            calls.push(if l.contains("TRAVERSE") {
                Call::Traverse(p)
            } else {
                Call::Feed(p)
            });
        } else if l.contains("ARC_FEED(") {
            calls.push(Call::Arc);
        } else if let Some(i) = l.find("NURBS_") {
            calls.push(Call::Spline(nums(&l[i..], "(")[0] as usize));
        } else if let Some(i) = l.find("MESSAGE(\"L") {
            let n = nums(&l[i + 10..], "");
            pos.push((n[0] as usize, [n[1], n[2], n[3]]));
        }
    }
    Ok((calls, pos))
}

/// A copy of `text` with a DEBUG line printing the position after every
/// line (not after the program end).
fn probe(text: &str, dir: &Path, name: &str) -> PathBuf {
    let mut out = String::new();
    for (i, l) in text.lines().enumerate() {
        out.push_str(l);
        out.push('\n');
        let u = l.to_uppercase();
        let ends = u.trim_start().starts_with('%')
            || u.split(|c: char| !c.is_ascii_alphanumeric())
                .any(|w| w == "M2" || w == "M02" || w == "M30");
        if !ends {
            out.push_str(&format!("(DEBUG,L{} #<_x> #<_y> #<_z>)\n", i + 1));
        }
    }
    let p = dir.join(name);
    std::fs::write(&p, out).unwrap();
    p
}

/// Our motion calls (splines from the exact reading: one per block, with
/// LinuxCNC's count of control points) and our position after every line,
/// in the program's units.
fn ours(text: &str) -> (Vec<Call>, Vec<[f64; 3]>) {
    let p: Program = parse_with(
        text.as_bytes(),
        &ParseOptions {
            splines: SplineReading::Exact,
            ..Default::default()
        },
    )
    .unwrap();
    let mut calls = Vec::new();
    let mut last_block = None;
    for m in p.moves() {
        let u = p.lines()[m.line - 1].units.mm_per_unit();
        let e = m.piece.end();
        let e = [e.x / u, e.y / u, e.z / u];
        if m.kind == MoveKind::Spline {
            if last_block == Some(m.piece.source_lines) {
                continue;
            }
            // The block's NURBS (a G6.2 may start with a straight line).
            let n: &Nurbs = p
                .moves()
                .iter()
                .filter(|o| o.piece.source_lines == m.piece.source_lines)
                .find_map(|o| match &o.piece.curve {
                    Curve::Nurbs(n) => Some(n),
                    _ => None,
                })
                .unwrap();
            let g6 = p.lines()[m.piece.source_lines.0 - 1]
                .words
                .iter()
                .any(|w| w.letter == 'G' && w.value == 6.2);
            calls.push(Call::Spline(if g6 {
                n.knots.len()
            } else {
                n.points.len()
            }));
            last_block = Some(m.piece.source_lines);
        } else if m.piece.rapid {
            calls.push(Call::Traverse(e));
        } else if matches!(m.piece.curve, Curve::Arc(_)) {
            calls.push(Call::Arc);
        } else {
            calls.push(Call::Feed(e));
        }
    }
    let mut pos = Vec::new();
    let mut cur = [0.0; 3];
    for l in p.lines() {
        if let Some(m) = l.moves.clone().last() {
            let e = p.moves()[m].piece.end();
            cur = [e.x, e.y, e.z];
        }
        let u = l.units.mm_per_unit();
        pos.push([cur[0] / u, cur[1] / u, cur[2] / u]);
    }
    (calls, pos)
}

fn close(p: &[f64; 3], q: &[f64; 3], tol: f64) -> bool {
    p.iter().zip(q).all(|(u, v)| (u - v).abs() <= tol)
}

/// Walks both call lists together; a straight move within print resolution
/// of the last position on one side only is skipped (rs274 prints %.4f).
fn same_calls(a: &[Call], b: &[Call]) -> Result<(), String> {
    let (mut i, mut j) = (0, 0);
    let mut last = [0.0f64; 3];
    let end = |c: &Call| match c {
        Call::Traverse(p) | Call::Feed(p) => Some(*p),
        _ => None,
    };
    while i < a.len() && j < b.len() {
        let matched = match (&a[i], &b[j]) {
            (Call::Traverse(p), Call::Traverse(q)) | (Call::Feed(p), Call::Feed(q)) => {
                close(p, q, 1.5e-4)
            }
            (x, y) => x == y,
        };
        if matched {
            if let Some(p) = end(&b[j]) {
                last = p;
            }
            i += 1;
            j += 1;
        } else if end(&a[i]).is_some_and(|p| close(&p, &last, 1.5e-4)) {
            i += 1;
        } else if end(&b[j]).is_some_and(|p| close(&p, &last, 1.5e-4)) {
            j += 1;
        } else {
            return Err(format!("call {i} / {j}: {:?} vs {:?}", a[i], b[j]));
        }
    }
    if a[i..]
        .iter()
        .chain(&b[j..])
        .all(|c| end(c).is_some_and(|p| close(&p, &last, 1.5e-4)))
    {
        Ok(())
    } else {
        Err(format!(
            "{} calls vs {} (stopped at {i} / {j})",
            a.len(),
            b.len()
        ))
    }
}

/// Compares one program with one LinuxCNC: Ok(positions compared), or
/// Err(rs274's error) when it refuses the program. With `g6_resync` false,
/// positions are compared up to the end of the first G6.2 block only:
/// master's interpreter then keeps the position of the block's last line
/// (a knot-only line: the position before the block), which our writer
/// corrects with a `G1` to the end point and programs from elsewhere do
/// not.
fn compare(
    which: Lcnc,
    text: &str,
    name: &str,
    dir: &Path,
    g6_resync: bool,
) -> Result<usize, String> {
    let probe_file = probe(text, dir, name);
    let (calls, pos) = run(which, &probe_file)?;
    let (our_calls, our_pos) = ours(text);
    same_calls(&our_calls, &calls).unwrap_or_else(|e| panic!("{name} ({which:?}): {e}"));
    let prog = parse_with(text.as_bytes(), &ParseOptions::default()).unwrap();
    // Lines where a G6.2 block ends (LinuxCNC's position is wrong there).
    let g6_ends: Vec<usize> = prog
        .moves()
        .iter()
        .filter(|m| {
            m.kind == MoveKind::Spline
                && prog.lines()[m.piece.source_lines.0 - 1]
                    .words
                    .iter()
                    .any(|w| w.letter == 'G' && w.value == 6.2)
        })
        .map(|m| m.line)
        .collect();
    let stop = g6_ends.first().copied().filter(|_| !g6_resync);
    let mut n = 0;
    for (line, p) in pos {
        if stop.is_some_and(|s| line >= s) {
            break;
        }
        if g6_ends.contains(&line) {
            continue;
        }
        let q = our_pos[line - 1];
        assert!(
            close(
                &p,
                &q,
                2e-6 + 1e-9 * q.iter().fold(0.0f64, |m, v| m.max(v.abs()))
            ),
            "{name} ({which:?}) line {line}: rs274 {p:?}, ours {q:?}"
        );
        n += 1;
    }
    Ok(n)
}

fn nurbs_files(sub: &str) -> Vec<PathBuf> {
    let Some(dir) = common::shared_paths() else {
        return Vec::new();
    };
    common::files_under(&dir.join("linuxcnc-nurbs").join(sub))
        .into_iter()
        .filter(|f| !std::fs::read(f).unwrap().contains(&b'#'))
        .collect()
}

#[test]
fn g5_programs_agree_with_rs274() {
    if !have_29() {
        return;
    }
    let dir = tempfile_dir("g5");
    let master = available(Lcnc::Master);
    let (mut with29, mut with_master) = (0, 0);
    for f in nurbs_files("G5") {
        let text = std::fs::read_to_string(&f).unwrap();
        let name = f.file_name().unwrap().to_string_lossy().to_string();
        match compare(Lcnc::V29, &text, &name, &dir, false) {
            Ok(n) => {
                assert!(n > 5, "{name}");
                with29 += 1;
            }
            Err(e) => eprintln!("{name}: LinuxCNC 2.9 refuses it: {e}"),
        }
        if master {
            compare(Lcnc::Master, &text, &name, &dir, false)
                .unwrap_or_else(|e| panic!("{name}: master refuses it: {e}"));
            with_master += 1;
        }
    }
    eprintln!("G5 programs: {with29} compared with 2.9, {with_master} with master");
    if common::shared_paths().is_some() {
        assert!(with29 >= 3, "{with29}");
    }
}

#[test]
fn g6_programs_agree_with_rs274_master() {
    if !available(Lcnc::Master) {
        eprintln!(
            "LinuxCNC master not found at {}: skipped",
            master_dir().display()
        );
        return;
    }
    let dir = tempfile_dir("g6");
    let mut compared = 0;
    for f in nurbs_files("G6") {
        let text = std::fs::read_to_string(&f).unwrap();
        let name = f.file_name().unwrap().to_string_lossy().to_string();
        compare(Lcnc::Master, &text, &name, &dir, false)
            .unwrap_or_else(|e| panic!("{name}: master refuses it: {e}"));
        compared += 1;
    }
    eprintln!("{compared} G6 programs compared with master");
}

fn tempfile_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fairpath-splines-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn curve(plane: Plane, degree: usize, uniform: bool, rational: bool) -> Nurbs {
    let raw = [
        [0.0, 0.0],
        [5.0, 8.0],
        [12.0, 9.0],
        [16.0, 1.0],
        [22.0, -4.0],
        [27.0, 2.0],
    ];
    let points: Vec<Vec3> = raw.iter().map(|p| plane.from_plane(*p, 0.0)).collect();
    let n = points.len();
    let knots = if uniform {
        fairpath::controller::linuxcnc::g5_2_knots(n, degree + 1).unwrap()
    } else {
        let mut k = vec![0.0; degree + 1];
        for i in 1..n - degree {
            k.push((i as f64).powf(1.3));
        }
        k.extend(std::iter::repeat_n(
            ((n - degree) as f64).powf(1.3),
            degree + 1,
        ));
        k
    };
    let weights = rational.then(|| (0..n).map(|i| 1.0 + 0.25 * (i % 3) as f64).collect());
    Nurbs::new(degree, knots, points, weights).unwrap()
}

/// What we write, LinuxCNC reads: G5.2 blocks in 2.9 (G17) and master (all
/// planes), G6.2 blocks in master; the same calls and positions.
#[test]
fn written_blocks_run_in_rs274() {
    if !have_29() {
        return;
    }
    let dir = tempfile_dir("written");
    let master = available(Lcnc::Master);
    let mut runs = 0;
    for plane in [Plane::Xy, Plane::Zx, Plane::Yz] {
        for (deg, uniform, rational) in [(3, true, false), (2, false, true), (3, false, false)] {
            for (units, mm) in [("G21", 1.0), ("G20", 25.4)] {
                for incremental in [false, true] {
                    let c = curve(plane, deg, uniform, rational);
                    let opts = SplineWriteOptions {
                        mm_per_unit: mm,
                        decimals: 4,
                        incremental,
                        ..SplineWriteOptions::default()
                    };
                    let dist = if incremental { "G91" } else { "G90" };
                    let head = format!("{units} {} G90 F50\nG0 X0 Y0 Z0\n{dist}\n", plane.gword());
                    let tail = format!("G1 {}1\nM2\n", ['X', 'Y', 'Z'][plane.axes().0]);
                    let g5 = head.clone() + &g5_2_blocks(&c, plane, &opts).unwrap() + &tail;
                    let name = format!("g5-{runs}.ngc");
                    if plane == Plane::Xy {
                        compare(Lcnc::V29, &g5, &name, &dir, true)
                            .unwrap_or_else(|e| panic!("2.9 refuses our G5.2:\n{g5}\n{e}"));
                    }
                    if master {
                        compare(Lcnc::Master, &g5, &name, &dir, true)
                            .unwrap_or_else(|e| panic!("master refuses our G5.2:\n{g5}\n{e}"));
                        let dialect = G6Dialect::Linuxcnc { plane, method: 1 };
                        let g6 = head.clone() + &g6_2_block(&c, dialect, &opts).unwrap() + &tail;
                        let name = format!("g6-{runs}.ngc");
                        compare(Lcnc::Master, &g6, &name, &dir, true)
                            .unwrap_or_else(|e| panic!("master refuses our G6.2:\n{g6}\n{e}"));
                    }
                    runs += 1;
                }
            }
        }
    }
    eprintln!("{runs} written programs run (master: {master})");
}
