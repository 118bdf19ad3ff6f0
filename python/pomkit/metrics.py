"""Error metrics between a Frame and a reference Frame.

uv_error and depth_error compare geometry where both frames hit; flip, psnr and ssim compare
colour as displayed (sRGB, clamped to [0, 1]). Each returns plain floats or a typed dict
(`UvError`, `DepthError`, `ShadowError`, `Comparison`); pass `image=True` to the colour metrics to
also get a per-pixel error image for plotting (uv_error's result always holds one under "image").
"""

from __future__ import annotations

from typing import TypedDict, cast

from ._errors import ArgumentError, ArgumentTypeError, MissingExtraError
import numpy as np

from ._frame import Frame
from ._color import linear_to_srgb
from ._scene import Scene
from . import _core

__all__ = ["uv_error", "depth_error", "mask_iou", "shadow_error", "flip", "psnr", "ssim", "jod", "regions", "compare",
           "ErrorStats", "UvError", "DepthError", "ShadowError", "Comparison"]


class ErrorStats(TypedDict):
    """An error's distribution over the pixels compared (NaN and n = 0 where there are none)."""
    mean: float
    p50: float
    p95: float
    p99: float
    max: float
    n: int


class UvError(ErrorStats):
    """`uv_error`: texels, the mask IoU, and the per-pixel error (NaN where not compared)."""
    mask_iou: float
    image: np.ndarray


class DepthError(ErrorStats):
    """`depth_error`: relative or world units, and the per-pixel error (NaN where not compared)."""
    image: np.ndarray


class ShadowError(TypedDict):
    """`shadow_error`: see its docstring."""
    iou: float
    vis_error: float
    false_shadow: float
    false_light: float
    shadowed: float
    ref_shadowed: float
    n: int
    compared: float
    image: np.ndarray


class Comparison(TypedDict, total=False):
    """`compare`: the keys of what both frames hold (colour: the flip keys; uv: the uv keys;
    visibility and the oracle: the shadow keys)."""
    mask_iou: float
    interior_px: int
    silhouette_px: int
    flip_floor: float
    flip: float
    flip_interior: float
    flip_silhouette: float
    uv_p50_interior: float
    uv_p95_interior: float
    uv_p99_interior: float
    uv_p95_silhouette: float
    shadow_iou: float
    shadow_vis_error: float
    shadow_false_shadow: float
    shadow_false_light: float


def _check(frame, ref):
    for name, f in (("frame", frame), ("ref", ref)):
        if not isinstance(f, Frame):
            raise ArgumentTypeError(f"{name}: expected a pomkit.Frame, got {type(f).__name__}")
    if frame.shape != ref.shape:
        raise ArgumentError(f"ref: frame is {frame.shape} but ref is {ref.shape}; render both at one size")


def mask_iou(frame: Frame, ref: Frame) -> float:
    """Intersection over union of the coverage masks (1.0 when both are empty)."""
    _check(frame, ref)
    inter = np.logical_and(frame.mask, ref.mask).sum()
    union = np.logical_or(frame.mask, ref.mask).sum()
    return float(inter / union) if union else 1.0


def _stats(e: np.ndarray) -> ErrorStats:
    if e.size == 0:
        return ErrorStats(mean=float("nan"), p50=float("nan"), p95=float("nan"), p99=float("nan"), max=float("nan"), n=0)
    return ErrorStats(mean=float(e.mean()), p50=float(np.percentile(e, 50)), p95=float(np.percentile(e, 95)),
                      p99=float(np.percentile(e, 99)), max=float(e.max()), n=int(e.size))


def _texels(o) -> np.ndarray:
    """Texels per unit of u and v on an object: (W t, H t)."""
    h, w = o.material.height.shape
    t = o.material.tiling
    return np.array([w * t, h * t], np.float64)


def uv_error(frame: Frame, ref: Frame, scene: Scene) -> UvError:
    """uv error in texels (|du| W t, |dv| H t, Euclidean) over the pixels both frames hit:
    mean, p50, p95, p99, max, n, plus mask_iou and the per-pixel "image" (NaN elsewhere).

    In a scene of several objects, the pixels compared are those where both frames hit the same
    object (their `object` AOVs), each measured in its own object's texels."""
    _check(frame, ref)
    both = frame.mask & ref.mask & np.isfinite(frame.uv).all(-1) & np.isfinite(ref.uv).all(-1)
    scale = np.zeros(frame.mask.shape + (2,))
    if len(scene.objects) == 1:
        scale[:] = _texels(scene.objects[0])
    else:
        same = frame.object == ref.object
        both &= same
        for i, o in enumerate(scene.objects):
            scale[frame.object == i] = _texels(o)
    d = (np.asarray(frame.uv, np.float64) - np.asarray(ref.uv, np.float64)) * scale
    err = np.linalg.norm(d, axis=-1)
    img = np.where(both, err, np.nan)
    return cast(UvError, dict(_stats(err[both]), mask_iou=mask_iou(frame, ref), image=img))


def shadow_error(frame: Frame, ref: Frame, scene: Scene, *, uv_tol: float = 0.5, threshold: float = 0.5) -> ShadowError:
    """Self-shadowing against a reference, where both frames show the same surface point.

    Both frames need `visibility` (the first directional light's, in [0, 1]): take the method's
    from `Renderer.render_visibility(scene, method)` and the reference's from `pk.oracle.hits(scene)`
    (the exact float64 oracle; 64 directions over the light's disk when its
    `angular_diameter` > 0) or from `render_visibility` with `pk.Tessellated()` (its shadow map:
    an approximate reference, ~1.5 shadow-map texels at edges). Pixels are compared where both
    hit, both visibilities are defined (the light faces the shading normal) and the hits lie
    within `uv_tol` texels of each other: elsewhere the two frames shade different points, which
    uv_error measures. A pixel is in shadow where its visibility is below `threshold`.

    Returns: iou (of the shadow masks; 1.0 when neither has a shadow), vis_error (mean
    |visibility - reference visibility|), false_shadow and false_light (fractions of the compared
    pixels shadowed where the reference is lit, and lit where it is shadowed), shadowed and
    ref_shadowed (shadowed fractions), n (pixels compared), compared (n over the reference's
    hits), and "image" (signed visibility difference, NaN where not compared)."""
    _check(frame, ref)
    for name, f in (("frame", frame), ("ref", ref)):
        if not f.has("visibility"):
            raise ArgumentError(f"{name}: has no visibility; use renderer.render_visibility(scene, method) or, for the "
                             "reference, pk.oracle.hits(scene)")
    va = np.asarray(frame.visibility, np.float64)
    vb = np.asarray(ref.visibility, np.float64)
    both = frame.mask & ref.mask & np.isfinite(va) & np.isfinite(vb)
    if frame.has("uv") and ref.has("uv"):
        e = uv_error(frame, ref, scene)["image"]
        both &= np.nan_to_num(e, nan=np.inf) <= uv_tol
    a = (va < threshold) & both
    b = (vb < threshold) & both
    n = int(both.sum())
    union = int((a | b).sum())
    diff = np.where(both, va - vb, np.nan)
    return ShadowError(
        iou=float((a & b).sum() / union) if union else 1.0,
        vis_error=float(np.abs(diff[both]).mean()) if n else float("nan"),
        false_shadow=float((a & ~b).sum() / n) if n else float("nan"),
        false_light=float((b & ~a).sum() / n) if n else float("nan"),
        shadowed=float(a.sum() / n) if n else float("nan"),
        ref_shadowed=float(b.sum() / n) if n else float("nan"),
        n=n,
        compared=float(n / max(int(ref.mask.sum()), 1)),
        image=diff,
    )


def depth_error(frame: Frame, ref: Frame, relative: bool = True) -> DepthError:
    """Distance error where both hit: |d - d_ref| / d_ref (relative, default) or world units."""
    _check(frame, ref)
    both = frame.mask & ref.mask
    e = np.abs(np.asarray(frame.depth, np.float64) - ref.depth)
    if relative:
        e = e / np.abs(ref.depth)
    return cast(DepthError, dict(_stats(e[both]), image=np.where(both, e, np.nan)))


def _ldr(f: Frame) -> np.ndarray:
    if not f.has("color"):
        raise ArgumentError("frame: has no colour to compare (render with 'color' in aovs=)")
    return linear_to_srgb(f.color).astype(np.float32)


def flip(frame: Frame, ref: Frame, image: bool = False, ppd: float = 67.0):
    """NVIDIA FLIP (flip-evaluator, LDR, on the sRGB images), mean over the image.
    With image=True returns (mean, error map)."""
    _check(frame, ref)
    try:
        import flip_evaluator
    except ImportError:
        raise MissingExtraError("flip needs flip-evaluator: pip install pomkit[reference]") from None
    emap, mean, _ = flip_evaluator.evaluate(_ldr(ref), _ldr(frame), "LDR", inputsRGB=True, applyMagma=False,
                                            parameters={"ppd": ppd})
    mean = float(mean)
    return (mean, np.asarray(emap)) if image else mean


def _linear_video(x, name: str) -> np.ndarray:
    """Frames (a Frame, a list of Frames, or (T, H, W, 3) / (H, W, 3) linear RGB) as float32 linear
    RGB, misses black."""
    if isinstance(x, Frame):
        x = [x]
    if isinstance(x, (list, tuple)) and x and all(isinstance(f, Frame) for f in x):
        return np.stack([np.where(f.mask[..., None], f.color, 0.0) if f.has("mask") else f.color for f in x]).astype(np.float32)
    a = np.asarray(x, dtype=np.float32)
    if a.ndim not in (3, 4) or a.shape[-1] != 3:
        raise ArgumentError(f"{name}: expected a Frame, a list of Frames or an array of shape (frames, H, W, 3), got {a.shape}")
    return a


def jod(test, reference, fps: float = 30.0, display: str = "standard_4k") -> float:
    """ColorVideoVDP's JOD (Mantiuk et al. 2024; the pure-Rust `colorvideovdp` crate in the core)
    of `test` against `reference`: each a Frame (an image), a list of Frames (a video at `fps`) or
    an array of linear RGB frames (T, H, W, 3). 10 is no visible difference; each unit down, a
    difference more people would object to. The colours are shown as sRGB (clamped to [0, 1])
    on `display`, one of `_core.jod_displays()` (default: a 30-inch 4K monitor at 0.75 m,
    200 cd/m²)."""
    t, r = _linear_video(test, "test"), _linear_video(reference, "reference")
    if t.shape != r.shape:
        raise ArgumentError(f"reference: shape {r.shape}, the test's is {t.shape}; score videos of one size and length")
    enc = [np.ascontiguousarray(linear_to_srgb(np.clip(v, 0.0, 1.0)), dtype=np.float32) for v in (t, r)]
    return float(_core.jod(enc[0], enc[1], float(fps), display))


def psnr(frame: Frame, ref: Frame, image: bool = False):
    """Peak signal-to-noise ratio of the sRGB images in dB (inf when identical).
    With image=True returns (psnr, squared-error image)."""
    _check(frame, ref)
    se = ((_ldr(frame) - _ldr(ref)) ** 2).mean(-1)
    mse = float(se.mean())
    v = float("inf") if mse == 0 else float(10 * np.log10(1.0 / mse))
    return (v, se) if image else v


def ssim(frame: Frame, ref: Frame, image: bool = False):
    """Structural similarity (scikit-image) of the sRGB images. With image=True returns (ssim, map)."""
    _check(frame, ref)
    try:
        from skimage.metrics import structural_similarity
    except ImportError:
        raise MissingExtraError("ssim needs scikit-image: pip install pomkit[reference]") from None
    v, full = structural_similarity(_ldr(ref), _ldr(frame), channel_axis=-1, data_range=1.0, full=True)
    return (float(v), full.mean(-1)) if image else float(v)


def regions(frame: Frame, ref: Frame, band: int = 4) -> dict[str, np.ndarray]:
    """The pixel regions `compare` scores separately: `silhouette`, every pixel within `band`
    pixels of either frame's outline (the edge of its hit mask, where a planar method cannot
    follow the displaced outline, and where one sample per pixel aliases); `interior`, the pixels
    both frames hit outside that band. (Boolean (H, W) arrays.)"""
    _check(frame, ref)
    a, b = np.asarray(frame.mask, bool), np.asarray(ref.mask, bool)
    # the outline: pixels whose 8-neighbourhood holds both a hit and a miss, in either frame
    # (the frame's border is no outline)
    outline = (a ^ b) | (_grow(a, 1) & _grow(~a, 1)) | (_grow(b, 1) & _grow(~b, 1))
    sil = _grow(outline, band)
    return dict(interior=a & b & ~sil, silhouette=sil)


def _grow(m: np.ndarray, n: int) -> np.ndarray:
    """`m` dilated n times by the 3 x 3 square."""
    out = m.copy()
    for _ in range(n):
        p = np.pad(out, 1, constant_values=False)
        out = np.zeros_like(m)
        for dy in range(3):
            for dx in range(3):
                out |= p[dy:dy + m.shape[0], dx:dx + m.shape[1]]
    return out


def compare(frame: Frame, reference: Frame, scene: Scene, *, band: int = 4, visibility: Frame | None = None,
            oracle: Frame | None = None) -> Comparison:
    """A frame's error against a reference, decomposed (a planar method's outline error, the
    aliasing of one sample per pixel and the interior's displacement error are different
    failures):

    - `interior`: FLIP and uv error (texels) where both frames hit, farther than `band` pixels
      from either outline (`regions`);
    - `silhouette`: FLIP over the band around the outlines, and the mask IoU;
    - `shadows` (when `visibility` is the method's `Renderer.render_visibility` frame and
      `oracle` is `pk.oracle.hits(scene)`): `shadow_error`'s IoU, visibility error and fractions;
    - `whole`: FLIP over the whole frame.

    FLIP needs colour in both frames (flip-evaluator: the `reference` extra); uv needs uv in both.
    Returns a flat dict: flip, flip_interior, flip_silhouette, uv_p50_interior, uv_p95_interior,
    uv_p99_interior, uv_p95_silhouette, mask_iou, interior_px, silhouette_px, flip_floor (the
    reference's `noise_floor`: 0 for `pk.oracle.image`, NaN when unknown), and shadow_iou,
    shadow_vis_error, shadow_false_shadow, shadow_false_light when given."""
    reg = regions(frame, reference, band)
    out = Comparison(mask_iou=mask_iou(frame, reference), interior_px=int(reg["interior"].sum()),
                     silhouette_px=int(reg["silhouette"].sum()))
    # the reference's own noise: the floor under every FLIP against it (0 for pk.oracle.image)
    floor = getattr(reference, "noise_floor", None)
    out["flip_floor"] = float("nan") if floor is None else float(floor)
    if frame.has("color") and reference.has("color"):
        whole, emap = flip(frame, reference, image=True)
        out["flip"] = whole

        def region_flip(m: np.ndarray) -> float:
            return float(emap[m].mean()) if m.any() else float("nan")
        out["flip_interior"] = region_flip(reg["interior"])
        out["flip_silhouette"] = region_flip(reg["silhouette"])
    if frame.has("uv") and reference.has("uv"):
        e = uv_error(frame, reference, scene)["image"]
        for k, m in reg.items():
            v = e[m & np.isfinite(e)]
            st = _stats(v)
            if k == "interior":
                out["uv_p50_interior"], out["uv_p95_interior"], out["uv_p99_interior"] = st["p50"], st["p95"], st["p99"]
            else:
                out["uv_p95_silhouette"] = st["p95"]
    if visibility is not None and oracle is not None:
        sh = shadow_error(visibility, oracle, scene)
        out["shadow_iou"], out["shadow_vis_error"] = sh["iou"], sh["vis_error"]
        out["shadow_false_shadow"], out["shadow_false_light"] = sh["false_shadow"], sh["false_light"]
    return out
