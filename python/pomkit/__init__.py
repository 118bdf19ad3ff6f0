"""pomkit: inverse displacement mapping on the GPU (wgpu/WGSL), from Python.

    import pomkit as pk
    scene = pk.Scene(mesh=pk.Mesh.plane(), material=pk.Material(pk.textures.bricks(256)),
                     camera=pk.Camera.look_at((0, 1.2, 1.6)), lights=[pk.DirectionalLight((-0.4, -1, -0.3), 3.0)])
    frame = pk.Renderer().render(scene, pk.POM())
"""

from . import _core
from ._errors import (ArgumentError, ArgumentTypeError, DeviceLostError, Error, GpuError, MissingExtraError, NoAdapterError,
                      ReferenceRendererError)
from ._assets import AssetReport, check_asset, load_mesh, load_objects
from ._files import load_albedo, load_height
from ._frame import AOV_NAMES, COST_AOVS, AovName, Frame
from ._methods import ALL_METHODS, NCS, POM, Prism, Bump, ConeStep, Custom, CurvedRelief, DistanceMapping, Exact, Flat, Hybrid, Method, Parallax, Relief, SteepParallax, Tessellated
from ._render import Renderer, adapters
from ._info import info
from ._color import linear_to_srgb, srgb_to_linear
from ._scene import Camera, DirectionalLight, Material, Mesh, Object, Scene, SphereLight
from . import metrics, oracle, presets, scenes, textures

__version__ = _core.__version__

__all__ = [
    "__version__", "Renderer", "adapters", "info", "Frame", "AOV_NAMES", "COST_AOVS", "AovName", "load_height", "load_albedo", "load_mesh", "load_objects", "check_asset", "AssetReport", "Scene", "Object", "Mesh", "Material", "Camera",
    "DirectionalLight", "SphereLight", "Method", "Flat", "Bump", "POM", "Parallax", "SteepParallax", "Relief", "Exact", "ConeStep", "NCS", "Prism", "Tessellated", "Custom", "CurvedRelief", "DistanceMapping", "Hybrid", "ALL_METHODS", "textures",
    "metrics", "oracle", "presets", "scenes", "bench", "choose", "reference", "testing", "explore", "Error", "ArgumentError", "ArgumentTypeError", "GpuError", "DeviceLostError", "NoAdapterError", "MissingExtraError",
    "ReferenceRendererError", "linear_to_srgb", "srgb_to_linear",
]


def __getattr__(name):
    # `pk.reference` and `pk.testing` import lazily: trimesh, Mitsuba and pytest only when used
    if name in ("reference", "testing", "bench"):
        import importlib
        return importlib.import_module("." + name, __name__)
    if name == "choose":  # the cheapest method and settings that meet a bound (pomkit/_choose.py)
        from ._choose import choose
        return choose
    if name == "explore":  # the notebook widget (pomkit/_explore.py; anywidget: the notebooks extra)
        from ._explore import explore
        return explore
    raise AttributeError(f"module 'pomkit' has no attribute {name!r}")
