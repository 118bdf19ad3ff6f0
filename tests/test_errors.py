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


def test_ctrl_c_reaches_python_during_a_long_oracle_call(tmp_path):
    """SIGINT (Ctrl-C) in the middle of a long `pk.oracle.image` stops it and raises
    KeyboardInterrupt at once, instead of after the whole computation."""
    import signal
    import subprocess
    import sys
    import time

    script = tmp_path / "long.py"
    script.write_text(
        "import signal, sys, time, pomkit as pk\n"
        # Python's own handler, whatever the parent left (a job started in the background by a
        # non-interactive shell inherits SIGINT ignored, and Python then installs no handler)
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "sc = pk.Scene(mesh=pk.Mesh.torus(), material=pk.Material(height=pk.textures.cobblestones(256), depth=0.1),\n"
        "              camera=pk.Camera.look_at((0.0, 1.2, 2.4), width=256, height=256),\n"
        "              lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0, angular_diameter=4.0)], ambient=0.2)\n"
        "pk.oracle.hits(sc)\n"  # warm: the shell built once
        "print('started', flush=True)\n"
        "t = time.perf_counter()\n"
        "try:\n"
        "    pk.oracle.image(sc, spp=256, cache=False)\n"
        "    print('finished', time.perf_counter() - t)\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', time.perf_counter() - t)\n"
    )
    p = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True)
    assert p.stdout is not None
    assert p.stdout.readline().strip() == "started"
    time.sleep(1.0)
    sent = time.perf_counter()
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=120)
    waited = time.perf_counter() - sent
    assert out.startswith("interrupted"), out
    assert waited < 5.0, waited
