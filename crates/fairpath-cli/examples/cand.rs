// scratch: per-run candidate planned times (not committed)
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{plan_run, PlanOptions};
use fairpath::smooth::Auto;
use std::path::Path;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let prog = fairpath_cli::pipeline::read_program(Path::new(&args[1])).unwrap();
    let tol: f64 = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(0.05);
    let budget = tol * 0.9;
    let opts = PlanOptions {
        limits: MachineLimits::thesis(),
        override_feed: true,
        window: None,
    };
    let mut tot = std::collections::BTreeMap::new();
    for (i, run) in prog.runs().iter().enumerate() {
        let orig = plan_run(
            &run.pieces,
            &PlanOptions {
                limits: MachineLimits {
                    junction_deviation: tol,
                    ..MachineLimits::thesis()
                },
                ..opts
            },
        )
        .map(|p| p.time)
        .unwrap_or(f64::NAN);
        let cands = Auto::default().candidates(run, budget).unwrap();
        let mut s = format!("run {i} ({} pcs) orig {orig:.3}", run.pieces.len());
        *tot.entry("orig").or_insert(0.0) += orig;
        let mut best = f64::INFINITY;
        for (name, c) in &cands {
            let t = plan_run(&c.pieces, &opts)
                .map(|p| p.time)
                .unwrap_or(f64::NAN);
            best = best.min(t);
            *tot.entry(*name).or_insert(0.0) += t;
            s += &format!(" | {name} {t:.3}");
        }
        *tot.entry("best").or_insert(0.0) += best;
        println!("{s}");
    }
    println!("{tot:?}");
}
