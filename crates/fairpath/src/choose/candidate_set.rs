//! A set of `auto`'s candidates (rows of [`CANDIDATES`]), named in an
//! options file as the summary names them: what
//! [`super::AutoOptions::leave_out`] leaves out.
//!
//! Why a user leaves candidates out: each is smoothed and costed on every
//! run it is offered on, so the set is what `auto`'s computing time is
//! made of; `scripts/auto-ablation.sh` measures what each one costs and
//! what it gains (`docs/auto-ablation.md`).

use super::candidates::{Offered, CANDIDATES};
use alloc::string::String;
use alloc::vec::Vec;

/// A set of rows of [`CANDIDATES`], by position.
#[derive(Clone, Copy, Default, PartialEq, Eq)]
pub struct CandidateSet(u32);

const _: () = assert!(CANDIDATES.len() <= 32, "a CandidateSet holds 32 rows");

impl CandidateSet {
    /// No candidate.
    pub const EMPTY: CandidateSet = CandidateSet(0);

    /// The rows named `names` (each a [`super::CandidateRow::name`]);
    /// the first name that no row has is the error.
    pub fn of_names<'a>(names: impl IntoIterator<Item = &'a str>) -> Result<Self, &'a str> {
        let mut bits = 0u32;
        for name in names {
            let i = CANDIDATES.iter().position(|r| r.name == name).ok_or(name)?;
            bits |= 1 << i;
        }
        Ok(CandidateSet(bits))
    }

    /// Whether the row at `index` of [`CANDIDATES`] is in the set.
    pub fn contains_row(self, index: usize) -> bool {
        index < 32 && (self.0 >> index) & 1 == 1
    }

    /// Whether the row named `name` is in the set (false for a name no row
    /// has).
    pub fn contains(self, name: &str) -> bool {
        CANDIDATES
            .iter()
            .position(|r| r.name == name)
            .is_some_and(|i| self.contains_row(i))
    }

    /// The names of the rows in the set, in the table's order.
    pub fn names(self) -> impl Iterator<Item = &'static str> {
        CANDIDATES
            .iter()
            .enumerate()
            .filter(move |(i, _)| self.contains_row(*i))
            .map(|(_, r)| r.name)
    }

    /// The row at `index` of [`CANDIDATES`] added to the set.
    pub fn insert_row(&mut self, index: usize) {
        assert!(index < CANDIDATES.len(), "no row {index}");
        self.0 |= 1 << index;
    }

    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The candidates offered on every run ([`Offered::Always`]).
    pub fn always_offered() -> CandidateSet {
        let bits = CANDIDATES
            .iter()
            .enumerate()
            .filter(|(_, r)| r.offered == Offered::Always)
            .fold(0u32, |b, (i, _)| b | 1 << i);
        CandidateSet(bits)
    }

    /// Whether the set holds every candidate offered on every run: left
    /// out, some run could have no candidate.
    pub fn holds_every_one_always_offered(self) -> bool {
        let always = CandidateSet::always_offered().0;
        self.0 & always == always
    }
}

impl core::fmt::Debug for CandidateSet {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_list().entries(self.names()).finish()
    }
}

/// The names of every candidate, for messages: `"a", "b", ...`.
pub fn candidate_names() -> String {
    let quoted: Vec<String> = CANDIDATES
        .iter()
        .map(|r| alloc::format!("{:?}", r.name))
        .collect();
    quoted.join(", ")
}

#[cfg(feature = "serde")]
impl serde::Serialize for CandidateSet {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.names())
    }
}

#[cfg(feature = "serde")]
impl<'de> serde::Deserialize<'de> for CandidateSet {
    /// A list of candidate names; an unknown name is an error that names
    /// it and lists the candidates.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let names: Vec<String> = Vec::deserialize(d)?;
        CandidateSet::of_names(names.iter().map(String::as_str)).map_err(|n| {
            <D::Error as serde::de::Error>::custom(alloc::format!(
                "unknown candidate {n:?}; auto's candidates are {}",
                candidate_names()
            ))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_map_to_rows_and_back() {
        let s = CandidateSet::of_names(["lotm", "fair"]).unwrap();
        assert!(s.contains("lotm") && s.contains("fair"));
        assert!(!s.contains("bspline-fit") && !s.contains("no such candidate"));
        // In the table's order, whatever the order given.
        let names: Vec<&str> = s.names().collect();
        assert_eq!(names, ["lotm", "fair"]);
        assert_eq!(CandidateSet::of_names(["lotm", "nope"]), Err("nope"));
        assert!(CandidateSet::EMPTY.is_empty() && CandidateSet::default().is_empty());
        let every: Vec<&str> = CANDIDATES.iter().map(|r| r.name).collect();
        let all = CandidateSet::of_names(every.iter().copied()).unwrap();
        assert_eq!(all.names().count(), CANDIDATES.len());
    }

    #[test]
    fn the_candidates_offered_on_every_run_cannot_all_be_left_out() {
        let always: Vec<&str> = CandidateSet::always_offered().names().collect();
        assert!(!always.is_empty());
        let all_always = CandidateSet::of_names(always.iter().copied()).unwrap();
        assert!(all_always.holds_every_one_always_offered());
        let but_one = CandidateSet::of_names(always[1..].iter().copied()).unwrap();
        assert!(!but_one.holds_every_one_always_offered());
    }
}
