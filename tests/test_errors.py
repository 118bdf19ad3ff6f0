"""Every exception pomkit raises is a `pk.Error`, and also the built-in kind that Python code
expects (ValueError for a bad value, TypeError for a wrong type, RuntimeError for the GPU,
ImportError for a missing extra), from the Rust core as from Python."""

from __future__ import annotations

import numpy as np
import pytest

import pomkit as pk


def test_every_exported_exception_is_a_pomkit_error():
    errors = [getattr(pk, n) for n in pk.__all__ if n.endswith("Error")]
    assert len(errors) >= 7
    assert all(issubclass(e, pk.Error) for e in errors)
    assert issubclass(pk.ArgumentError, ValueError) and issubclass(pk.ArgumentTypeError, TypeError)
    assert issubclass(pk.GpuError, RuntimeError) and issubclass(pk.DeviceLostError, pk.GpuError)
    assert issubclass(pk.MissingExtraError, ImportError)


def test_the_core_raises_pomkit_errors():
    # the adapter choice is checked in Rust (src/gpu), the message naming the argument
    with pytest.raises(pk.ArgumentError, match="adapter"):
        pk.Renderer(adapter="no-such-adapter-here")


def test_python_checks_raise_pomkit_errors(renderer):
    with pytest.raises(pk.ArgumentError, match="depth"):
        pk.Material(np.zeros((4, 4)), depth=-1.0)
    with pytest.raises(pk.ArgumentTypeError, match="scene"):
        renderer.render(42, pk.POM())
    with pytest.raises(ValueError):  # still a ValueError for code that catches that
        pk.Material(np.zeros((4, 4)), depth=float("nan"))
