//! The thesis' kinds of case (seed 003, chapter 4) as we build them:
//! shared by the `thesis_cases` example and the tests that check the
//! fairing on them (`tests/thesis_cases.rs`).

use fairpath::geom::fit::chord_params;
use fairpath::geom::{Nurbs, ParamCurve, Vec3};
use std::f64::consts::PI;

/// One case: its name, what it stands for, the curve, and the thesis'
/// published rows (curvature, length, time: original and the three radii)
/// where the case is one of its own.
pub struct Case {
    pub name: &'static str,
    pub what: &'static str,
    pub curve: Nurbs,
    pub published: Option<[[f64; 4]; 3]>,
}

/// A clamped uniform cubic B-spline on `points`.
pub fn clamped(points: Vec<Vec3>) -> Nurbs {
    let n = points.len();
    let spans = n - 3;
    let mut knots = vec![0.0; 4];
    knots.extend((1..spans).map(|i| i as f64 / spans as f64));
    knots.extend([1.0; 4]);
    Nurbs::new(3, knots, points, None).expect("a valid clamped spline")
}

/// The cubic B-spline interpolating `pts` at their chord-length
/// parameters, on averaged knots (Piegl and Tiller, The NURBS Book,
/// section 9.2.1: eqs. 9.5 and 9.8), as a CAM system's spline interpolation does: the
/// collocation system solved by Gaussian elimination.
pub fn interpolate(pts: &[Vec3]) -> Nurbs {
    let n = pts.len();
    let params = chord_params(pts);
    // Eq. 9.8: interior knot j + 3 is the mean of parameters j+1..j+3.
    let mut knots = vec![params[0]; 4];
    for j in 1..n - 3 {
        knots.push((params[j] + params[j + 1] + params[j + 2]) / 3.0);
    }
    knots.extend([params[n - 1]; 4]);
    // Basis function j at parameter t: the x of the spline whose control
    // points are all zero but the j-th.
    let basis = |j: usize, t: f64| {
        let mut e = vec![Vec3::ZERO; n];
        e[j] = Vec3::new(1.0, 0.0, 0.0);
        Nurbs::new(3, knots.clone(), e, None)
            .expect("valid")
            .eval(t)
            .x
    };
    let mut a: Vec<Vec<f64>> = params
        .iter()
        .map(|&t| (0..n).map(|j| basis(j, t)).collect())
        .collect();
    let mut rhs: Vec<Vec3> = pts.to_vec();
    for col in 0..n {
        let piv = (col..n)
            .max_by(|&i, &k| a[i][col].abs().total_cmp(&a[k][col].abs()))
            .expect("rows");
        a.swap(col, piv);
        rhs.swap(col, piv);
        let pivot = a[col].clone();
        for row in col + 1..n {
            let f = a[row][col] / pivot[col];
            if f != 0.0 {
                for (x, p) in a[row][col..].iter_mut().zip(&pivot[col..]) {
                    *x -= f * p;
                }
                let r = rhs[col];
                rhs[row] -= r * f;
            }
        }
    }
    let mut ctrl = vec![Vec3::ZERO; n];
    for row in (0..n).rev() {
        let mut v = rhs[row];
        for k in row + 1..n {
            v -= ctrl[k] * a[row][k];
        }
        ctrl[row] = v / a[row][row];
    }
    Nurbs::new(3, knots, ctrl, None).expect("an interpolating spline")
}

/// The cases, in the order of the report.
pub fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    // The thesis' case 5: a straight line whose spline has two control
    // points displaced 0.2 mm (CAM-induced ripples), 32 control points.
    // 32 points of a 100 mm line, two of them 0.2 mm off.
    let mut line: Vec<Vec3> = (0..32)
        .map(|i| Vec3::new(100.0 * i as f64 / 31.0, 0.0, 0.0))
        .collect();
    line[10].y += 0.2;
    line[21].y += 0.2;
    out.push(Case {
        name: "line-two-points",
        what: "straight line, 32 control points, two displaced 0.2 mm (thesis case 5)",
        curve: clamped(line.clone()),
        published: Some([
            [0.093916, 0.08424, 0.04706, 0.005922],
            [100.444, 100.383, 100.157, 100.017],
            [1.341, 1.304, 1.065, 0.334],
        ]),
    });
    // The same, as a CAM system makes it: a spline interpolating 32 points
    // of the line, two of them 0.2 mm off (the interpolant rings around
    // them: curvature nearer the thesis' case).
    out.push(Case {
        name: "line-two-points-interpolated",
        what: "straight line, a spline through 32 points, two of them 0.2 mm off (thesis case 5)",
        curve: interpolate(&line),
        published: Some([
            [0.093916, 0.08424, 0.04706, 0.005922],
            [100.444, 100.383, 100.157, 100.017],
            [1.341, 1.304, 1.065, 0.334],
        ]),
    });
    // Case 5 with sharp bumps: the thesis' line is 0.444 mm longer than
    // straight with 9.4 rad of turning (Tables 4-1 and 4-3), yet nearly
    // straight in the 0.25 mm tube, so its bumps are narrow and steep, not
    // the gentle ones of a uniform polygon. Here: a 28-point uniform
    // polygon of the line, the points nearest 30 and 70 mm each replaced
    // by three (one displaced 0.2 mm, its neighbours `SHARP_BUMP_SPACING`
    // either side): 32 control points. Its length and turning stay below
    // the thesis' (the exact geometry is only in its figures).
    out.push(Case {
        name: "line-two-points-sharp",
        what: "straight line, 32 control points, two displaced 0.2 mm with neighbours 0.05 mm away (thesis case 5, sharp bumps)",
        curve: clamped(sharp_bumps(SHARP_BUMP_SPACING)),
        published: Some([
            [0.093916, 0.08424, 0.04706, 0.005922],
            [100.444, 100.383, 100.157, 100.017],
            [1.341, 1.304, 1.065, 0.334],
        ]),
    });
    // The thesis' case 6: a square whose 90-degree corners a spline
    // interpolation turned into ripples: 28 points around a square (7 a
    // side, the corners among them), from the middle of one side round to
    // the same point. The thesis gives the case as a figure and its
    // figures of the original (average curvature 0.175172 1/mm, length
    // 123.277 mm); the points next to each corner, a share `NEAR` of the
    // side from it, make the interpolation overshoot there, and the side
    // and `NEAR` were chosen, on a grid (side 29.9 to 30.7 mm, `NEAR` 0.03
    // to 0.06), as those whose original comes nearest both: 0.1765 1/mm
    // and 123.296 mm. (Seven points evenly spaced on a side of 30.8 mm
    // gave the thesis' length but half its curvature.)
    const SIDE: f64 = 30.0;
    const NEAR: f64 = 0.037;
    let corners = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(SIDE, 0.0, 0.0),
        Vec3::new(SIDE, SIDE, 0.0),
        Vec3::new(0.0, SIDE, 0.0),
    ];
    let mut square = Vec::new();
    for k in 0..4 {
        let (a, b) = (corners[k], corners[(k + 1) % 4]);
        for f in [0.0, NEAR, 0.2, 0.4, 0.6, 0.8, 1.0 - NEAR] {
            square.push(a + (b - a) * f);
        }
    }
    square.rotate_left(3);
    square.push(square[0]);
    out.push(Case {
        name: "square-ripples",
        what: "square of side 30 mm, its corners interpolated by a spline through 29 points, two of them 1.11 mm from each corner (thesis case 6)",
        curve: interpolate(&square),
        published: Some([
            [0.175172, 0.168204, 0.143115, 0.131753],
            [123.277, 123.200, 122.914, 122.263],
            [1.970, 1.922, 1.757, 1.647],
        ]),
    });
    // A smooth design curve like the thesis' case 1 (766 mm, 62 control
    // points, peak curvature about 0.175 1/mm): a wave of two harmonics.
    let design: Vec<Vec3> = (0..62)
        .map(|i| {
            let x = 640.0 * i as f64 / 61.0;
            let y = 40.0 * (2.0 * PI * x / 320.0).sin() + 8.0 * (2.0 * PI * x / 80.0).sin();
            Vec3::new(x, y, 0.0)
        })
        .collect();
    out.push(Case {
        name: "design-wave",
        what: "smooth design curve, 62 control points (like thesis case 1)",
        curve: clamped(design),
        published: None,
    });
    // Single ripples of increasing curvature: a 50 mm line of 16 control
    // points with the middle one displaced by d.
    for (name, d) in [
        ("ripple-0.02", 0.02),
        ("ripple-0.05", 0.05),
        ("ripple-0.1", 0.1),
        ("ripple-0.2", 0.2),
    ] {
        let mut pts: Vec<Vec3> = (0..16)
            .map(|i| Vec3::new(50.0 * i as f64 / 15.0, 0.0, 0.0))
            .collect();
        pts[8].y += d;
        out.push(Case {
            name,
            what: "50 mm line, 16 control points, one displaced",
            curve: clamped(pts),
            published: None,
        });
    }
    out
}

/// Spacing (mm) of the neighbours of the displaced points of
/// `line-two-points-sharp`: narrow bumps, as the thesis' length and
/// turning for its case 5 imply (0.02, 0.05 and 0.125 mm: the original
/// plans 0.856, 0.848 and 0.829 s in the thesis' model, and each is
/// straightened in the 0.125 mm tube).
const SHARP_BUMP_SPACING: f64 = 0.05;

/// The control points of `line-two-points-sharp` (see [`cases`]).
fn sharp_bumps(spacing: f64) -> Vec<Vec3> {
    let mut pts = Vec::new();
    for i in 0..28 {
        let x = 100.0 * i as f64 / 27.0;
        if [30.0, 70.0]
            .iter()
            .any(|b: &f64| (x - b).abs() < 50.0 / 27.0)
        {
            pts.push(Vec3::new(x - spacing, 0.0, 0.0));
            pts.push(Vec3::new(x, 0.2, 0.0));
            pts.push(Vec3::new(x + spacing, 0.0, 0.0));
        } else {
            pts.push(Vec3::new(x, 0.0, 0.0));
        }
    }
    pts
}
