import os
import tempfile

import numpy as np
import pytest

os.environ.setdefault("XDG_RUNTIME_DIR", tempfile.mkdtemp(prefix="pomkit-xdg-"))

import pomkit as pk  # noqa: E402


@pytest.fixture(scope="session")
def renderer():
    return pk.Renderer()


def raster_floor(oracle, scene) -> float:
    """The uv error (texels) that a GPU's rasterizer alone leaves against the oracle's rays
    through the pixel centres: it snaps vertices to 1/256 pixel (D3D11's rule, which Vulkan's GPUs
    keep) and interpolates positions and uv from the snapped corners, which moves a pixel's ray
    by about its footprint / 256 (measured on an H200: Tessellated at 8 vertices a texel and the
    bisections of ConeStep level off there); llvmpipe interpolates from the corners as given."""
    texels = np.array(scene.material.height.shape[::-1], np.float64) * scene.material.tiling
    uv, m = oracle.uv * texels, oracle.mask
    steps = np.linalg.norm(uv[:, 1:] - uv[:, :-1], axis=-1)[m[:, 1:] & m[:, :-1]]
    return float(np.median(steps)) / 256 if steps.size else 0.0


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
