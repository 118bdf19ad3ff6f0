"""Procedural height maps: the scenes of the papers without shipping image files.

Every function returns a (size, size) float32 array in [0, 1] (h = 1 is the base surface),
tiles seamlessly, and is deterministic for a given seed.

The same bits on every machine: the maps are built from exactly rounded operations only (+, -,
*, /, sqrt, floor, comparisons) and numpy's PCG64 stream. No libm or SIMD transcendental
(sin, hypot, pow) is called, since those differ between CPUs (numpy dispatches them to SVML
where AVX-512 is present) and between C libraries; `sine` evaluates its sine as a polynomial,
`fit` averages areas with prefix sums. tests/test_hashes.py holds the digests. One exception:
`text` draws with Pillow's font rasteriser, whose glyphs may change with Pillow's version.
"""

from __future__ import annotations

from ._errors import ArgumentError, ArgumentTypeError, MissingExtraError
from typing import Callable, Optional

import numpy as np

from . import _validate as _v

__all__ = ["bricks", "brick_albedo", "cobblestones", "pyramids", "sine", "noise", "spikes", "text", "constant", "real", "fit", "normalize", "bake", "ALL"]


def _check_size(size) -> int:
    return _v.integer("size", size, 1, 16384, strict=True)


def _grid(size: int):
    c = (np.arange(size, dtype=np.float64) + 0.5) / size
    return np.meshgrid(c, c)  # u (columns), v (rows)


def _hypot(x, y):
    """sqrt(x^2 + y^2) from exactly rounded operations (np.hypot is libm's)."""
    return np.sqrt(x * x + y * y)


def _sin_turns(t):
    """sin(2 pi t) from exactly rounded operations: t reduced to a quarter turn r in
    [-1/4, 1/4] (exactly: t - floor(t + 1/2) and a reflection), then the Taylor polynomial of
    sin(2 pi r) to degree 25 (error below 1e-16), by Horner's rule."""
    t = np.asarray(t, np.float64)
    r = t - np.floor(t + 0.5)                      # [-1/2, 1/2)
    r = np.where(r > 0.25, 0.5 - r, np.where(r < -0.25, -0.5 - r, r))
    x = 2.0 * 3.141592653589793 * r                # [-pi/2, pi/2]
    x2 = x * x
    acc = np.zeros_like(x)
    for k in range(12, -1, -1):                    # terms x^(2k+1) / (2k+1)!
        acc = acc * x2 + _SIN_COEF[k]
    return acc * x


# (-1)^k / (2k+1)!, exact rationals rounded once
_SIN_COEF = []
_f = 1
for _k in range(13):
    _SIN_COEF.append((-1) ** _k / _f)
    _f *= (2 * _k + 2) * (2 * _k + 3)
del _f, _k


def _smoothstep(e0, e1, x):
    t = np.clip((x - e0) / (e1 - e0), 0.0, 1.0)
    return t * t * (3 - 2 * t)


def _finish(h) -> np.ndarray:
    return np.clip(h, 0.0, 1.0).astype(np.float32)


def constant(size: int = 64, value: float = 0.5) -> np.ndarray:
    """A flat map at height `value` (the analytic test case)."""
    size = _check_size(size)
    return np.full((size, size), float(value), dtype=np.float32)


def bricks(size: int = 512, rows: int = 8, cols: int = 4, mortar: float = 0.06, bevel: float = 0.04,
           mortar_height: float = 0.35, seed: int = 0) -> np.ndarray:
    """Running-bond bricks: bevelled brick tops near h = 1 (slightly varied per brick) with
    recessed mortar joints."""
    size = _check_size(size)
    u, v = _grid(size)
    rng = np.random.default_rng(seed)
    y = v * rows
    r = np.floor(y).astype(int)
    x = u * cols + 0.5 * (r % 2)
    c = np.floor(x).astype(int) % cols
    fx, fy = x - np.floor(x), y - np.floor(y)
    # distance to the brick's edge in brick-height units
    aspect = rows / cols
    dx = np.minimum(fx, 1 - fx) / aspect
    dy = np.minimum(fy, 1 - fy)
    d = np.minimum(dx, dy)
    top = 1.0 - 0.08 * rng.random((rows, cols))[r % rows, c]
    prof = _smoothstep(mortar * 0.5, mortar * 0.5 + bevel, d)
    return _finish(mortar_height + (top - mortar_height) * prof)


def brick_albedo(h: np.ndarray, seed: int = 1) -> np.ndarray:
    """An sRGB uint8 albedo for a `bricks` height map: brick reds on the tops, grey mortar below
    (the demo's plane)."""
    rng = np.random.default_rng(seed)
    t = np.clip((h - 0.45) / 0.3, 0.0, 1.0)[..., None]
    grain = 1.0 + 0.08 * (rng.random(h.shape)[..., None] - 0.5)
    brick = np.array([170.0, 74.0, 52.0]) * (0.85 + 0.3 * (h[..., None] - 0.9))
    mortar = np.array([150.0, 146.0, 138.0])
    return np.clip((mortar * (1 - t) + brick * t) * grain, 0, 255).astype(np.uint8)


def cobblestones(size: int = 512, cells: int = 12, seed: int = 0, gap: float = 0.08) -> np.ndarray:
    """Rounded stones on a Voronoi diagram (tileable), with gaps between them."""
    size = _check_size(size)
    u, v = _grid(size)
    rng = np.random.default_rng(seed)
    pts = (np.stack(np.meshgrid(np.arange(cells), np.arange(cells)), -1).reshape(-1, 2) + rng.random((cells * cells, 2))) / cells
    f1 = np.full(u.shape, np.inf)
    f2 = np.full(u.shape, np.inf)
    for ox in (-1, 0, 1):
        for oy in (-1, 0, 1):
            for p in pts:
                dd = _hypot(u - (p[0] + ox), v - (p[1] + oy))
                f2 = np.where(dd < f1, f1, np.minimum(f2, dd))
                f1 = np.minimum(f1, dd)
    edge = (f2 - f1) * cells  # 0 on the cell borders
    dome = np.sqrt(np.clip(1.0 - (f1 * cells / 0.9) ** 2, 0.0, 1.0))
    return _finish(0.15 + 0.85 * _smoothstep(gap, gap + 0.25, edge) * (0.6 + 0.4 * dome))


def pyramids(size: int = 512, count: int = 8) -> np.ndarray:
    """A grid of count x count square pyramids: apex h = 1, base h = 0."""
    size = _check_size(size)
    u, v = _grid(size)
    fx = (u * count) % 1.0
    fy = (v * count) % 1.0
    return _finish(1.0 - 2.0 * np.maximum(np.abs(fx - 0.5), np.abs(fy - 0.5)))


def sine(size: int = 512, freq: float = 4.0) -> np.ndarray:
    """0.5 + 0.5 sin(2 pi f u) sin(2 pi f v): smooth, with frequency `freq` per tile (an
    integer keeps it tileable)."""
    size = _check_size(size)
    u, v = _grid(size)
    return _finish(0.5 + 0.5 * _sin_turns(freq * u) * _sin_turns(freq * v))


def noise(size: int = 512, octaves: int = 6, base: int = 4, persistence: float = 0.5, seed: int = 0) -> np.ndarray:
    """Tileable fBm of periodic value noise, normalised to [0, 1]."""
    size = _check_size(size)
    rng = np.random.default_rng(seed)
    u, v = _grid(size)
    acc = np.zeros_like(u)
    amp, total = 1.0, 0.0
    for o in range(octaves):
        n = base * 2 ** o
        lattice = rng.random((n, n))
        x, y = u * n, v * n
        x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
        tx, ty = _smoothstep(0, 1, x - x0), _smoothstep(0, 1, y - y0)
        a = lattice[y0 % n, x0 % n]
        b = lattice[y0 % n, (x0 + 1) % n]
        c = lattice[(y0 + 1) % n, x0 % n]
        d = lattice[(y0 + 1) % n, (x0 + 1) % n]
        acc += amp * ((a * (1 - tx) + b * tx) * (1 - ty) + (c * (1 - tx) + d * tx) * ty)
        total += amp
        amp *= persistence
    acc /= total
    return _finish((acc - acc.min()) / max(acc.max() - acc.min(), 1e-12))


def spikes(size: int = 512, count: int = 64, radius_texels: float = 1.5, seed: int = 0) -> np.ndarray:
    """Thin cones (a few texels wide) reaching h = 1 on a floor at h = 0: the high-frequency
    stress case that fixed-step searches miss."""
    size = _check_size(size)
    rng = np.random.default_rng(seed)
    u, v = _grid(size)
    h = np.zeros_like(u)
    r = radius_texels / size
    for p in rng.random((count, 2)):
        dx = (u - p[0] + 0.5) % 1.0 - 0.5
        dy = (v - p[1] + 0.5) % 1.0 - 0.5
        h = np.maximum(h, 1.0 - _hypot(dx, dy) / r)
    return _finish(h)


def text(size: int = 512, message: str = "pomkit", raised: float = 1.0, background: float = 0.4) -> np.ndarray:
    """Raised letters (rendered with Pillow's built-in font) on a lower background."""
    size = _check_size(size)
    from PIL import Image, ImageDraw, ImageFilter, ImageFont

    img = Image.new("L", (size, size), 0)
    draw = ImageDraw.Draw(img)
    fsize = max(8, int(size / max(len(message), 1) * 1.6))
    try:
        font = ImageFont.load_default(size=fsize)
    except TypeError:  # Pillow < 10.1
        font = ImageFont.load_default()
    box = draw.textbbox((0, 0), message, font=font)
    w, h = box[2] - box[0], box[3] - box[1]
    draw.text(((size - w) / 2 - box[0], (size - h) / 2 - box[1]), message, fill=255, font=font)
    img = img.filter(ImageFilter.GaussianBlur(radius=max(size / 256, 0.5)))
    a = np.asarray(img, dtype=np.float64) / 255.0
    return _finish(background + (raised - background) * a)


#: name -> function, for sweeps over every map
ALL: dict[str, Callable[..., np.ndarray]] = {"bricks": bricks, "cobblestones": cobblestones, "pyramids": pyramids, "sine": sine,
       "noise": noise, "spikes": spikes, "text": text}


def _real_source(name: str) -> np.ndarray:
    if name in ("terrain", "seafloor"):
        try:
            from matplotlib.cbook import get_sample_data
        except ImportError:
            raise MissingExtraError(f"name: the {name!r} map is an elevation model that matplotlib ships; "
                              "pip install matplotlib (or pomkit[bench])") from None
        fname, key = ("jacksboro_fault_dem.npz", "elevation") if name == "terrain" else ("topobathy.npz", "topo")
        with np.load(get_sample_data(fname, asfileobj=False)) as z:
            return np.asarray(z[key], np.float64)
    try:
        import skimage.data
    except ImportError:
        raise MissingExtraError(f"name: the {name!r} map is a photograph that scikit-image ships; "
                          "pip install scikit-image (or pomkit[reference])") from None
    return np.asarray(getattr(skimage.data, name)(), np.float64)


#: real content, not made by pomkit: two elevation models and two photographs taken as heights
REAL: dict[str, str] = {
    "terrain": "Jacksboro fault, Tennessee: a USGS elevation model (344x403, int16 metres; matplotlib's sample data)",
    "seafloor": "topography and bathymetry, 91x120 (matplotlib's sample data)",
    "gravel": "a photograph of gravel, luminance as height (scikit-image's data.gravel)",
    "moon": "a photograph of the Moon's surface, luminance as height (scikit-image's data.moon)",
}


def real(name: str, size: Optional[int] = 128) -> np.ndarray:
    """A height map from real data that a dependency ships (see `REAL`): the largest centred
    square, resampled to `size`² by area averaging (None: kept at its own size and shape), and
    normalised as users normalise their maps: min to exactly 0, max to exactly 1."""
    if name not in REAL:
        raise ArgumentError(f"name: one of {', '.join(REAL)}, got {name!r}")
    return fit(_real_source(name), size)


def _area_resample(a: np.ndarray, n: int, axis: int) -> np.ndarray:
    """Resample `a` to `n` samples along `axis` by area averaging (a box filter over each output
    sample's footprint, fractional at its ends), from the cumulative sum: the integral of the
    piecewise-constant signal at the footprint's ends, differenced. Sequential sums and exact
    operations only, so the result is the same on every machine (Pillow's BOX filter was)."""
    m = a.shape[axis]
    a = np.moveaxis(a, axis, 0)
    c = np.concatenate([np.zeros((1,) + a.shape[1:]), np.cumsum(a, axis=0)], axis=0)  # C[i] = sum a[:i]
    x = np.arange(n + 1, dtype=np.float64) * m / n                                      # footprint ends
    i = np.minimum(np.floor(x).astype(np.int64), m - 1)
    f = (x - i)[(...,) + (None,) * (a.ndim - 1)]
    integral = c[i] + f * a[i]                                                          # int_0^x
    out = (integral[1:] - integral[:-1]) * (n / m)
    return np.moveaxis(out, 0, axis)


def fit(a, size: Optional[int] = 128) -> np.ndarray:
    """Any 2-D array (an elevation model, a photograph's luminance) as a height map: its largest
    centred square, resampled to `size`² by area averaging (None: kept at its own size and
    shape), and normalised as users normalise their maps: min to exactly 0, max to exactly 1."""
    a = np.asarray(a, np.float64)
    if a.ndim != 2:
        raise ArgumentError(f"a: expected a 2-D array, got shape {a.shape}")
    if size is not None:
        size = _check_size(size)
        n = min(a.shape)
        r0, c0 = (a.shape[0] - n) // 2, (a.shape[1] - n) // 2
        a = a[r0:r0 + n, c0:c0 + n]
        a = _area_resample(_area_resample(a, size, 0), size, 1)
    lo, hi = float(a.min()), float(a.max())
    return ((a - lo) / (hi - lo) if hi > lo else np.zeros_like(a)).astype(np.float32)


def normalize(h, base: Optional[float] = None) -> np.ndarray:
    """A height map stretched to fill [0, 1], as a float32 array of its shape.

    pomkit's h = 1 is the mesh's surface and h = 0 lies the material's depth below it. A map
    that holds heights lo..hi spends the shell's depth on heights it never takes: every march
    steps through the whole shell, so its steps are (hi - lo) times as fine on the relief as they
    could be (`check_asset` reports the range and `relief_depth`).

    base: None stretches lo..hi to 0..1; the relief then touches the mesh's surface (its top
    moves up by depth * (1 - hi)), and a material depth of depth * (hi - lo) keeps its shape.
    A number is the map's zero level (PlayCanvas's `heightMapBase`): the height that lies on the
    mesh's surface. It maps to 1 and lo to 0, so the surface stays where the map's author put
    it; a material depth of depth * (base - lo) keeps the relief. pomkit displaces inward only,
    so heights above `base` (relief that would stand out of the mesh) are clipped to 1, with a
    warning that counts them."""
    a = np.asarray(h, np.float64)
    if a.ndim != 2 or a.size == 0:
        raise ArgumentError(f"h: expected a non-empty 2-D height map, got shape {a.shape}")
    if not np.isfinite(a).all():
        raise ArgumentError("h: holds NaN or infinite heights; replace them before normalising")
    lo, hi = float(a.min()), float(a.max())
    if base is None:
        top = hi
    else:
        if isinstance(base, bool) or not isinstance(base, (int, float, np.integer, np.floating)):
            raise ArgumentTypeError(f"base: expected a number (the map's zero level) or None, got {type(base).__name__}")
        top = float(base)
        if not np.isfinite(top) or top <= lo:
            raise ArgumentError(f"base: the zero level must lie above the map's lowest height {lo:g}, got {top:g}")
        above = int((a > top).sum())
        if above:
            import warnings
            warnings.warn(f"normalize: {above} texels lie above the zero level base={top:g} (relief standing out of the "
                          f"mesh); pomkit displaces inward only, so they are clipped to the surface", stacklevel=2)
    if top <= lo:
        return np.ones_like(a, np.float32)
    return np.clip((a - lo) / (top - lo), 0.0, 1.0).astype(np.float32)


def bake(mesh, f: Callable[[np.ndarray], np.ndarray], size: int = 512, gutter: int = 4) -> np.ndarray:
    """A height map for `mesh`'s uv atlas: `f`, a function of the surface, evaluated where each
    texel centre lies on the mesh (`f(points)` takes (k, 3) float64 positions in the mesh's space
    and returns k heights in [0, 1]), as a (size, size) float32 array.

    A texel whose centre lies in a uv triangle takes f at that triangle's point (barycentric, as
    the rasteriser interpolates). A texel within `gutter` texels of a chart takes f at the nearest
    point of the nearest uv triangle, so that filtered samples near a chart's edge read the
    surface's own heights, and the two sides of a seam agree wherever f is continuous on the
    surface (to within the bilinear field's interpolation: pk.check_asset measures it). Texels
    farther from every chart hold the mean height. The map repeats (uvs wrap)."""
    size = _check_size(size)
    gutter = _v.integer("gutter", gutter, 0, 4096)
    if not callable(f):
        raise ArgumentTypeError(f"f: expected a function of (k, 3) positions, got {type(f).__name__}")
    pos = np.asarray(mesh.positions, np.float64)
    uv = np.asarray(mesh.uvs, np.float64) * size
    tri = np.asarray(mesh.indices, np.int64).reshape(-1, 3)
    best = np.full((size, size), np.inf)  # distance in texels to the point taken
    points = np.zeros((size, size, 3))
    reach = gutter + 0.5
    for t in tri:
        q = uv[t]
        area = (q[1, 0] - q[0, 0]) * (q[2, 1] - q[0, 1]) - (q[2, 0] - q[0, 0]) * (q[1, 1] - q[0, 1])
        if abs(area) < 1e-12:
            continue
        x0, y0 = np.ceil(q.min(0) - 0.5 - reach).astype(int)
        x1, y1 = np.floor(q.max(0) - 0.5 + reach).astype(int)
        xs, ys = np.meshgrid(np.arange(x0, x1 + 1), np.arange(y0, y1 + 1))
        c = np.stack([xs.ravel() + 0.5, ys.ravel() + 0.5], 1)
        # barycentric weights of the texel centres, then the nearest point of the triangle
        w1 = ((c[:, 0] - q[0, 0]) * (q[2, 1] - q[0, 1]) - (q[2, 0] - q[0, 0]) * (c[:, 1] - q[0, 1])) / area
        w2 = ((q[1, 0] - q[0, 0]) * (c[:, 1] - q[0, 1]) - (c[:, 0] - q[0, 0]) * (q[1, 1] - q[0, 1])) / area
        w = np.stack([1.0 - w1 - w2, w1, w2], 1)
        d = np.zeros(len(c))
        out = (w < 0).any(1)
        if out.any():
            dist = np.full(int(out.sum()), np.inf)
            wo = np.zeros((int(out.sum()), 3))
            for k in range(3):
                a, b = q[k], q[(k + 1) % 3]
                e = b - a
                s = np.clip(((c[out] - a) @ e) / (e @ e), 0.0, 1.0)
                dk = np.linalg.norm(a + s[:, None] * e - c[out], axis=1)
                better = dk < dist
                dist[better] = dk[better]
                wo[better] = 0.0
                wo[better, k] = 1.0 - s[better]
                wo[better, (k + 1) % 3] = s[better]
            w[out] = wo
            d[out] = dist
        take = (d <= reach) & (d < best[ys.ravel() % size, xs.ravel() % size])
        if not take.any():
            continue
        r, cc = ys.ravel()[take] % size, xs.ravel()[take] % size
        best[r, cc] = d[take]
        points[r, cc] = w[take] @ pos[t]
    filled = np.isfinite(best)
    if not (best == 0).any() and not filled.any():
        raise ArgumentError("mesh: no texel lies on or near any uv triangle; the uvs cover no texel of a map this size")
    h = np.zeros((size, size))
    vals = np.asarray(f(points[filled]), np.float64).reshape(-1)
    if vals.shape[0] != int(filled.sum()) or not np.all(np.isfinite(vals)):
        raise ArgumentError("f: must return one finite height per point")
    h[filled] = vals
    h[~filled] = h[filled].mean()
    return np.clip(h, 0.0, 1.0).astype(np.float32)
