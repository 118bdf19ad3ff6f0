"""pk.Custom: a method written in WGSL, run by pomkit's surface pass (docs/custom_methods.md)."""

from pathlib import Path

import numpy as np
import pytest

import pomkit as pk
from conftest import plane_scene

EXAMPLES = Path(pk.__file__).parent / "wgsl"
STEEP = (EXAMPLES / "steep_custom.wgsl").read_text()
ENGINE = (EXAMPLES / "engine_pom.wgsl").read_text()


@pytest.mark.parametrize("theta", [0.0, 45.0, 80.0])
@pytest.mark.parametrize("shadows", ["none", "hard", "soft"])
def test_custom_steep_matches_the_builtin_bit_for_bit(renderer, theta, shadows):
    scene = plane_scene(pk.textures.bricks(128), theta_deg=theta, size=64,
                        lights=[pk.DirectionalLight((-0.4, -1, -0.3), 3.0, 2.0)], ambient=0.1)
    # the same field for both (SteepParallax marches level 0 by default, a Custom method the
    # footprint's level unless told)
    for mip in (False, True):
        a = renderer.render(scene, pk.SteepParallax(steps=24, shadows=shadows, mip_filtering=mip))
        b = renderer.render(scene, pk.Custom(wgsl=STEEP, name="steep_custom", params={"steps": 24.0}, shadows=shadows,
                                             mip_filtering=mip))
        for aov in ("color", "uv", "depth", "mask", "steps", "lod", "flags"):
            assert np.array_equal(getattr(a, aov), getattr(b, aov), equal_nan=True), (aov, mip)


def test_engine_style_pom_converges_toward_the_oracle(renderer):
    """The engine-style loop is an approximation: with more layers its error against the exact
    hit must shrink, and it must hit where the oracle does."""
    scene = plane_scene(pk.textures.pyramids(128), theta_deg=60.0, size=64)
    o = pk.oracle.hits(scene)
    errs = []
    for n in (8.0, 64.0):
        f = renderer.render(scene, pk.Custom(wgsl=ENGINE, name="engine_pom", params={"min_layers": n, "max_layers": n, "divide_by_z": 1.0}))
        m = f.mask & o.mask
        assert m.sum() > 0.9 * o.mask.sum()
        errs.append(np.percentile(np.linalg.norm((f.uv[m] - o.uv[m]) * 128, axis=-1), 95))
    assert errs[1] < errs[0], errs


def test_a_wgsl_error_is_a_value_error_naming_wgsl_with_the_line(renderer):
    bad = "#import pomkit::march::{Ray, Hit}\n\nfn march(r: Ray) -> Hit {\n    return undefined_hit;\n}\n"
    scene = plane_scene(pk.textures.bricks(32), size=16)
    with pytest.raises(ValueError) as e:
        renderer.render(scene, pk.Custom(wgsl=bad, name="broken"))
    msg = str(e.value)
    assert msg.startswith("wgsl:") and "broken.wgsl" in msg and ":4:" in msg, msg
    # the renderer stays usable
    assert renderer.render(scene, pk.POM()).mask.any()


@pytest.mark.parametrize("kwargs,arg", [
    (dict(wgsl="fn nothing() {}"), "wgsl"),
    (dict(wgsl=STEEP, name="has space"), "name"),
    (dict(wgsl=STEEP, params={"steps2": 1.0}), "params"),
    (dict(wgsl=STEEP, params={"steps": float("nan")}), "params"),
])
def test_bad_custom_arguments_name_the_argument(kwargs, arg):
    with pytest.raises(ValueError, match=arg):
        pk.Custom(**kwargs)
