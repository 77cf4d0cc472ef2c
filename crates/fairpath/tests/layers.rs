//! The library's layers point one way. Each top-level module of
//! `crates/fairpath/src` has a layer; a module may import (`crate::x`)
//! only modules of lower layers, never one of its own layer or above, so
//! there are no circles and the verifier stays independent of the methods.
//!
//! ```text
//! 0 math, budget, seeded  numbers, the tolerance ledger, the unit tests' generator
//! 1 geom                  curves, distances, continuity classes
//! 2 path                  pieces tied to input lines, runs
//! 3 smooth | feed | verify | controller   methods | planning | checking | controllers' arithmetic
//! 4 render                writing curves as a controller's blocks (judged by feed)
//! 5 choose                auto (objective injected) and the registry of methods
//! 6 pipeline              the verified pipeline (entry point)
//! ```

use std::collections::BTreeMap;
use std::path::Path;

fn layer(module: &str) -> Option<u32> {
    Some(match module {
        "math" | "budget" | "seeded" => 0,
        "geom" => 1,
        "path" => 2,
        "smooth" | "feed" | "verify" | "controller" => 3,
        "render" => 4,
        "choose" => 5,
        "pipeline" => 6,
        _ => return None,
    })
}

/// `crate::name` references on code lines (comments skipped), with lines.
fn crate_refs(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(k) = rest.find("crate::") {
            let tail = &rest[k + "crate::".len()..];
            let name: String = tail
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                out.push((i + 1, name));
            }
            rest = tail;
        }
    }
    out
}

#[test]
fn imports_point_down_the_layers() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    crate::common::rust_files(&src, &mut files);
    let mut bad = Vec::new();
    let mut seen: BTreeMap<String, u32> = BTreeMap::new();
    for f in &files {
        let rel = f.strip_prefix(&src).unwrap();
        let first = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        let module = first.trim_end_matches(".rs").to_string();
        if module == "lib" {
            continue;
        }
        let Some(own) = layer(&module) else {
            bad.push(format!("{}: module `{module}` has no layer", rel.display()));
            continue;
        };
        seen.insert(module.clone(), own);
        let text = std::fs::read_to_string(f).unwrap();
        for (line, name) in crate_refs(&text) {
            if name == module {
                continue;
            }
            match layer(&name) {
                Some(l) if l < own => {}
                Some(l) => bad.push(format!(
                    "{}:{line}: `{module}` (layer {own}) imports `{name}` (layer {l})",
                    rel.display()
                )),
                None => {}
            }
        }
    }
    assert!(
        bad.is_empty(),
        "imports against the layers:\n{}",
        bad.join("\n")
    );
    for m in ["geom", "path", "smooth", "feed", "verify", "choose"] {
        assert!(seen.contains_key(m), "module {m} not found");
    }
}

#[test]
fn the_scanner_sees_imports_and_skips_comments() {
    let refs = crate_refs(
        "use crate::feed::plan; // crate::choose\n/// [`crate::smooth`]\nx(crate::geom::Vec3)",
    );
    let names: Vec<&str> = refs.iter().map(|(_, n)| n.as_str()).collect();
    assert_eq!(names, ["feed", "geom"]);
}
