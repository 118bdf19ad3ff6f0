//! Errors across the boundary: the core's `Error` as pomkit's Python exceptions, the classes of
//! `pomkit._errors` (each a `pk.Error`): `InvalidArgument` and `Limit` -> ArgumentError (a
//! ValueError), `WrongType` -> ArgumentTypeError (a TypeError), `NoAdapter` -> NoAdapterError,
//! `Gpu` -> GpuError, `DeviceLost` -> DeviceLostError (RuntimeErrors), `Interrupted` ->
//! KeyboardInterrupt.

use crate::error::Error;
use pyo3::prelude::*;

// pomkit's exception classes (python/pomkit/_errors.py), imported once and kept (pyo3's
// `import_exception!`); the extension lives inside the package, so the module is always there
pyo3::import_exception!(pomkit._errors, ArgumentError);
pyo3::import_exception!(pomkit._errors, ArgumentTypeError);
pyo3::import_exception!(pomkit._errors, NoAdapterError);
pyo3::import_exception!(pomkit._errors, GpuError);
pyo3::import_exception!(pomkit._errors, DeviceLostError);

impl From<Error> for PyErr {
    fn from(e: Error) -> PyErr {
        let msg = e.to_string();
        match e {
            Error::InvalidArgument { .. } | Error::Limit { .. } => ArgumentError::new_err(msg),
            Error::WrongType { .. } => ArgumentTypeError::new_err(msg),
            Error::NoAdapter(_) => NoAdapterError::new_err(msg),
            Error::Gpu(_) => GpuError::new_err(msg),
            Error::DeviceLost(_) => DeviceLostError::new_err(msg),
            Error::Interrupted => pyo3::exceptions::PyKeyboardInterrupt::new_err("interrupted"),
        }
    }
}

/// pomkit's ArgumentError (a ValueError) with `msg`, which names the argument and the fix.
pub(crate) fn argument_error(msg: impl Into<String>) -> PyErr {
    ArgumentError::new_err(msg.into())
}

/// Run `f` (a long computation of the core) on a thread of its own while this thread, without
/// the GIL, waits for it and checks Python's signals every 50 ms: Ctrl-C asks the computation to
/// stop (`progress::request_stop`, which its loops poll), waits for it to wind down and raises
/// KeyboardInterrupt in Python.
pub(crate) fn interruptible<T: Send>(
    py: Python<'_>,
    f: impl FnOnce() -> crate::error::Result<T> + Send,
) -> PyResult<T> {
    use crate::progress;
    progress::clear_stop();
    let caller = std::thread::current();
    std::thread::scope(|s| {
        let worker = s.spawn(move || {
            let out = f();
            caller.unpark();
            out
        });
        loop {
            if worker.is_finished() {
                break;
            }
            py.detach(|| std::thread::park_timeout(std::time::Duration::from_millis(50)));
            if worker.is_finished() {
                break;
            }
            if let Err(e) = py.check_signals() {
                progress::request_stop();
                let _ = py.detach(|| worker.join());
                progress::clear_stop();
                return Err(e);
            }
        }
        match worker.join() {
            Ok(r) => r.map_err(PyErr::from),
            Err(_) => Err(pyo3::exceptions::PyRuntimeError::new_err(
                "a pomkit computation panicked",
            )),
        }
    })
}
