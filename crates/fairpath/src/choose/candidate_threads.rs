//! `auto`'s candidates smoothed, bounded and costed side by side.

use alloc::vec::Vec;

/// `f(i)` for `i in 0..n`, in order: with `std` on scoped threads, as many
/// as the machine has cores (at most `n`), each taking the next index when
/// done (the candidates are independent, and a workstation has the cores;
/// a thread per candidate cost more in starting threads than it gained);
/// one after the other without.
pub(super) fn map_candidates<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    #[cfg(feature = "std")]
    {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let workers = cores().min(n);
        if workers > 1 {
            let (f, next) = (&f, &AtomicUsize::new(0));
            let done: Vec<(usize, T)> = std::thread::scope(|s| {
                let handles: Vec<_> = (0..workers)
                    .map(|_| {
                        s.spawn(move || {
                            let mut mine = Vec::new();
                            loop {
                                let i = next.fetch_add(1, Ordering::Relaxed);
                                if i >= n {
                                    break mine;
                                }
                                mine.push((i, f(i)));
                            }
                        })
                    })
                    .collect();
                handles
                    .into_iter()
                    .flat_map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
                    .collect()
            });
            let mut out: Vec<Option<T>> = (0..n).map(|_| None).collect();
            for (i, t) in done {
                out[i] = Some(t);
            }
            return out
                .into_iter()
                .map(|t| t.expect("every index done"))
                .collect();
        }
    }
    (0..n).map(f).collect()
}

/// The machine's cores (asked once: the answer reads system files).
#[cfg(feature = "std")]
fn cores() -> usize {
    static CORES: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |c| c.get()))
}
