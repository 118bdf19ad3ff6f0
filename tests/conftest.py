import os
import tempfile

import numpy as np
import pytest

os.environ.setdefault("XDG_RUNTIME_DIR", tempfile.mkdtemp(prefix="pomkit-xdg-"))

import pomkit as pk  # noqa: E402


@pytest.fixture(scope="session")
def renderer():
    return pk.Renderer()


def plane_scene(height, *, depth=0.1, theta_deg=45.0, size=128, fov=30.0, tiling=1.0, lights=(), ambient=0.0,
                albedo=None, dist=2.0):
    """A size-2 plane seen from +Z at `theta_deg` from its normal, looking at the origin."""
    t = np.radians(theta_deg)
    eye = (0.0, dist * np.cos(t), dist * np.sin(t))
    return pk.Scene(
        mesh=pk.Mesh.plane(2.0),
        material=pk.Material(height, depth=depth, tiling=tiling, albedo=albedo),
        camera=pk.Camera.look_at(eye=eye, target=(0, 0, 0), up=(0, 0, -1), fov_y=fov, width=size, height=size),
        lights=list(lights),
        ambient=ambient,
    )
