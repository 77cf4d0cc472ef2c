//! `Arc::chord_params`: evenly spaced chords of an arc (circular, helical
//! or spiral, as G2/G3 and rounded coordinates make them) within the
//! chord asked, both ways, and not many more than a circle needs.

use fairpath::geom::{point_segment_distance, Arc, ParamCurve, Vec3};
use proptest::prelude::*;

/// An arc about the Z axis through the origin from angle `a0`, of radius
/// `r` at the start, turning `sweep`, ending at radius `r * (1 + spread)`
/// and `rise` higher.
fn arc(r: f64, a0: f64, sweep: f64, spread: f64, rise: f64, cw: bool) -> Arc {
    let a1 = if cw { a0 - sweep } else { a0 + sweep };
    let r1 = r * (1.0 + spread);
    let start = Vec3::new(r * a0.cos(), r * a0.sin(), 0.0);
    let end = Vec3::new(r1 * a1.cos(), r1 * a1.sin(), rise);
    Arc::from_center(start, end, Vec3::ZERO, Vec3::Z, cw, 1, 1e-12).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Every point of the arc is within `chord` of the chord at the same
    /// parameter (so of the polyline, and every chord point of the arc).
    #[test]
    fn chords_are_within_the_chord_of_the_arc(
        r in 0.01f64..500.0,
        a0 in -3.2f64..3.2,
        sweep in 0.01f64..6.2,
        spread in prop_oneof![Just(0.0), -1e-3f64..1e-3, -0.5f64..0.5],
        rise in prop_oneof![Just(0.0), -20.0f64..20.0],
        cw in any::<bool>(),
        chord_exp in -7.0f64..-1.0,
    ) {
        let a = arc(r, a0, sweep, spread, rise, cw);
        let chord = 10f64.powf(chord_exp);
        let Some(ts) = a.chord_params(chord, 1 << 20) else {
            // Only where the snapped ends leave no room, or too many chords.
            let n = (a.second_derivative_bound() / (8.0 * chord)).sqrt();
            prop_assert!(n > (1 << 19) as f64, "refused with {n} chords");
            return Ok(());
        };
        prop_assert_eq!(ts[0], 0.0);
        prop_assert_eq!(*ts.last().unwrap(), 1.0);
        for w in ts.windows(2) {
            let (p0, p1) = (a.eval(w[0]), a.eval(w[1]));
            for k in 0..=16 {
                let s = k as f64 / 16.0;
                let q = a.eval(w[0] + s * (w[1] - w[0]));
                let lerp = p0.lerp(p1, s);
                let slack = 1e-12 * (r * (1.0 + spread.abs()) + rise.abs());
                prop_assert!(
                    q.dist(lerp) <= chord + slack,
                    "{} from the chord at {}", q.dist(lerp), chord
                );
                prop_assert!(point_segment_distance(q, p0, p1) <= chord + slack);
            }
        }
    }
}

/// On a circle, about as many chords as the sagitta needs, `sweep / (2
/// acos(1 - chord / r))`: the bound of `C''` is exact there.
#[test]
fn a_circle_gets_about_the_chords_its_sagitta_needs() {
    for (r, sweep, chord) in [(10.0, 6.0, 5e-6), (0.5, 1.0, 1e-3), (200.0, 0.1, 1e-4)] {
        let a = arc(r, 0.3, sweep, 0.0, 0.0, false);
        let n = a.chord_params(chord, 1 << 20).unwrap().len() - 1;
        let needed = (sweep / (2.0 * (1.0 - chord / r).acos())).ceil() as usize;
        assert!(
            n >= needed && n <= needed + 1,
            "{n} chords, {needed} needed"
        );
    }
}
