//! The public constructors of curves check their input: valid definitions
//! construct and evaluate to finite points, each kind of invalid one is the
//! matching error, arbitrary input never panics, and evaluating a curve
//! built around the checks (a struct literal) gives NaN, not a panic.

use fairpath::geom::{
    arc_length, flatten_params, Arc, ArcError, Nurbs, NurbsError, ParamCurve, Vec3,
};
use proptest::prelude::*;

fn v(x: f64, y: f64, z: f64) -> Vec3 {
    Vec3::new(x, y, z)
}

fn pt() -> impl Strategy<Value = Vec3> {
    (-100.0..100.0f64, -100.0..100.0f64, -100.0..100.0f64).prop_map(|(x, y, z)| v(x, y, z))
}

/// A valid definition: degree, knots (clamped or not, with repeated
/// interior knots), points, weights.
#[derive(Clone, Debug)]
struct Def {
    degree: usize,
    knots: Vec<f64>,
    points: Vec<Vec3>,
    weights: Option<Vec<f64>>,
}

impl Def {
    fn build(&self) -> Result<Nurbs, NurbsError> {
        Nurbs::new(
            self.degree,
            self.knots.clone(),
            self.points.clone(),
            self.weights.clone(),
        )
    }
}

fn valid_def() -> impl Strategy<Value = Def> {
    (
        1..=Nurbs::MAX_DEGREE,
        0usize..6,
        any::<bool>(),
        any::<bool>(),
    )
        .prop_flat_map(|(degree, extra, clamped, rational)| {
            let n = degree + 1 + extra;
            (
                Just(degree),
                prop::collection::vec(pt(), n),
                // Knot increments: zero (a repeated knot) or positive.
                prop::collection::vec(prop_oneof![Just(0.0), 0.1..3.0f64], n + degree),
                prop::collection::vec(0.05..20.0f64, n),
                Just(clamped),
                Just(rational),
                -50.0..50.0f64,
            )
        })
        .prop_map(|(degree, points, steps, ws, clamped, rational, start)| {
            let n = points.len();
            let mut knots = vec![start];
            for (i, s) in steps.iter().enumerate() {
                // Clamped: degree + 1 equal knots at each end; interior
                // increments below the degree keep a non-empty domain.
                let zero = clamped && (i < degree || i >= n);
                let inside = (degree..n).contains(&i);
                let step = if zero {
                    0.0
                } else if inside && i == degree {
                    s.max(0.1)
                } else {
                    *s
                };
                knots.push(knots[i] + step);
            }
            Def {
                degree,
                knots,
                points,
                weights: rational.then_some(ws),
            }
        })
}

/// One way of breaking a valid definition, and the error it must give.
#[derive(Clone, Copy, Debug)]
enum Break {
    DegreeZero,
    DegreeTooHigh(usize),
    DropPoint,
    ExtraKnot,
    MissingKnot,
    Decreasing,
    NanKnot,
    InfinitePoint,
    ZeroWeight,
    NegativeWeight,
    NanWeight,
    WeightCount,
    OverflowingWeight,
    EmptyDomain,
    KnotRangeOverflow,
}

fn a_break() -> impl Strategy<Value = Break> {
    prop_oneof![
        Just(Break::DegreeZero),
        (Nurbs::MAX_DEGREE + 1..64usize).prop_map(Break::DegreeTooHigh),
        Just(Break::DropPoint),
        Just(Break::ExtraKnot),
        Just(Break::MissingKnot),
        Just(Break::Decreasing),
        Just(Break::NanKnot),
        Just(Break::InfinitePoint),
        Just(Break::ZeroWeight),
        Just(Break::NegativeWeight),
        Just(Break::NanWeight),
        Just(Break::WeightCount),
        Just(Break::OverflowingWeight),
        Just(Break::EmptyDomain),
        Just(Break::KnotRangeOverflow),
    ]
}

/// Applies `b` to `d` and says whether the result must be `e` (by variant).
fn broken(mut d: Def, b: Break, i: usize) -> (Def, fn(&NurbsError) -> bool) {
    let n = d.points.len();
    let i = i % n;
    let weights = |d: &mut Def| d.weights.get_or_insert_with(|| vec![1.0; n]).clone();
    match b {
        Break::DegreeZero => {
            d.degree = 0;
            (d, |e| matches!(e, NurbsError::BadDegree(0)))
        }
        Break::DegreeTooHigh(p) => {
            d.degree = p;
            (d, |e| matches!(e, NurbsError::BadDegree(_)))
        }
        Break::DropPoint => {
            // Keeps the knot count right for the fewer points, so only the
            // point count is wrong.
            d.points.truncate(d.degree);
            d.knots.truncate(2 * d.degree + 1);
            d.weights = None;
            (d, |e| matches!(e, NurbsError::TooFewPoints { .. }))
        }
        Break::ExtraKnot => {
            let last = *d.knots.last().unwrap();
            d.knots.push(last + 1.0);
            (d, |e| matches!(e, NurbsError::KnotCount { .. }))
        }
        Break::MissingKnot => {
            d.knots.pop();
            (d, |e| matches!(e, NurbsError::KnotCount { .. }))
        }
        Break::Decreasing => {
            let k = i % (d.knots.len() - 1);
            d.knots[k + 1] = d.knots[k] - 1.0;
            (d, |e| matches!(e, NurbsError::KnotsDecreasing { .. }))
        }
        Break::NanKnot => {
            d.knots[i] = f64::NAN;
            (d, |e| matches!(e, NurbsError::NotFinite))
        }
        Break::InfinitePoint => {
            d.points[i].y = f64::INFINITY;
            (d, |e| matches!(e, NurbsError::NotFinite))
        }
        Break::ZeroWeight | Break::NegativeWeight | Break::NanWeight => {
            let mut w = weights(&mut d);
            w[i] = match b {
                Break::ZeroWeight => 0.0,
                Break::NegativeWeight => -1.0,
                _ => f64::NAN,
            };
            d.weights = Some(w);
            (d, |e| matches!(e, NurbsError::BadWeights))
        }
        Break::WeightCount => {
            let mut w = weights(&mut d);
            w.push(1.0);
            d.weights = Some(w);
            (d, |e| matches!(e, NurbsError::BadWeights))
        }
        Break::OverflowingWeight => {
            // A finite weight whose product with a coordinate overflows.
            d.weights = Some(vec![1e307; n]);
            d.points[i].x = 1e3;
            (d, |e| matches!(e, NurbsError::NotFinite))
        }
        Break::EmptyDomain => {
            let k = d.knots[d.degree];
            for x in &mut d.knots[d.degree..=n] {
                *x = k;
            }
            for j in n + 1..d.knots.len() {
                d.knots[j] = d.knots[j].max(k);
            }
            (d, |e| matches!(e, NurbsError::EmptyDomain))
        }
        Break::KnotRangeOverflow => {
            d.knots[0] = -1.7e308;
            let last = d.knots.len() - 1;
            d.knots[last] = 1.7e308;
            (d, |e| matches!(e, NurbsError::NotFinite))
        }
    }
}

/// An f64 that is often NaN, infinite, huge, tiny or zero.
fn wild_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(f64::MAX),
        Just(-f64::MAX),
        Just(f64::MIN_POSITIVE),
        Just(0.0),
        Just(-0.0),
        Just(1.0),
        -10.0..10.0f64,
        -1e300..1e300f64,
    ]
}

fn wild_pt() -> impl Strategy<Value = Vec3> {
    (wild_f64(), wild_f64(), wild_f64()).prop_map(|(x, y, z)| v(x, y, z))
}

/// Everything a consumer asks of a curve, at `k` parameters.
fn evaluate_all<C: ParamCurve>(c: &C, k: usize) -> Vec<Vec3> {
    let (a, b) = c.domain();
    let mut out = Vec::new();
    for i in 0..=k {
        let t = a + (b - a) * i as f64 / k as f64;
        out.push(c.eval(t));
        out.push(c.deriv1(t));
        out.push(c.deriv2(t));
        let _ = c.curvature(t);
        let _ = c.curvature_vector(t);
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Valid definitions construct, pass `validate`, and evaluate to
    /// finite points and derivatives everywhere in the domain.
    #[test]
    fn valid_nurbs_construct_and_evaluate_finitely(d in valid_def()) {
        let c = d.build();
        prop_assert!(c.is_ok(), "{:?}: {:?}", d, c);
        let c = c.unwrap();
        prop_assert_eq!(c.validate(), Ok(()));
        for p in evaluate_all(&c, 16) {
            prop_assert!(p.is_finite(), "{:?}", d);
        }
        prop_assert!(arc_length(&c, 1e-6).is_finite());
    }

    /// Each kind of invalid definition is its error, from `new` and from
    /// `validate` alike.
    #[test]
    fn invalid_nurbs_are_their_error(d in valid_def(), b in a_break(), i in 0usize..64) {
        let (bad, expected) = broken(d, b, i);
        let got = bad.build();
        prop_assert!(
            matches!(&got, Err(e) if expected(e)),
            "{:?} gave {:?}",
            b,
            got
        );
        let literal = Nurbs {
            degree: bad.degree,
            knots: bad.knots.clone(),
            points: bad.points.clone(),
            weights: bad.weights.clone(),
        };
        prop_assert_eq!(literal.validate().err(), got.err());
        // Evaluating and splitting it anyway does not panic.
        let _ = evaluate_all(&literal, 4);
        let _ = literal.breakpoints();
        let _ = literal.bezier_spans();
        let _ = literal.insert_knot(0.5, 2);
    }

    /// Arbitrary definitions (any degree, NaN, infinities, huge values,
    /// knot counts near the right one, sorted or not) never panic; what
    /// constructs validates, and its evaluation, length and flattening
    /// finish without panicking.
    #[test]
    fn arbitrary_nurbs_input_never_panics(
        (degree, points, knots, weights) in (0usize..12, 0usize..12, -1i32..=1, any::<bool>())
            .prop_flat_map(|(degree, n, dk, sorted)| {
                let nk = (n as i32 + degree as i32 + 1 + dk).max(0) as usize;
                (
                    Just(degree),
                    prop::collection::vec(wild_pt(), n),
                    prop::collection::vec(wild_f64(), nk).prop_map(move |mut k| {
                        if sorted {
                            k.sort_by(f64::total_cmp);
                        }
                        k
                    }),
                    prop::option::of(prop::collection::vec(
                        prop_oneof![wild_f64(), 0.1..10.0f64],
                        n,
                    )),
                )
            }),
    ) {
        if let Ok(c) = Nurbs::new(degree, knots, points, weights) {
            prop_assert_eq!(c.validate(), Ok(()));
            let _ = evaluate_all(&c, 4);
            let _ = arc_length(&c, 1e-3);
            let _ = flatten_params(&c, 1e-3);
            let _ = c.bezier_spans();
        }
    }

    /// Struct literals that break the shape evaluation indexes by (degree
    /// above the maximum, wrong knot or weight counts) evaluate to NaN.
    #[test]
    fn malformed_literals_evaluate_to_nan(
        degree in 0usize..20,
        n_knots in 0usize..30,
        points in prop::collection::vec(pt(), 0..12),
        n_weights in prop::option::of(0usize..12),
    ) {
        let c = Nurbs {
            degree,
            knots: (0..n_knots).map(|k| k as f64).collect(),
            weights: n_weights.map(|n| vec![1.0; n]),
            points,
        };
        match c.validate() {
            Err(
                NurbsError::BadDegree(_)
                | NurbsError::TooFewPoints { .. }
                | NurbsError::KnotCount { .. }
                | NurbsError::BadWeights,
            ) => {
                prop_assert!(c.domain().0.is_nan());
                for p in evaluate_all(&c, 4) {
                    prop_assert!(p.x.is_nan(), "{:?}", c);
                }
            }
            Err(e) => prop_assert!(false, "unexpected {:?}", e),
            Ok(()) => prop_assert!(c.eval(c.domain().0).is_finite()),
        }
    }

    /// `Arc::from_center` never panics; an arc it builds has finite
    /// radii, sweep and rise.
    #[test]
    fn arc_from_center_never_panics(
        start in wild_pt(),
        end in wild_pt(),
        center in wild_pt(),
        axis in prop_oneof![Just(Vec3::Z), Just(Vec3::Y), Just(Vec3::X), wild_pt()],
        clockwise in any::<bool>(),
        turns in prop_oneof![Just(0u32), Just(1), Just(3), Just(u32::MAX)],
    ) {
        if let Ok(a) = Arc::from_center(start, end, center, axis, clockwise, turns, 1e-9) {
            prop_assert!(a.r0.is_finite() && a.r1.is_finite());
            prop_assert!(a.sweep.is_finite() && a.sweep > 0.0 && a.rise.is_finite());
            let _ = evaluate_all(&a, 4);
        }
    }
}

#[test]
fn degree_above_the_maximum_is_an_error_naming_it() {
    let n = 10;
    let knots: Vec<f64> = (0..n + 10).map(|k| k.clamp(9, 10) as f64).collect();
    let points: Vec<Vec3> = (0..n).map(|i| v(i as f64, 0.0, 0.0)).collect();
    let e = Nurbs::new(9, knots, points, None).unwrap_err();
    assert_eq!(e, NurbsError::BadDegree(9));
    assert_eq!(e.to_string(), "degree 9 is not supported (1 to 7)");
}

#[test]
fn degree_9_literal_evaluates_to_nan_instead_of_panicking() {
    let points: Vec<Vec3> = (0..10).map(|i| v(i as f64, 0.0, 0.0)).collect();
    let mut knots = vec![0.0; 10];
    knots.extend([1.0; 10]);
    let c = Nurbs {
        degree: 9,
        knots,
        points,
        weights: None,
    };
    assert!(matches!(c.validate(), Err(NurbsError::BadDegree(9))));
    assert!(c.eval(0.5).x.is_nan());
    assert!(c.deriv1(0.5).x.is_nan());
    assert!(c.deriv2(0.5).x.is_nan());
    assert!(c.domain().0.is_nan());
}

/// Fuzz input 5eedf00d-122 (a JSON cubic whose weights ran from 1e-12 to
/// 1e308): its derivatives were NaN and the arc-length quadrature bisected
/// 2^30 intervals (hours). 1e308 times a coordinate overflows: such
/// weights are now refused, and a curve built around the check still has a
/// length in bounded time.
#[test]
fn fuzz_json_122_weights_1e_minus12_to_1e308_are_refused_and_length_terminates() {
    let knots = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let points = vec![
        v(0.0, 0.0, 0.0),
        v(1.0, 1.0, 0.0),
        v(2.0, 0.0, 0.0),
        v(3.0, 1.0, 0.0),
    ];
    let weights = vec![8.02131094460001, 1e-12, 3.0, 1e308];
    let e = Nurbs::new(3, knots.clone(), points.clone(), Some(weights.clone())).unwrap_err();
    assert_eq!(e, NurbsError::NotFinite);
    let c = Nurbs {
        degree: 3,
        knots,
        points,
        weights: Some(weights),
    };
    let started = std::time::Instant::now();
    let _ = arc_length(&c, 1e-3);
    let _ = flatten_params(&c, 1e-3);
    assert!(started.elapsed().as_secs() < 10, "{:?}", started.elapsed());
}

#[test]
fn arc_of_points_too_far_apart_for_f64_is_not_finite() {
    let e = Arc::from_center(
        v(1e308, 0.0, 0.0),
        v(1e308, 0.0, 0.0),
        v(-1e308, 0.0, 0.0),
        Vec3::Z,
        false,
        1,
        1e-9,
    );
    assert_eq!(e.unwrap_err(), ArcError::NotFinite);
}

/// A valid cubic reaching `reach` mm, with a sharp turn in the middle.
fn far_cubic(reach: f64) -> Nurbs {
    Nurbs::new(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0],
        vec![
            v(0.0, 0.0, 0.0),
            v(reach, 0.0, 0.0),
            v(reach, reach, 0.0),
            v(0.0, reach, reach),
            v(-reach, 0.0, 1.0),
        ],
        None,
    )
    .unwrap()
}

/// Flattening a curve 1e100 mm long to 1 um would take 2^40 spans: it
/// stops at the span budget, in order, ends included.
#[test]
fn flattening_a_curve_1e100_mm_long_is_bounded() {
    let c = far_cubic(1e100);
    let started = std::time::Instant::now();
    let ts = flatten_params(&c, 1e-3);
    assert!(started.elapsed().as_secs() < 20, "{:?}", started.elapsed());
    assert!(ts.len() <= (1 << 20) + 1, "{}", ts.len());
    assert_eq!((ts[0], *ts.last().unwrap()), (0.0, 1.0));
    assert!(ts.windows(2).all(|w| w[0] < w[1]));
}

/// Fuzz input 5eedf00d-85 reached X2.9e297: the length of a curve that
/// long to 1 um is below the rounding of its sums, and the quadrature
/// bisected 2^30 intervals; it now stops at the rounding floor.
#[test]
fn length_of_a_curve_1e297_mm_long_terminates() {
    for reach in [2.9e297, 1e150] {
        let c = far_cubic(reach);
        let started = std::time::Instant::now();
        let l = arc_length(&c, 1e-3);
        assert!(started.elapsed().as_secs() < 10, "{:?}", started.elapsed());
        // |C'|^2 overflows beyond 1e154 mm: the length is then infinite.
        assert!(l > reach, "{l}");
    }
    // An ordinary curve still gets its accuracy.
    let small = far_cubic(10.0);
    let (a, b) = (arc_length(&small, 1e-9), arc_length(&small, 1e-3));
    assert!((a - b).abs() < 1e-3);
}
