"""The asset zoo: meshes pomkit did not generate, unwrapped by xatlas (seams, charts, gutters),
with height maps baked over their atlas by `pk.textures.bake`.

- `rock`: a closed, lumpy icosphere (1280 triangles), smooth normals, an xatlas atlas;
- `terrain`: a height-field patch with open borders, an xatlas atlas;
- `mirrored_slab`: a gently curved slab whose left half mirrors the right half's uvs about the
  middle (one chart folded onto itself, as symmetric game assets are);
- `crate`: a box with split normals at its 12 hard edges (24 vertices), an xatlas atlas;
- `big`: a lumpy icosphere of 20480 triangles, an xatlas atlas;
- `thin_wing`, `post`, `flipped_cap`, `cards`: kinds of the corpus of other people's models the
  zoo lacked (docs/assets.md, "Assets from the wild"): a flat-shaded wing thinner than the shell
  near its trailing edge, a flat-shaded thin box, a disc whose centre normal points against its
  face, a cloud of separate quads (open borders everywhere, some seen from behind);
- `smooth_box`: the crate's 12 triangles with one normal a corner, the mean of its three faces'
  (54.7 degrees from each face at the corners): the default cube of a modelling tool exported
  smooth-shaded, whose normals curve where its faces do not.

Each returns (mesh, height). The fields baked are 3-D functions of the surface point, so the two
sides of a seam agree to within the bilinear field's interpolation.
"""

from __future__ import annotations

import functools

import numpy as np

import pomkit as pk


def _lumps(p: np.ndarray) -> np.ndarray:
    """A smooth 3-D field in [0, 1]: a few plane waves."""
    s = np.sin(5.0 * p[:, 0] + 1.0) * np.sin(4.0 * p[:, 1] - 0.5) * np.sin(6.0 * p[:, 2] + 0.3)
    return 0.5 + 0.5 * s


def _cells(p: np.ndarray) -> np.ndarray:
    """Sharper 3-D content: cobbles from a 3-D lattice's distance to its nearest point."""
    q = p * 6.0
    f = q - np.floor(q) - 0.5
    d = np.sqrt((f * f).sum(1))
    return np.clip(1.0 - 1.6 * d, 0.0, 1.0) ** 0.5


def _unwrap(positions: np.ndarray, normals: np.ndarray, faces: np.ndarray, padding: int = 4, resolution: int = 256):
    """xatlas's atlas of a mesh: vertices split along the seams, uvs in [0, 1] turned from
    xatlas's v-up convention to pomkit's (v down)."""
    import xatlas

    atlas = xatlas.Atlas()
    atlas.add_mesh(positions.astype(np.float32), faces.astype(np.uint32), normals.astype(np.float32))
    po = xatlas.PackOptions()
    po.padding = padding
    po.resolution = resolution
    atlas.generate(pack_options=po)
    vmap, idx, uvs = atlas[0]
    uvs = np.stack([uvs[:, 0], 1.0 - uvs[:, 1].astype(np.float64)], 1)
    return positions[vmap], normals[vmap], uvs, idx


def _lumpy_sphere(subdivisions: int):
    import trimesh

    s = trimesh.creation.icosphere(subdivisions=subdivisions)
    v = np.asarray(s.vertices, np.float64)
    r = 0.8 + 0.12 * np.sin(3.0 * v[:, 0] + 1.0) * np.cos(2.0 * v[:, 1]) + 0.06 * np.sin(5.0 * v[:, 2])
    s = trimesh.Trimesh(v * r[:, None], s.faces, process=False)
    return np.asarray(s.vertices), np.asarray(s.vertex_normals), np.asarray(s.faces)


def _atlas_sphere(subdivisions: int, size: int, field):
    p, n, f = _lumpy_sphere(subdivisions)
    p, n, uv, idx = _unwrap(p, n, f, resolution=size)
    mesh = pk.Mesh.from_arrays(p, n, uv, idx, tangents="mikktspace")
    return mesh, pk.textures.bake(mesh, field, size)


@functools.lru_cache(maxsize=None)
def rock(size: int = 256):
    return _atlas_sphere(3, size, _cells)


@functools.lru_cache(maxsize=None)
def big(size: int = 512):
    return _atlas_sphere(5, size, _lumps)


@functools.lru_cache(maxsize=None)
def terrain(size: int = 256):
    k = 24
    x, z = np.meshgrid(np.linspace(-1.0, 1.0, k + 1), np.linspace(-1.0, 1.0, k + 1))
    y = 0.15 * np.sin(2.0 * x + 0.5) * np.cos(1.5 * z)
    p = np.stack([x, y, z], -1).reshape(-1, 3)
    gx = 0.3 * np.cos(2.0 * x + 0.5) * np.cos(1.5 * z)
    gz = -0.225 * np.sin(2.0 * x + 0.5) * np.sin(1.5 * z)
    n = np.stack([-gx, np.ones_like(x), -gz], -1).reshape(-1, 3)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    w = k + 1
    f = []
    for j in range(k):
        for i in range(k):
            a = j * w + i
            f += [[a, a + w, a + 1], [a + 1, a + w, a + w + 1]]
    p, n, uv, idx = _unwrap(p, n, np.asarray(f), resolution=size)
    mesh = pk.Mesh.from_arrays(p, n, uv, idx, tangents="mikktspace")
    return mesh, pk.textures.bake(mesh, _lumps, size)


@functools.lru_cache(maxsize=None)
def mirrored_slab(size: int = 128):
    """A slab curved about the Z axis, x in [-1, 1]; u = |x| (mirrored about x = 0), v along z."""
    k = 16
    x, z = np.meshgrid(np.linspace(-1.0, 1.0, 2 * k + 1), np.linspace(-0.6, 0.6, k + 1))
    y = 0.25 * (1.0 - x * x)
    p = np.stack([x, y, z], -1).reshape(-1, 3)
    n = np.stack([0.5 * x, np.ones_like(x), np.zeros_like(x)], -1).reshape(-1, 3)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    uv = np.stack([0.05 + 0.9 * np.abs(x), 0.05 + 0.9 * (z + 0.6) / 1.2], -1).reshape(-1, 2)
    w = 2 * k + 1
    f = []
    for j in range(k):
        for i in range(2 * k):
            a = j * w + i
            f += [[a, a + w, a + 1], [a + 1, a + w, a + w + 1]]
    # the axis's vertices split, as an exporter writes a mirrored asset: each side's tangent has
    # its own handedness (a vertex shared across the axis would carry one for both)
    f = np.asarray(f)
    axis = np.arange(k + 1) * w + k
    dup = {int(v): len(p) + i for i, v in enumerate(axis)}
    left = (p[f][:, :, 0] < 0.0).any(axis=1)
    f[left] = np.vectorize(lambda v: dup.get(int(v), int(v)))(f[left])
    p, n, uv = (np.concatenate([a, a[axis]]) for a in (p, n, uv))
    mesh = pk.Mesh.from_arrays(p, n, uv, f, tangents="mikktspace")
    return mesh, pk.textures.bake(mesh, _cells, size)


@functools.lru_cache(maxsize=None)
def crate(size: int = 256):
    """A box of edge 1.2 with one normal per face: every edge is hard."""
    p, n, f = [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            nn = np.zeros(3)
            nn[axis] = sign
            u, v = np.zeros(3), np.zeros(3)
            u[(axis + 1) % 3], v[(axis + 2) % 3] = 1.0, 1.0
            base = len(p)
            for a, b in ((-1, -1), (1, -1), (-1, 1), (1, 1)):
                p.append(0.6 * (nn + a * u + b * v))
                n.append(nn)
            q = [[base, base + 1, base + 2], [base + 1, base + 3, base + 2]]
            fn = np.cross(p[base + 1] - p[base], p[base + 2] - p[base])
            f += q if fn @ nn > 0 else [[t[0], t[2], t[1]] for t in q]
    p, n, uv, idx = _unwrap(np.asarray(p), np.asarray(n), np.asarray(f), resolution=size)
    mesh = pk.Mesh.from_arrays(p, n, uv, idx, tangents="mikktspace")
    return mesh, pk.textures.bake(mesh, _cells, size)


@functools.lru_cache(maxsize=None)
def smooth_box(size: int = 256):
    """The crate with each vertex's normal averaged over the faces that meet at its corner."""
    mesh, h = crate(size)
    p = np.asarray(mesh.positions, np.float64)
    n = np.sign(p) / np.sqrt(3.0)
    return pk.Mesh.from_arrays(p, n, mesh.uvs, mesh.indices, tangents="mikktspace"), h

def faceted_sphere(segments: int = 96, size: int = 128):
    """A uv sphere shaded flat: every triangle has its own corners and its face's normal, so that every
    edge is hard (as SphereWithLightUvScaling4X.ac of assimp's test models is), with the poles'
    triangles that have no area left out; at `segments` 200 its triangles are narrower than
    the shell is deep at depth 0.04. Its heights: zoo.crate's bricks."""
    base = pk.Mesh.sphere(1.0, segments, max(segments // 2, 2))
    p = np.asarray(base.positions, np.float64)
    uv = np.asarray(base.uvs, np.float64)
    tri = np.asarray(base.indices).reshape(-1, 3)
    fn = np.cross(p[tri[:, 1]] - p[tri[:, 0]], p[tri[:, 2]] - p[tri[:, 0]])
    area = np.linalg.norm(fn, axis=1)
    tri, fn = tri[area > 1e-9], fn[area > 1e-9] / area[area > 1e-9, None]
    mesh = pk.Mesh.from_arrays(p[tri].reshape(-1, 3), np.repeat(fn, 3, axis=0), uv[tri].reshape(-1, 2),
                               np.arange(3 * len(tri), dtype=np.uint32), tangents="mikktspace")
    return mesh, crate(size)[1]


def cracked_plane(size: int = 128):
    """A 2 x 2 plane (y up) in two halves that meet along x = 0 without sharing an edge: the left
    half cut into 4 rows, the right into 6, so that the halves' border edges run along each
    other (T-junctions, as hand-made low-poly models have where parts were modelled apart). The
    uvs are planar across both halves, so the surface goes on across the crack. Its heights:
    zoo.crate's bricks."""
    def grid(x0: float, x1: float, rows: int):
        xs, zs = np.linspace(x0, x1, 3), np.linspace(-1.0, 1.0, rows + 1)
        X, Z = np.meshgrid(xs, zs)
        p = np.stack([X.ravel(), np.zeros(X.size), Z.ravel()], -1)
        tri = []
        for j in range(rows):
            for i in range(2):
                a, b = j * 3 + i, j * 3 + i + 1
                c, d = a + 3, b + 3
                tri += [(a, c, b), (b, c, d)]
        return p, np.array(tri)
    (pl, tl), (pr, tr) = grid(-1.0, 0.0, 4), grid(0.0, 1.0, 6)
    p = np.concatenate([pl, pr])
    tri = np.concatenate([tl, tr + len(pl)])
    uv = np.stack([(p[:, 0] + 1.0) / 2.0, (p[:, 2] + 1.0) / 2.0], -1)
    n = np.tile([0.0, 1.0, 0.0], (len(p), 1))
    return pk.Mesh.from_arrays(p, n, uv, tri.astype(np.uint32).ravel()), crate(size)[1]


def split_plane(size: int = 128, depth: float = 0.1):
    """cracked_plane's two halves as two objects, as a model split into primitives by material
    is: the left half as it stands, the right half modelled 3 units to the right at twice the
    size and placed back by its transform (a scale of 0.5, its depth halved with it). The crack
    runs between the objects, so that no mesh of its own shows it."""
    mesh, h = cracked_plane(size)
    p, uv = mesh.positions, mesh.uvs
    tri = np.asarray(mesh.indices, np.int64).reshape(-1, 3)
    objs = []
    for right in (False, True):
        keep = tri[(p[tri].mean(1)[:, 0] > 0.0) == right]
        used, idx = np.unique(keep, return_inverse=True)
        q = p[used].copy()
        m = np.eye(4)
        if right:
            q = (q + [3.0, 0.0, 0.0]) * 2.0
            m = np.diag([0.5, 0.5, 0.5, 1.0]) @ np.array([[1, 0, 0, -6.0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
        n = np.tile([0.0, 1.0, 0.0], (len(q), 1))
        half = pk.Mesh.from_arrays(q, n, uv[used], idx.astype(np.uint32).ravel())
        objs.append(pk.Object(half, pk.Material(h, depth=depth * (2.0 if right else 1.0)), transform=m))
    return objs


def _faceted(p, faces, size: int = 128):
    """A flat-shaded mesh of `faces` (polygons of indices into `p`, counter-clockwise seen from
    outside): each face its own corners and its face's normal, so that every edge is hard;
    triangulated as fans, unwrapped by xatlas, with zoo.crate's cells baked over the atlas."""
    p = np.asarray(p, np.float64)
    q, n, f = [], [], []
    for poly in faces:
        c = p[list(poly)]
        nn = np.cross(c[1] - c[0], c[2] - c[0])
        nn /= np.linalg.norm(nn)
        base = len(q)
        q += list(c)
        n += [nn] * len(c)
        f += [[base, base + k, base + k + 1] for k in range(1, len(c) - 1)]
    q, n, uv, idx = _unwrap(np.asarray(q), np.asarray(n), np.asarray(f), resolution=size)
    mesh = pk.Mesh.from_arrays(q, n, uv, idx, tangents="mikktspace")
    return mesh, pk.textures.bake(mesh, _cells, size)


@functools.lru_cache(maxsize=None)
def thin_wing(size: int = 128):
    """A wing of chord 1 and span 2, flat-shaded (every edge hard), 0.08 thick at its blunt
    leading edge and tapering to a 4.6-degree trailing edge: from midchord back it is thinner
    than a shell 0.04 deep, so a wall down one side's normal at the trailing edge comes out of
    the other side (crrcsim's gliders, Fireworks_C.ac)."""
    p = [(0, 0.04, -1), (0, -0.04, -1), (1, 0, -1), (0, 0.04, 1), (0, -0.04, 1), (1, 0, 1)]
    faces = [(0, 3, 5, 2), (1, 2, 5, 4), (0, 1, 4, 3), (0, 2, 1), (3, 4, 5)]
    return _faceted(p, faces, size)


@functools.lru_cache(maxsize=None)
def post(size: int = 128):
    """A box post 0.15 x 1.2 x 0.15, flat-shaded (minetest's fence gates: boxes whose corners
    bent CurvedRelief's quadric on their flat faces)."""
    x, y, z = 0.075, 0.6, 0.075
    p = [(-x, -y, -z), (x, -y, -z), (x, y, -z), (-x, y, -z), (-x, -y, z), (x, -y, z), (x, y, z), (-x, y, z)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (3, 7, 6, 2), (0, 4, 7, 3), (1, 2, 6, 5)]
    return _faceted(p, faces, size)


def flipped_cap(segments: int = 16):
    """A flat disc of radius 1 in y = 0 (normal +Y), a fan of `segments` triangles about its
    centre, whose centre vertex carries the normal -Y, against its face, and its rim +Y (the
    sum agrees with the face), as openarena's fan.md3 has its hub's caps."""
    a = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    rim = np.c_[np.cos(a), np.zeros(segments), -np.sin(a)]
    p = np.vstack([[0.0, 0.0, 0.0], rim])
    n = np.tile([0.0, 1.0, 0.0], (segments + 1, 1))
    n[0] = (0.0, -1.0, 0.0)
    uv = 0.5 + 0.45 * p[:, [0, 2]]
    idx = np.array([[0, 1 + k, 1 + (k + 1) % segments] for k in range(segments)], np.uint32)
    return pk.Mesh.from_arrays(p.astype(np.float32), n.astype(np.float32), uv.astype(np.float32), idx.ravel())


def cards(n: int = 120, seed: int = 3):
    """`n` separate square quads (0.16-0.4 across, at random places and orientations in the cube
    [-1, 1]^3), each its own [0, 1]^2 chart, as effect and foliage models are built (openarena's
    kamwave.md3: stacks of sprite cards): 4n open border sides, and from any view some quads face
    away."""
    rng = np.random.default_rng(seed)
    p, nrm, uv, idx = [], [], [], []
    for k in range(n):
        c = rng.uniform(-1.0, 1.0, 3)
        a = rng.normal(size=3)
        a /= np.linalg.norm(a)
        b = np.cross(a, rng.normal(size=3))
        b /= np.linalg.norm(b)
        s = rng.uniform(0.08, 0.2)
        p += [c - s * a - s * b, c + s * a - s * b, c + s * a + s * b, c - s * a + s * b]
        nrm += [np.cross(a, b)] * 4
        uv += [(0, 0), (1, 0), (1, 1), (0, 1)]
        idx += [4 * k, 4 * k + 1, 4 * k + 2, 4 * k, 4 * k + 2, 4 * k + 3]
    return pk.Mesh.from_arrays(np.array(p, np.float32), np.array(nrm, np.float32), np.array(uv, np.float32),
                               np.array(idx, np.uint32))


ZOO = {"rock": rock, "terrain": terrain, "mirrored_slab": mirrored_slab, "crate": crate, "big": big}


def views(mesh, n: int = 3, size: int = 96, fov: float = 35.0, elevations=None):
    """`n` cameras around the mesh's bounding sphere, from 35 degrees above the equator, or one
    from each of `elevations` (degrees)."""
    elevations = (35.0,) * n if elevations is None else tuple(elevations)
    n = len(elevations)
    lo, hi = mesh.positions.min(0), mesh.positions.max(0)
    c = 0.5 * (lo + hi)
    r = 0.5 * float(np.linalg.norm(hi - lo))
    d = r / np.sin(np.radians(fov) / 2.0) * 1.05
    out = []
    for k in range(n):
        a = 2.0 * np.pi * k / n + 0.4
        e = np.radians(elevations[k])
        eye = c + d * np.array([np.cos(e) * np.cos(a), np.sin(e), np.cos(e) * np.sin(a)])
        out.append(pk.Camera.look_at(tuple(eye), tuple(c), fov_y=fov, width=size, height=size))
    return out


def scene(name: str, camera, depth: float = 0.04):
    mesh, h = ZOO[name]()
    return pk.Scene(mesh=mesh, material=pk.Material(h, depth=depth), camera=camera,
                    lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)], ambient=0.1)


def interior_holes(mask: np.ndarray, inside: np.ndarray) -> int:
    """Pixels of `inside` (the reference's coverage, eroded by 3 pixels) that `mask` misses."""
    from scipy import ndimage

    core = ndimage.binary_erosion(inside, iterations=3)
    return int((core & ~mask).sum())
