//! Every shared program parses or fails with a clear error.
use crate::common;
use fairpath::geom::Curve;

#[test]
fn corpus_parses_or_is_rejected_clearly() {
    let Some(dir) = common::shared_paths() else {
        return;
    };
    let mut ok = 0;
    let mut rejected = Vec::new();
    for f in common::files_under(&dir) {
        let bytes = std::fs::read(&f).unwrap();
        let rel = f.strip_prefix(&dir).unwrap().display().to_string();
        match fairpath_gcode::parse(&bytes) {
            Ok(p) => {
                ok += 1;
                // runs are continuous
                for r in p.runs() {
                    for w in r.pieces.windows(2) {
                        // Exact, except between two arcs (a few ulps).
                        let both_arcs =
                            matches!((&w[0].curve, &w[1].curve), (Curve::Arc(_), Curve::Arc(_)));
                        if both_arcs {
                            assert!(w[0].end().dist(w[1].start()) < 1e-12, "{rel}");
                        } else {
                            assert_eq!(
                                w[0].end(),
                                w[1].start(),
                                "{rel} line {}",
                                w[1].source_lines.0
                            );
                        }
                    }
                }
            }
            Err(e) => {
                assert!(e.line >= 1 && e.column >= 1, "{rel}: {e}");
                rejected.push(format!("{rel}: {e}"));
            }
        }
    }
    eprintln!("{ok} parsed, {} rejected:", rejected.len());
    for r in &rejected {
        eprintln!("  {r}");
    }
}
