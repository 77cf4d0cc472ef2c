//! Float functions that work without `std` (through `libm`), so the library
//! builds for `core + alloc` targets such as a controller's firmware.

#[inline]
pub fn sqrt(x: f64) -> f64 {
    libm::sqrt(x)
}
#[inline]
pub fn sin(x: f64) -> f64 {
    libm::sin(x)
}
#[inline]
pub fn cos(x: f64) -> f64 {
    libm::cos(x)
}
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}
#[inline]
pub fn acos(x: f64) -> f64 {
    libm::acos(x.clamp(-1.0, 1.0))
}
#[inline]
pub fn abs(x: f64) -> f64 {
    libm::fabs(x)
}
#[inline]
pub fn powi(x: f64, n: i32) -> f64 {
    let mut r = 1.0;
    for _ in 0..n.unsigned_abs() {
        r *= x;
    }
    if n < 0 {
        1.0 / r
    } else {
        r
    }
}
#[inline]
pub fn ceil(x: f64) -> f64 {
    libm::ceil(x)
}
#[inline]
pub fn floor(x: f64) -> f64 {
    libm::floor(x)
}
