"""Type stubs for the compiled core (pomkit._core). The pyo3 layer only converts: scenes come
as `pomkit.Scene` objects and methods as the dataclasses of pomkit._methods, each read
attribute by attribute into the core's typed structs (src/python/fields.rs)."""

from typing import Any, Callable, Literal, Optional, Sequence, TypedDict, final, type_check_only

import numpy as np

from ._methods import Method
from ._scene import Scene

__all__ = ["AOV_DOCS", "AOV_NAMES", "AlbedoData", "COST_AOV_NAMES", "CONE_KINDS", "FILTERING_KINDS", "HeightData", "MAX_LIGHTS", "NORMALS_MODES", "PIPELINES",
           "MAX_STEPS_LIMIT", "MeshData", "PATTERN_KINDS", "PRISM_BYTES", "PRISM_VERTEX_BYTES", "REFINE_KINDS", "RenderedFrame", "Renderer", "SCHEMA", "Shells", "SCHEMA_SETTINGS", "ASSET_REPORT_FIELDS", "METHOD_FIELDS", "HYBRID_FINE_KINDS", "SHADOW_KINDS", "WALK_BYTES_PER_TRIANGLE",
           "__version__", "adapters", "bounding_sphere", "check_asset", "oracle_hits", "oracle_image", "light_power", "load_gltf", "jod", "jod_displays", "load_image", "mesh_cube", "mesh_cylinder", "mesh_from_arrays", "mesh_plane", "mesh_sphere", "mesh_torus", "reference_directions", "reference_normals", "set_cache_dir", "set_progress_hook", "shell_findings", "tessellate"]
__version__: str
#: GPU bytes of one triangle's walk data (NCS and curved relief)
WALK_BYTES_PER_TRIANGLE: int
#: GPU bytes of one prism's data (its Rgba32Uint texels) and of one boundary-face vertex
PRISM_BYTES: int
PRISM_VERTEX_BYTES: int
MAX_LIGHTS: int
AOV_NAMES: list[str]
COST_AOV_NAMES: list[str]
SHADOW_KINDS: list[str]
FILTERING_KINDS: list[str]
CONE_KINDS: list[str]
NORMALS_MODES: list[str]
PIPELINES: list[str]
REFINE_KINDS: list[str]
PATTERN_KINDS: list[str]
MAX_STEPS_LIMIT: int
AOV_DOCS: dict[str, str]
#: the scene's schema classes (src/scene/schema.rs): name -> (doc, [(field, kind, default
#: literal or None, lo, hi, doc)]), from which pomkit._schema builds Camera and the lights
SCHEMA: dict[str, tuple[str, list[tuple[str, str, Optional[str], Optional[float], Optional[float], str]]]]
SCHEMA_SETTINGS: dict[str, list[str]]
ASSET_REPORT_FIELDS: list[tuple[str, str, str]]
METHOD_FIELDS: list[tuple[str, list[str]]]
HYBRID_FINE_KINDS: list[str]


@final
class MeshData:
    """A mesh's arrays, copied and content-hashed once (pomkit.Mesh makes it on first use)."""
    def __new__(cls, positions: np.ndarray, normals: np.ndarray, uvs: np.ndarray, tangents: np.ndarray,
                uv_scale: np.ndarray, indices: np.ndarray, charts: np.ndarray) -> "MeshData": ...
    @property
    def key(self) -> int: ...

@final
class HeightData:
    """A height map, copied and content-hashed once (pomkit.Material makes it on first use)."""
    def __new__(cls, height: np.ndarray) -> "HeightData": ...
    @property
    def key(self) -> int: ...

@final
class Shells:
    """The shells the oracle keeps between calls (its objects' prisms and bounding volumes, the
    latest four by mesh content and depth). pk.oracle holds one for the process."""
    def __new__(cls) -> "Shells": ...
    def __len__(self) -> int: ...

@final
class AlbedoData:
    """A linear RGB albedo, copied and content-hashed once."""
    def __new__(cls, albedo: np.ndarray) -> "AlbedoData": ...
    @property
    def key(self) -> int: ...

@final
class RenderedFrame:
    """A render as it crosses the boundary (pomkit.Frame wraps it)."""
    #: numpy arrays by AOV name (AOV_NAMES, their meaning AOV_DOCS), None for those not asked for
    @property
    def arrays(self) -> dict[str, Optional[np.ndarray]]: ...
    @property
    def gpu_ms(self) -> Optional[float]: ...
    @property
    def wall_ms(self) -> float: ...


@type_check_only
class MeshArrays(TypedDict):
    """A mesh's arrays (`mesh_plane` and the other generators, `mesh_from_arrays`)."""
    positions: np.ndarray    # (n, 3) float32
    normals: np.ndarray      # (n, 3) float32
    uvs: np.ndarray          # (n, 2) float32
    indices: np.ndarray      # (m,) uint32
    tangents: np.ndarray     # (n, 4) float32
    uv_scale: np.ndarray     # (n, 2) float32
    charts: np.ndarray       # (c, 3) uint32


@type_check_only
class MeshFromArrays(MeshArrays):
    """`mesh_from_arrays`: the arrays and the repairs made."""
    degenerate_uv_triangles: int
    fallback_vertices: int
    replaced_normals: int


@type_check_only
class GltfPart(MeshArrays):
    """`load_gltf`: a node's primitives that share a material and uv presence, as one mesh."""
    material: Optional[int]
    has_uvs: bool            # False: no usable TEXCOORD_0 (uvs projected per triangle), drawn undisplaced
    primitives: list[int]
    tangent_source: Literal["file", "mikktspace"]
    flat_normals: int
    replaced_normals: int


@type_check_only
class GltfNode(TypedDict):
    """`load_gltf`: one mesh node of a glTF file."""
    name: str
    transform: list[float]   # 16, row-major: the node's world transform
    skipped: list[tuple[int, str]]   # (primitive, why): points, lines and arealess primitives left out
    parts: list[GltfPart]


@type_check_only
class GltfTexture(TypedDict):
    rgba: np.ndarray         # (H, W, 4) uint8, sRGB
    wrap: tuple[str, str]    # the sampler's wrapS, wrapT: "repeat", "clamp" or "mirror"
    tex_coord: int


@type_check_only
class GltfMaterial(TypedDict):
    name: Optional[str]
    base_color_factor: list[float]   # linear RGBA
    base_color_texture: Optional[GltfTexture]


@type_check_only
class GltfFile(TypedDict):
    nodes: list[GltfNode]
    materials: list[GltfMaterial]
    texture_errors: list[tuple[int, str]]


@type_check_only
class AdapterDict(TypedDict):
    name: str
    backend: str
    device_type: str
    driver: str


@type_check_only
class TessellationDict(TypedDict):
    """The displaced surface (`tessellate`)."""
    positions: np.ndarray    # (n, 3) float32
    normals: np.ndarray      # (n, 3) float32
    uvs: np.ndarray          # (n, 2) float32
    faces: np.ndarray        # (m, 3) uint32
    base_normals: np.ndarray  # (n, 3) float32, the base mesh's basis each vertex was displaced from
    tangents: np.ndarray     # (n, 4) float32, w the bitangent's sign
    uv_scale: np.ndarray     # (n, 2) float32, mesh uv per unit length along the tangents


@type_check_only
class OracleDict(TypedDict):
    """The CPU oracle's arrays (`oracle_hits`)."""
    uv: np.ndarray           # (H, W, 2) float64
    depth: np.ndarray        # (H, W) float64
    mask: np.ndarray         # (H, W) bool
    cells: np.ndarray        # (H, W) uint32
    visibility: np.ndarray   # (H, W) float64
    object: np.ndarray       # (H, W) int32, -1 where no hit


@type_check_only
class OracleImageDict(OracleDict):
    """`oracle_image`'s colour and coverage, and the oracle's frame at the pixel centres."""
    color: np.ndarray        # (H, W, 3) float32
    coverage: np.ndarray     # (H, W) float32


@type_check_only
class RendererInfo(TypedDict):
    name: str
    backend: str
    device_type: str
    driver: str
    timestamps: bool
    float32_filterable: bool
    max_texture_dimension_2d: int
    max_buffer_size: int
    max_storage_buffer_binding_size: int
    max_storage_buffers_per_shader_stage: int
    features: list[tuple[str, bool, str]]
    wgpu_version: str
    pipeline: Literal["auto", "raster", "compute"]
    auto_pipeline: Literal["raster", "compute"]


@final
class Renderer:
    def __new__(cls, adapter: Optional[str] = None, pipeline: str = "auto") -> "Renderer": ...
    def render(self, scene: Scene, method: Method, aovs: Optional[Sequence[str]] = None, spp: int = 1) -> RenderedFrame: ...
    def render_many(self, scenes: Sequence[Scene], method: Method,
                    aovs: Optional[Sequence[str]] = None, spp: int = 1) -> list[RenderedFrame]: ...
    def update_height(self, old: HeightData, new: HeightData) -> bool: ...
    def info(self) -> RendererInfo: ...
    def pipeline_probe(self) -> tuple[float, float]: ...
    # (builds with the test-hooks feature, the tests' own, add _provoke_validation_error and
    # _destroy_device; a user's wheel has neither, so the stub declares neither)

def adapters() -> list[AdapterDict]: ...
def oracle_hits(scene: Scene, light_bias: float = 0.0, shells: Optional[Shells] = None) -> OracleDict: ...
def light_power(light: Any) -> tuple[float, float, float]: ...
def bounding_sphere(scene: Scene) -> tuple[tuple[float, float, float], float]: ...
def oracle_image(scene: Scene, spp: int, shadows: bool = True, shells: Optional[Shells] = None) -> OracleImageDict: ...
def reference_normals(scene: Scene, object: int, uvs: np.ndarray, base_normals: np.ndarray, tangents: np.ndarray,
                      uv_scale: np.ndarray) -> np.ndarray: ...
def reference_directions(axes: np.ndarray, tan_r: np.ndarray, q: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]: ...
def tessellate(scene: Scene, texels_per_vertex: float, object: int = 0,
               pattern: Literal["fan", "grid"] = "fan") -> TessellationDict: ...
def mesh_from_arrays(positions: np.ndarray, normals: np.ndarray, uvs: np.ndarray, indices: np.ndarray,
                     tangents: Optional[np.ndarray] = None,
                     frames: Literal["pomkit", "mikktspace"] = "pomkit",
                     normals_mode: Literal["file", "recompute", "repair"] = "file") -> MeshFromArrays: ...
def load_gltf(path: str, normals: Literal["file", "recompute", "repair"] = "file") -> GltfFile: ...
def shell_findings(mesh: MeshData, depth: float) -> tuple[int, int]: ...
def check_asset(mesh: MeshData, height: Optional[HeightData] = None, tiling: float = 1.0,
                depth: Optional[float] = None) -> dict[str, Any]: ...
def mesh_plane(size: float, segments: int) -> MeshArrays: ...
def mesh_sphere(radius: float, segments: int, rings: int) -> MeshArrays: ...
def mesh_torus(major: float, minor: float, segments: int, tube_segments: int) -> MeshArrays: ...
def mesh_cylinder(radius: float, height: float, segments: int, rings: int) -> MeshArrays: ...
def mesh_cube(size: float, segments: int) -> MeshArrays: ...
def load_image(path: Any, kind: Literal["height", "albedo"]) -> tuple[np.ndarray, int]: ...
def set_progress_hook(hook: Optional[Callable[[str, int, int], None]]) -> None: ...
def set_cache_dir(path: Optional[str]) -> None: ...
def jod(test: np.ndarray, reference: np.ndarray, fps: float = 30.0, display: str = "standard_4k") -> float: ...
def jod_displays() -> list[str]: ...
