//! `auto`'s candidates smoothed, bounded and costed side by side.

use alloc::vec::Vec;

/// `f(i)` for `i in 0..n`, in order: with `std` on the work-stealing pool
/// the runs are smoothed on ([`crate::pipeline::par_map`]), so that the
/// candidates of a run use the cores the other runs leave idle and no
/// thread is started per call; one after the other without.
pub(super) fn map_candidates<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    crate::pipeline::par_map(n, f)
}
