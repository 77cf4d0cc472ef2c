//! The three principal planes in which G-code writes arcs.

use super::Vec3;

/// A principal plane of G2/G3 arcs, with the local coordinates `(a, b, h)`
/// in which an arc turning counter-clockwise (G3) turns from `a` towards
/// `b`, and `h` runs along the plane's normal (the helical axis).
///
/// | plane | G word | `(a, b)` | normal `h` |
/// |---|---|---|---|
/// | [`Plane::XY`] | G17 | (X, Y) | +Z |
/// | [`Plane::ZX`] | G18 | (Z, X) | +Y |
/// | [`Plane::YZ`] | G19 | (Y, Z) | +X |
///
/// (RS274/NGC, section 3.5.3: G2 is clockwise seen from the positive end
/// of the normal axis, so each `(a, b, h)` is right-handed.)
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Plane {
    XY,
    ZX,
    YZ,
}

impl Plane {
    /// All three, in G17, G18, G19 order.
    pub const ALL: [Plane; 3] = [Plane::XY, Plane::ZX, Plane::YZ];

    /// Unit normal (the positive helical axis).
    pub fn normal(self) -> Vec3 {
        match self {
            Plane::XY => Vec3::Z,
            Plane::ZX => Vec3::Y,
            Plane::YZ => Vec3::X,
        }
    }

    /// The G word selecting the plane.
    pub fn gcode(self) -> &'static str {
        match self {
            Plane::XY => "G17",
            Plane::ZX => "G18",
            Plane::YZ => "G19",
        }
    }

    /// Index (0 = X, 1 = Y, 2 = Z) of the axes `a`, `b` and `h`.
    pub fn axes(self) -> [usize; 3] {
        match self {
            Plane::XY => [0, 1, 2],
            Plane::ZX => [2, 0, 1],
            Plane::YZ => [1, 2, 0],
        }
    }

    /// Local coordinates `(a, b, h)` of `p`.
    pub fn local(self, p: Vec3) -> [f64; 3] {
        let c = p.to_array();
        let [a, b, h] = self.axes();
        [c[a], c[b], c[h]]
    }

    /// The point with local coordinates `(a, b, h)`.
    pub fn point(self, l: [f64; 3]) -> Vec3 {
        let mut c = [0.0; 3];
        let [a, b, h] = self.axes();
        c[a] = l[0];
        c[b] = l[1];
        c[h] = l[2];
        Vec3::from_array(c)
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
            let [a, b, h] = pl.axes();
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
