"""The quad counter: the 2 x 2 pixel quads each triangle of a frame touches, by a software
rasteriser over the method's geometry (the base mesh, the prisms' faces, the displaced mesh),
the cost model's `quads` term (costfit.py's `cost_model`), and the SIMD groups that run in lock
step."""

from __future__ import annotations

import math

import numpy as np

from pomkit import _core, _methods, _scene
from pomkit._displaced import core_transform

#: the pixel block that runs in lock step (a SIMD group: 8 x 4 = 32 lanes, a warp)
GROUP = (4, 8)


def group_total(a: np.ndarray, block: tuple[int, int] = GROUP) -> float:
    """The work of a per-pixel count `a` (H, W) when the pixels of each `block` run in lock
    step: every lane waits for the block's longest, so each block costs its maximum times its
    size. Summed over the frame (the blocks tile it from the top-left; the edges' partial blocks
    count their own pixels)."""
    h, w = a.shape
    bh, bw = block
    ph, pw = -h % bh, -w % bw
    x = np.pad(a.astype(np.float64), ((0, ph), (0, pw)), constant_values=-np.inf)
    m = x.reshape((h + ph) // bh, bh, (w + pw) // bw, bw).max(axis=(1, 3))
    n = np.isfinite(x).reshape((h + ph) // bh, bh, (w + pw) // bw, bw).sum(axis=(1, 3))
    return float(np.sum(np.where(n > 0, m, 0.0) * n))


def _facing(positions: np.ndarray, faces: np.ndarray, transform: np.ndarray, eye: np.ndarray) -> np.ndarray:
    """Which triangles (counter-clockwise front faces, as the passes draw them) face `eye`."""
    p = positions @ transform[:3, :3].T + transform[:3, 3]
    a, b, c = p[faces[:, 0]], p[faces[:, 1]], p[faces[:, 2]]
    n = np.cross(b - a, c - a)
    return np.einsum("ij,ij->i", n, eye - a) > 0.0


def _to_pixels(camera: _scene.Camera, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """World points (N, 3) -> pixel coordinates (N, 2; x right, y down, the image's corners at
    (0, 0) and (width, height)) and their depth along the view direction."""
    f, r, u = camera.basis()
    d = p - np.asarray(camera.eye, np.float64)
    z = d @ f
    t = math.tan(math.radians(camera.fov_y) / 2)
    zs = np.where(z > 1e-9, z, 1e-9)
    x = (d @ r) / zs / (t * camera.width / camera.height)
    y = (d @ u) / zs / t
    return np.stack([(x + 1) / 2 * camera.width, (1 - y) / 2 * camera.height], -1), z


def _clipped(tri: np.ndarray, width: float, height: float) -> tuple[float, float]:
    """Area and bounding-box extent w + h of one triangle (3, 2) clipped to the image
    (Sutherland-Hodgman)."""
    poly = [tuple(v) for v in tri]
    for axis, bound, keep_below in ((0, 0.0, False), (0, width, True), (1, 0.0, False), (1, height, True)):
        out = []
        for k in range(len(poly)):
            a, b = poly[k], poly[(k + 1) % len(poly)]
            ina = a[axis] <= bound if keep_below else a[axis] >= bound
            inb = b[axis] <= bound if keep_below else b[axis] >= bound
            if ina:
                out.append(a)
            if ina != inb:
                w = (bound - a[axis]) / (b[axis] - a[axis])
                out.append((a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1])))
        poly = out
        if not poly:
            return 0.0, 0.0
    xs, ys = np.array([v[0] for v in poly]), np.array([v[1] for v in poly])
    area = 0.5 * abs(float(np.dot(xs, np.roll(ys, -1)) - np.dot(ys, np.roll(xs, -1))))
    return area, float(np.ptp(xs) + np.ptp(ys))


def quad_count(xy: np.ndarray, width: int, height: int) -> float:
    """The 2 x 2 pixel quads that triangles `xy` (N, 3, 2, in pixels) touch on a `width` x
    `height` image, summed: a GPU shades a triangle's fragments in whole quads, so a triangle of a
    pixel or less costs a quad (four lanes) and a long sliver a quad per two pixels of its length.
    Per triangle, the expected count over its placement within a pixel: the area of the triangle
    grown by the quad (its Minkowski sum with a 2 x 2 square) over the quad's area,
    (A + 2 (w + h) + 4) / 4, A its area and w x h its bounding box on the image (both clipped to
    the image; triangles wholly off it count none)."""
    if len(xy) == 0:
        return 0.0
    lo, hi = xy.min(1), xy.max(1)
    size = np.array([width, height], np.float64)
    on = ((np.clip(hi, 0, size) - np.clip(lo, 0, size)) > 0).all(1)
    e1, e2 = xy[:, 1] - xy[:, 0], xy[:, 2] - xy[:, 0]
    area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    extent = (hi - lo).sum(1)
    inside = (lo >= 0).all(1) & (hi <= size).all(1)
    for k in np.flatnonzero(on & ~inside):
        area[k], extent[k] = _clipped(xy[k], float(width), float(height))
    keep = on & (area > 0)
    return float(((area + 2.0 * extent + 4.0) / 4.0)[keep].sum())


def triangle_counts(scene: _scene.Scene, method) -> tuple[int, int, float]:
    """(`primitives`, `rasterised`, `quads`) of a frame, from one pass over its objects
    (Tessellated's displaced mesh built once). `quads` (`quad_count`) over the rasterised
    triangles that lie in front of the eye; for Prism over the base triangles, one shell face
    each (the shell's offset is left out)."""
    eye = np.asarray(scene.camera.eye, dtype=np.float64)
    submitted = facing = 0
    quads = 0.0
    for i, o in enumerate(scene.objects):
        tr = np.asarray(o.transform, dtype=np.float64)
        if isinstance(method, _methods.Tessellated):
            tr = core_transform(o)  # the tessellation is of the core's (unmirrored) mesh
            t = _core.tessellate(scene, float(method.texels_per_vertex), i, method.pattern)
            pos, faces = np.asarray(t["positions"], np.float64), np.asarray(t["faces"])
        else:
            pos, faces = np.asarray(o.mesh.positions, np.float64), np.asarray(o.mesh.indices).reshape(-1, 3)
        f = _facing(pos, faces, tr, eye)
        if isinstance(method, _methods.Prism):
            submitted += 2 * len(f)
            facing += len(f)
            drawn = np.ones_like(f)
        else:
            submitted += len(f)
            facing += int(f.sum())
            drawn = f
        xy, z = _to_pixels(scene.camera, pos @ tr[:3, :3].T + tr[:3, 3])
        tris = faces[drawn]
        front = (z[tris] > 1e-6).all(1)
        quads += quad_count(xy[tris[front]], scene.camera.width, scene.camera.height)
    return submitted, facing, quads


def primitives(scene: _scene.Scene, method) -> int:
    """The triangles a frame submits to the rasteriser for `method`: the base meshes' for the
    per-pixel methods, the displaced mesh's for Tessellated (its lattice at `texels_per_vertex`),
    and for Prism the shell's boundary (a top and a bottom per base triangle; the unshared sides
    of an open mesh's border are left out, a few per cent). What a user counts on their own
    scene to estimate the cost with the model's coefficients."""
    return triangle_counts(scene, method)[0]


def rasterised(scene: _scene.Scene, method) -> int:
    """The triangles of `primitives` that reach the rasteriser: the passes cull back faces, so
    those that face the camera. A closed mesh sends about half of what it submits. Prism: its
    tops where the base triangle faces the camera, and its bottoms (the base triangles turned
    inward) where it faces away; counted on the base mesh (the shell's offset is left out)."""
    return triangle_counts(scene, method)[1]


def quads(scene: _scene.Scene, method) -> float:
    """The 2 x 2 pixel quads the frame's rasterised triangles touch (`quad_count`): what the
    cost model charges the rasteriser and the fragment shader's partial quads, a term that grows
    with the triangles as they shrink below a few pixels (Tessellated's fine lattices)."""
    return triangle_counts(scene, method)[2]
