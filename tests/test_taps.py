"""Every tap is counted (issue 68): a method's `steps` AOV counts each height sample its search
takes, the entry tap and every refinement tap included, and `fetches` counts the same samples
(one hardware-filtered fetch each). Held on one pixel against a hand count: over a constant map
at height c every tap reads c, so the count follows from the search's own rule alone.

PlayCanvas's review of its parallax (playcanvas/engine #9213) found `parallaxSamples` leaving out
the entry tap and the five refinement taps; these counts are the ones the cost model and the
bench read."""

from __future__ import annotations

import dataclasses
import math

import pytest

import pomkit as pk
from pomkit.bench import plane_scene

C = 0.3  # the map's height: n (1 - C) is never a whole number for the counts below


def pom(n: int) -> int:
    """The entry tap, then a tap every 1/n of the shell until one lies at or below the field."""
    return 1 + math.ceil(n * (1 - C))


def relief(linear: int, binary: int) -> int:
    """POM's linear search, then one tap per bisection."""
    return pom(linear) + binary


def contact_refinement(steps: int) -> int:
    """No entry tap; coarse taps 1/(steps + 1) apart until one lies below; then the last coarse
    interval again in steps of 1/(taps left) of it, until a tap lies below."""
    dt = 1.0 / (steps + 1)
    k = math.ceil((1 - C) / dt)  # the first coarse tap below
    left = steps - (k - 1)
    t, fine, taps = (k - 1) * dt, dt / left, k
    while True:
        t += fine
        taps += 1
        if 1 - t <= C:
            return taps


def playcanvas(n: int) -> int:
    """The entry tap, the linear search in steps of 1/n (here capped: n = samples), five halvings."""
    return 1 + math.ceil(n * (1 - C)) + 5


CASES = {
    "POM": (pk.POM(shadows="none", adaptive=False, min_steps=16, max_steps=16, lod_threshold=1000.0), pom(16)),
    "Relief": (pk.Relief(linear_steps=12, binary_steps=5), relief(12, 5)),
    "qgis_contact_refinement": (pk.presets.qgis_contact_refinement(), contact_refinement(15)),
    "playcanvas_pom": (dataclasses.replace(pk.presets.playcanvas_pom(), params={**pk.presets.playcanvas_pom().params, "samples": 4.0}),
                       playcanvas(4)),
}


@pytest.mark.parametrize("name", CASES)
def test_the_counters_match_a_hand_count_on_one_pixel(renderer, name):
    method, want = CASES[name]
    # deep enough that PlayCanvas's step count (one per two texels) reaches its cap of 4
    sc = plane_scene(pk.textures.constant(256, C), 60.0, 64, depth=0.2)
    f = renderer.render(sc, method, aovs=("color", "mask", "steps", "fetches"))
    y, x = 32, 32
    assert f.mask[y, x]
    assert f.steps[y, x] == want, f"{name}: steps {f.steps[y, x]} at the centre, the hand count {want}"
    assert f.fetches[y, x] == want, f"{name}: fetches {f.fetches[y, x]}, one per tap: {want}"
