// scratch: per-section choice potential
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{plan_run, PlanOptions};
use fairpath::geom::{Curve, Line};
use fairpath::smooth::Auto;
use fairpath::{Piece, Run};
use std::path::Path;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let prog = fairpath_cli::pipeline::read_program(Path::new(&args[1])).unwrap();
    let cut: f64 = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(10.0);
    let opts = PlanOptions {
        limits: MachineLimits::thesis(),
        override_feed: true,
        window: None,
    };
    let (mut per_run_best, mut per_sub_best, mut nsub) = (0.0, 0.0, 0);
    for run in prog.runs().iter() {
        // split at midpoints of long lines
        let mut subs: Vec<Vec<Piece>> = vec![vec![]];
        for p in &run.pieces {
            if let Curve::Line(l) = &p.curve {
                if l.length() > cut {
                    let m = l.p0.lerp(l.p1, 0.5);
                    let mut a = p.clone();
                    a.curve = Curve::Line(Line::new(l.p0, m));
                    let mut b = p.clone();
                    b.curve = Curve::Line(Line::new(m, l.p1));
                    subs.last_mut().unwrap().push(a);
                    subs.push(vec![b]);
                    continue;
                }
            }
            subs.last_mut().unwrap().push(p.clone());
        }
        let mut totals: Vec<(&str, f64, usize)> = vec![];
        for s in &subs {
            let r = Run::new(s.clone());
            let cands = Auto::default().candidates(&r, 0.045).unwrap();
            let mut best = f64::INFINITY;
            for (name, c) in &cands {
                let t = plan_run(&c.pieces, &opts)
                    .map(|p| p.time)
                    .unwrap_or(f64::INFINITY);
                best = best.min(t);
                match totals.iter_mut().find(|(n, _, _)| n == name) {
                    Some(e) => {
                        e.1 += t;
                        e.2 += 1
                    }
                    None => totals.push((name, t, 1)),
                }
            }
            per_sub_best += best;
            nsub += 1;
        }
        per_run_best += totals
            .iter()
            .filter(|x| x.2 == subs.len())
            .map(|x| x.1)
            .fold(f64::INFINITY, f64::min);
    }
    println!(
        "runs {} subs {nsub}: per-run best {per_run_best:.2}, per-sub best {per_sub_best:.2}",
        prog.runs().len()
    );
}
