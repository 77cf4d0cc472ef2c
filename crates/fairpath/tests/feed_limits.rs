//! Speed caps from machine limits: each cap makes its own constraint hold
//! with equality, and bad limits are rejected by name.

use fairpath::feed::junction::{corner_blend, junction_cap};
use fairpath::feed::limits::{speed_cap, Constraint, MachineLimits, PathPoint};
use fairpath::geom::Vec3;

fn circle_point(r: f64) -> PathPoint {
    PathPoint {
        tangent: Vec3::new(0.0, 1.0, 0.0),
        curvature: Vec3::new(-1.0 / r, 0.0, 0.0),
        dkappa_ds: 0.0,
    }
}

#[test]
fn bad_limits_are_named() {
    let mut m = MachineLimits::thesis();
    assert!(m.validate().is_ok());
    m.jerk = f64::NAN;
    assert_eq!(m.validate().unwrap_err().name, "jerk");
    m.jerk = 1.0;
    m.period = 0.0;
    assert_eq!(m.validate().unwrap_err().name, "interpolation period");
    m.period = 0.001;
    m.axis_acc[2] = -5.0;
    let e = m.validate().unwrap_err();
    assert_eq!(e.name, "Z acceleration");
    assert!(e.to_string().contains("Z acceleration"));
    m.axis_acc[2] = 5.0;
    // A block time may be 0 (none), not negative or infinite.
    m.block_time = 0.0;
    assert!(m.validate().is_ok());
    for bad in [-0.001, f64::INFINITY, f64::NAN] {
        m.block_time = bad;
        assert!(m.validate().unwrap_err().name.starts_with("block time"));
    }
}

#[test]
fn straight_line_is_capped_by_feed_and_axes() {
    let mut m = MachineLimits::thesis();
    m.axis_vel = [100.0, 400.0, 400.0];
    let t = Vec3::new(1.0, 1.0, 0.0) / 2f64.sqrt();
    let p = PathPoint {
        tangent: t,
        curvature: Vec3::ZERO,
        dkappa_ds: 0.0,
    };
    let (v, c) = speed_cap(&m, 1000.0, &p);
    assert_eq!(c, Constraint::AxisVelocity);
    assert!((v - 100.0 * 2f64.sqrt()).abs() < 1e-9);
    let (v, c) = speed_cap(&m, 50.0, &p);
    assert_eq!((v, c), (50.0, Constraint::Feed));
}

#[test]
fn circle_caps_hold_with_equality_for_the_binding_constraint() {
    let m = MachineLimits::thesis();
    for r in [0.01, 0.1, 1.0, 10.0, 100.0, 1000.0] {
        let p = circle_point(r);
        let (v, c) = speed_cap(&m, 1e9, &p);
        let k = 1.0 / r;
        // Every constraint holds at the cap.
        assert!(k * v * v <= m.normal_acc * (1.0 + 1e-12), "r {r}");
        assert!(k * k * v * v * v <= m.jerk * (1.0 + 1e-12), "r {r}");
        let chord = v * m.period;
        let sag = r - (r * r - chord * chord / 4.0).max(0.0).sqrt();
        assert!(
            sag <= m.chord_error * (1.0 + 1e-9) || chord >= 2.0 * r,
            "r {r}: sag {sag}"
        );
        assert!(v <= m.max_feed);
        // And the binding one with equality.
        let tight = match c {
            Constraint::NormalAcceleration => k * v * v / m.normal_acc,
            Constraint::NormalJerk => k * k * v * v * v / m.jerk,
            Constraint::ChordError => sag / m.chord_error,
            Constraint::Feed => v / m.max_feed,
            Constraint::AxisAcceleration => k * v * v / m.axis_acc[0],
            Constraint::AxisVelocity => v / m.axis_vel[1],
            other => panic!("unexpected {other:?}"),
        };
        assert!((tight - 1.0).abs() < 1e-9, "r {r}: {c:?} at {tight}");
    }
    // Thesis machine: a 1 mm radius is jerk-bound: (J r^2)^(1/3) = 27.1 mm/s.
    let (v, c) = speed_cap(&m, 1e9, &circle_point(1.0));
    assert_eq!(c, Constraint::NormalJerk);
    assert!((v - 20000f64.cbrt()).abs() < 1e-9);
}

#[test]
fn curvature_change_caps_clothoids() {
    let m = MachineLimits::thesis();
    let p = PathPoint {
        tangent: Vec3::X,
        curvature: Vec3::ZERO,
        dkappa_ds: 2.0,
    };
    let (v, c) = speed_cap(&m, 1e9, &p);
    assert_eq!(c, Constraint::CurvatureChange);
    assert!((2.0 * v * v * v - m.jerk).abs() < 1e-6);
}

#[test]
fn junction_caps() {
    let m = MachineLimits::thesis();
    let a = Vec3::X;
    let b = Vec3::new(0.0, 1.0, 0.0);
    // 90 degrees: a circle of radius e sin45 / (1 - sin45) tangent to both
    // moves; its middle is e from the corner.
    let v = junction_cap(&m, a, b, Vec3::ZERO, Vec3::ZERO, f64::INFINITY);
    let s45 = 0.5f64.sqrt();
    let r = m.junction_deviation * s45 / (1.0 - s45);
    assert!((r / s45 - r - m.junction_deviation).abs() < 1e-15);
    let want = (m.normal_acc * r)
        .sqrt()
        .min((m.jerk * r * r).cbrt())
        .min((m.jerk * m.period * r).sqrt());
    assert!((v - want).abs() < 1e-12);
    // Gentler corners are faster.
    let c = Vec3::new(1.0, 0.1, 0.0) / 1.01f64.sqrt();
    assert!(junction_cap(&m, a, c, Vec3::ZERO, Vec3::ZERO, f64::INFINITY) > v);
    // Straight on: no cap.
    assert_eq!(
        junction_cap(&m, a, a, Vec3::ZERO, Vec3::ZERO, f64::INFINITY),
        f64::INFINITY
    );
    // Tangent line into a 10 mm arc: v^2 / 10 = J Ts.
    let v = junction_cap(
        &m,
        a,
        a,
        Vec3::ZERO,
        Vec3::new(0.0, 0.1, 0.0),
        f64::INFINITY,
    );
    assert!((v * v * 0.1 - m.jerk * m.period).abs() < 1e-9);
}

#[test]
fn corner_circles_fit_in_half_the_moves() {
    let m = MachineLimits::thesis();
    // A 1 degree turn: the junction-deviation circle (R = 0.01 cos(a) /
    // (1 - cos(a)), about 263 mm) would take 2.3 mm from each move.
    let phi = 1f64.to_radians();
    let a = Vec3::X;
    let b = Vec3::new(phi.cos(), phi.sin(), 0.0);
    let free = corner_blend(&m, a, b, f64::INFINITY).unwrap();
    let ca = (0.5 * phi).cos();
    assert!((free.radius - m.junction_deviation * ca / (1.0 - ca)).abs() < 1e-9 * free.radius);
    assert!(free.tangent_length > 2.0);
    // Between 1 mm moves it may take only 0.5 mm: R = 0.5 / tan(phi / 2).
    let fit = corner_blend(&m, a, b, 0.5).unwrap();
    assert!((fit.tangent_length - 0.5).abs() < 1e-12);
    assert!((fit.radius - 0.5 / (0.5 * phi).tan()).abs() < 1e-9);
    // Its curvature points inside the corner and is 1/R.
    assert!((fit.curvature.norm() - 1.0 / fit.radius).abs() < 1e-12);
    assert!(fit.curvature.y > 0.0);
    // Short moves are slower than long ones.
    let v_free = junction_cap(&m, a, b, Vec3::ZERO, Vec3::ZERO, f64::INFINITY);
    let v_fit = junction_cap(&m, a, b, Vec3::ZERO, Vec3::ZERO, 0.5);
    assert!(v_fit < v_free);
    assert!((v_fit - (m.jerk * m.period * fit.radius).sqrt()).abs() < 1e-9 * v_fit);
    // A reversal stops the machine.
    assert_eq!(junction_cap(&m, a, -a, Vec3::ZERO, Vec3::ZERO, 1.0), 0.0);
}

#[test]
fn a_circle_inside_the_chord_error_has_no_chord_error_cap() {
    // Regression (line-contouring-xz.ngc): a near-reversal transition of
    // radius 0.45 um was crawled at 2 um/s, capped by the chord error of a
    // circle smaller than the chord error itself.
    let m = MachineLimits::thesis();
    let tiny = circle_point(0.4 * m.chord_error);
    let (_, c) = speed_cap(&m, 1e9, &tiny);
    assert_ne!(c, Constraint::ChordError);
    // Just above half the chord error the cap applies, and is continuous
    // with the formula.
    let r = 0.6 * m.chord_error;
    let (v, _) = speed_cap(
        &MachineLimits {
            normal_acc: 1e30,
            jerk: 1e30,
            axis_acc: [1e30; 3],
            ..m
        },
        1e9,
        &circle_point(r),
    );
    let e = m.chord_error;
    assert!((v - 2.0 / m.period * (2.0 * r * e - e * e).sqrt()).abs() < 1e-9);
}

/// The thesis' time model (seed 003, eq. 4-1): without the jerk caps on
/// curves, a circle of 2 mm (centripetal jerk cap 43.1 mm/s, below the
/// centripetal acceleration's 89.4 mm/s) and a clothoid point (curvature
/// change) are capped by `sqrt(A / kappa)` alone.
#[test]
fn the_thesis_model_caps_curves_by_centripetal_acceleration_only() {
    let full = MachineLimits::thesis();
    let thesis = MachineLimits {
        jerk_on_curves: false,
        ..full
    };
    let circle = circle_point(2.0);
    let (v, c) = speed_cap(&full, 400.0, &circle);
    assert_eq!(c, Constraint::NormalJerk);
    assert!((v - (20000.0f64 * 4.0).cbrt()).abs() < 1e-9, "{v}");
    let (v, c) = speed_cap(&thesis, 400.0, &circle);
    assert_eq!(c, Constraint::NormalAcceleration);
    assert!((v - (4000.0f64 * 2.0).sqrt()).abs() < 1e-9, "{v}");
    let clothoid = PathPoint {
        dkappa_ds: 100.0,
        ..circle_point(20.0)
    };
    assert_eq!(
        speed_cap(&full, 1e9, &clothoid).1,
        Constraint::CurvatureChange
    );
    let (v, c) = speed_cap(&thesis, 1e9, &clothoid);
    assert_eq!(c, Constraint::NormalAcceleration);
    assert!((v - (4000.0f64 * 20.0).sqrt()).abs() < 1e-9, "{v}");
}
