//! Errors of the core. The Python layer maps each variant to a Python exception
//! (`InvalidArgument`/`Limit` -> ValueError, `NoAdapter` -> NoAdapterError, `Gpu` -> GpuError,
//! `DeviceLost` -> DeviceLostError; the last three subclass RuntimeError).

use std::fmt;

#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// A bad argument: names the argument and says how to fix it.
    InvalidArgument { arg: String, msg: String },
    /// An argument of the wrong type (a field that is not a number, a handle that is not one):
    /// names the argument and the type it takes.
    WrongType { arg: String, msg: String },
    /// A size over a device limit: names the argument and the limit.
    Limit { arg: String, msg: String },
    /// No GPU adapter could be found or opened.
    NoAdapter(String),
    /// A wgpu validation or out-of-memory error, with wgpu's message.
    Gpu(String),
    /// The device was lost; a new Renderer must be created.
    DeviceLost(String),
    /// The caller asked a long computation to stop (Ctrl-C reaching Python: `progress::request_stop`).
    Interrupted,
}

impl Error {
    pub fn arg(arg: &str, msg: impl Into<String>) -> Self {
        Error::InvalidArgument {
            arg: arg.to_string(),
            msg: msg.into(),
        }
    }
    pub fn wrong_type(arg: &str, msg: impl Into<String>) -> Self {
        Error::WrongType {
            arg: arg.to_string(),
            msg: msg.into(),
        }
    }
    pub fn limit(arg: &str, msg: impl Into<String>) -> Self {
        Error::Limit {
            arg: arg.to_string(),
            msg: msg.into(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidArgument { arg, msg } => write!(f, "{arg}: {msg}"),
            Error::Limit { arg, msg } => write!(f, "{arg}: {msg}"),
            Error::WrongType { arg, msg } => write!(f, "{arg}: {msg}"),
            Error::NoAdapter(m) => write!(f, "no GPU adapter: {m}"),
            Error::Gpu(m) => write!(f, "GPU error: {m}"),
            Error::DeviceLost(m) => write!(f, "GPU device lost: {m}"),
            Error::Interrupted => write!(f, "interrupted"),
        }
    }
}

impl std::error::Error for Error {}

pub type Result<T> = std::result::Result<T, Error>;
