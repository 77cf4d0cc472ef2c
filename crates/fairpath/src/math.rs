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
/// `sqrt(x^2 + y^2)` without overflow. With `std` this is the platform C
/// library's `hypot` (glibc on Linux), so that code replicating a C
/// program's arithmetic (LinuxCNC's splines) rounds as that program does on
/// the same platform; without `std`, `libm`'s (within 1 ulp of it).
#[inline]
pub fn hypot(x: f64, y: f64) -> f64 {
    #[cfg(feature = "std")]
    {
        x.hypot(y)
    }
    #[cfg(not(feature = "std"))]
    {
        libm::hypot(x, y)
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
#[inline]
pub fn abs(x: f64) -> f64 {
    libm::fabs(x)
}
/// The cube root, correctly rounded (`libm`'s: the same bits on every
/// platform, and monotonic).
#[inline]
pub fn cbrt(x: f64) -> f64 {
    libm::cbrt(x)
}
/// Whether `cbrt(x) >= v` surely (`v > 0`), without taking the root: `x`
/// above `v^3` by more than the rounding of `v^3` and of the product (`v^3`
/// computed is within 2 ulps; 16 ulps more put `x` above `v^3` itself, so
/// the exact root is above `v` and [`cbrt`], correctly rounded, at least
/// `v`). False where it cannot tell. The cube root is the slowest of a
/// speed cap's operations: where it cannot set the cap, it is skipped.
#[inline]
pub fn cbrt_at_least(x: f64, v: f64) -> bool {
    x > v * v * v * (1.0 + 16.0 * f64::EPSILON)
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
