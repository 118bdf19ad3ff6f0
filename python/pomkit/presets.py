"""What engines ship, rebuilt from pomkit's own methods and parameters, for the Pareto chart.

Each preset follows the engine's published shader source or documentation as far as pomkit's
parameters can express it; where they cannot, the docstring says what differs.
"""

from __future__ import annotations

from importlib.resources import files

from ._methods import POM, Custom, Relief

__all__ = ["bevy_pom", "bevy_relief", "godot_deep_parallax", "godot_deep_parallax_97646", "engine_pom", "playcanvas_pom", "silhouette_pom", "hdrp_pom", "qgis_contact_refinement", "ALL_PRESETS"]

NO_LOD = 1000.0  # engines without a POM -> bump hand-over


def bevy_pom() -> POM:
    """Bevy's `ParallaxMappingMethod::Occlusion` (pbr `parallax_mapping.wgsl`): the layer count
    is interpolated by |V.z| from `max_parallax_layer_count` (16) head-on... to 1, with the
    depth map sampled at level 0 and a linear interpolation between the last two layers; no
    self-shadowing, no LOD hand-over."""
    return POM(min_steps=1, max_steps=16, shadows="none", lod_threshold=NO_LOD, mip_filtering=False)


def bevy_relief() -> Relief:
    """Bevy's `ParallaxMappingMethod::Relief { max_steps: 5 }`: the linear search of the
    occlusion method, then 5 binary-search steps. Difference: Bevy's linear layer count adapts
    with |V.z| (16 to 1); pomkit's Relief takes a fixed 16."""
    return Relief(linear_steps=16, binary_steps=5, mip_filtering=False)


def _engine_loop(name: str, min_layers: float, max_layers: float, divide_by_z: bool, mip_filtering: bool) -> Custom:
    src = (files("pomkit") / "wgsl" / "engine_pom.wgsl").read_text()
    return Custom(wgsl=src, name=name, mip_filtering=mip_filtering,
                  params={"min_layers": min_layers, "max_layers": max_layers, "divide_by_z": float(divide_by_z)})


def godot_deep_parallax() -> Custom:
    """Godot 4's StandardMaterial3D `heightmap_deep_parallax` as it ships (material.cpp): layers
    mixed between `heightmap_max_layers` (32) and `heightmap_min_layers` (8) by |V.z|, the
    depth accumulated layer by layer, the slide `view_dir.xy * heightmap_scale` (V.xy, not
    V.xy / V.z: the offset stays within one depth at grazing angles, which flattens the relief
    there), one interpolation between the last two layers, the footprint's mip level
    (`texture()`), no self-shadowing. The engine loop of pomkit/wgsl/engine_pom.wgsl with
    divide_by_z = 0."""
    return _engine_loop("godot_deep_parallax", 8.0, 32.0, divide_by_z=False, mip_filtering=True)


def godot_deep_parallax_97646() -> Custom:
    """Godot's reworked deep parallax (godotengine/godot PR #97646, open): the same loop with its
    "Z correction" (the slide divided by V.z, the ray's own slope), "Write Depth" (the depth of
    the displaced point) and "Correct Shadow Receive" (the shadow map read at the displaced
    point). pomkit writes the displaced point's depth and reads a casting light's shadow map
    there for every per-pixel method, so those two are what any method here does; the preset
    differs from `godot_deep_parallax` by the Z correction alone. The PR's built-in
    interpolation between layers is the loop's own."""
    return _engine_loop("godot_deep_parallax_97646", 8.0, 32.0, divide_by_z=True, mip_filtering=True)


def engine_pom() -> Custom:
    """The parallax occlusion loop most engines and tutorials ship (accumulated position, layer
    count blended by the view angle between 8 and 32, one interpolation between the last two
    layers, level-0 sampling), as a `pk.Custom` method: pomkit/wgsl/engine_pom.wgsl, our own
    adaptation of the common description (docs/custom_methods.md)."""
    return _engine_loop("engine_pom", 8.0, 32.0, divide_by_z=True, mip_filtering=False)


def playcanvas_pom() -> Custom:
    """PlayCanvas v2.22's marched parallax (`parallaxMode = PARALLAX_OCCLUSION`, August 2026):
    one mip level for the whole march, one step per two texels of it (at most 16, not rounded),
    the slide capped at 5 times the depth, a fade to no offset where the march covers about a
    texel, five halvings after the linear search. A `pk.Custom` method,
    pomkit/wgsl/playcanvas_pom.wgsl, rebuilt from the engine's pull-request descriptions
    (playcanvas/engine #9213, #9219, #9223); its soft self-shadows are not rebuilt."""
    src = (files("pomkit") / "wgsl" / "playcanvas_pom.wgsl").read_text()
    return Custom(wgsl=src, name="playcanvas_pom", mip_filtering=True,
                  params={"samples": 16.0, "texels_per_step": 2.0, "max_slope": 5.0, "fade_lo": 0.5, "fade_hi": 1.5})


def silhouette_pom() -> Custom:
    """"Silhouette POM" as engines spread it in 2026 (three.js PR #33953, Terrain3D, Unity and
    Unreal packs): POM (8 to 32 layers by the view angle, linear refinement) whose hit is
    discarded outside the texture's [0, 1] uv bounds, cutting a planar face's silhouette without
    prisms. A `pk.Custom` method, pomkit/wgsl/silhouette_pom.wgsl, our own writing of that
    description; tests/test_presets.py measures its outline against the oracle's, POM's and
    Prism's. The curved variant of the kind (the ray bent by the surface's curvature, discarded
    where it leaves the shell) is curved relief mapping, `pk.CurvedRelief` (Oliveira & Policarpo's
    per-vertex quadric), measured on the curved suite in docs/tables/silhouettes.md."""
    src = (files("pomkit") / "wgsl" / "silhouette_pom.wgsl").read_text()
    return Custom(wgsl=src, name="silhouette_pom", params={"min_steps": 8.0, "max_steps": 32.0})


def hdrp_pom() -> Custom:
    """Unity HDRP's pixel displacement (Lit, Displacement Mode: Pixel displacement): 5 to 15
    steps linear in the view angle (truncated), a linear search, up to three secant steps that
    stop within 0.01 of the field, the footprint's mip level, the offset faded out above level
    5. A `pk.Custom` method, pomkit/wgsl/hdrp_pom.wgsl, our own writing after the pipeline's
    public sources (PerPixelDisplacement.hlsl, Unity-Technologies/Graphics)."""
    src = (files("pomkit") / "wgsl" / "hdrp_pom.wgsl").read_text()
    return Custom(wgsl=src, name="hdrp_pom", mip_filtering=True,
                  params={"min_samples": 5.0, "max_samples": 15.0, "lod_threshold": 5.0})


def qgis_contact_refinement() -> Custom:
    """QGIS's contact-refinement parallax mapping (qgis/QGIS #65955, April 2026, chosen there
    after POM and steep parallax): 15 coarse taps 1/16 of the shell apart, then the one interval
    that holds the crossing walked again in as many taps as the coarse search had left, and the
    line through the last tap above and the first below intersected with the ray; the
    footprint's mip level; the slide offset-limited, V.xy (2 - N.V). At most 16 taps a pixel
    (17 where no coarse tap lies below and the floor is tapped). A `pk.Custom` method,
    pomkit/wgsl/contact_refinement.wgsl, our own writing after QGIS's metalrough.frag; its zero
    level at mid-grey is pomkit's h = 1 (the mesh's surface) instead."""
    src = (files("pomkit") / "wgsl" / "contact_refinement.wgsl").read_text()
    return Custom(wgsl=src, name="qgis_contact_refinement", mip_filtering=True,
                  params={"steps": 15.0, "offset_limiting": 1.0}, windowed=True)


#: name -> factory. Unreal's ParallaxOcclusionMapping material function is not included: its
#: algorithm is only available in the engine's own sources, which are not public material we can
#: verify here.
ALL_PRESETS = {"bevy_pom": bevy_pom, "bevy_relief": bevy_relief, "godot_deep_parallax": godot_deep_parallax,
               "godot_deep_parallax_97646": godot_deep_parallax_97646, "engine_pom": engine_pom,
               "playcanvas_pom": playcanvas_pom, "silhouette_pom": silhouette_pom,
               "hdrp_pom": hdrp_pom, "qgis_contact_refinement": qgis_contact_refinement}

