//! The three principal planes in which G-code writes arcs.

use super::Vec3;

/// A principal plane of G2/G3 arcs, with the local coordinates `(a, b, h)`
/// in which an arc turning counter-clockwise (G3) turns from `a` towards
/// `b`, and `h` runs along the plane's normal (the helical axis).
///
/// | plane | G word | `(a, b)` | normal `h` |
/// |---|---|---|---|
/// | [`Plane::Xy`] | G17 | (X, Y) | +Z |
/// | [`Plane::Zx`] | G18 | (Z, X) | +Y |
/// | [`Plane::Yz`] | G19 | (Y, Z) | +X |
///
/// The same pairs as LinuxCNC's `ARC_FEED` `(first, second)` and its spline
/// code's `(NURBS_X, NURBS_Y)`.
///
/// (RS274/NGC, section 3.5.3: G2 is clockwise seen from the positive end
/// of the normal axis, so each `(a, b, h)` is right-handed.)
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
    /// All three, in G17, G18, G19 order.
    pub const ALL: [Plane; 3] = [Plane::Xy, Plane::Zx, Plane::Yz];

    /// Unit normal (the positive helical axis): a turn from the first
    /// in-plane axis towards the second is counter-clockwise about it.
    pub fn normal(self) -> Vec3 {
        match self {
            Plane::Xy => Vec3::Z,
            Plane::Zx => Vec3::Y,
            Plane::Yz => Vec3::X,
        }
    }

    /// The G word selecting the plane.
    pub fn gword(self) -> &'static str {
        match self {
            Plane::Xy => "G17",
            Plane::Zx => "G18",
            Plane::Yz => "G19",
        }
    }

    /// Indices (0 = X, 1 = Y, 2 = Z) of the axes `a`, `b` and `h`.
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::Xy => (0, 1, 2),
            Plane::Zx => (2, 0, 1),
            Plane::Yz => (1, 2, 0),
        }
    }

    /// Local coordinates `(a, b, h)` of `p`.
    pub fn local(self, p: Vec3) -> [f64; 3] {
        let c = p.to_array();
        let (a, b, h) = self.axes();
        [c[a], c[b], c[h]]
    }

    /// The point with local coordinates `(a, b, h)`.
    pub fn point(self, l: [f64; 3]) -> Vec3 {
        let mut c = [0.0; 3];
        let (a, b, h) = self.axes();
        c[a] = l[0];
        c[b] = l[1];
        c[h] = l[2];
        Vec3::from_array(c)
    }

    /// The in-plane coordinates `(a, b)` of `p`.
    pub fn to_plane(self, p: Vec3) -> [f64; 2] {
        let l = self.local(p);
        [l[0], l[1]]
    }

    /// The coordinate of `p` along the normal axis.
    pub fn off_plane(self, p: Vec3) -> f64 {
        self.local(p)[2]
    }

    /// The point with in-plane coordinates `ab` and normal coordinate `off`.
    pub fn from_plane(self, ab: [f64; 2], off: f64) -> Vec3 {
        self.point([ab[0], ab[1], off])
    }

    /// The plane `points` lie in (their coordinate along its normal varies
    /// by at most `tol` mm), G17 first.
    pub fn of_points(points: &[Vec3], tol: f64) -> Option<Plane> {
        Plane::ALL.into_iter().find(|pl| {
            let h0 = points.first().map_or(0.0, |p| pl.off_plane(*p));
            points
                .iter()
                .all(|p| crate::math::abs(pl.off_plane(*p) - h0) <= tol)
        })
    }

    /// The plane whose normal is `n` (either sign), if it is one of the
    /// three axes exactly.
    pub fn of_normal(n: Vec3) -> Option<Plane> {
        Plane::ALL
            .into_iter()
            .find(|p| n == p.normal() || n == -p.normal())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn local_coordinates_are_right_handed_and_invert() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        for pl in Plane::ALL {
            assert_eq!(pl.point(pl.local(p)), p);
            let (a, b, h) = pl.axes();
            let unit = |i: usize| {
                let mut c = [0.0; 3];
                c[i] = 1.0;
                Vec3::from_array(c)
            };
            assert_eq!(unit(a).cross(unit(b)), unit(h));
            assert_eq!(unit(h), pl.normal());
        }
    }
}
