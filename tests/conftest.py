import os
import tempfile

import numpy as np
import pytest

os.environ.setdefault("XDG_RUNTIME_DIR", tempfile.mkdtemp(prefix="pomkit-xdg-"))

import pomkit as pk  # noqa: E402
from hypothesis import settings  # noqa: E402

# Hypothesis draws the same examples on every run (CI is repeatable); POMKIT_HYPOTHESIS_RANDOM=1
# draws fresh ones, to search further (with POMKIT_DIFF_EXAMPLES / POMKIT_FUZZ_EXAMPLES for more)
settings.register_profile("repeatable", derandomize=True, database=None)
settings.register_profile("random", derandomize=False)
settings.load_profile("random" if os.environ.get("POMKIT_HYPOTHESIS_RANDOM") == "1" else "repeatable")


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
    """`pk.scenes.tilted_plane` with the unit tests' defaults (depth 0.1, 45°, fov 30, 2 units away)."""
    return pk.scenes.tilted_plane(height, theta_deg, size, depth=depth, tiling=tiling, fov=fov, distance=dist,
                                  lights=lights, ambient=ambient, albedo=albedo)
