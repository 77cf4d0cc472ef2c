// scratch: per-run original vs auto
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{plan_run, PlanOptions};
use fairpath::smooth::{Auto, Smoother};
use std::path::Path;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let prog = fairpath_cli::pipeline::read_program(Path::new(&args[1])).unwrap();
    let tol = 0.05;
    let opts = PlanOptions {
        limits: MachineLimits {
            junction_deviation: tol,
            ..MachineLimits::thesis()
        },
        override_feed: true,
        window: None,
    };
    let mut rows = vec![];
    for (i, run) in prog.runs().iter().enumerate() {
        let o = plan_run(&run.pieces, &opts).unwrap().time;
        let a = Auto::default().smooth_run(run, tol * 0.9).unwrap();
        let t = plan_run(&a.pieces, &opts).unwrap().time;
        let line = run.pieces[0].source_lines.0;
        rows.push((
            t - 0.7 * o,
            i,
            line,
            run.pieces.len(),
            o,
            t,
            a.chosen.clone(),
        ));
    }
    rows.sort_by(|a, b| b.0.total_cmp(&a.0));
    for r in rows.iter().take(12) {
        println!(
            "excess {:.3} run {} line {} pcs {} orig {:.3} auto {:.3} ratio {:.2} {:?}",
            r.0,
            r.1,
            r.2,
            r.3,
            r.4,
            r.5,
            r.5 / r.4,
            r.6
        );
    }
    let (so, sa): (f64, f64) = rows
        .iter()
        .fold((0.0, 0.0), |acc, r| (acc.0 + r.4, acc.1 + r.5));
    println!("total orig {so:.2} auto {sa:.2} ratio {:.3}", sa / so);
}
