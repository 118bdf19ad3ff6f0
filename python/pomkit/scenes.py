"""Ready-made scenes and transforms: the scenes the docs, the demo and the tests share.

`translate`, `rotate` and `scale` build 4x4 object-to-world matrices for `pomkit.Object`.
"""

from __future__ import annotations

import numpy as np

from . import textures
from ._scene import Camera, DirectionalLight, Material, Mesh, Object, Scene

__all__ = ["translate", "rotate", "scale", "sunk_sphere", "cobbled", "wavy_sphere"]


def translate(x: float, y: float, z: float) -> np.ndarray:
    """A 4x4 translation (an object-to-world `transform`)."""
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


def scale(x: float, y: float, z: float) -> np.ndarray:
    """A 4x4 (non-uniform) scale."""
    return np.diag([float(x), float(y), float(z), 1.0])


def rotate(axis, degrees: float) -> np.ndarray:
    """A 4x4 rotation about `axis` by `degrees` (right-handed)."""
    a = np.asarray(axis, np.float64)
    x, y, z = a / np.linalg.norm(a)
    t = np.radians(degrees)
    c, s = np.cos(t), np.sin(t)
    m = np.eye(4)
    m[:3, :3] = [[c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
                 [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
                 [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)]]
    return m


def tilted_plane(height, theta: float = 60.0, size: int = 128, *, depth: float = 0.08, tiling: float = 1.0,
                 fov: float = 40.0, distance: float = 1.6, lights=(), ambient: float = 0.0, albedo=None,
                 extent: float = 1.0) -> Scene:
    """A plane under a height map, as the bench sweeps it: `pk.Mesh.plane(2.0)` under `height`, seen from `distance` at
    `theta` degrees from its normal, looking at the origin with the image's top towards -z (the
    far side at grazing angles), fov `fov`, `size` x `size` pixels. The one source of every tilted
    plane in the tests, the bench and the tables, each naming what it sets apart from these
    defaults. `extent` k makes the plane k times wider with the map tiled k times more, the same
    texels where the camera looks: the plane's open border (where the displaced surface ends,
    and past which the texture-space marches go on tiling) then lies farther out of view."""
    t = np.radians(theta)
    return Scene(mesh=Mesh.plane(2.0 * extent), material=Material(height, depth=depth, tiling=tiling * extent, albedo=albedo),
                 camera=Camera.look_at(eye=(0.0, distance * np.cos(t), distance * np.sin(t)), target=(0, 0, 0),
                                       up=(0, 0, -1), fov_y=fov, width=size, height=size),
                 lights=list(lights), ambient=ambient)


def cobbled(mesh: Mesh, size: int, tiles: float, map_size: int = 512) -> Scene:
    """Cobblestones (`map_size`², 8 cells) `tiles` times over a curved `mesh`, seen from above
    its rim at `size`², one light: the bench's and the tables' curved scene."""
    return Scene(mesh=mesh, material=Material(textures.cobblestones(map_size, cells=8), depth=0.12, tiling=tiles),
                 camera=Camera.look_at((0.0, 1.0, 2.8), fov_y=40, width=size, height=size),
                 lights=[DirectionalLight((-0.4, -1, -0.3), 3.0)])


def sunk_sphere(size: int = 256, *, sink: float = 0.3, floor_map: int = 128, sphere_map: int = 64,
                displaced: bool = True, cast_shadows: bool = True, with_sphere: bool = True) -> Scene:
    """Two objects: a displaced sphere (radius 0.5, cobblestones) sunk `sink` into a displaced
    brick floor, lit from the side so that the sphere casts its shadow onto the bricks.
    `displaced=False` sets both depths to 0 (the base meshes); `with_sphere=False` leaves the
    floor alone (the same light and camera)."""
    floor = Object(Mesh.plane(4.0), Material(textures.bricks(floor_map), depth=0.08 if displaced else 0.0, tiling=2.0))
    ball = Object(Mesh.sphere(0.5, 64, 32),
                  Material(textures.cobblestones(sphere_map, cells=6), depth=0.1 if displaced else 0.0, tiling=1.0),
                  translate(0.0, 0.5 - sink, 0.0))
    cam = Camera.look_at(eye=(0.2, 1.6, 2.6), target=(0.0, 0.15, 0.0), fov_y=40, width=size, height=size)
    return Scene(objects=[floor, ball] if with_sphere else [floor], camera=cam,
                 lights=[DirectionalLight((0.8, -1.0, -0.5), 3.0, cast_shadows=cast_shadows)], ambient=0.05)


def wavy_sphere(radius: float = 0.8, amplitude: float = 0.1, waves: int = 3, segments: int = 64,
                rings: int = 64) -> Mesh:
    """A closed surface of revolution about +Y, a sphere whose radius ripples with the polar angle:
    rho(phi) = radius + amplitude cos(2 waves phi). Bulges (convex both ways) alternate with
    necks where the profile is concave: saddles (the curvatures along and around of opposite
    sign). Closed, with poles and a seam like `Mesh.sphere` (u = angle around / 2 pi, v = phi /
    pi from the top). The test case for methods that approximate the base surface by a quadric
    (curved relief mapping fails at saddles)."""
    th = np.linspace(0.0, 2.0 * np.pi, segments + 1)
    ph = np.linspace(0.0, np.pi, rings + 1)
    T, P = np.meshgrid(th, ph)
    rho = radius + amplitude * np.cos(2.0 * waves * P)
    drho = -2.0 * waves * amplitude * np.sin(2.0 * waves * P)
    d = np.stack([np.sin(P) * np.cos(T), np.cos(P), np.sin(P) * np.sin(T)], -1)
    e_phi = np.stack([np.cos(P) * np.cos(T), -np.sin(P), np.cos(P) * np.sin(T)], -1)
    pos = (rho[..., None] * d).reshape(-1, 3)
    nrm = rho[..., None] * d - drho[..., None] * e_phi
    nrm = (nrm / np.linalg.norm(nrm, axis=-1, keepdims=True)).reshape(-1, 3)
    uv = np.stack([T / (2.0 * np.pi), P / np.pi], -1).reshape(-1, 2)
    idx = []
    w = segments + 1
    for j in range(rings):
        for i in range(segments):
            a, b, c, e = j * w + i, j * w + i + 1, (j + 1) * w + i, (j + 1) * w + i + 1
            if j > 0:
                idx += [a, b, c]
            if j < rings - 1:
                idx += [b, e, c]
    idx_a = np.asarray(idx, np.int64).reshape(-1, 3)
    # wound counter-clockwise seen from outside
    fn = np.cross(pos[idx_a[:, 1]] - pos[idx_a[:, 0]], pos[idx_a[:, 2]] - pos[idx_a[:, 0]])
    if (np.einsum("ij,ij->i", fn, nrm[idx_a[:, 0]]) < 0).mean() > 0.5:
        idx_a = idx_a[:, [0, 2, 1]]
    return Mesh.from_arrays(pos, nrm, uv, idx_a.astype(np.uint32))
