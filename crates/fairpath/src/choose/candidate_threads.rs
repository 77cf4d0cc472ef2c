//! `auto`'s candidates smoothed, bounded and costed side by side.

use alloc::vec::Vec;

/// `f(i)` for `i in 0..n`, in order: with `std` on rayon's global pool,
/// the one the runs are smoothed on ([`crate::pipeline::par_map`], a layer
/// above), each index a job of its own, so that the candidates of a run
/// use the cores the other runs leave idle and no thread is started per
/// call; one after the other without.
pub(super) fn map_candidates<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    #[cfg(feature = "std")]
    {
        use rayon::prelude::*;
        let f = &f;
        (0..n).into_par_iter().with_max_len(1).map(f).collect()
    }
    #[cfg(not(feature = "std"))]
    {
        (0..n).map(f).collect()
    }
}
