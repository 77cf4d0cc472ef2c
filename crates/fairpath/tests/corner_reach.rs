//! Every corner is reached: a corner transition's apex lies within
//! `CORNER_REACH_SHARE` tolerances of its corner point however sharp the
//! corner, so the tip of a spike or of a V-carve's stroke is cut by at
//! most that (one-sidedly, a transition within the band of its two moves
//! may turn back anywhere the moves are closer than twice the band, a
//! whole move short of a spike's tip).

use crate::common::{polyline_run, v};
use fairpath::budget::CORNER_REACH_SHARE;
use fairpath::choose::{Auto, OUTER_CORNERS};
use fairpath::geom::Vec3;
use fairpath::path::{Piece, Run};
use fairpath::smooth::{BsplineCorner, BsplineFit, Ctm, Fair, Lotm, Smoother};
use fairpath::verify::{follows_in_order, verify_run, VerifyOptions};
use proptest::prelude::*;

/// Whether `path` passes within the reach of `tol` of every inner vertex
/// of `run`, in order.
fn reaches_every_corner(run: &Run, path: &[Piece], tol: f64) -> bool {
    let gates: Vec<(Vec3, f64)> = run.pieces[..run.pieces.len() - 1]
        .iter()
        .map(|p| (p.end(), CORNER_REACH_SHARE * tol))
        .collect();
    follows_in_order(path, &gates, 1e-3 * tol)
}

fn methods() -> Vec<(&'static str, Box<dyn Smoother>)> {
    vec![
        ("bspline-corner", Box::new(BsplineCorner::default())),
        ("lotm", Box::new(Lotm::default())),
        ("ctm", Box::new(Ctm::default())),
        ("bspline-fit", Box::new(BsplineFit::default())),
        ("fair", Box::new(Fair::default())),
        ("auto", Box::new(Auto::default())),
    ]
}

/// Two 10 mm moves that turn by `turn_deg` degrees.
fn corner(turn_deg: f64) -> Run {
    let a = turn_deg.to_radians();
    polyline_run(&[
        v(0.0, 0.0, 0.0),
        v(10.0, 0.0, 0.0),
        v(10.0 + 10.0 * a.cos(), 10.0 * a.sin(), 0.0),
    ])
}

/// Every method at 0.05 mm, turns from 100 to 179.9 degrees: within the
/// tolerance and through the corner's reach. Before the reach,
/// `bspline-corner` cut a 160-degree corner's tip by 0.28 mm and a
/// 179.5-degree one's by 2.5 mm (`auto` 4.9 mm), inside the band all
/// the same.
#[test]
fn every_method_reaches_the_tip_of_a_sharp_corner() {
    let tol = 0.05;
    for turn in [
        100.0, 120.0, 150.0, 160.0, 170.0, 175.0, 179.0, 179.5, 179.9,
    ] {
        let run = corner(turn);
        for (name, m) in methods() {
            let out = m.smooth_run(&run, tol).unwrap();
            let rep = verify_run(&run.pieces, &out.pieces, &VerifyOptions::new(tol));
            assert!(rep.within(tol), "{name} at {turn} degrees");
            assert!(
                reaches_every_corner(&run, &out.pieces, tol),
                "{name} at {turn} degrees does not reach the corner"
            );
        }
    }
}

/// Regression, a V-carve engraving (`random-programs.py` seed 9711,
/// `r013_engrave.ngc`, lines 15 to 29 of its fourth part): a stroke of
/// 0.25 mm moves at depth, a spur up to the surface at a letter's corner
/// and back down the same line. `auto`'s outer-edge candidate moved the
/// spur's foot outward on the way up and on the way down, so on its guide
/// the tip was no longer a reversal but a corner of about 176 degrees,
/// blended in the raised band: the path turned back 0.225 mm short of
/// the tip, within 0.05 mm of the spur all the same. Twenty-seven of
/// the program's 33 tips were cut so.
#[test]
fn regression_r013_engrave_the_outer_edges_reach_a_v_tip() {
    let tol = 0.05;
    let d = -1.246;
    let run = polyline_run(&[
        v(45.343, 2.206, d),
        v(45.052, 2.182, d),
        v(44.781, 2.194, d),
        v(44.532, 2.242, d),
        v(44.303, 2.326, d),
        v(44.094, 2.445, d),
        v(43.906, 2.601, d),
        v(43.739, 2.792, d),
        v(43.593, 3.02, d),
        v(43.467, 3.284, d),
        v(43.361, 3.583, d),
        v(44.203, 4.503, 0.0),
        v(43.361, 3.583, d),
        v(43.133, 3.641, d),
        v(42.905, 3.699, d),
        v(42.677, 3.757, d),
        v(42.449, 3.815, d),
    ]);
    let all = Auto::default().candidates(&run, tol).unwrap();
    let (_, outer) = all.iter().find(|(n, _)| *n == OUTER_CORNERS).unwrap();
    let rep = verify_run(&run.pieces, &outer.pieces, &VerifyOptions::new(tol));
    assert!(rep.within(tol));
    assert!(reaches_every_corner(&run, &outer.pieces, tol));
    let out = Auto::default().smooth_run(&run, tol).unwrap();
    assert!(reaches_every_corner(&run, &out.pieces, tol));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random zigzags whose corners turn by 60 to 179.9 degrees, moves of
    /// 0.05 to 10 mm: every corner method and `auto`'s outer-edge
    /// candidate pass every vertex within its reach, in order.
    #[test]
    fn the_corner_methods_reach_every_corner(
        legs in prop::collection::vec((0.05f64..10.0, 60.0f64..179.9, any::<bool>()), 2..8),
        tol in 0.01f64..0.2,
    ) {
        let mut pts = vec![v(0.0, 0.0, 0.0)];
        let mut heading = 0.0f64;
        for &(len, turn, left) in &legs {
            let p = *pts.last().unwrap();
            pts.push(p + v(heading.cos(), heading.sin(), 0.0) * len);
            heading += if left { turn } else { -turn }.to_radians();
        }
        let p = *pts.last().unwrap();
        pts.push(p + v(heading.cos(), heading.sin(), 0.0) * 5.0);
        let run = polyline_run(&pts);
        for (name, m) in methods().into_iter().take(3) {
            let out = m.smooth_run(&run, tol).unwrap();
            prop_assert!(reaches_every_corner(&run, &out.pieces, tol), "{}", name);
        }
        let all = Auto::default().candidates(&run, tol).unwrap();
        if let Some((_, outer)) = all.iter().find(|(n, _)| *n == OUTER_CORNERS) {
            prop_assert!(reaches_every_corner(&run, &outer.pieces, tol));
        }
    }
}
