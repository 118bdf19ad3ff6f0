import os
import tempfile

import numpy as np
import pytest

os.environ.setdefault("XDG_RUNTIME_DIR", tempfile.mkdtemp(prefix="pomkit-xdg-"))
# Blender's Cycles (pk.reference.render_cycles) runs in the venv `scripts/setup.sh blender` makes
_BLENDER = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), ".venv-blender", "bin", "python")
if os.path.exists(_BLENDER):
    os.environ.setdefault("POMKIT_BLENDER_PYTHON", _BLENDER)

import pomkit as pk  # noqa: E402
from hypothesis import settings  # noqa: E402
# pomkit's pytest helpers are opt-in (a package's tests import its fixture, or run pytest with
# -p pomkit.testing): this suite's tests use its `oracle_frame` and `reference_frame` fixtures
from pomkit.testing import oracle_frame, reference_frame  # noqa: E402,F401

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


def marched_past_border(frame) -> np.ndarray:
    """Pixels whose hit lies past the mesh's uv square: a texture-space march that went on past a
    plane's open border, where the displaced surface (and the oracle) ends (docs/conventions.md,
    "The displaced surface")."""
    uv = frame.uv
    return frame.mask & ((uv < 0.0) | (uv > 1.0)).any(-1)


def light_crosses_border(scene, oracle) -> np.ndarray:
    """Pixels of a plane scene (`plane_scene`) whose oracle hit's ray toward the first light
    reaches the plane's top (y = 0) outside the plane: light that comes in through the open
    border, which the texture-space marches (tiling the plane without end) cannot see."""
    half = float(np.abs(scene.mesh.positions[:, [0, 2]]).max())
    eye = np.asarray(scene.camera.eye, np.float64)
    p = eye + scene.camera.rays().astype(np.float64) * oracle.depth[..., None]
    to_light = -np.asarray(scene.lights[0].direction, np.float64)
    to_light /= np.linalg.norm(to_light)
    q = p + to_light * (-p[..., 1:2] / to_light[1])
    with np.errstate(invalid="ignore"):
        inside = (np.abs(q[..., 0]) <= half) & (np.abs(q[..., 2]) <= half)
    return oracle.mask & ~inside


def plane_scene(height, *, depth=0.1, theta_deg=45.0, size=128, fov=30.0, tiling=1.0, lights=(), ambient=0.0,
                albedo=None, dist=2.0):
    """`pk.scenes.tilted_plane` with the unit tests' defaults (depth 0.1, 45°, fov 30, 2 units away)."""
    return pk.scenes.tilted_plane(height, theta_deg, size, depth=depth, tiling=tiling, fov=fov, distance=dist,
                                  lights=lights, ambient=ambient, albedo=albedo)
