//! The oracle's rows of pixels, on the machine's cores, and the request to stop them.

use crate::error::{Error, Result};

/// `f(row)` for every row in 0..rows, on the machine's cores (at most 8 threads, each taking
/// the next row not yet taken), in row order.
pub(crate) fn par_rows<T: Send>(rows: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let threads = std::thread::available_parallelism()
        .map(|x| x.get())
        .unwrap_or(1)
        .clamp(1, 8)
        .min(rows.max(1));
    let next = AtomicUsize::new(0);
    let (f, next) = (&f, &next);
    let mut done: Vec<(usize, T)> = std::thread::scope(|sc| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                sc.spawn(move || {
                    let mut mine = Vec::new();
                    loop {
                        let r = next.fetch_add(1, Ordering::Relaxed);
                        // rows past the end, or a request to stop (the caller then answers
                        // Error::Interrupted: `interrupted`)
                        if r >= rows || crate::progress::stop_requested() {
                            break mine;
                        }
                        mine.push((r, f(r)));
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|b| b.join().expect("a row worker panicked"))
            .collect()
    });
    done.sort_by_key(|(r, _)| *r);
    done.into_iter().map(|(_, t)| t).collect()
}

/// Error::Interrupted where the computation was asked to stop (its rows are then incomplete).
pub(crate) fn interrupted() -> Result<()> {
    if crate::progress::stop_requested() {
        return Err(Error::Interrupted);
    }
    Ok(())
}
