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
pub fn ceil(x: f64) -> f64 {
    libm::ceil(x)
}
#[inline]
pub fn floor(x: f64) -> f64 {
    libm::floor(x)
}
#[inline]
pub fn abs(x: f64) -> f64 {
    libm::fabs(x)
}
#[inline]
pub fn cbrt(x: f64) -> f64 {
    libm::cbrt(x)
}
#[inline]
pub fn tan(x: f64) -> f64 {
    libm::tan(x)
}
#[inline]
#[allow(dead_code)] // for methods that need it
pub fn acos(x: f64) -> f64 {
    libm::acos(x)
}
#[inline]
#[allow(dead_code)] // for methods that need it
pub fn exp(x: f64) -> f64 {
    libm::exp(x)
}
#[inline]
#[allow(dead_code)] // for methods that need it
pub fn ln(x: f64) -> f64 {
    libm::log(x)
}
#[inline]
#[allow(dead_code)] // for methods that need it
pub fn powf(x: f64, y: f64) -> f64 {
    libm::pow(x, y)
}
