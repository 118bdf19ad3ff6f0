"""pomkit's exceptions: every one is a `pk.Error`, and each also subclasses the built-in
exception that Python code would expect for its kind (ValueError, TypeError, RuntimeError,
ImportError), so that `except ValueError` keeps working. The Rust core raises the same classes
(src/python/errors.rs)."""

from __future__ import annotations

__all__ = ["Error", "ArgumentError", "ArgumentTypeError", "GpuError", "DeviceLostError", "NoAdapterError",
           "MissingExtraError", "ReferenceRendererError"]


class Error(Exception):
    """Every error pomkit raises."""


class ArgumentError(Error, ValueError):
    """An argument pomkit cannot take; the message names the argument and the fix."""


class ArgumentTypeError(Error, TypeError):
    """An argument of the wrong type; the message names the argument and the type it takes."""


class GpuError(Error, RuntimeError):
    """A wgpu validation or out-of-memory error, with wgpu's message."""


class DeviceLostError(GpuError):
    """The GPU device was lost; create a new Renderer."""


class NoAdapterError(Error, RuntimeError):
    """No usable GPU adapter; the message names what to install or which backend to use."""


class MissingExtraError(Error, ImportError):
    """An optional package is missing; the message names the pip extra that installs it."""


class ReferenceRendererError(Error, RuntimeError):
    """An independent reference renderer (Mitsuba) cannot run here; the message says why."""
