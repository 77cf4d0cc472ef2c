//! Straight segments.

use super::{ParamCurve, Vec3};

/// A straight segment from `p0` to `p1`, parameter `t` in `[0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    pub p0: Vec3,
    pub p1: Vec3,
}

impl Line {
    pub fn new(p0: Vec3, p1: Vec3) -> Self {
        Line { p0, p1 }
    }
    pub fn length(&self) -> f64 {
        self.p0.dist(self.p1)
    }
    pub fn direction(&self) -> Vec3 {
        self.p1 - self.p0
    }
}

impl ParamCurve for Line {
    fn domain(&self) -> (f64, f64) {
        (0.0, 1.0)
    }
    fn eval(&self, t: f64) -> Vec3 {
        self.p0.lerp(self.p1, t)
    }
    fn deriv1(&self, _t: f64) -> Vec3 {
        self.p1 - self.p0
    }
    fn deriv2(&self, _t: f64) -> Vec3 {
        Vec3::ZERO
    }
    fn closed_length(&self, a: f64, b: f64, _accuracy: f64) -> Option<f64> {
        Some(self.length() * (b - a))
    }
}
