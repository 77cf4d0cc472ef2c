//! What the smoothings of one run share: the section fits and the tube
//! fairings already made, each made once.
//!
//! `auto` smooths a run with several candidates side by side, and its
//! sections and fallback smooth parts of it again; `fair` itself fairs a
//! run's curves once per alternative it weighs. Where two of them fit the
//! same section or fair the same curve with the same options, the second
//! takes the first's result: [`fit_polyline_faired`] and [`fair_in_tube`]
//! are pure functions of their arguments, so what the memo gives is what
//! the call would make, bit for bit. A call that another thread is making
//! waits for it instead of making it again (a program's spline run had its
//! peak pass made four times over by `auto`'s two `fair` candidates and its
//! fallback, at the same time on two cores). Without `std` the memo keeps
//! nothing (the candidates then run one after the other, and no lock is at
//! hand).

use super::fit_fairing::{fit_polyline_faired, SectionFit};
use crate::geom::band_fit::RelaxOptions;
use crate::geom::fit::EndCondition;
use crate::geom::tube_fair::{fair_in_tube, Faired, TubeFairError, TubeFairOptions};
use crate::geom::{Nurbs, Vec3};
#[cfg(feature = "std")]
use alloc::{collections::BTreeMap, sync::Arc, vec::Vec};

/// Fits and fairings already made for one run (see the module
/// documentation).
#[derive(Default)]
pub struct RunMemo {
    #[cfg(feature = "std")]
    fits: Table<FitKey, Option<SectionFit>>,
    #[cfg(feature = "std")]
    fairings: Table<FairKey, Result<Faired, TubeFairError>>,
}

impl core::fmt::Debug for RunMemo {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let mut d = f.debug_struct("RunMemo");
        #[cfg(feature = "std")]
        d.field("fits", &self.fits.len())
            .field("fairings", &self.fairings.len());
        d.finish()
    }
}

impl RunMemo {
    /// [`fit_polyline_faired`] with these arguments, from the memo when it
    /// was made before.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn fit(
        &self,
        pts: &[Vec3],
        start: EndCondition,
        end: EndCondition,
        target: f64,
        weights: (f64, f64),
        raises: usize,
        relax: Option<&RelaxOptions>,
    ) -> Option<SectionFit> {
        let make = || fit_polyline_faired(pts, start, end, target, weights, raises, relax);
        #[cfg(feature = "std")]
        {
            let key = FitKey {
                pts: pts.iter().map(|&p| vec_bits(p)).collect(),
                ends: [end_bits(start), end_bits(end)],
                numbers: [target.to_bits(), weights.0.to_bits(), weights.1.to_bits()],
                raises,
                relax: relax.copied(),
            };
            let slot = (key.pts.len(), key.pts.first().copied().unwrap_or_default());
            self.fits.get_or_make(slot, key, make)
        }
        #[cfg(not(feature = "std"))]
        make()
    }

    /// [`fair_in_tube`] of `curve` with `opts`, from the memo when it was
    /// made before.
    pub(super) fn fair_in_tube(
        &self,
        curve: &Nurbs,
        opts: &TubeFairOptions,
    ) -> Result<Faired, TubeFairError> {
        let make = || fair_in_tube(curve, opts);
        #[cfg(feature = "std")]
        {
            let key = FairKey {
                degree: curve.degree,
                knots: curve.knots.iter().map(|x| x.to_bits()).collect(),
                points: curve.points.iter().map(|&p| vec_bits(p)).collect(),
                weights: (curve.weights.as_ref()).map(|w| w.iter().map(|x| x.to_bits()).collect()),
                opts: *opts,
            };
            let slot = (
                key.points.len(),
                key.points.first().copied().unwrap_or_default(),
            );
            self.fairings.get_or_make(slot, key, make)
        }
        #[cfg(not(feature = "std"))]
        make()
    }
}

#[cfg(all(test, feature = "std"))]
impl RunMemo {
    /// How many fairings it holds.
    pub(super) fn fairings_held(&self) -> usize {
        self.fairings.len()
    }
}

/// What a fit of [`fit_polyline_faired`] depends on, every number by its
/// bits: the points, the end conditions, the target, the weights, the
/// raises and the relaxation.
#[cfg(feature = "std")]
#[derive(Clone, Debug, PartialEq)]
struct FitKey {
    pts: Vec<[u64; 3]>,
    ends: [Option<[u64; 3]>; 2],
    numbers: [u64; 3],
    raises: usize,
    relax: Option<RelaxOptions>,
}

/// What a fairing of [`fair_in_tube`] depends on: the curve, every number
/// by its bits, and the options (valid options hold no NaN, so `==` tells
/// them apart; an invalid one is an error made again).
#[cfg(feature = "std")]
#[derive(Clone, Debug, PartialEq)]
struct FairKey {
    degree: usize,
    knots: Vec<u64>,
    points: Vec<[u64; 3]>,
    weights: Option<Vec<u64>>,
    opts: TubeFairOptions,
}

#[cfg(feature = "std")]
fn vec_bits(p: Vec3) -> [u64; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

#[cfg(feature = "std")]
fn end_bits(e: EndCondition) -> Option<[u64; 3]> {
    match e {
        EndCondition::Free => None,
        EndCondition::Tangent(d) => Some(vec_bits(d)),
    }
}

/// Where an entry is looked up first: the points' count and the first
/// point's bits; then the keys in full.
#[cfg(feature = "std")]
type Slot = (usize, [u64; 3]);

/// Results by key, each made once: the first caller of a key makes it,
/// later callers (on any thread) wait for it and take a copy.
#[cfg(feature = "std")]
#[allow(clippy::type_complexity)]
struct Table<K, V> {
    entries: std::sync::Mutex<BTreeMap<Slot, Vec<(K, Arc<std::sync::OnceLock<V>>)>>>,
}

#[cfg(feature = "std")]
impl<K, V> Default for Table<K, V> {
    fn default() -> Self {
        Table {
            entries: std::sync::Mutex::new(BTreeMap::new()),
        }
    }
}

#[cfg(feature = "std")]
impl<K: PartialEq, V: Clone> Table<K, V> {
    /// The value of `key` (looked up under `slot`), made by `make` if no
    /// caller has made it or is making it.
    fn get_or_make(&self, slot: Slot, key: K, make: impl FnOnce() -> V) -> V {
        let cell = {
            let mut entries = self.entries.lock().unwrap_or_else(|e| e.into_inner());
            let list = entries.entry(slot).or_default();
            match list.iter().find(|(k, _)| *k == key) {
                Some((_, cell)) => Arc::clone(cell),
                None => {
                    let cell = Arc::new(std::sync::OnceLock::new());
                    list.push((key, Arc::clone(&cell)));
                    cell
                }
            }
        };
        // Made outside the table's lock: other keys go on meanwhile.
        cell.get_or_init(make).clone()
    }

    /// How many keys it holds.
    fn len(&self) -> usize {
        let entries = self.entries.lock().unwrap_or_else(|e| e.into_inner());
        entries.values().map(Vec::len).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::tube_fair::PeakPass;
    use alloc::vec::Vec;

    /// A wavy polyline of 0.2 mm steps.
    fn wave(n: usize, amp: f64) -> Vec<Vec3> {
        (0..n)
            .map(|i| {
                let x = 0.2 * i as f64;
                Vec3::new(x, amp * libm::sin(x), 0.0)
            })
            .collect()
    }

    /// The memo gives what the fit gives, on a hit as on a miss, and keeps
    /// fits whose arguments differ in one number apart.
    #[test]
    fn the_memo_gives_the_fit_and_tells_arguments_apart() {
        let memo = RunMemo::default();
        let relax = RelaxOptions::default();
        let pts = wave(40, 0.3);
        let d = EndCondition::Tangent(Vec3::new(1.0, 0.0, 0.0));
        let free = EndCondition::Free;
        let cases = [
            (free, free, 0.045, (1.0, 0.0), 6, Some(&relax)),
            (d, free, 0.045, (1.0, 0.0), 6, Some(&relax)),
            (free, free, 0.04, (1.0, 0.0), 6, Some(&relax)),
            (free, free, 0.045, (1.0, 3.0), 6, Some(&relax)),
            (free, free, 0.045, (1.0, 0.0), 0, None),
        ];
        for _ in 0..2 {
            for &(start, end, target, w, raises, relax) in &cases {
                let direct = fit_polyline_faired(&pts, start, end, target, w, raises, relax);
                assert!(direct.is_some());
                let memo_fit = memo.fit(&pts, start, end, target, w, raises, relax);
                assert_eq!(memo_fit, direct);
            }
        }
        // Other points (same count, same first point) are another fit.
        let other = wave(40, 0.2);
        let direct = fit_polyline_faired(&other, free, free, 0.045, (1.0, 0.0), 6, Some(&relax));
        let memo_fit = memo.fit(&other, free, free, 0.045, (1.0, 0.0), 6, Some(&relax));
        assert_eq!(memo_fit, direct);
        assert_eq!(memo.fits.len(), cases.len() + 1);
    }

    /// The memo gives what the fairing gives, on threads asking for the
    /// same curve at the same time as one after the other, made once per
    /// key; another radius, another peak pass or another curve is another
    /// fairing, and an error is remembered as an error.
    #[test]
    fn the_memo_gives_the_fairing_once_per_curve_and_options() {
        let memo = RunMemo::default();
        let fit = fit_polyline_faired(
            &wave(60, 0.4),
            EndCondition::Free,
            EndCondition::Free,
            0.01,
            (1.0, 0.0),
            0,
            None,
        )
        .expect("a fit");
        let curve = fit.curve;
        let mut other = curve.clone();
        other.points[5].y += 0.01;
        let base = TubeFairOptions::new(0.05);
        let options = [
            base,
            TubeFairOptions {
                radius: 0.02,
                ..base
            },
            TubeFairOptions {
                peak_pass: PeakPass::Curvature,
                ..base
            },
        ];
        for opts in &options {
            for c in [&curve, &other] {
                let direct = fair_in_tube(c, opts);
                assert!(direct.is_ok());
                let got: Vec<_> = std::thread::scope(|s| {
                    let hs: Vec<_> = (0..3)
                        .map(|_| s.spawn(|| memo.fair_in_tube(c, opts)))
                        .collect();
                    hs.into_iter().map(|h| h.join().unwrap()).collect()
                });
                for g in got {
                    assert_eq!(g, direct);
                }
                assert_eq!(memo.fair_in_tube(c, opts), direct);
            }
        }
        assert_eq!(memo.fairings.len(), options.len() * 2);
        let bad = TubeFairOptions {
            radius: -1.0,
            ..base
        };
        assert_eq!(memo.fair_in_tube(&curve, &bad), fair_in_tube(&curve, &bad));
        assert!(memo.fair_in_tube(&curve, &bad).is_err());
    }
}
