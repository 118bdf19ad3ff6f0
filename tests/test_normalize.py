"""A height map's range, normalised and reported (issue 68): `pk.textures.normalize` stretches a
map to [0, 1] (with an optional zero level, PlayCanvas's `heightMapBase`), and `check_asset`
reports the range a map uses, the depth that range gives the relief, and what normalising
changes. docs/tables/stability.md measures normalising against more layers."""

from __future__ import annotations

import numpy as np
import pytest

import pomkit as pk


def _squeezed(lo=0.55, hi=0.85, size=64):
    return lo + (hi - lo) * pk.textures.real("terrain", size)


def test_normalize_stretches_the_range_to_zero_one():
    h = _squeezed()
    n = pk.textures.normalize(h)
    assert n.dtype == np.float32 and n.shape == h.shape
    assert n.min() == 0.0 and n.max() == 1.0
    # an affine map of the heights: the relief's shape is kept
    lo, hi = h.min(), h.max()
    np.testing.assert_allclose(n, (h - lo) / (hi - lo), atol=1e-6)


def test_a_zero_level_lies_on_the_mesh_and_relief_above_it_is_clipped_and_counted():
    h = _squeezed()
    base = 0.8
    with pytest.warns(UserWarning, match=r"texels lie above the zero level base=0.8"):
        n = pk.textures.normalize(h, base=base)
    above = h > base
    assert above.any() and (n[above] == 1.0).all()
    np.testing.assert_allclose(n[~above], (h[~above] - h.min()) / (base - h.min()), atol=1e-6)
    assert n.min() == 0.0


@pytest.mark.parametrize("base,match", [(0.1, "base: the zero level must lie above"), ("x", "base: expected a number")])
def test_a_bad_zero_level_names_the_argument(base, match):
    with pytest.raises(pk.ArgumentError if base != "x" else pk.ArgumentTypeError, match=match):
        pk.textures.normalize(_squeezed(), base=base)


def test_check_asset_reports_the_range_its_depth_and_the_remedy():
    h = _squeezed()
    depth = 0.08
    r = pk.check_asset(pk.Mesh.plane(), pk.Material(h, depth=depth))
    assert r.height_min == pytest.approx(float(h.min()), abs=1e-6)
    assert r.height_max == pytest.approx(float(h.max()), abs=1e-6)
    assert r.relief_depth == pytest.approx(depth * (float(h.max()) - float(h.min())), rel=1e-5)
    warning = next(w for w in r.warnings if "holds only" in w)
    assert "pk.textures.normalize" in warning and f"{depth * (h.max() - h.min()):.4g}" in warning
    fixed = pk.check_asset(pk.Mesh.plane(), pk.Material(pk.textures.normalize(h), depth=r.relief_depth))
    assert (fixed.height_min, fixed.height_max) == (0.0, 1.0)
    assert fixed.relief_depth == pytest.approx(r.relief_depth)
    assert not any("holds only" in w for w in fixed.warnings)
    assert "heights used" in str(r)


def test_without_a_map_the_range_is_not_reported():
    r = pk.check_asset(pk.Mesh.plane())
    assert r.height_min is None and r.height_max is None and r.relief_depth is None
