//! The core's CPU work on the machine's cores, through rayon's pool: the oracle's rows, the shell's
//! construction, Hybrid's coarse bounds and `check_asset`'s per-triangle checks.
//!
//! The pool has one thread per core (rayon's default, no cap). `POMKIT_THREADS` sets its size,
//! and `RAYON_NUM_THREADS` does where `POMKIT_THREADS` is unset; either is read once, when the
//! process first runs parallel work.

use std::sync::Once;

static INIT: Once = Once::new();

/// The thread count `POMKIT_THREADS` asks for (a whole number of at least 1), if it is set.
fn requested() -> Option<usize> {
    std::env::var("POMKIT_THREADS")
        .ok()
        .and_then(|v| v.trim().parse::<usize>().ok())
        .filter(|&n| n >= 1)
}

/// Size rayon's global pool from `POMKIT_THREADS` before its first use (a no-op afterwards, and
/// where a caller built the pool first).
pub fn init() {
    INIT.call_once(|| {
        if let Some(n) = requested() {
            let _ = rayon::ThreadPoolBuilder::new().num_threads(n).build_global();
        }
    });
}

/// The threads parallel work runs on.
pub fn threads() -> usize {
    init();
    rayon::current_num_threads()
}

#[cfg(test)]
mod tests {
    /// No cap: the pool has a thread per core unless POMKIT_THREADS or RAYON_NUM_THREADS says
    /// otherwise (the oracle's rows had a hand-made pool of at most 8).
    #[test]
    fn the_pool_has_a_thread_per_core() {
        if std::env::var_os("POMKIT_THREADS").is_some() || std::env::var_os("RAYON_NUM_THREADS").is_some() {
            return;
        }
        let cores = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1);
        assert_eq!(super::threads(), cores);
    }
}
