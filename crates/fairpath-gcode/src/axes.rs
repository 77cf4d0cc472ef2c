//! The linear axes by number, as [`fairpath::geom::Plane::axes`] numbers
//! them: X, Y, Z are 0, 1, 2; their words and their arc-centre words.

use fairpath::geom::Vec3;

/// The axis words, by axis number.
pub(crate) const AXIS_LETTERS: [char; 3] = ['X', 'Y', 'Z'];

/// The arc-centre words (offsets along X, Y, Z), by axis number.
pub(crate) const CENTER_LETTERS: [char; 3] = ['I', 'J', 'K'];

/// The coordinate of `p` along axis `a`.
pub(crate) fn axis(p: Vec3, a: usize) -> f64 {
    match a {
        0 => p.x,
        1 => p.y,
        _ => p.z,
    }
}

/// Sets the coordinate of `p` along axis `a` to `v`.
pub(crate) fn set_axis(p: &mut Vec3, a: usize, v: f64) {
    match a {
        0 => p.x = v,
        1 => p.y = v,
        _ => p.z = v,
    }
}
