//! Tests of the double-S profile (`feed::double_s`) and of jerk-limited
//! reachability (`feed::reach`).
//!
//! Reference values marked "book" are printed in Biagiotti and Melchiorri,
//! *Trajectory Planning for Automatic Machines and Robots* (2008), section
//! 3.4 (Examples 3.9-3.12), to four decimals. Where the values are also
//! derived by hand in a comment, that derivation is independent of the code.

use fairpath::feed::{
    max_entry_velocity, max_reachable_velocity, velocity_change, DoubleS, FeedError, Limits,
    Method, State,
};

// ---------------------------------------------------------------- helpers

/// splitmix64: a small deterministic PRNG.
struct Rng(u64);
impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.unit()).exp()
    }
}

/// Time-optimal acceleration-limited (infinite jerk) trapezoid time over `h`
/// from `v0` to `v1`, computed independently of the library. Requires
/// `h >= |v1² - v0²| / (2 amax)`.
fn trapezoid_time(h: f64, v0: f64, v1: f64, vmax: f64, amax: f64) -> f64 {
    let vp = (amax * h + 0.5 * (v0 * v0 + v1 * v1)).sqrt().min(vmax);
    let ta = (vp - v0) / amax;
    let td = (vp - v1) / amax;
    let da = (vp * vp - v0 * v0) / (2.0 * amax);
    let dd = (vp * vp - v1 * v1) / (2.0 * amax);
    let tv = if vp > 0.0 { (h - da - dd) / vp } else { 0.0 };
    ta + td + tv.max(0.0)
}

fn close(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got}, want {want} (tolerance {tol})"
    );
}

fn rel_close(got: f64, want: f64, rel: f64, what: &str) {
    close(got, want, rel * want.abs(), what);
}

/// The book's printed values of one example.
struct Book {
    ta: f64,
    tv: f64,
    td: f64,
    tj1: f64,
    tj2: f64,
    t: f64,
    vlim: f64,
}

fn check_book(p: &DoubleS, b: &Book, tol: f64, rel: bool, name: &str) {
    let ph = p.phases();
    let cmp = |got: f64, want: f64, what: &str| {
        let t = if rel { tol * want.abs().max(1e-2) } else { tol };
        close(got, want, t, &format!("{name} {what}"));
    };
    cmp(ph.ta, b.ta, "Ta");
    cmp(ph.tv, b.tv, "Tv");
    cmp(ph.td, b.td, "Td");
    cmp(ph.tj1, b.tj1, "Tj1");
    cmp(ph.tj2, b.tj2, "Tj2");
    cmp(p.duration(), b.t, "T");
    cmp(p.vlim(), b.vlim, "vlim");
}

fn lim(vmax: f64, amax: f64, jmax: f64) -> Limits {
    Limits::new(vmax, amax, jmax).unwrap()
}

// ---------------------------------------------------------- book examples

/// Book Example 3.9: q0=0, q1=10, v0=1, v1=0, vmax=5, amax=10, jmax=30.
/// Own derivation (Case 1): (vmax - v0) jmax = 120 >= amax² = 100, so
/// Tj1 = 1/3, Ta = 1/3 + 4/10 = 11/15; likewise Tj2 = 1/3, Td = 1/3 + 1/2 =
/// 5/6; Tv = 10/5 - (11/15)/2 * 1.2 - (5/6)/2 = 1.14333, so T = Ta + Tv + Td
/// = 2.70999. (The total 2.7600 quoted to us for this example disagrees with
/// the sum of its own phases; we assert the derived 2.7100.)
#[test]
fn book_example_3_9_vmax_reached() {
    let l = lim(5.0, 10.0, 30.0);
    let book = Book {
        ta: 0.7333,
        tv: 1.1433,
        td: 0.8333,
        tj1: 0.3333,
        tj2: 0.3333,
        t: 2.7100,
        vlim: 5.0,
    };
    for m in [Method::Fastest, Method::Book] {
        let p = DoubleS::plan_with(10.0, 1.0, 0.0, &l, m).unwrap();
        check_book(&p, &book, 1e-4, false, "3.9");
        let ph = p.phases();
        close(ph.ta, 11.0 / 15.0, 1e-12, "Ta exact");
        close(ph.td, 5.0 / 6.0, 1e-12, "Td exact");
        close(ph.tv, 2.0 - 11.0 / 25.0 - 5.0 / 12.0, 1e-12, "Tv exact");
        close(p.alim_a(), 10.0, 1e-12, "alim_a");
        close(p.alim_d(), -10.0, 1e-12, "alim_d");
    }
}

/// Book Example 3.10: as 3.9 with vmax = 10: vmax not reached, amax reached
/// in both phases, eq. 3.23 with a = amax: Delta = 100/9 + 2 + 10 (40 - 2/3)
/// = 406.444, Ta = (10/3 - 2 + 20.1605)/20 = 1.0747.
#[test]
fn book_example_3_10_vmax_not_reached() {
    let l = lim(10.0, 10.0, 30.0);
    let book = Book {
        ta: 1.0747,
        tv: 0.0,
        td: 1.1747,
        tj1: 0.3333,
        tj2: 0.3333,
        t: 2.2494,
        vlim: 8.4136,
    };
    let delta: f64 = 100.0 / 9.0 + 2.0 + 10.0 * (40.0 - 2.0 / 3.0);
    let ta = (10.0 / 3.0 - 2.0 + delta.sqrt()) / 20.0;
    for m in [Method::Fastest, Method::Book] {
        let p = DoubleS::plan_with(10.0, 1.0, 0.0, &l, m).unwrap();
        check_book(&p, &book, 1e-4, false, "3.10");
        close(p.phases().ta, ta, 1e-12, "Ta exact");
        close(p.phases().tv, 0.0, 1e-12, "Tv");
    }
}

/// Book Example 3.11: v0 = 7 (vmax = 10): amax not reached; the book reduces
/// amax by gamma = 0.99 steps, we take the exact limit: 1 % tolerance.
#[test]
fn book_example_3_11_amax_not_reached() {
    let l = lim(10.0, 10.0, 30.0);
    let book = Book {
        ta: 0.4666,
        tv: 0.0,
        td: 1.4718,
        tj1: 0.2321,
        tj2: 0.2321,
        t: 1.9384,
        vlim: 8.6329,
    };
    let p = DoubleS::plan_with(10.0, 7.0, 0.0, &l, Method::Book).unwrap();
    check_book(&p, &book, 0.01, true, "3.11");
    // Exact limit of the reduction: the acceleration phase has no constant
    // part (Ta = 2 Tj).
    close(p.phases().ta, 2.0 * p.phases().tj1, 1e-9, "Ta = 2 Tj");
    // The fastest method is faster and still within the limits.
    let f = DoubleS::plan(10.0, 7.0, 0.0, &l).unwrap();
    assert!(f.duration() < p.duration() - 0.1, "{}", f.duration());
    assert!(f.vlim() <= 10.0 && f.alim_a() <= 10.0 && f.alim_d() >= -10.0);
}

/// Book Example 3.12: v0 = 7.5: only deceleration (eq. 3.26a). Own
/// derivation: Td = 2 h / (v0 + v1) = 2.6667; Tj2 = (300 - sqrt(30 (3000 -
/// 56.25 * 7.5))) / 225 = 0.0973.
#[test]
fn book_example_3_12_only_deceleration() {
    let l = lim(10.0, 10.0, 30.0);
    let book = Book {
        ta: 0.0,
        tv: 0.0,
        td: 2.6667,
        tj1: 0.0,
        tj2: 0.0973,
        t: 2.6667,
        vlim: 7.5,
    };
    let p = DoubleS::plan_with(10.0, 7.5, 0.0, &l, Method::Book).unwrap();
    check_book(&p, &book, 1e-4, false, "3.12");
    let tj2 = (300.0 - (30.0f64 * (3000.0 - 56.25 * 7.5)).sqrt()) / 225.0;
    close(p.phases().tj2, tj2, 1e-12, "Tj2 exact");
    // Book: alim_d = -2.9190 (= -jmax Tj2).
    close(p.alim_d(), -30.0 * tj2, 1e-12, "alim_d");
    // The fastest method accelerates first: about 1.76 s.
    let f = DoubleS::plan(10.0, 7.5, 0.0, &l).unwrap();
    assert!(f.duration() < 1.8, "{}", f.duration());
    assert!(f.vlim() > 7.5);
}

/// Only acceleration (eq. 3.26b), the mirror image of Example 3.12.
#[test]
fn only_acceleration_mirror() {
    let l = lim(10.0, 10.0, 30.0);
    let p = DoubleS::plan_with(10.0, 0.0, 7.5, &l, Method::Book).unwrap();
    let ph = p.phases();
    close(ph.td, 0.0, 0.0, "Td");
    close(ph.ta, 2.6667, 1e-4, "Ta");
    close(ph.tj1, 0.0973, 1e-4, "Tj1");
    close(p.vlim(), 7.5, 0.0, "vlim");
    check_profile(&p, &l, "mirror");
}

// ------------------------------------------------------- input validation

#[test]
fn bad_input_is_an_error_naming_it() {
    let l = lim(10.0, 10.0, 30.0);
    for (name, bad) in [
        (
            "vmax",
            Limits {
                vmax: f64::NAN,
                ..l
            },
        ),
        ("vmax", Limits { vmax: 0.0, ..l }),
        ("amax", Limits { amax: -1.0, ..l }),
        (
            "amax",
            Limits {
                amax: f64::INFINITY,
                ..l
            },
        ),
        ("jmax", Limits { jmax: 0.0, ..l }),
    ] {
        match DoubleS::plan(1.0, 0.0, 0.0, &bad) {
            Err(FeedError::BadLimit { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{name}: {other:?}"),
        }
        assert!(Limits::new(bad.vmax, bad.amax, bad.jmax).is_err());
    }
    for (name, h, v0, v1) in [
        ("h", -1.0, 0.0, 0.0),
        ("h", f64::NAN, 0.0, 0.0),
        ("v0", 1.0, -1.0, 0.0),
        ("v1", 1.0, 0.0, f64::NAN),
    ] {
        match DoubleS::plan(h, v0, v1, &l) {
            Err(FeedError::BadValue { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{name}: {other:?}"),
        }
    }
    assert!(matches!(
        DoubleS::plan(1.0, 11.0, 0.0, &l),
        Err(FeedError::AboveVmax { name: "v0", .. })
    ));
    // 10 -> 0 needs (10/2)(1/3 + 1) = 6.667 mm.
    match DoubleS::plan(5.0, 10.0, 0.0, &l) {
        Err(FeedError::Infeasible { needed, .. }) => close(needed, 20.0 / 3.0, 1e-12, "needed"),
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        max_reachable_velocity(0.0, 1.0, 0.0, 1.0),
        Err(FeedError::BadLimit { name: "amax", .. })
    ));
    assert!(matches!(
        max_entry_velocity(0.0, -1.0, 1.0, 1.0),
        Err(FeedError::BadValue { name: "length", .. })
    ));
    // Degenerate but valid.
    let z = DoubleS::plan(0.0, 0.0, 0.0, &l).unwrap();
    assert_eq!(z.duration(), 0.0);
    let c = DoubleS::plan(5.0, 10.0, 10.0, &l).unwrap();
    close(c.duration(), 0.5, 1e-15, "cruise only");
}

// ------------------------------------------------------ random properties

/// Checks a planned profile: no NaN, limits, continuity at phase
/// boundaries, monotone position from 0 to h, end velocity.
fn check_profile(p: &DoubleS, l: &Limits, ctx: &str) {
    const REL: f64 = 1e-9;
    let t_end = p.duration();
    let h = p.length();
    assert!(t_end.is_finite() && t_end >= 0.0, "{ctx}: T = {t_end}");
    let ph = p.phases();
    for (x, n) in [
        (ph.tj1, "tj1"),
        (ph.ta, "ta"),
        (ph.tv, "tv"),
        (ph.tj2, "tj2"),
        (ph.td, "td"),
    ] {
        assert!(x.is_finite() && x >= 0.0, "{ctx}: {n} = {x}");
    }
    assert!(ph.ta >= 2.0 * ph.tj1 * (1.0 - REL), "{ctx}: Ta < 2 Tj1");
    assert!(ph.td >= 2.0 * ph.tj2 * (1.0 - REL), "{ctx}: Td < 2 Tj2");
    let ok = |s: &State, t: f64| {
        assert!(
            s.q.is_finite() && s.v.is_finite() && s.a.is_finite() && s.j.is_finite(),
            "{ctx}: NaN at t = {t}: {s:?}"
        );
        assert!(s.v <= l.vmax * (1.0 + REL), "{ctx}: v {} at {t}", s.v);
        assert!(s.v >= -REL * l.vmax, "{ctx}: negative v {} at {t}", s.v);
        assert!(s.a.abs() <= l.amax * (1.0 + REL), "{ctx}: a {} at {t}", s.a);
        assert!(s.j.abs() <= l.jmax * (1.0 + REL), "{ctx}: j {} at {t}", s.j);
        assert!(
            s.q >= -REL * h && s.q <= h * (1.0 + REL),
            "{ctx}: q {} at {t}",
            s.q
        );
    };
    let n = 200;
    let mut last_q = 0.0;
    for i in 0..=n {
        let t = t_end * i as f64 / n as f64;
        let s = p.eval(t);
        ok(&s, t);
        assert!(s.q >= last_q - REL * h, "{ctx}: q decreases at {t}");
        last_q = s.q;
    }
    // Continuity at the phase boundaries (the position at T - Td from the
    // acceleration side must meet the deceleration side, i.e. the profile
    // covers exactly h).
    let bounds = [
        ph.tj1,
        ph.ta - ph.tj1,
        ph.ta,
        ph.ta + ph.tv,
        t_end - ph.td + ph.tj2,
        t_end - ph.tj2,
        t_end,
    ];
    let d = 1e-12 * t_end.max(1e-300);
    for b in bounds {
        if b <= 0.0 {
            continue;
        }
        let (s0, s1) = (p.eval(b - d), p.eval(b + d));
        let s = p.eval(b);
        ok(&s, b);
        let tq = REL * h + 2.0 * d * l.vmax;
        let tv = REL * l.vmax + 2.0 * d * l.amax;
        let ta = REL * l.amax + 2.0 * d * l.jmax;
        assert!(
            (s1.q - s0.q).abs() <= tq,
            "{ctx}: q jump at {b}: {s0:?} {s1:?}"
        );
        assert!(
            (s1.v - s0.v).abs() <= tv,
            "{ctx}: v jump at {b}: {s0:?} {s1:?}"
        );
        assert!(
            (s1.a - s0.a).abs() <= ta,
            "{ctx}: a jump at {b}: {s0:?} {s1:?}"
        );
    }
    let end = p.eval(t_end);
    assert_eq!(end.q, h);
    assert_eq!(end.v, p.v1());
    let before = p.eval(t_end * (1.0 - 1e-12));
    assert!((before.q - h).abs() <= REL * h + 1e-12 * t_end * l.vmax);
}

fn random_case(rng: &mut Rng) -> (f64, f64, f64, Limits) {
    let vmax = rng.log_uniform(1.0, 1000.0);
    let amax = rng.log_uniform(10.0, 1e4);
    let jmax = rng.log_uniform(100.0, 1e6);
    let pick_v = |rng: &mut Rng| match rng.next_u64() % 6 {
        0 => 0.0,
        1 => vmax,
        _ => rng.uniform(0.0, vmax),
    };
    let v0 = pick_v(rng);
    let v1 = pick_v(rng);
    let h = if rng.next_u64() % 50 == 0 {
        0.0
    } else {
        rng.log_uniform(1e-4, 1e3)
    };
    (h, v0, v1, lim(vmax, amax, jmax))
}

#[test]
fn random_profiles_respect_limits_and_end_exactly() {
    let mut rng = Rng(0x5EED_0001);
    let (mut planned, mut infeasible) = (0, 0);
    let mut classes = [0usize; 5];
    for case in 0..20_000u32 {
        let (h, v0, v1, l) = random_case(&mut rng);
        let ctx = format!("case {case}: h={h} v0={v0} v1={v1} {l:?}");
        let fast = DoubleS::plan(h, v0, v1, &l);
        let book = DoubleS::plan_with(h, v0, v1, &l, Method::Book);
        let (fast, book) = match (fast, book) {
            (Ok(f), Ok(b)) => (f, b),
            (Err(FeedError::Infeasible { needed, .. }), Err(FeedError::Infeasible { .. })) => {
                infeasible += 1;
                assert!(needed > h, "{ctx}");
                continue;
            }
            other => panic!("{ctx}: {other:?}"),
        };
        planned += 1;
        let ph = book.phases();
        let class = if ph.tv > 0.0 {
            0 // vmax reached
        } else if ph.ta == 0.0 && ph.td > 0.0 {
            1 // only deceleration (3.26a)
        } else if ph.td == 0.0 && ph.ta > 0.0 {
            2 // only acceleration (3.26b)
        } else if ph.ta > 0.0 && book.alim_a() < l.amax * (1.0 - 1e-9) {
            3 // amax reduced (gamma)
        } else {
            4 // amax reached both ways, or degenerate
        };
        classes[class] += 1;
        check_profile(&fast, &l, &format!("fastest {ctx}"));
        check_profile(&book, &l, &format!("book {ctx}"));
        let trap = trapezoid_time(h, v0, v1, l.vmax, l.amax);
        for (p, m) in [(&fast, "fastest"), (&book, "book")] {
            assert!(
                p.duration() >= trap * (1.0 - 1e-9),
                "{m} {ctx}: T = {} below trapezoid {trap}",
                p.duration()
            );
        }
        assert!(
            fast.duration() <= book.duration() * (1.0 + 1e-9) + 1e-12,
            "{ctx}: fastest {} slower than book {}",
            fast.duration(),
            book.duration()
        );
    }
    assert!(
        planned > 5_000 && infeasible > 100,
        "{planned} {infeasible}"
    );
    // Every case of the book's algorithm is exercised.
    assert!(classes.iter().all(|&n| n >= 100), "{classes:?}");
}

/// As jmax grows without bound, T tends to the acceleration-limited
/// (trapezoidal) time; the excess is at most a few amax/jmax.
#[test]
fn infinite_jerk_limit_is_the_trapezoid() {
    let cases = [
        (10.0, 1.0, 0.0, 5.0, 10.0),
        (10.0, 1.0, 0.0, 10.0, 10.0),
        (10.0, 7.0, 0.0, 10.0, 10.0),
        (10.0, 7.5, 0.0, 10.0, 10.0),
        (0.5, 0.0, 0.0, 100.0, 1000.0),
        (3.0, 20.0, 20.0, 50.0, 500.0),
        (3.0, 0.0, 40.0, 50.0, 500.0),
    ];
    for (h, v0, v1, vmax, amax) in cases {
        let trap = trapezoid_time(h, v0, v1, vmax, amax);
        for m in [Method::Fastest, Method::Book] {
            let mut jmax = 10.0 * amax;
            let mut last = f64::INFINITY;
            while jmax <= 1e12 * amax {
                let p = match DoubleS::plan_with(h, v0, v1, &lim(vmax, amax, jmax), m) {
                    Ok(p) => p,
                    // Feasible only with a large enough jerk.
                    Err(FeedError::Infeasible { .. }) if last.is_infinite() => {
                        jmax *= 10.0;
                        continue;
                    }
                    Err(e) => panic!("{e}"),
                };
                let excess = p.duration() - trap;
                assert!(excess >= -1e-9 * trap, "{m:?} {h} {v0} {v1}: {excess}");
                assert!(
                    excess <= 4.0 * amax / jmax + 1e-9 * trap,
                    "{m:?} {h} {v0} {v1} jmax {jmax}: excess {excess}"
                );
                assert!(excess <= last + 1e-12, "not converging");
                last = excess;
                jmax *= 10.0;
            }
            assert!(last <= 1e-9 * trap, "{m:?}: final excess {last}");
        }
    }
}

// ------------------------------------------------------------------ reach

/// Brute-force jerk-limited acceleration from `v0` within `length`: steps of
/// `dt` with the largest jerk (at most `jmax`, acceleration at most `amax`)
/// that still leaves room to ramp the acceleration back to zero (ramp-down
/// from `a` at jerk `-jmax` lasts `a/jmax`, covers `v a/jmax + a³/(3 jmax²)`
/// and adds `a²/(2 jmax)` to the velocity).
fn brute_reach(v0: f64, length: f64, amax: f64, jmax: f64, dt: f64) -> f64 {
    let ramp = |v: f64, a: f64| v * a / jmax + a * a * a / (3.0 * jmax * jmax);
    let (mut x, mut v, mut a) = (0.0, v0, 0.0f64);
    loop {
        let mut moved = false;
        for j in [jmax.min((amax - a) / dt), 0.0] {
            let xn = x + v * dt + a * dt * dt / 2.0 + j * dt * dt * dt / 6.0;
            let vn = v + a * dt + j * dt * dt / 2.0;
            let an = a + j * dt;
            if xn + ramp(vn, an) <= length {
                (x, v, a) = (xn, vn, an);
                moved = true;
                break;
            }
        }
        if !moved {
            return v + a * a / (2.0 * jmax);
        }
    }
}

#[test]
fn reach_matches_brute_force() {
    let mut rng = Rng(0x5EED_0002);
    for case in 0..60u32 {
        let amax = rng.log_uniform(10.0, 1e4);
        let jmax = rng.log_uniform(100.0, 1e6);
        let v0 = if case.is_multiple_of(4) {
            0.0
        } else {
            rng.log_uniform(0.1, 500.0)
        };
        let length = rng.log_uniform(1e-3, 100.0);
        let v = max_reachable_velocity(v0, length, amax, jmax).unwrap();
        let c = velocity_change(v0, v, amax, jmax).unwrap();
        let dt = c.duration / 20_000.0;
        let brute = brute_reach(v0, length, amax, jmax, dt);
        let ctx = format!("case {case}: v0={v0} L={length} A={amax} J={jmax}");
        // The brute force wastes O(dt) of the length, so it is slightly low.
        assert!(brute <= v * (1.0 + 1e-9), "{ctx}: brute {brute} > {v}");
        rel_close(brute, v, 1e-3 * (v - v0) / v + 1e-9, &ctx);
    }
}

#[test]
fn reach_round_trips_and_feeds_double_s() {
    let mut rng = Rng(0x5EED_0003);
    let (mut sat, mut unsat) = (0, 0);
    for case in 0..20_000u32 {
        let amax = rng.log_uniform(10.0, 1e4);
        let jmax = rng.log_uniform(100.0, 1e6);
        let v0 = if case.is_multiple_of(5) {
            0.0
        } else {
            rng.log_uniform(1e-3, 1e3)
        };
        let length = rng.log_uniform(1e-6, 1e3);
        let ctx = format!("case {case}: v0={v0} L={length} A={amax} J={jmax}");
        let v = max_reachable_velocity(v0, length, amax, jmax).unwrap();
        assert!(v.is_finite() && v >= v0, "{ctx}: {v}");
        let c = velocity_change(v0, v, amax, jmax).unwrap();
        if c.peak_acceleration >= amax {
            sat += 1;
        } else {
            unsat += 1;
        }
        // Round trip: v = v0 + dv is rounded to an ulp of v, a relative error
        // of eps v / dv in dv (and half that in the distance when the
        // acceleration does not saturate).
        if v > v0 {
            let rel = 1e-12 + f64::EPSILON * v / (v - v0);
            rel_close(c.distance, length, rel, &format!("{ctx}: round trip"));
        }
        assert_eq!(max_entry_velocity(v0, length, amax, jmax).unwrap(), v);
        // The reached velocity is plannable over exactly this length, both
        // ways.
        let l = lim(v * 1.5 + 1.0, amax, jmax);
        let up = DoubleS::plan(length, v0, v, &l).unwrap_or_else(|e| panic!("{ctx}: {e}"));
        check_profile(&up, &l, &ctx);
        let down = DoubleS::plan(length, v, v0, &l).unwrap_or_else(|e| panic!("{ctx}: {e}"));
        check_profile(&down, &l, &ctx);
        // Slightly more is unreachable.
        if v - v0 > 1e-6 * v {
            assert!(
                DoubleS::plan(length, v0, v * (1.0 + 1e-9) + 1e-12, &l).is_err(),
                "{ctx}"
            );
        }
    }
    assert!(sat > 1000 && unsat > 1000, "{sat} {unsat}");
}

/// Closed forms at the saturation boundary: with dv = A²/J both branches
/// give L_sat = (2 v0 + A²/J) A/J.
#[test]
fn reach_is_continuous_at_saturation() {
    let (v0, a, j) = (3.0, 10.0, 30.0);
    let l_sat = (2.0 * v0 + a * a / j) * a / j;
    let at = max_reachable_velocity(v0, l_sat, a, j).unwrap();
    close(at, v0 + a * a / j, 1e-12, "dv at L_sat");
    let below = max_reachable_velocity(v0, l_sat * (1.0 - 1e-12), a, j).unwrap();
    let above = max_reachable_velocity(v0, l_sat * (1.0 + 1e-12), a, j).unwrap();
    assert!(below <= at && at <= above && above - below < 1e-9);
    // Unsaturated from rest: v1³ = J L².
    let v = max_reachable_velocity(0.0, 0.1, 1e3, 30.0).unwrap();
    close(v * v * v, 30.0 * 0.01, 1e-15, "v³ = J L²");
}
