//! G2 transitions at the joints next to arcs (`blend_arc_joints`) after the
//! corner methods, on random runs of lines and circular or helical arcs
//! meeting at corners and tangentially: within the tolerance of the
//! original run (the independent verifier), endpoints exact, pieces
//! joined bit for bit, and every joint G2 but the corners kept.

use crate::common;
use common::{check_guarantees, v};
use fairpath::geom::{Arc, Curve, Line, ParamCurve, Vec3};
use fairpath::path::{Piece, Run};
use fairpath::smooth::{blend_arc_joints, BsplineCorner, CornerReason, Lotm, Smoother};
use fairpath::verify::{verify_run, Continuity, VerifyOptions};
use proptest::prelude::*;

fn piece(curve: Curve, line: usize) -> Piece {
    Piece {
        curve,
        rapid: false,
        source_lines: (line, line),
        feed: Some(1000.0),
    }
}

/// One step of a random run: a line (`turn` rad from the current heading
/// in the XY plane, `len` mm, rising `rise`), or an arc of `sweep` rad and
/// radius `len` turning left or right (`turn` > 0 or not) after a corner
/// of `turn` rad, rising `rise`. `tangent`: no corner before it.
#[derive(Clone, Copy, Debug)]
struct Step {
    arc: bool,
    turn: f64,
    len: f64,
    sweep: f64,
    rise: f64,
    tangent: bool,
}

fn step() -> impl Strategy<Value = Step> {
    (
        any::<bool>(),
        -2.5..2.5f64,
        0.2..8.0f64,
        0.1..4.0f64,
        prop_oneof![Just(0.0), -0.5..0.5f64],
        any::<bool>(),
    )
        .prop_map(|(arc, turn, len, sweep, rise, tangent)| Step {
            arc,
            turn,
            len,
            sweep,
            rise,
            tangent,
        })
}

/// The run the steps draw from the origin, heading along +X.
fn run_of(steps: &[Step]) -> Run {
    let mut p = v(0.0, 0.0, 0.0);
    let mut heading: f64 = 0.0;
    let mut pieces = Vec::new();
    for (i, s) in steps.iter().enumerate() {
        if !s.tangent {
            heading += s.turn;
        }
        let dir = v(heading.cos(), heading.sin(), 0.0);
        if s.arc {
            let left = s.turn > 0.0;
            let normal = v(0.0, 0.0, if left { 1.0 } else { -1.0 });
            let center = p + normal.cross(dir) * s.len;
            let a = p - center;
            let (sn, cs) = s.sweep.sin_cos();
            let rotated = a * cs + normal.cross(a) * sn;
            let end = center + rotated + v(0.0, 0.0, s.rise);
            let arc = Arc::from_center(p, end, center, v(0.0, 0.0, 1.0), !left, 1, 1e-9).unwrap();
            heading += if left { s.sweep } else { -s.sweep };
            p = arc.p1;
            pieces.push(piece(Curve::from(arc), i + 1));
        } else {
            let end = p + dir * s.len + v(0.0, 0.0, s.rise);
            pieces.push(piece(Curve::Line(Line::new(p, end)), i + 1));
            p = end;
        }
    }
    Run::new(pieces)
}

fn check(steps: &[Step], tol: f64, method: &dyn Smoother) -> Result<(), TestCaseError> {
    let run = run_of(steps);
    let mut out = method.smooth_run(&run, tol).unwrap();
    blend_arc_joints(&mut out, tol);
    let rep = verify_run(&run.pieces, &out.pieces, &VerifyOptions::new(tol));
    check_guarantees(&out, &rep, tol)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn bspline_corner_then_arc_joints(steps in prop::collection::vec(step(), 1..12), tol in prop_oneof![Just(0.005), Just(0.05), Just(0.5)]) {
        check(&steps, tol, &BsplineCorner::default())?;
    }

    #[test]
    fn lotm_then_arc_joints(steps in prop::collection::vec(step(), 1..12), tol in prop_oneof![Just(0.005), Just(0.05), Just(0.5)]) {
        check(&steps, tol, &Lotm::default())?;
    }
}

/// LinuxCNC's `helix_slowdown.ngc` (in mm): a line into a half circle at
/// a right angle keeps its corner (sharper than `MAX_TURN`: the planner
/// passes it faster than a transition inside the band); a line tangent to
/// the half circle, or meeting it at 20 degrees, gets a G2 transition of
/// its own, the arc cut back, not replaced.
#[test]
fn helix_slowdown_right_angle_is_kept_tangent_and_shallow_joints_become_g2() {
    let s = 25.4;
    let half = |from: Vec3, to: Vec3| {
        let c = (from + to) * 0.5;
        Arc::from_center(from, to, c, v(0.0, 0.0, 1.0), true, 1, 1e-9).unwrap()
    };
    let arc = half(v(s, 0.0, 0.0), v(0.0, 0.0, 0.0));
    // The arc starts at (s, 0) heading -Y; lines arriving there heading
    // +X (a right angle), -Y (tangent) and 20 degrees off -Y.
    let (sin20, cos20) = 20f64.to_radians().sin_cos();
    let arrivals = [
        (v(1.0, 0.0, 0.0), false),
        (v(0.0, -1.0, 0.0), true),
        (v(sin20, -cos20, 0.0), true),
    ];
    for (dir, blended) in arrivals {
        let first = Line::new(v(s, 0.0, 0.0) - dir * s, v(s, 0.0, 0.0));
        let run = Run::new(vec![
            piece(Curve::Line(first), 1),
            piece(Curve::from(arc), 2),
        ]);
        let mut out = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
        let kept_before = out.kept_corners.len();
        blend_arc_joints(&mut out, 0.05);
        let rep = verify_run(&run.pieces, &out.pieces, &VerifyOptions::new(0.05));
        assert!(rep.deviation_bound <= 0.05, "{}", rep.deviation_bound);
        if !blended {
            assert_eq!(kept_before, 1);
            assert_eq!(out.kept_corners.len(), 1);
            assert_eq!(out.transitions, 0);
            continue;
        }
        assert!(out.kept_corners.is_empty(), "{:?}", out.kept_corners);
        assert_eq!(out.transitions, 1);
        assert_eq!(out.pieces.len(), 3);
        assert!(rep.joints.iter().all(|j| j.class == Continuity::G2));
        let Curve::Arc(rest) = &out.pieces[2].curve else {
            panic!("the arc stays an arc");
        };
        assert_eq!(rest.p1, arc.p1);
        assert!((rest.r0 - arc.r0).abs() < 1e-12);
    }
}

/// A line that turns back along the arc it came from keeps its corner.
#[test]
fn a_near_reversal_next_to_an_arc_is_kept() {
    let arc = Arc::from_center(
        v(0.0, 0.0, 0.0),
        v(10.0, 0.0, 0.0),
        v(5.0, 0.0, 0.0),
        v(0.0, 0.0, 1.0),
        true,
        1,
        1e-9,
    )
    .unwrap();
    // The arc ends heading -Y; the line leaves heading +Y, slightly out.
    let end = arc.p1;
    let line = Line::new(end, end + v(0.1, 3.0, 0.0));
    let run = Run::new(vec![
        piece(Curve::from(arc), 1),
        piece(Curve::Line(line), 2),
    ]);
    let mut out = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
    blend_arc_joints(&mut out, 0.05);
    assert_eq!(out.transitions, 0);
    assert!(out
        .kept_corners
        .iter()
        .any(|k| k.reason == CornerReason::ArcJoint && k.at.dist(end) < 1e-12));
    assert!(arc.unit_tangent(1.0).unwrap().dot(v(0.0, -1.0, 0.0)) > 0.999);
}

/// The corner methods' `arc_joints` option on a rounded rectangle (lines
/// and tangent arcs of 5 mm, curvature steps of 0.2 1/mm at every joint):
/// kept, each joint is G1 and plans as the program; blended, every joint
/// is G2 and the run plans faster (3.723 s -> 3.197 s as written by
/// `fairpath smooth -m bspline-corner` with `arc_joints = "blended"`).
#[test]
fn rounded_rectangle_with_arc_joints_blended_is_g2_and_plans_faster() {
    use fairpath::feed::limits::MachineLimits;
    use fairpath::feed::plan::{plan_run, PlanOptions};
    use fairpath::smooth::{ArcJoints, BsplineCornerOptions, Ctm, CtmOptions, LotmOptions};
    let arc = |from: Vec3, to: Vec3, c: Vec3| {
        Arc::from_center(from, to, c, v(0.0, 0.0, 1.0), false, 1, 1e-9).unwrap()
    };
    let line = |a: Vec3, b: Vec3| Curve::Line(Line::new(a, b));
    let run = Run::new(vec![
        piece(line(v(5.0, 0.0, 0.0), v(45.0, 0.0, 0.0)), 1),
        piece(
            Curve::from(arc(v(45.0, 0.0, 0.0), v(50.0, 5.0, 0.0), v(45.0, 5.0, 0.0))),
            2,
        ),
        piece(line(v(50.0, 5.0, 0.0), v(50.0, 25.0, 0.0)), 3),
        piece(
            Curve::from(arc(
                v(50.0, 25.0, 0.0),
                v(45.0, 30.0, 0.0),
                v(45.0, 25.0, 0.0),
            )),
            4,
        ),
        piece(line(v(45.0, 30.0, 0.0), v(5.0, 30.0, 0.0)), 5),
    ]);
    let opts = PlanOptions {
        limits: MachineLimits::thesis(),
        override_feed: true,
        window: None,
        ends: Default::default(),
    };
    let kept_time = plan_run(&run.pieces, &opts).unwrap().time;
    let blended = ArcJoints::Blended;
    let methods: [Box<dyn Smoother>; 3] = [
        Box::new(BsplineCorner {
            options: BsplineCornerOptions {
                arc_joints: blended,
                ..Default::default()
            },
        }),
        Box::new(Lotm {
            options: LotmOptions {
                arc_joints: blended,
                ..Default::default()
            },
        }),
        Box::new(Ctm {
            options: CtmOptions {
                arc_joints: blended,
                ..Default::default()
            },
        }),
    ];
    for m in methods {
        let out = m.smooth_run(&run, 0.05).unwrap();
        assert_eq!(out.transitions, 4, "{}", m.name());
        let rep = verify_run(&run.pieces, &out.pieces, &VerifyOptions::new(0.05));
        assert!(rep.deviation_bound <= 0.05);
        assert!(
            rep.joints.iter().all(|j| j.class == Continuity::G2),
            "{}",
            m.name()
        );
        let t = plan_run(&out.pieces, &opts).unwrap().time;
        assert!(
            t < 0.97 * kept_time,
            "{}: {t} s against {kept_time} s",
            m.name()
        );
    }
    // The default keeps them.
    let out = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
    assert_eq!(out.transitions, 0);
    assert_eq!(out.pieces.len(), run.pieces.len());
}
