//! Nothing is lost in what `fairpath smooth` writes, on every reference
//! program it reads: every line without motion in order, every N number,
//! every feed; the file gets the permissions a new file gets (or keeps
//! those of the file it replaces); the input is never overwritten unless
//! `--in-place` asks for it.

use crate::common;

use common::{bin, example};
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Programs above this size (bytes) are left to the benchmarks.
const MAX_BYTES: u64 = 200_000;

/// Programs longer than this many lines are sampled: cut after the last
/// line at most this far in that does not end inside a spline block, and
/// smoothed from a temporary copy (the smoothing of the large programs
/// keeps this test near two minutes in CI; their lines repeat a few
/// shapes).
const SAMPLE_LINES: usize = 400;

/// Programs that lose something today: each must still lose something
/// here (so that the list cannot go stale silently), and each entry names
/// the kind of loss (a word of the loss's description); losses of any other
/// kind still fail. Empty: `rgh.ngc` (a feed on nearly every line, most of
/// them lost while runs spanned feed changes) was the last, fixed when a
/// feed change started ending runs (`fairpath-gcode`'s `group_runs`).
const KNOWN_FAILURES: &[(&str, &str)] = &[];

/// Letters of words that make a line a motion line here: axes, arc centres
/// and radius (lines of spline blocks are told by `in_block` and by their
/// moves: `G5.3` ends a block and holds its moves).
const MOTION_LETTERS: &str = "XYZABCUVWIJKR";

/// Relative difference below which two feeds are the same number (the
/// writer writes a feed it converts with 4 decimals).
const SAME_FEED: f64 = 1e-6;

fn shared_root() -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/paths");
    p.is_dir().then_some(p)
}

fn programs(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            programs(&p, out);
        } else if matches!(
            p.extension().and_then(|e| e.to_str()),
            Some("ngc" | "gcode" | "nc" | "tap")
        ) {
            out.push(p);
        }
    }
}

/// The N numbers of `text`: N words, and those named in the writer's
/// `(N30-N50 merged into ...)` comments (a stretch names every number from
/// its first to its last).
struct Numbers {
    words: HashSet<u64>,
    stretches: Vec<(f64, f64)>,
}

impl Numbers {
    fn of(program: &fairpath_gcode::Program) -> Numbers {
        let mut words = HashSet::new();
        let mut stretches = Vec::new();
        for l in program.lines() {
            for w in l.words.iter().filter(|w| w.letter == 'N') {
                words.insert(w.value.to_bits());
            }
            let Some(open) = l.text.find('(') else {
                continue;
            };
            if !l.text.contains(" merged into ") {
                continue;
            }
            let items = l.text[open + 1..].split(" merged into ").next().unwrap();
            for item in items.split(' ') {
                let n = |t: &str| t.trim_start_matches('N').parse::<f64>().ok();
                match item.split_once('-') {
                    Some((a, b)) => stretches.push((n(a).unwrap(), n(b).unwrap())),
                    None => stretches.push((n(item).unwrap(), n(item).unwrap())),
                }
            }
        }
        Numbers { words, stretches }
    }

    fn has(&self, v: f64) -> bool {
        self.words.contains(&v.to_bits()) || self.stretches.iter().any(|&(a, b)| a <= v && v <= b)
    }
}

/// What `output` lost of `input` (empty: nothing): lines without motion
/// missing or out of order, N numbers, feeds.
fn losses(input: &str, output: &str) -> Vec<String> {
    let a = fairpath_gcode::parse(input.as_bytes()).unwrap();
    let b = match fairpath_gcode::parse(output.as_bytes()) {
        Ok(b) => b,
        Err(e) => return vec![format!("the output does not read back: {e}")],
    };
    let mut lost = Vec::new();
    // Lines without motion, in order (a subsequence of the output's lines).
    let out_lines: Vec<&str> = b.lines().iter().map(|l| l.text.as_str()).collect();
    let mut at = 0;
    for l in a.lines() {
        let motion = l.in_block
            || !l.moves.is_empty()
            || l.words.iter().any(|w| MOTION_LETTERS.contains(w.letter));
        if motion {
            continue;
        }
        match out_lines[at..].iter().position(|o| *o == l.text) {
            Some(k) => at += k + 1,
            None => {
                lost.push(format!(
                    "line {} {:?} missing or out of order",
                    l.number, l.text
                ));
                break;
            }
        }
    }
    // N numbers.
    let numbers = Numbers::of(&b);
    for l in a.lines() {
        for w in l.words.iter().filter(|w| w.letter == 'N') {
            if !numbers.has(w.value) {
                lost.push(format!("line {}: N{} lost", l.number, w.text));
            }
        }
    }
    // Feeds, as numbers in the program's units.
    let feeds = |p: &fairpath_gcode::Program| -> Vec<f64> {
        p.lines()
            .iter()
            .filter(|l| l.interpreted)
            .flat_map(|l| l.words.iter().filter(|w| w.letter == 'F').map(|w| w.value))
            .collect()
    };
    let written = feeds(&b);
    for f in feeds(&a) {
        if !written
            .iter()
            .any(|&g| (g - f).abs() <= SAME_FEED * f.abs().max(1.0))
        {
            lost.push(format!("feed F{f} lost"));
        }
    }
    lost.dedup();
    lost
}

/// The program to smooth for `path`: itself, or its first lines (see
/// [`SAMPLE_LINES`]) in `dir`, in a file named after `rel` (the corpus
/// holds programs of one name in several folders, e.g. two texts of
/// `blur_torus.ngc`, which the workers may sample at the same time).
fn sample(path: &Path, rel: &str, program: &fairpath_gcode::Program, dir: &Path) -> PathBuf {
    let lines = program.lines();
    if lines.len() <= SAMPLE_LINES {
        return path.to_path_buf();
    }
    let cut = (1..=SAMPLE_LINES)
        .rev()
        .find(|&k| !lines[k - 1].in_block)
        .unwrap_or(SAMPLE_LINES);
    let mut text = String::new();
    for l in &lines[..cut] {
        text.push_str(&l.text);
        text.push_str(l.ending);
    }
    let to = dir.join(format!("sample-{}", rel.replace('/', "_")));
    std::fs::write(&to, text).unwrap();
    to
}

#[cfg(unix)]
fn mode(p: &Path) -> u32 {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(p).unwrap().permissions().mode() & 0o7777
}

/// The mode a new file gets here: 0666 less the umask, as a probe file
/// created in `dir` shows (the umask is not changed to read it).
#[cfg(unix)]
fn new_file_mode(dir: &Path) -> u32 {
    let probe = dir.join("umask-probe");
    std::fs::File::create(&probe).unwrap();
    let m = mode(&probe);
    std::fs::remove_file(&probe).unwrap();
    m
}

/// What one program smoothed gives: `Ok(losses)`, or `Err(stderr)` when
/// smooth failed.
type Outcome = Result<Vec<String>, String>;

/// One program smoothed; `None` when fairpath does not read it.
/// `new_mode` is the mode a new file gets in `dir` (probed once, before the
/// threads start: a probe per call raced between the two threads).
fn smooth_and_compare(path: &Path, rel: &str, dir: &Path, new_mode: u32) -> Option<Outcome> {
    let bytes = std::fs::read(path).unwrap();
    let program = match fairpath_gcode::parse(&bytes) {
        Ok(p) if !p.is_empty() => p,
        // Rejected (or nothing to smooth): not this test's business.
        _ => return None,
    };
    let input = sample(path, rel, &program, dir);
    let out = dir.join(format!("{}.out.ngc", rel.replace('/', "_")));
    let r = bin()
        .arg("smooth")
        .arg(&input)
        .arg("-o")
        .arg(&out)
        .args(["--tolerance", "0.05mm"])
        .output()
        .unwrap();
    if !r.status.success() {
        return Some(Err(String::from_utf8_lossy(&r.stderr).into_owned()));
    }
    #[cfg(unix)]
    {
        let want = new_mode;
        if mode(&out) != want {
            return Some(Ok(vec![format!(
                "output mode {:o}, a new file gets {want:o}",
                mode(&out)
            )]));
        }
    }
    let a = String::from_utf8_lossy(&std::fs::read(&input).unwrap()).into_owned();
    let b = std::fs::read_to_string(&out).unwrap();
    Some(Ok(losses(&a, &b)))
}

#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn every_reference_program_keeps_its_lines_n_numbers_and_feeds() {
    let Some(root) = shared_root() else {
        eprintln!("../shared/paths not found: skipped");
        return;
    };
    let mut files = Vec::new();
    programs(&root, &mut files);
    files.retain(|f| std::fs::metadata(f).unwrap().len() < MAX_BYTES);
    let files = common::largest_first(files);
    assert!(files.len() > 100, "found {} programs", files.len());
    let dir = tempfile::tempdir().unwrap();
    #[cfg(unix)]
    let new_mode = new_file_mode(dir.path());
    #[cfg(not(unix))]
    let new_mode = 0;
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<(String, Outcome)>> = Mutex::new(Vec::new());
    // Two at a time: CI machines have two cores.
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::SeqCst);
                let Some(f) = files.get(k) else {
                    break;
                };
                let rel = f
                    .strip_prefix(&root)
                    .unwrap()
                    .to_string_lossy()
                    .into_owned();
                if let Some(r) = smooth_and_compare(f, &rel, dir.path(), new_mode) {
                    results.lock().unwrap().push((rel, r));
                }
            });
        }
    });
    let mut results = results.into_inner().unwrap();
    results.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(results.len() > 80, "smoothed {} programs", results.len());
    let mut failures = Vec::new();
    for (rel, r) in &results {
        let known = KNOWN_FAILURES
            .iter()
            .find(|(k, _)| k == rel)
            .map(|(_, kind)| *kind);
        match (r, known) {
            (Err(e), _) => failures.push(format!("{rel}: smooth failed: {e}")),
            (Ok(lost), Some(kind)) => {
                if !lost.iter().any(|l| l.contains(kind)) {
                    failures.push(format!(
                        "{rel}: listed in KNOWN_FAILURES but loses no {kind} now: remove it from the list"
                    ));
                }
                let other: Vec<&String> = lost.iter().filter(|l| !l.contains(kind)).collect();
                if !other.is_empty() {
                    failures.push(format!("{rel}: {other:?}"));
                }
            }
            (Ok(lost), None) if !lost.is_empty() => {
                failures.push(format!("{rel}: {}", lost.join("; ")))
            }
            (Ok(_), None) => {}
        }
    }
    for (k, _) in KNOWN_FAILURES {
        if !results.iter().any(|(rel, _)| rel == k) {
            failures.push(format!("{k}: in KNOWN_FAILURES but not smoothed here"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    eprintln!(
        "{} programs smoothed, {} of them with known losses",
        results.len(),
        KNOWN_FAILURES.len()
    );
}

/// A bundled example program copied to `dir` with `mode`.
fn program_in(dir: &Path, name: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::copy(example("pocket-corners.ngc"), &p).unwrap();
    p
}

fn smooth(args: &[&std::ffi::OsStr]) -> std::process::Output {
    bin()
        .arg("smooth")
        .args(args)
        .args(["--tolerance", "0.05mm"])
        .output()
        .unwrap()
}

#[cfg(unix)]
#[test]
fn an_output_replacing_a_file_keeps_its_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let input = program_in(dir.path(), "in.ngc");
    let out = dir.path().join("out.ngc");
    for m in [0o644, 0o640, 0o664] {
        std::fs::write(&out, "old").unwrap();
        std::fs::set_permissions(&out, std::fs::Permissions::from_mode(m)).unwrap();
        let r = smooth(&[input.as_os_str(), "-o".as_ref(), out.as_os_str()]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        assert_eq!(mode(&out), m);
        assert_ne!(std::fs::read_to_string(&out).unwrap(), "old");
    }
    // A new file: 0666 less the umask, not a temporary file's 0600.
    let new = dir.path().join("new.ngc");
    let r = smooth(&[input.as_os_str(), "-o".as_ref(), new.as_os_str()]);
    assert!(r.status.success());
    assert_eq!(mode(&new), new_file_mode(dir.path()));
}

#[test]
fn the_input_is_never_the_output_unless_in_place() {
    let dir = tempfile::tempdir().unwrap();
    let input = program_in(dir.path(), "in.ngc");
    let before = std::fs::read(&input).unwrap();
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    let mut names = vec![
        input.clone(),
        dir.path().join("sub").join("..").join("in.ngc"),
    ];
    #[cfg(unix)]
    {
        let hard = dir.path().join("hard.ngc");
        std::fs::hard_link(&input, &hard).unwrap();
        let soft = dir.path().join("soft.ngc");
        std::os::unix::fs::symlink(&input, &soft).unwrap();
        names.extend([hard, soft]);
    }
    for out in &names {
        let r = smooth(&[input.as_os_str(), "-o".as_ref(), out.as_os_str()]);
        assert!(!r.status.success(), "{}", out.display());
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(
            err.contains("is the input program") && err.contains("--in-place"),
            "{err}"
        );
        assert_eq!(std::fs::read(&input).unwrap(), before);
    }
    // -o another file with --in-place: which one is meant?
    let other = dir.path().join("other.ngc");
    let r = smooth(&[
        input.as_os_str(),
        "--in-place".as_ref(),
        "-o".as_ref(),
        other.as_os_str(),
    ]);
    assert!(!r.status.success());
    assert!(!other.exists());
    // Neither -o nor --in-place: NAME.smoothed.EXT beside the input, the
    // input untouched.
    let r = smooth(&[input.as_os_str()]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(input.with_extension("smoothed.ngc").exists());
    assert_eq!(std::fs::read(&input).unwrap(), before);
    // simulate's CSV files never go over the program either.
    for flag in ["--profile", "--segments"] {
        let r = bin()
            .arg("simulate")
            .arg(&input)
            .arg(flag)
            .arg(&names[1])
            .output()
            .unwrap();
        assert!(!r.status.success(), "{flag}");
        assert!(
            String::from_utf8_lossy(&r.stderr).contains("is the input program"),
            "{flag}"
        );
        assert_eq!(std::fs::read(&input).unwrap(), before);
    }
}

#[test]
fn in_place_replaces_the_input_and_keeps_its_permissions() {
    let dir = tempfile::tempdir().unwrap();
    let input = program_in(dir.path(), "in.ngc");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&input, std::fs::Permissions::from_mode(0o640)).unwrap();
    }
    let before = std::fs::read_to_string(&input).unwrap();
    let r = smooth(&[input.as_os_str(), "--in-place".as_ref()]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let after = std::fs::read_to_string(&input).unwrap();
    assert_ne!(after, before);
    assert!(after.contains("\n(smoothed by fairpath)\n"), "{after}");
    assert!(losses(&before, &after).is_empty());
    #[cfg(unix)]
    assert_eq!(mode(&input), 0o640);
    // No temporary file left behind.
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left, ["in.ngc"]);
    // -o naming the input itself is allowed with --in-place.
    let r = smooth(&[
        input.as_os_str(),
        "--in-place".as_ref(),
        "-o".as_ref(),
        input.as_os_str(),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
}

/// Like `tolerance_parabolic_check.ngc` (LinuxCNC's quick tests): an
/// inch program that blends with `G64 P0.02 Q0.0`, here along a parabola
/// of 80 short G1 moves (which `smooth` rewrites) and a corner.
fn parabolic() -> String {
    let mut t = String::from("G90 G20\n\nG64 P0.02 Q0.0\n\n(parabola)\nG0 Z1\nG0 X-1 Y1\nG0 Z0\n");
    for k in 0..=80 {
        let x = -1.0 + 0.025 * k as f64;
        t.push_str(&format!("G1 X{x:.4} Y{:.4} F40\n", x * x));
    }
    t.push_str("G0 Z1\nM30\n");
    t
}

#[test]
fn tolerance_parabolic_check_runs_under_the_blend_share_for_every_controller() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("tolerance_parabolic_check.ngc");
    let program = parabolic();
    std::fs::write(&input, &program).unwrap();
    let out = dir.path().join("out.ngc");
    let tolerance = 0.05;
    // The budget's blending share for curves written as arcs.
    let budget = fairpath::budget::ToleranceBudget::new(
        tolerance,
        Some(fairpath::budget::OUTPUT_SHARE * tolerance),
        0.0,
    )
    .unwrap();
    let share = fairpath_gcode::emit::CURVE_BLEND_SHARE * budget.output;
    for controller in ["generic", "fanuc", "linuxcnc"] {
        let r = bin()
            .arg("smooth")
            .arg(&input)
            .arg("-o")
            .arg(&out)
            .args(["--tolerance", "0.05mm", "--format", "arcs"])
            .args(["--controller", controller])
            .output()
            .unwrap();
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let text = std::fs::read_to_string(&out).unwrap();
        let written = fairpath_gcode::parse(text.as_bytes()).unwrap();
        let lines = written.lines();
        let mut smoothed = 0;
        for run in written.run_spans() {
            let inside = lines[run.first_line - 1]
                .path_control_after
                .clone()
                .unwrap();
            if inside == "G64 P0.02 Q0.0" {
                continue; // kept as the program wrote it
            }
            smoothed += 1;
            // Ours: P within 1% below the share (inches), Q0.
            let p: f64 = inside
                .strip_prefix("G64 P")
                .and_then(|t| t.strip_suffix(" Q0").or_else(|| t.strip_suffix(" Q0.")))
                .unwrap_or_else(|| panic!("{controller}: {inside}\n{text}"))
                .parse()
                .unwrap();
            let p_mm = p * 25.4;
            assert!(
                p_mm <= share && p_mm >= 0.99 * share,
                "{controller}: {inside}"
            );
            // The program's own after the run.
            let after = lines[run.last_line..]
                .iter()
                .find(|l| l.path_control_after.as_deref() != Some(inside.as_str()))
                .and_then(|l| l.path_control_after.clone());
            assert_eq!(
                after.as_deref(),
                Some("G64 P0.02 Q0.0"),
                "{controller}\n{text}"
            );
        }
        assert!(smoothed > 0, "{controller}: no run smoothed\n{text}");
        assert!(losses(&program, &text).is_empty(), "{controller}\n{text}");
    }
}

/// `synthetic/butterfly-80.ngc` with an N number on every line and a
/// comment on every fifth move: every N number and comment is written, in
/// order, where `smooth` merges the moves into curves.
#[test]
fn a_numbered_commented_butterfly_keeps_every_n_number_and_comment() {
    let Some(root) = shared_root() else {
        eprintln!("../shared/paths not found: skipped");
        return;
    };
    let original = std::fs::read_to_string(root.join("synthetic/butterfly-80.ngc")).unwrap();
    let mut text = String::new();
    let mut comments = Vec::new();
    for (k, l) in original.lines().enumerate() {
        text.push_str(&format!("N{} {l}", 10 * (k + 1)));
        if l.starts_with("G1") && k % 5 == 0 {
            let c = format!("(move {k})");
            text.push(' ');
            text.push_str(&c);
            comments.push(c);
        }
        text.push('\n');
    }
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("butterfly-numbered.ngc");
    std::fs::write(&input, &text).unwrap();
    let out = dir.path().join("out.ngc");
    let r = smooth(&[input.as_os_str(), "-o".as_ref(), out.as_os_str()]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let written = std::fs::read_to_string(&out).unwrap();
    assert_eq!(losses(&text, &written), Vec::<String>::new(), "{written}");
    let mut rest = written.as_str();
    for c in &comments {
        let at = rest
            .find(c.as_str())
            .unwrap_or_else(|| panic!("{c} missing or out of order in\n{written}"));
        rest = &rest[at + c.len()..];
    }
    // The moves were rewritten: N numbers went on blocks and into merged
    // comments.
    assert!(written.contains(" merged into "), "{written}");
    assert!(written.lines().any(|l| l.starts_with("N40 G")), "{written}");
}
