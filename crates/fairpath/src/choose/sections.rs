//! The sections of `auto` (see [`super::auto`]): a run cut at the middle
//! of its long lines, each section smoothed by its own fastest candidate.

use super::auto::Auto;
use super::candidates::{is_corner_method, is_fair};
use crate::geom::{classify_joint, Continuity, JointTolerances};
use crate::geom::{Curve, Line, ParamCurve, Vec3};
use crate::path::{Piece, Run};
use crate::smooth::{RunMemo, SmoothError, SmoothedRun};
use alloc::collections::BTreeMap;
use alloc::vec::Vec;

/// Default [`super::AutoOptions::section_lines`] (mm): a run is cut at the lines
/// longer than 5 mm, then at those longer than 3 mm, then 1 mm, and the
/// fastest of the three mixes (or the whole run) is kept. Long lines cut
/// sections whose best candidates differ (a raster's passes and its
/// step-overs); shorter cuts give short features their own choices. The
/// sections the lengths share are smoothed once.
pub const SECTION_LINES: [f64; 3] = [5.0, 3.0, 1.0];

/// Largest run (pieces) that is also smoothed section by section: the
/// sections are smoothed and planned besides the whole run (the mix is kept
/// only when the whole run plans faster with it), which doubles the work.
pub const SECTION_MAX_PIECES: usize = 20_000;

/// The section a [`SectionCache`] entry was smoothed for: its pieces and
/// whether each end is a cut line.
type Section = (Run, bool, bool);

/// Where a section is looked up first: its first and last points (f64
/// bits) and its piece count.
type SectionKey = ([u64; 3], [u64; 3], usize);

/// Which candidates a section mix takes each section's fastest among.
///
/// Each section's choice is planned from rest to rest and the mix as one
/// run, so a candidate that wins its section can make the mix slower than
/// one of fewer candidates. The mixes of fewer candidates stay
/// available: each is kept only where it plans faster than the whole run
/// and every other mix, so offering a candidate cannot make `auto` slower
/// by its objective.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Mix {
    /// Every candidate offered.
    All,
    /// All but `fair` (which may also leave a cut joint not G2); tried
    /// where a mix chose `fair` somewhere or failed.
    WithoutFair,
    /// The fits only: neither `fair` nor the corner methods, whose
    /// transitions win a section planned from rest to rest and can slow
    /// the mix (`Cereal.ngc`, `lotm`: docs/methods.md). Tried where a mix
    /// with a corner method was kept as the fastest so far.
    FitsOnly,
}

/// The mixes, in the order they are tried.
pub(super) const MIXES: [Mix; 3] = [Mix::All, Mix::WithoutFair, Mix::FitsOnly];

impl Mix {
    /// Whether the candidate named `name` takes part in this mix.
    pub(super) fn admits(self, name: &str) -> bool {
        match self {
            Mix::All => true,
            Mix::WithoutFair => !is_fair(name),
            Mix::FitsOnly => !is_fair(name) && !is_corner_method(name),
        }
    }
}

/// The candidate kept for a section in each of [`MIXES`] (`None`: none
/// met its cut lines G2).
type Choices = [Option<SmoothedRun>; 3];

/// Sections already smoothed, with the candidates kept for each
/// ([`Choices`]). `auto` cuts a run at several line lengths
/// ([`SECTION_LINES`]); a section between two long lines is
/// the same at every length and is smoothed once.
#[derive(Default)]
pub(super) struct SectionCache {
    /// By [`SectionKey`], then the sections themselves, compared in full.
    entries: BTreeMap<SectionKey, Vec<(Section, Choices)>>,
}

fn point_bits(p: Vec3) -> [u64; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

impl SectionCache {
    fn key(run: &Run) -> SectionKey {
        let first = run.pieces.first().map_or(Vec3::ZERO, |p| p.curve.start());
        let last = run.pieces.last().map_or(Vec3::ZERO, |p| p.curve.end());
        (point_bits(first), point_bits(last), run.pieces.len())
    }

    /// The choices for `run` with cut lines at its start and end as
    /// `cut_ends` says, if it was smoothed (compared in full; nothing is
    /// copied to look it up).
    fn get(&self, run: &Run, cut_ends: (bool, bool)) -> Option<&Choices> {
        self.entries
            .get(&Self::key(run))?
            .iter()
            .find(|((r, a, b), _)| (*a, *b) == cut_ends && r == run)
            .map(|(_, best)| best)
    }

    fn insert(&mut self, section: Section, best: Choices) {
        self.entries
            .entry(Self::key(&section.0))
            .or_default()
            .push((section, best));
    }
}

impl Auto {
    /// `run` smoothed section by section (see [`split_at_long_lines`]), the
    /// fastest candidate kept in each section among those that meet the
    /// cut lines G2 and that `mix` admits ([`Mix`]); `None` when some
    /// section has no such candidate or a cut joint is not G2 (the caller
    /// then chooses for the whole run). Sections found in `cache` are not
    /// smoothed again, and fits and fairings found in `memo` not made again.
    pub(super) fn smooth_sections(
        &self,
        sections: &[(Run, Option<Vec3>, Option<Vec3>)],
        tolerance: f64,
        (cache, memo): (&mut SectionCache, &RunMemo),
        mix: Mix,
    ) -> Result<Option<SmoothedRun>, SmoothError> {
        let jt = JointTolerances::from_tolerance(tolerance);
        let mut out = SmoothedRun::default();
        for (run, before, after) in sections {
            let cut_ends = (before.is_some(), after.is_some());
            if cache.get(run, cut_ends).is_none() {
                let best = self.best_for_section(run, (*before, *after), tolerance, jt, memo)?;
                cache.insert((run.clone(), cut_ends.0, cut_ends.1), best);
            }
            let Some(best) = cache
                .get(run, cut_ends)
                .and_then(|c| c[mix as usize].as_ref())
            else {
                return Ok(None);
            };
            if let (Some(prev), Some(next)) = (out.pieces.last(), best.pieces.first()) {
                if classify_joint(&prev.curve, &next.curve, &jt) != Continuity::G2 {
                    return Ok(None);
                }
            }
            out.append(best);
        }
        Ok(Some(out))
    }

    /// The fastest candidate for one section that meets its cut lines
    /// (directions `before`, `after`) G2, among those each of [`MIXES`]
    /// admits ([`Choices`]).
    fn best_for_section(
        &self,
        run: &Run,
        (before, after): (Option<Vec3>, Option<Vec3>),
        tolerance: f64,
        jt: JointTolerances,
        memo: &RunMemo,
    ) -> Result<Choices, SmoothError> {
        let cut_ends = (before.is_some(), after.is_some());
        let (mut ranking, _) = self.ranked_candidates(run, tolerance, cut_ends, memo)?;
        let eligible = |c: &SmoothedRun| meets_cut_lines(c, (before, after), jt);
        let chosen = MIXES
            .map(|mix| ranking.cheapest(|c| c.chosen.iter().all(|n| mix.admits(n)) && eligible(c)));
        Ok(chosen.map(|i| i.map(|i| ranking.cands[i].clone())))
    }
}

/// Whether `c` meets the cut lines before and after it (their directions,
/// `None` where it is not cut there) G2: tangent along them, without
/// curvature.
pub(super) fn meets_cut_lines(
    c: &SmoothedRun,
    (before, after): (Option<Vec3>, Option<Vec3>),
    jt: JointTolerances,
) -> bool {
    let (Some(first), Some(last)) = (c.pieces.first(), c.pieces.last()) else {
        return false;
    };
    let starts_straight = before.is_none_or(|d| {
        let p = first.curve.start();
        let line = Curve::Line(Line::new(p - d, p));
        classify_joint(&line, &first.curve, &jt) == Continuity::G2
    });
    let ends_straight = after.is_none_or(|d| {
        let p = last.curve.end();
        let line = Curve::Line(Line::new(p, p + d));
        classify_joint(&last.curve, &line, &jt) == Continuity::G2
    });
    starts_straight && ends_straight
}

/// `run` cut at the middle of every line longer than `min_line` into
/// sections, each with the direction (scaled to half the cut line) of the
/// line it starts on (`None` for the first) and ends on (`None` for the
/// last).
pub fn split_at_long_lines(run: &Run, min_line: f64) -> Vec<(Run, Option<Vec3>, Option<Vec3>)> {
    let mut out = Vec::new();
    let mut current: Vec<Piece> = Vec::new();
    let mut before = None;
    for p in &run.pieces {
        if let Curve::Line(l) = &p.curve {
            if l.p0.dist(l.p1) > min_line {
                let mid = l.p0.lerp(l.p1, 0.5);
                let half = mid - l.p0;
                let mut a = p.clone();
                a.curve = Curve::Line(Line::new(l.p0, mid));
                current.push(a);
                out.push((Run::new(core::mem::take(&mut current)), before, Some(half)));
                before = Some(half);
                let mut b = p.clone();
                b.curve = Curve::Line(Line::new(mid, l.p1));
                current.push(b);
                continue;
            }
        }
        current.push(p.clone());
    }
    out.push((Run::new(current), before, None));
    out
}

#[cfg(test)]
mod tests {
    use super::super::candidates::{
        CANDIDATES, CURVES_AS_WRITTEN, FAIR, FAIR_STRAIGHTENED, FAIR_THROUGH_SHALLOW,
    };
    use super::*;

    /// Each mix admits what its name says, the fits every mix, and a
    /// mix's index is its place among the choices ([`Choices`]).
    #[test]
    fn each_mix_admits_its_candidates() {
        for (k, mix) in MIXES.iter().enumerate() {
            assert_eq!(*mix as usize, k);
        }
        for row in CANDIDATES.iter() {
            let n = row.name;
            let fair = n == FAIR || n == FAIR_THROUGH_SHALLOW || n == FAIR_STRAIGHTENED;
            let corner =
                matches!(n, "bspline-corner" | "lotm" | "ctm") || CURVES_AS_WRITTEN.contains(&n);
            assert!(Mix::All.admits(n), "{n}");
            assert_eq!(Mix::WithoutFair.admits(n), !fair, "{n}");
            assert_eq!(Mix::FitsOnly.admits(n), !fair && !corner, "{n}");
            if n.starts_with("bspline-fit") {
                assert!(MIXES.iter().all(|m| m.admits(n)), "{n}");
            }
        }
    }
}
