"""An independent check of `pk.metrics.jod` (the pure-Rust `colorvideovdp` crate in the core)
against ColorVideoVDP's own PyTorch package (`cvvdp` on PyPI, module `pycvvdp`), on clips of
pomkit's: a method's video against the oracle's (POM(8), Exact, Parallax along an orbit over a
photograph), a constant brightening, a brightening that alternates frame to frame, and a video
against itself. The same sRGB-encoded frames go to both; the JODs agree to 1e-4.

Optional: PyTorch is several GB, so the check runs where `pycvvdp` imports, or where
POMKIT_CVVDP_PYTHON names an interpreter that has it (a venv of its own:
`python -m venv /tmp/cvenv && /tmp/cvenv/bin/pip install cvvdp`), and is skipped otherwise.
Measured on this project's machine with cvvdp 0.5.7 and torch 2.15 (CPU): the six JODs agree
to 5e-7 (POM(8) 9.7999, Exact 9.9965, Parallax 7.5363, brightened 9.9996, flickering 6.2320,
itself 10)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import pomkit as pk
from pomkit import metrics
from pomkit._color import linear_to_srgb

pytestmark = pytest.mark.slow

PYTHON = os.environ.get("POMKIT_CVVDP_PYTHON")


def _in_process() -> bool:
    try:
        import pycvvdp  # noqa: F401
        return True
    except ImportError:
        return False


def _clips() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    r = pk.Renderer()
    sc = pk.scenes.tilted_plane(pk.textures.real("gravel", 128), 60.0, 96,
                                lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)], ambient=0.1)
    scenes = pk.bench.camera_path(sc, "orbit", 12)
    ref = metrics._linear_video([pk.oracle.image(s, spp=4, shadows=False) for s in scenes], "reference")
    clips = {name: (metrics._linear_video([r.render(s, m, spp=4) for s in scenes], "frames"), ref)
             for name, m in (("POM(8)", pk.POM(shadows="none").with_steps(8)), ("Exact", pk.Exact()),
                             ("Parallax", pk.Parallax()))}
    clips["brightened"] = (ref * 1.15, ref)
    clips["flickering"] = (np.stack([ref[k] * (1.15 if k % 2 else 0.87) for k in range(len(ref))]), ref)
    clips["itself"] = (ref, ref)
    return clips


@pytest.mark.skipif(not (_in_process() or PYTHON), reason="optional: needs the PyTorch `cvvdp` package, in this "
                    "environment or in the interpreter POMKIT_CVVDP_PYTHON names")
def test_the_rust_jod_is_colorvideovdps(tmp_path):
    enc = lambda v: np.ascontiguousarray(linear_to_srgb(np.clip(v, 0.0, 1.0)), dtype=np.float32)  # noqa: E731
    ours = {}
    for i, (name, (t, r)) in enumerate(_clips().items()):
        ours[name] = metrics.jod(t, r, fps=30.0, display="standard_4k")
        np.save(tmp_path / f"{i}_t.npy", enc(t))
        np.save(tmp_path / f"{i}_r.npy", enc(r))
    script = textwrap.dedent(f"""
        import json, numpy as np, torch, pycvvdp
        m = pycvvdp.cvvdp(display_name="standard_4k", device=torch.device("cpu"))
        out = []
        for i in range({len(ours)}):
            t, r = np.load(r"{tmp_path}/%d_t.npy" % i), np.load(r"{tmp_path}/%d_r.npy" % i)
            out.append(float(m.predict(t, r, dim_order="FHWC", frames_per_second=30.0)[0]))
        print(json.dumps(out))
        """)
    run = subprocess.run([PYTHON or sys.executable, "-c", script], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    theirs = dict(zip(ours, json.loads(run.stdout.strip().splitlines()[-1])))
    for name in ours:
        assert abs(ours[name] - theirs[name]) <= 1e-4, (name, ours[name], theirs[name])
    assert theirs["itself"] == pytest.approx(10.0) and theirs["flickering"] < theirs["brightened"]
