//! The oracle's rows of pixels, on the machine's cores (src/parallel.rs), and the request to stop
//! them.

use crate::error::{Error, Result};
use rayon::prelude::*;

/// `f(row)` for every row in 0..rows, in parallel on rayon's pool, in row order. Once a stop is
/// requested (Ctrl-C), the rows not yet started are left out (the caller then answers
/// Error::Interrupted: `interrupted`).
pub(crate) fn par_rows<T: Send>(rows: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    crate::parallel::init();
    let done: Vec<Option<T>> = (0..rows)
        .into_par_iter()
        .with_max_len(1)
        .map(|r| (!crate::progress::stop_requested()).then(|| f(r)))
        .collect();
    done.into_iter().flatten().collect()
}

/// Error::Interrupted where the computation was asked to stop (its rows are then incomplete).
pub(crate) fn interrupted() -> Result<()> {
    if crate::progress::stop_requested() {
        return Err(Error::Interrupted);
    }
    Ok(())
}
