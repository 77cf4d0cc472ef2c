//! The seeded generator of the crate's unit tests (splitmix64, as ruckig's
//! and the integration tests' seeded tests): the same draws on every
//! platform, so a failing case is found again by its seed.

/// splitmix64.
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    /// Uniform in `[0, 1)`.
    pub(crate) fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E3779B97F4A7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in `0..n` (`n > 0`).
    pub(crate) fn below(&mut self, n: usize) -> usize {
        (self.next() * n as f64) as usize % n
    }
    /// `10^e`, `e` uniform in `[lo, hi]`: magnitudes over many decades.
    pub(crate) fn decades(&mut self, lo: f64, hi: f64) -> f64 {
        libm::pow(10.0, lo + (hi - lo) * self.next())
    }
}
