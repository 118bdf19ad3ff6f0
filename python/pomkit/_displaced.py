"""The displaced surface as arrays (`_core.tessellate` with the object's transform applied), for
the references that render it as a mesh (Mitsuba, pyrender, trimesh)."""

from __future__ import annotations

from ._errors import ArgumentTypeError, MissingExtraError
from typing import Final

import numpy as np

from . import _core, _methods
from . import _validate as _v
from ._scene import Scene

_EXTRA = "pip install pomkit[reference]"

#: the displaced mesh the references render, Tessellated's default pattern (one source: the
#: dataclass's default): part of their cache keys, so that a render of an older mesh (the
#: two-triangle grid) is not read back as this one's
MESH: Final = _methods.Tessellated.pattern
#: how the displaced mesh winds its triangles: at depth 0 each as its base triangle, with depth
#: about its own interpolated normals (part of the references' cache keys, with MESH: renders
#: of a mesh wound otherwise are not read back)
WINDING: Final = "base triangle at depth 0, own normals with depth"


def require(module: str):
    try:
        return __import__(module)
    except ImportError as e:
        raise MissingExtraError(f"{module} is needed for references: {_EXTRA} ({e})") from None


def displaced_arrays(scene: Scene, resolution: float = 2.0, object: int = 0) -> dict:
    """positions, normals, uvs, faces of object `object`'s displaced surface in world space (its
    transform applied; normals by the inverse transpose); `resolution` vertices per texel. Also
    the base mesh's basis each vertex was displaced from, in the core's object space
    (base_normals, tangents, uv_scale: what `_core.reference_normals` takes; `core_transform`)."""
    if not isinstance(scene, Scene):
        raise ArgumentTypeError(f"scene: expected a pomkit.Scene, got {type(scene).__name__}")
    resolution = _v.number("resolution", resolution, 1 / 1024, 64)  # vertices per texel
    object = _v.integer("object", object, 0, len(scene.objects) - 1, strict=True)
    t = _core.tessellate(scene, 1.0 / float(resolution), int(object), MESH)
    a: dict[str, np.ndarray] = {k: np.asarray(v) for k, v in t.items()}
    o = scene.objects[int(object)]
    if not o.is_identity:
        m = core_transform(o)
        a["positions"] = (a["positions"] @ m[:3, :3].T + m[:3, 3]).astype(np.float32)
        n = a["normals"] @ np.linalg.inv(m[:3, :3])  # (M^-T n) as rows
        a["normals"] = (n / np.linalg.norm(n, axis=1, keepdims=True)).astype(np.float32)
    return a


def mirrors_key(scene: Scene) -> dict:
    """The cache-key entry of a scene with a mirroring object: its displaced mesh is placed by
    `core_transform` (renders cached before that held the mirror image of the object)."""
    mirrors = any(core_transform(o) is not o.transform for o in scene.objects)
    return {"mirrors": "core_transform"} if mirrors else {}


def core_transform(o) -> np.ndarray:
    """The transform of the mesh the core holds for object `o`: `o.transform`, or for a mirroring
    one `o.transform @ diag(-1, 1, 1, 1)` over the mesh reflected through x = 0 (pomkit.Object).
    Arrays the core returns in object space (`_core.tessellate`, `_core.reference_normals`) take
    this one to world space; its determinant is positive, so windings stay as the core gives them."""
    return o._oriented[1]
