//! Errors across the boundary: the core's `Error` as pomkit's Python exceptions, the classes of
//! `pomkit._errors` (each a `pk.Error`): `InvalidArgument` and `Limit` -> ArgumentError (a
//! ValueError), `NoAdapter` -> NoAdapterError, `Gpu` -> GpuError, `DeviceLost` -> DeviceLostError
//! (RuntimeErrors).

use crate::error::Error;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyType;

/// The exception `name` of `pomkit._errors` with `msg`; a plain ValueError or RuntimeError where
/// that module cannot be imported (the core loaded without its package).
fn pomkit_error(name: &str, msg: String, value_error: bool) -> PyErr {
    Python::attach(|py| {
        let ty = py
            .import("pomkit._errors")
            .and_then(|m| m.getattr(name))
            .and_then(|t| t.cast_into::<PyType>().map_err(PyErr::from));
        match ty {
            Ok(t) => PyErr::from_type(t, msg),
            Err(_) if value_error => PyValueError::new_err(msg),
            Err(_) => PyRuntimeError::new_err(msg),
        }
    })
}

impl From<Error> for PyErr {
    fn from(e: Error) -> PyErr {
        if e == Error::Interrupted {
            return pyo3::exceptions::PyKeyboardInterrupt::new_err("interrupted");
        }
        let name = match e {
            Error::InvalidArgument { .. } | Error::Limit { .. } => "ArgumentError",
            Error::NoAdapter(_) => "NoAdapterError",
            Error::Gpu(_) => "GpuError",
            Error::DeviceLost(_) => "DeviceLostError",
            Error::Interrupted => unreachable!("answered above"),
        };
        let value_error = name == "ArgumentError";
        pomkit_error(name, e.to_string(), value_error)
    }
}

/// pomkit's ArgumentError (a ValueError) with `msg`, which names the argument and the fix.
pub(crate) fn argument_error(msg: impl Into<String>) -> PyErr {
    pomkit_error("ArgumentError", msg.into(), true)
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
