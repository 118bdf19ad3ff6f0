//! Progress of long builds, where they are kept on disk, and a request to stop them (Ctrl-C).
//!
//! A method's builder (the cone map, the distance volume) reports the rows it has done to the
//! hook the caller set (the Python layer sets one that shows a tqdm bar once a build has run
//! for 2 s). A build that took longer than `keep_after()` (1 s) is kept in the cache directory the
//! caller set (Python's `pomkit._cache.cache_dir()`), keyed by what it is built from and by the
//! builder's own source, and read from there next time instead of being built again.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, RwLock};
use std::time::Duration;

/// A build that took longer than this is kept on disk (`$POMKIT_KEEP_BUILDS_AFTER_MS` overrides
/// the 1000 ms, e.g. 0 to keep every build).
pub fn keep_after() -> Duration {
    let ms = std::env::var("POMKIT_KEEP_BUILDS_AFTER_MS")
        .ok()
        .and_then(|v| v.parse::<u64>().ok())
        .unwrap_or(1000);
    Duration::from_millis(ms)
}

pub type Hook = Arc<dyn Fn(&str, u64, u64) + Send + Sync>;

static STOP: AtomicBool = AtomicBool::new(false);

/// Ask the running long computations to stop (the Python layer does on Ctrl-C).
pub fn request_stop() {
    STOP.store(true, Ordering::Relaxed);
}

/// Forget a request to stop (before a new computation starts).
pub fn clear_stop() {
    STOP.store(false, Ordering::Relaxed);
}

/// Whether the computations were asked to stop: their loops poll this and end early.
pub fn stop_requested() -> bool {
    STOP.load(Ordering::Relaxed)
}

static HOOK: RwLock<Option<Hook>> = RwLock::new(None);
static DIR: RwLock<Option<PathBuf>> = RwLock::new(None);

/// Set (or clear) the hook told `(label, done, total)` as a build goes.
pub fn set_hook(hook: Option<Hook>) {
    if let Ok(mut h) = HOOK.write() {
        *h = hook;
    }
}

/// Tell the hook, if any, that `done` of `total` units of the build `label` are done.
pub fn report(label: &str, done: u64, total: u64) {
    let hook = HOOK.read().ok().and_then(|h| h.clone());
    if let Some(h) = hook {
        h(label, done, total);
    }
}

/// Set (or clear) the directory long builds are kept in.
pub fn set_cache_dir(dir: Option<PathBuf>) {
    if let Ok(mut d) = DIR.write() {
        *d = dir;
    }
}

fn path(kind: &str, key: u64) -> Option<PathBuf> {
    DIR.read()
        .ok()
        .and_then(|d| d.clone())
        .map(|d| d.join(format!("{kind}-{key:016x}.bin")))
}

/// The bytes kept for (`kind`, `key`), if any and of the expected length (a short or damaged
/// file is removed and built again).
pub fn load(kind: &str, key: u64, len: usize) -> Option<Vec<u8>> {
    let p = path(kind, key)?;
    let mut bytes = std::fs::read(&p).ok()?;
    let ok =
        bytes.len() == 16 + len && bytes[..8] == *b"pomkit01" && bytes[8..16] == key.to_le_bytes();
    if !ok {
        let _ = std::fs::remove_file(&p);
        return None;
    }
    bytes.drain(..16); // in place: no second copy of a map-sized file
    Some(bytes)
}

/// Keep `parts`, one after the other, for (`kind`, `key`): streamed to a file beside and
/// renamed, so that a reader never sees a partial file and no copy of the whole is made.
/// Failing to keep a build is not an error.
pub fn store(kind: &str, key: u64, parts: &[&[u8]]) {
    use std::io::Write;
    let Some(p) = path(kind, key) else { return };
    let tmp = p.with_extension(format!("tmp{}", std::process::id()));
    let write = || -> std::io::Result<()> {
        let mut f = std::io::BufWriter::new(std::fs::File::create(&tmp)?);
        f.write_all(b"pomkit01")?;
        f.write_all(&key.to_le_bytes())?;
        for part in parts {
            f.write_all(part)?;
        }
        f.into_inner().map_err(|e| e.into_error())?.sync_all()
    };
    if write().is_err() || std::fs::rename(&tmp, &p).is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
}
