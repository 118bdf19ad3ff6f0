"""Scene model: plain validated data (mesh, material, camera, lights).

Conventions (see docs/conventions.md): h = 1 is the base surface, h = 0 lies
`depth` below it along the base normal; array row r, column c is the texel centred at
u = (c + 0.5) / W, v = (r + 0.5) / H; the camera's ray of pixel (i, j) passes through the
pixel centre; a directional light's `direction` is the way the light travels.
"""

from __future__ import annotations

from ._errors import ArgumentError, ArgumentTypeError
import math
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal, Optional, Sequence

import numpy as np

from . import _core
from . import _schema
from . import _validate as _v

__all__ = ["Mesh", "Material", "Camera", "DirectionalLight", "SphereLight", "Object", "Scene"]


_vec3, _rgb, _float_array = _v.vec3, _v.rgb, _v.float_array


_handle, _without_handles = _schema.handle, _schema.without_handles


def _readonly(a: np.ndarray) -> np.ndarray:
    a.flags.writeable = False
    return a


#: what a mesh's vertex normals get (`_core.NORMALS_MODES`; `Mesh.from_arrays`, `pk.load_mesh`)
NormalsMode = Literal["file", "recompute", "repair"]


@dataclass(frozen=True, eq=False)
class Mesh:
    """A triangle mesh with per-vertex normals, uvs and tangent bases.

    Build one with `Mesh.plane`, `sphere`, `torus`, `cylinder`, `cube`, `from_arrays` or
    `from_trimesh`. Tangents are 4-vectors (xyz, w) as in glTF: the bitangent is
    w * cross(N, T) and points along dP/dv. `uv_scale` is the world length per unit of u and v
    (|dP/du|, |dP/dv|) at each vertex. Triangles are stored counter-clockwise seen from where
    the normals point (the renderer culls back faces).
    """

    positions: np.ndarray
    normals: np.ndarray
    uvs: np.ndarray
    indices: np.ndarray
    tangents: np.ndarray
    uv_scale: np.ndarray
    charts: np.ndarray
    kind: str = "arrays"
    #: how a built-in mesh was made: (kind, {parameter: value}) of the core's generator. Scene
    #: hashes read this, not the vertices, which come from the platform's sinf and cosf.
    recipe: Optional[tuple] = None

    @classmethod
    def _from_core(cls, a: "_core.MeshArrays", kind: str) -> "Mesh":
        r = lambda x: _readonly(np.asarray(x))
        return cls(r(a["positions"]), r(a["normals"]), r(a["uvs"]), r(a["indices"]), r(a["tangents"]),
                   r(a["uv_scale"]), r(a["charts"]), kind=kind)

    @classmethod
    def _generate(cls, kind: 'Literal["plane", "sphere", "torus", "cylinder", "cube"]', **params: Any) -> "Mesh":
        mesh = cls._from_core(getattr(_core, f"mesh_{kind}")(**params), kind)
        object.__setattr__(mesh, "recipe", (kind, params))
        return mesh

    @classmethod
    def plane(cls, size: float = 2.0, segments: int = 1) -> "Mesh":
        """Square in the XZ plane at y = 0, normal +Y, centred at the origin.

        u grows with +X and v with +Z, so row 0 of a map is the far edge for a camera on +Z.
        """
        return cls._generate("plane", size=_pos("size", size), segments=_count("segments", segments))

    @classmethod
    def sphere(cls, radius: float = 1.0, segments: int = 64, rings: int = 32) -> "Mesh":
        """UV sphere centred at the origin.

        u = longitude / 2pi around +Y (u = 0 on +X, growing toward -Z), v = polar angle / pi
        from the north pole (+Y, v = 0) to the south pole (v = 1). The poles are rows of
        coincident vertices and u = 0/1 is a seam of duplicated vertices: both are test cases.
        """
        return cls._generate("sphere", radius=_pos("radius", radius), segments=_count("segments", segments),
                             rings=_count("rings", rings))

    @classmethod
    def torus(cls, major: float = 1.0, minor: float = 0.35, segments: int = 64, tube_segments: int = 32) -> "Mesh":
        """Torus around +Y centred at the origin.

        u = angle around the axis / 2pi, v = angle around the tube / 2pi (v = 0 on the outer
        equator, rising toward +Y). Continuous and periodic in both directions.
        """
        return cls._generate("torus", major=_pos("major", major), minor=_pos("minor", minor),
                             segments=_count("segments", segments), tube_segments=_count("tube_segments", tube_segments))

    @classmethod
    def cylinder(cls, radius: float = 0.5, height: float = 1.5, segments: int = 64, rings: int = 1) -> "Mesh":
        """Open cylinder (no caps) around +Y, centred at the origin.

        u = angle / 2pi (u = 0 on +X), v from the top rim (v = 0) to the bottom rim (v = 1).
        """
        return cls._generate("cylinder", radius=_pos("radius", radius), height=_pos("height", height),
                             segments=_count("segments", segments), rings=_count("rings", rings))

    @classmethod
    def cube(cls, size: float = 1.5, segments: int = 1) -> "Mesh":
        """Cube of edge `size` centred at the origin; each face carries the whole uv square."""
        return cls._generate("cube", size=_pos("size", size), segments=_count("segments", segments))

    @classmethod
    def from_arrays(cls, positions, normals, uvs, indices, tangents: Any = None, *,
                    normals_mode: "NormalsMode" = "file") -> "Mesh":
        """A mesh from numpy arrays: positions (n,3), normals (n,3), uvs (n,2) in pomkit's
        convention (v down: row 0 of a map at v = 0), indices (m,) or (m/3,3).

        tangents: an (n,4) array in pomkit's handedness (the bitangent w * cross(N, T) points
        along +dP/dv, minus glTF's w), or which frames to compute: "mikktspace" (None, the
        default: MikkTSpace, what glTF asks for where a file has none, what engines bake normal
        maps against, and what `pk.load_mesh` gives the same arrays: one asset, one frame) or
        "pomkit" (dP/du per triangle, area-weighted per vertex, the uv derivatives a height
        field's displacement follows; the generated meshes' frames). Triangles with degenerate uvs get a fallback frame and a
        warning; a mesh with no usable uvs raises.

        normals_mode: "file" (the default) keeps the normals as given and refuses an unusable one
        (NaN, Inf or zero length), naming its vertex; "repair" recomputes only those (a warning
        counts them); "recompute" recomputes all. A recomputed normal is the area-weighted face
        normal around the vertex's position (both sides of a uv seam alike), hard edges (faces
        more than 60 degrees apart) kept hard."""
        if normals_mode not in _core.NORMALS_MODES:
            raise ArgumentError(f"normals: expected one of {', '.join(map(repr, _core.NORMALS_MODES))}, got {normals_mode!r}")
        p = _float_array("positions", positions, 3)
        n = _float_array("normals", normals, 3)
        uv = _float_array("uvs", uvs, 2)
        try:
            idx = np.asarray(indices)
        except Exception:
            raise ArgumentTypeError("indices: expected an integer array") from None
        if idx.dtype.kind not in "iu":
            raise ArgumentTypeError(f"indices: expected an integer array, got dtype {idx.dtype}")
        idx = idx.reshape(-1)
        if idx.size and (idx.min() < 0):
            raise ArgumentError(f"indices: index {int(idx.min())} is negative")
        if idx.size and idx.max() >= len(p):
            raise ArgumentError(f"indices: index {int(idx.max())} is out of range for {len(p)} vertices")
        idx = np.ascontiguousarray(idx, dtype=np.uint32)
        if tangents is None or isinstance(tangents, str):
            frames = "mikktspace" if tangents is None else tangents
            if frames not in ("pomkit", "mikktspace"):
                raise ArgumentError(f'tangents: expected "pomkit", "mikktspace" or an (n, 4) array, got {frames!r}')
            out = _core.mesh_from_arrays(p, n, uv, idx, None, "mikktspace" if frames == "mikktspace" else "pomkit",
                                         normals_mode)
        else:
            out = _core.mesh_from_arrays(p, n, uv, idx, _float_array("tangents", tangents, 4), "pomkit", normals_mode)
        if out["replaced_normals"] and normals_mode == "repair":
            warnings.warn(f"{out['replaced_normals']} unusable normal(s) recomputed from the faces (normals_mode=\"repair\")",
                          RuntimeWarning, stacklevel=2)
        degenerate, fallback = out["degenerate_uv_triangles"], out["fallback_vertices"]
        if degenerate:
            warnings.warn(
                f"{degenerate} triangle(s) have degenerate uvs; {fallback} vertex(es) got a fallback tangent basis",
                RuntimeWarning,
                stacklevel=2,
            )
        return cls._from_core(out, "arrays")

    @classmethod
    def from_trimesh(cls, mesh, tangents: Any = "mikktspace", *, normals_mode: "NormalsMode" = "file") -> "Mesh":
        """A mesh from a `trimesh.Trimesh` with uvs (`mesh.visual.uv`).

        trimesh keeps uvs with v pointing up (it flips glTF's v on load and samples images at
        1 - v); pomkit's v points down (row 0 of a map at v = 0, as glTF's), so the uvs become
        (u, 1 - v). Normals are `mesh.vertex_normals`: the file's only where trimesh kept them
        (`trimesh.load(path, process=False)`; its default processing merges vertices and
        recomputes normals). For glTF, `pk.load_mesh` reads the file as it is, tangents included.
        tangents: as in `from_arrays`; MikkTSpace by default, as for a loaded asset.
        normals_mode: as in `from_arrays`."""
        uv = getattr(getattr(mesh, "visual", None), "uv", None)
        if uv is None:
            raise ArgumentError("mesh: the trimesh has no uvs (mesh.visual.uv); give it a parameterisation")
        uv = np.asarray(uv, dtype=np.float64)
        uv = np.stack([uv[:, 0], 1.0 - uv[:, 1]], axis=1)
        return cls.from_arrays(mesh.vertices, mesh.vertex_normals, uv, mesh.faces, tangents=tangents,
                               normals_mode=normals_mode)

    def _arrays(self) -> dict:
        return dict(positions=self.positions, normals=self.normals, uvs=self.uvs, indices=self.indices,
                    tangents=self.tangents, uv_scale=self.uv_scale, charts=self.charts)

    def _core_data(self) -> "_core.MeshData":
        """The core's copy of the arrays with their content key, made on the first render and
        kept (the arrays are read-only), so that later renders neither copy nor hash them."""
        return _handle(self, "_core_mesh", lambda: _core.MeshData(
            self.positions, self.normals, self.uvs, self.tangents, self.uv_scale, self.indices,
            np.ascontiguousarray(self.charts, dtype=np.uint32).reshape(-1, 3)))

    __getstate__ = _without_handles


def _pos(name: str, x) -> float:
    return _v.number(name, x, 0.0, 1e12, lo_open=True)


def _count(name: str, x) -> int:
    return _v.integer(name, x, 1, 100_000)


class _MaterialBase(_schema.SchemaClass):
    """A material's methods; its fields are the core's (src/scene/mod.rs)."""

    def _height_data(self) -> "_core.HeightData":
        return self._handle_of("height")

    def _albedo_data(self) -> "Optional[_core.AlbedoData]":
        return self._handle_of("albedo")



class _CameraBase(_schema.SchemaClass):
    """A camera's methods; its fields are the core's (src/scene/camera.rs), typed for mypy in
    `_schema_classes.pyi` (here `c` is the instance seen as that class)."""

    @classmethod
    def look_at(cls, eye, target=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0), fov_y: float = 45.0,
                width: int = 256, height: int = 256) -> "Camera":
        return cls(eye, target, up, fov_y, width, height)  # type: ignore[call-arg, return-value]

    def _check(self) -> None:
        c: Any = self
        f = np.subtract(c.target, c.eye)
        if np.linalg.norm(f) < 1e-9:
            raise ArgumentError("eye: eye and target coincide; move the eye away from the target")
        u = np.asarray(c.up)
        if np.linalg.norm(u) < 1e-12 or np.linalg.norm(np.cross(f / np.linalg.norm(f), u / np.linalg.norm(u))) < 1e-6:
            raise ArgumentError("up: up is zero or parallel to the view direction; pass another up vector")

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(forward, right, up) unit vectors in float64."""
        c: Any = self
        f = np.subtract(c.target, c.eye)
        f = f / np.linalg.norm(f)
        r = np.cross(f, c.up)
        r = r / np.linalg.norm(r)
        return f, r, np.cross(r, f)

    def rays(self) -> np.ndarray:
        """(H, W, 3) float64 unit directions of the rays through the pixel centres."""
        c: Any = self
        f, r, u = self.basis()
        t = math.tan(math.radians(c.fov_y) / 2)
        w, h = c.width, c.height
        x = ((np.arange(w) + 0.5) / w * 2 - 1) * t * w / h
        y = (1 - (np.arange(h) + 0.5) / h * 2) * t
        d = f[None, None, :] + x[None, :, None] * r[None, None, :] + y[:, None, None] * u[None, None, :]
        return d / np.linalg.norm(d, axis=-1, keepdims=True)


class _LightBase(_schema.SchemaClass):
    """What every light has; its fields are the core's (src/scene/mod.rs)."""

    @property
    def power(self) -> tuple[float, float, float]:
        """What the light delivers, its tint included (the core's `Light::power`): a directional
        light's linear RGB irradiance, a sphere light's intensity in W/sr."""
        p = _core.light_power(self)
        return (float(p[0]), float(p[1]), float(p[2]))


class _DirectionalBase(_LightBase):
    """A directional light's check."""

    def _check(self) -> None:
        if np.linalg.norm(getattr(self, "direction")) < 1e-12:
            raise ArgumentError("direction: must be a non-zero vector")


if TYPE_CHECKING:
    from ._schema_classes import Camera, DirectionalLight, Material, SphereLight
else:
    Material = _schema.build("Material", _MaterialBase, __name__)
    Camera = _schema.build("Camera", _CameraBase, __name__)
    DirectionalLight = _schema.build("DirectionalLight", _DirectionalBase, __name__)
    SphereLight = _schema.build("SphereLight", _LightBase, __name__)


#: the most lights a scene takes (the core's; the shaders' light array has this size)
MAX_LIGHTS: int = _core.MAX_LIGHTS


def _transform(t: Any) -> Optional[np.ndarray]:
    """A validated 4x4 affine object-to-world matrix (read-only float64), None for the identity."""
    if t is None:
        return None
    try:
        m = np.array(t, dtype=np.float64)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"transform: expected a 4x4 numpy array, got {type(t).__name__}") from None
    if m.shape != (4, 4):
        raise ArgumentError(f"transform: expected a 4x4 matrix, got shape {m.shape}")
    if not np.all(np.isfinite(m)):
        raise ArgumentError("transform: contains NaN or Inf; give a finite 4x4 matrix")
    if not np.array_equal(m[3], [0.0, 0.0, 0.0, 1.0]):
        raise ArgumentError(f"transform: must be affine, with last row [0, 0, 0, 1]; got {m[3].tolist()}")
    lin = m[:3, :3]
    scale = float(np.abs(lin).max())
    if scale == 0.0 or abs(np.linalg.det(lin)) <= 1e-12 * scale ** 3:
        raise ArgumentError("transform: the matrix is singular (it flattens the object); give an invertible one")
    if np.array_equal(m, np.eye(4)):
        return None
    return _readonly(m)


def _oriented(mesh: Mesh, m: np.ndarray) -> tuple:
    """(mesh, transform) as the core takes them: unchanged, or for a mirroring transform the
    mesh reflected through x = 0 under m @ diag(-1, 1, 1, 1) (the same world surface, fronts
    counter-clockwise)."""
    if np.linalg.det(m[:3, :3]) > 0.0:
        return mesh, m
    flip = np.array([-1.0, 1.0, 1.0], np.float32)
    r = lambda x: _readonly(np.ascontiguousarray(x))
    tangents = np.asarray(mesh.tangents, np.float32) * np.array([-1.0, 1.0, 1.0, -1.0], np.float32)
    tri = np.asarray(mesh.indices).reshape(-1, 3)[:, [0, 2, 1]].reshape(-1)
    # (the uv grids' triangles are wound for the given mesh, so the reflected one has none)
    reflected = Mesh(r(np.asarray(mesh.positions, np.float32) * flip), r(np.asarray(mesh.normals, np.float32) * flip),
                     mesh.uvs, r(tri), r(tangents), mesh.uv_scale,
                     r(np.zeros((0, 3), np.uint32)), kind=mesh.kind)
    return reflected, _readonly(m @ np.diag([-1.0, 1.0, 1.0, 1.0]))


@dataclass(frozen=True, eq=False)
class Object:
    """One object of a scene: a base mesh, its material and an object-to-world `transform`.

    transform: a 4x4 affine matrix (numpy array; it may rotate, translate and scale,
    non-uniformly too, or mirror), or None for the identity. The mesh, its normals and tangent
    bases and the displacement live in object space: `material.depth` is in object units, along
    the object-space normal, and the displaced surface is the transform applied to it. Normals
    transform by the inverse transpose. `transform` reads back as a 4x4 array (the identity
    when None was given).

    A mirroring transform (determinant < 0, as glTF nodes with a negative scale have) turns
    counter-clockwise fronts clockwise. The object renders it as the same world surface: the
    core is given the mesh reflected through x = 0 (positions, normals and tangents; the
    tangents' handedness and the triangles' winding reversed) under the transform times
    diag(-1, 1, 1), which keeps fronts counter-clockwise. `mesh` and `transform` read back as
    given.
    """

    mesh: Mesh
    material: Material
    transform: Any = None

    def __post_init__(self):
        if not isinstance(self.mesh, Mesh):
            raise ArgumentTypeError(f"mesh: expected a pomkit.Mesh, got {type(self.mesh).__name__}")
        if not isinstance(self.material, Material):
            raise ArgumentTypeError(f"material: expected a pomkit.Material, got {type(self.material).__name__}")
        m = _transform(self.transform)
        object.__setattr__(self, "transform", _readonly(np.eye(4)) if m is None else m)
        object.__setattr__(self, "_oriented", _oriented(self.mesh, self.transform))

    @property
    def is_identity(self) -> bool:
        return bool(np.array_equal(self.transform, np.eye(4)))


@dataclass(frozen=True, eq=False)
class Scene:
    """Objects, a camera, up to four lights and a constant ambient radiance.

    Give either `mesh` and `material` (one object, untransformed) or `objects`, a list of
    `pomkit.Object`. An object's index in `objects` is its id in the `object` AOV. `mesh` and
    `material` read back as the single object's when the scene has one object (transformed or
    not), None when it has several.
    """

    mesh: Optional[Mesh] = None
    material: Optional[Material] = None
    # required: a Camera after __post_init__ (None only as the dataclass default)
    camera: Camera = None  # type: ignore[assignment]
    lights: Sequence[Any] = field(default_factory=tuple)
    ambient: Any = 0.0
    # a tuple of Object after __post_init__, whichever way the scene was given
    objects: Sequence[Object] = None  # type: ignore[assignment]

    def __post_init__(self):
        objects = self.objects
        given = self.mesh is not None or self.material is not None
        if objects is not None:
            if isinstance(objects, Object):
                objects = (objects,)
            if not isinstance(objects, (list, tuple)):
                raise ArgumentTypeError(f"objects: expected a list of pomkit.Object, got {type(objects).__name__}")
            objects = tuple(objects)
            if not objects:
                raise ArgumentError("objects: the list is empty; give at least one pomkit.Object")
            for o in objects:
                if not isinstance(o, Object):
                    raise ArgumentTypeError(f"objects: expected pomkit.Object items, got {type(o).__name__}")
            if given:
                raise ArgumentError("objects: give either mesh= and material= (one object) or objects=, not both "
                                 "(to copy a scene with changes, use scene.replace(...))")
        else:
            if not isinstance(self.mesh, Mesh):
                raise ArgumentTypeError(f"mesh: expected a pomkit.Mesh, got {type(self.mesh).__name__}; "
                                "or give objects=[pomkit.Object(mesh, material)]")
            if not isinstance(self.material, Material):
                raise ArgumentTypeError(f"material: expected a pomkit.Material, got {type(self.material).__name__}")
            objects = (Object(self.mesh, self.material),)
        object.__setattr__(self, "objects", objects)
        single = objects[0] if len(objects) == 1 else None
        object.__setattr__(self, "mesh", single.mesh if single else None)
        object.__setattr__(self, "material", single.material if single else None)
        if not isinstance(self.camera, Camera):
            raise ArgumentTypeError(f"camera: expected a pomkit.Camera, got {type(self.camera).__name__}")
        lights = tuple(self.lights) if isinstance(self.lights, (list, tuple)) else (self.lights,)
        for l in lights:
            if not isinstance(l, (DirectionalLight, SphereLight)):
                raise ArgumentTypeError(f"lights: expected DirectionalLight or SphereLight, got {type(l).__name__}")
        if len(lights) > MAX_LIGHTS:
            raise ArgumentError(f"lights: at most {MAX_LIGHTS} lights are supported, got {len(lights)}")
        object.__setattr__(self, "lights", lights)
        object.__setattr__(self, "ambient", _rgb("ambient", self.ambient))

    @property
    def single(self) -> Object:
        """The scene's only object; a ValueError for scenes of several objects."""
        if len(self.objects) != 1:
            raise ArgumentError(f"scene: this takes a scene of one object, got {len(self.objects)}")
        return self.objects[0]

    def replace(self, **changes) -> "Scene":
        """A copy with some fields changed. On a scene of one object, `mesh=` and `material=`
        replace that object's (keeping its transform)."""
        import dataclasses
        if "objects" in changes:
            changes.setdefault("mesh", None)
            changes.setdefault("material", None)
        elif "mesh" in changes or "material" in changes:
            o = self.single
            changes["objects"] = (Object(changes.pop("mesh", o.mesh), changes.pop("material", o.material),
                                         None if o.is_identity else o.transform),)
            changes["mesh"] = changes["material"] = None
        else:
            changes.update(objects=self.objects, mesh=None, material=None)
        return dataclasses.replace(self, **changes)
