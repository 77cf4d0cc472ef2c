//! What CNC controllers do with the codes fairpath reads and writes, as pure
//! arithmetic (no I/O): so that a program can be read as a controller runs
//! it, and so that the deviation of what a controller will run for a block
//! fairpath is about to write can be measured before it is written.
//!
//! * [`linuxcnc`]: LinuxCNC's G5, G5.1 and G5.2/G5.3 splines: its knot
//!   vector, its NURBS evaluation and the biarcs its canon layer turns them
//!   into.

pub mod linuxcnc;

use crate::geom::Vec3;

/// A working plane (G17, G18, G19) with LinuxCNC's in-plane coordinate
/// order: the pair its spline code calls `(NURBS_X, NURBS_Y)` and its
/// `ARC_FEED` calls `(first, second)`: (X, Y) in G17, (Z, X) in G18,
/// (Y, Z) in G19. A counter-clockwise turn in that pair is a
/// counter-clockwise turn about [`Plane::normal`] (+Z, +Y, +X).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Plane {
    /// G17
    Xy,
    /// G18
    Zx,
    /// G19
    Yz,
}

impl Plane {
    /// Indices (0 = X, 1 = Y, 2 = Z) of the first and second in-plane axes
    /// and of the normal axis.
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::Xy => (0, 1, 2),
            Plane::Zx => (2, 0, 1),
            Plane::Yz => (1, 2, 0),
        }
    }

    /// Unit normal: a turn from the first in-plane axis towards the second
    /// is counter-clockwise about it.
    pub fn normal(self) -> Vec3 {
        match self {
            Plane::Xy => Vec3::Z,
            Plane::Zx => Vec3::Y,
            Plane::Yz => Vec3::X,
        }
    }

    /// The in-plane coordinates `(first, second)` of `p`.
    pub fn to_plane(self, p: Vec3) -> [f64; 2] {
        let (a, b, _) = self.axes();
        let c = p.to_array();
        [c[a], c[b]]
    }

    /// The coordinate of `p` along the normal axis.
    pub fn off_plane(self, p: Vec3) -> f64 {
        p.to_array()[self.axes().2]
    }

    /// The point with in-plane coordinates `ab` and normal coordinate `off`.
    pub fn from_plane(self, ab: [f64; 2], off: f64) -> Vec3 {
        let (a, b, n) = self.axes();
        let mut c = [0.0; 3];
        c[a] = ab[0];
        c[b] = ab[1];
        c[n] = off;
        Vec3::from_array(c)
    }

    /// The G word selecting the plane.
    pub fn gword(self) -> &'static str {
        match self {
            Plane::Xy => "G17",
            Plane::Zx => "G18",
            Plane::Yz => "G19",
        }
    }
}
