//! The control polygon as the method walks it: open, with two ends, or
//! closed, where indices wrap round the seam (thesis section 5.1.1: "the
//! algorithm would simply look at the other end of the array for the
//! points preceding it").
//!
//! A closed path comes as a clamped cubic whose first and last control
//! points are the same point (the seam, where the run starts and ends).
//! Its ring is the first `m - 1` control points: the seam is ring point 0,
//! its neighbours are ring points 1 and `m - 2`, and the last control point
//! follows the seam (which never moves, see [`super::EndRule`]).

/// Layout of the ring of control points the categories and directions
/// are computed on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Polygon {
    /// Points in the ring: all `m` control points of an open curve, the
    /// first `m - 1` of a closed one.
    pub n: usize,
    /// Whether indices wrap round the seam.
    pub closed: bool,
}

impl Polygon {
    /// The layout of `m` control points, closed or not.
    pub fn new(m: usize, closed: bool) -> Polygon {
        Polygon {
            n: if closed { m - 1 } else { m },
            closed,
        }
    }

    /// Ring index `i + k`: wrapped on a closed polygon, `None` past an open
    /// polygon's ends.
    pub fn at(&self, i: usize, k: isize) -> Option<usize> {
        let n = self.n as isize;
        let j = i as isize + k;
        if self.closed {
            Some(j.rem_euclid(n) as usize)
        } else if (0..n).contains(&j) {
            Some(j as usize)
        } else {
            None
        }
    }

    /// Whether ring point `i` is an end: the first and last point of an
    /// open polygon, the seam (ring point 0) of a closed one. Ends never
    /// move and belong to no smooth group.
    pub fn is_end(&self, i: usize) -> bool {
        i == 0 || (!self.closed && i + 1 == self.n)
    }

    /// The two end legs as (end point, its neighbour): ring points (0, 1)
    /// and (n-1, n-2) open, (0, 1) and (0, n-1) closed.
    pub fn end_legs(&self) -> [(usize, usize); 2] {
        if self.closed {
            [(0, 1), (0, self.n - 1)]
        } else {
            [(0, 1), (self.n - 1, self.n - 2)]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_and_closed_indices() {
        let open = Polygon::new(6, false);
        assert_eq!(open.at(1, -2), None);
        assert_eq!(open.at(3, 2), Some(5));
        assert_eq!(open.at(4, 2), None);
        assert!(open.is_end(0) && open.is_end(5) && !open.is_end(4));
        let closed = Polygon::new(7, true);
        assert_eq!(closed.n, 6);
        assert_eq!(closed.at(1, -2), Some(5));
        assert_eq!(closed.at(5, 2), Some(1));
        assert!(closed.is_end(0) && !closed.is_end(5));
        assert_eq!(closed.end_legs(), [(0, 1), (0, 5)]);
    }
}
