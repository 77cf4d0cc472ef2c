// scratch: section-option variants per run
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{plan_run, PlanOptions};
use fairpath::geom::Curve;
use fairpath::smooth::{
    sample_curves, Auto, BsplineFit, BsplineFitOptions, SectionOptions, Smoother,
};
use std::path::Path;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let prog = fairpath_cli::pipeline::read_program(Path::new(&args[1])).unwrap();
    let tol = 0.045;
    let opts = PlanOptions {
        limits: MachineLimits::thesis(),
        override_feed: true,
        window: None,
    };
    let variants: Vec<(f64, f64)> = vec![
        (1.0, 0.5),
        (2.0, 0.5),
        (4.0, 0.5),
        (1.0, 1.0),
        (2.0, 1.0),
        (4.0, 1.0),
        (1e6, 1.0),
    ];
    let mut tot = vec![0.0; variants.len() + 2];
    for run in prog.runs().iter() {
        let has = run
            .pieces
            .iter()
            .any(|p| !matches!(p.curve, Curve::Line(_)));
        let (input, t) = if has {
            (sample_curves(run, 0.05 * tol), tol * 0.95)
        } else {
            (run.clone(), tol)
        };
        let auto = Auto::default().smooth_run(run, tol).unwrap();
        let ta = plan_run(&auto.pieces, &opts).unwrap().time;
        tot[variants.len()] += ta;
        let mut best = ta;
        for (i, &(ce, mt)) in variants.iter().enumerate() {
            let o = BsplineFitOptions {
                sections: SectionOptions {
                    chord_error_per_tol: ce,
                    max_turn: mt,
                    ..SectionOptions::default()
                },
                ..BsplineFitOptions::default()
            };
            let r = BsplineFit { options: o }.smooth_run(&input, t).unwrap();
            let tt = plan_run(&r.pieces, &opts).unwrap().time;
            tot[i] += tt;
            best = best.min(tt);
        }
        tot[variants.len() + 1] += best;
    }
    println!(
        "{variants:?} auto best\n{:?}",
        tot.iter()
            .map(|x| (x * 100.0).round() / 100.0)
            .collect::<Vec<_>>()
    );
}
