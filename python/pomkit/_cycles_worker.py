"""Blender's Cycles as a reference renderer: run as a script by a Python that has `bpy` (Blender
5.0 as a module, which wants numpy < 2, so it runs beside pomkit's interpreter, not in it).

    python _cycles_worker.py scene.npz out.npz

It imports only bpy and numpy. `scene.npz` holds one object's arrays, its height map, material,
camera, directional lights and settings (written by `pomkit.reference.render_cycles`); `out.npz`
gets `color` (H, W, 3) linear, `uv` (H, W, 2) in pomkit's convention (NaN where nothing is hit),
`depth` (H, W) the distance from the eye, and `mask`.

The displacement is Cycles' own: a Displacement node (midlevel 1, scale = depth, object space)
on the height map (linear interpolation, repeating), true displacement on a simple (not
Catmull-Clark) adaptive subdivision at `dicing` pixels, along the interpolated vertex normals,
so that S = P + depth (h - 1) N. The mesh is welded by position (and normal) with its uvs per
corner, as a Blender user merges by distance: a seam is then one surface (pomkit's rule); a hard
edge stays split, since Cycles displaces along vertex normals, so its sides part there. The
geometry AOVs come from a second render of one sample through a 0.01-pixel box filter, whose
surfaces emit (u, v, distance from the camera); the colour is a Diffuse BSDF lit by sun lights
and a constant world, with no bounces (direct light only), box-filtered over one pixel. A camera
ray passes through faces it meets from behind (a transparent BSDF there, camera rays only), as
pomkit's rasteriser culls them and the oracle sees the surface from the side it enters.
"""

from __future__ import annotations

import os
import sys
import tempfile
import time

import numpy as np


def _weld(positions, normals, uvs, indices):
    """Vertices merged by exact position and normal (a seam's sides become one vertex; a hard
    edge's stay apart: Cycles' adaptive subdivision displaces along vertex normals, not custom
    per-corner ones); per corner (loop) uvs and normals."""
    both = np.concatenate([positions, normals], 1)
    keys, inverse = np.unique(both, axis=0, return_inverse=True)
    keys = keys[:, :3]
    inverse = inverse.reshape(-1)
    tris = indices.reshape(-1, 3)
    faces = inverse[tris]
    # a triangle with two corners in one place (a pole's fan) has no area: Blender drops it
    keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 2] != faces[:, 0])
    corners = tris[keep].reshape(-1)
    return keys, faces[keep], uvs[corners], normals[corners]


def _mesh(bpy, a):
    verts, faces, corner_uv, corner_n = _weld(a["positions"].astype(np.float64), a["normals"].astype(np.float64),
                                              a["uvs"].astype(np.float64), a["indices"].astype(np.int64))
    me = bpy.data.meshes.new("base")
    me.from_pydata(verts.tolist(), [], faces.tolist())
    uvl = me.uv_layers.new(name="UVMap")
    # Blender's v points up (row 0 of an image is its bottom); pomkit's points down
    flat = np.stack([corner_uv[:, 0], 1.0 - corner_uv[:, 1]], 1).astype(np.float32)
    uvl.data.foreach_set("uv", flat.reshape(-1))
    me.shade_smooth()
    n = corner_n / np.linalg.norm(corner_n, axis=1, keepdims=True)
    me.normals_split_custom_set([tuple(v) for v in n])
    me.update()
    return me


def _image(bpy, name, rgb):
    """A float image, Non-Color, from an (H, W) or (H, W, 3) array in pomkit's row order."""
    h, w = rgb.shape[:2]
    img = bpy.data.images.new(name, w, h, alpha=True, float_buffer=True)
    img.colorspace_settings.name = "Non-Color"
    px = np.ones((h, w, 4), np.float32)
    px[..., :3] = rgb[..., None] if rgb.ndim == 2 else rgb
    img.pixels.foreach_set(px[::-1].reshape(-1))
    img.pack()
    return img


def _material(bpy, a):
    nt_mat = bpy.data.materials.new("m")
    nt_mat.use_nodes = True
    nt_mat.displacement_method = "DISPLACEMENT"
    nt = nt_mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    tc = nt.nodes.new("ShaderNodeTexCoord")
    mapping = nt.nodes.new("ShaderNodeMapping")
    mapping.inputs["Scale"].default_value = (float(a["tiling"]), float(a["tiling"]), 1.0)
    nt.links.new(tc.outputs["UV"], mapping.inputs["Vector"])
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = _image(bpy, "height", a["height"])
    tex.interpolation = "Linear"
    tex.extension = "REPEAT"
    nt.links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
    disp = nt.nodes.new("ShaderNodeDisplacement")
    disp.space = "OBJECT"
    disp.inputs["Midlevel"].default_value = 1.0
    disp.inputs["Scale"].default_value = float(a["depth"])
    nt.links.new(tex.outputs["Color"], disp.inputs["Height"])
    nt.links.new(disp.outputs["Displacement"], out.inputs["Displacement"])
    cam = nt.nodes.new("ShaderNodeCameraData")
    xyz = nt.nodes.new("ShaderNodeCombineXYZ")
    sep = nt.nodes.new("ShaderNodeSeparateXYZ")
    nt.links.new(tc.outputs["UV"], sep.inputs["Vector"])
    nt.links.new(sep.outputs["X"], xyz.inputs["X"])
    nt.links.new(sep.outputs["Y"], xyz.inputs["Y"])
    nt.links.new(cam.outputs["View Distance"], xyz.inputs["Z"])
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = 1.0
    nt.links.new(xyz.outputs["Vector"], em.inputs["Color"])
    bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Roughness"].default_value = 0.0
    if "albedo" in a:
        alb = nt.nodes.new("ShaderNodeTexImage")
        alb.image = _image(bpy, "albedo", a["albedo"])
        alb.interpolation = "Linear"
        alb.extension = "REPEAT"
        nt.links.new(mapping.outputs["Vector"], alb.inputs["Vector"])
        nt.links.new(alb.outputs["Color"], bsdf.inputs["Color"])
    else:
        bsdf.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1.0)
    # one material for both renders (the diced geometry is kept between them): the Value node
    # "geometry" picks the emission of (u, v, distance) (1) or the diffuse BSDF (0)
    pick = nt.nodes.new("ShaderNodeValue")
    pick.name = "geometry"
    mix = nt.nodes.new("ShaderNodeMixShader")
    nt.links.new(pick.outputs["Value"], mix.inputs["Fac"])
    nt.links.new(bsdf.outputs["BSDF"], mix.inputs[1])
    nt.links.new(em.outputs["Emission"], mix.inputs[2])
    # a camera ray goes on through a face it meets from behind (pomkit's rule: the rasteriser
    # culls back faces, the oracle enters the shell through its top); shadow rays do not
    geom = nt.nodes.new("ShaderNodeNewGeometry")
    path = nt.nodes.new("ShaderNodeLightPath")
    both = nt.nodes.new("ShaderNodeMath")
    both.operation = "MULTIPLY"
    nt.links.new(geom.outputs["Backfacing"], both.inputs[0])
    nt.links.new(path.outputs["Is Camera Ray"], both.inputs[1])
    through = nt.nodes.new("ShaderNodeBsdfTransparent")
    cull = nt.nodes.new("ShaderNodeMixShader")
    nt.links.new(both.outputs["Value"], cull.inputs["Fac"])
    nt.links.new(mix.outputs["Shader"], cull.inputs[1])
    nt.links.new(through.outputs["BSDF"], cull.inputs[2])
    nt.links.new(cull.outputs["Shader"], out.inputs["Surface"])
    return nt_mat


def _look_at(eye, target, up):
    f = target - eye
    f /= np.linalg.norm(f)
    r = np.cross(f, up)
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = r, u, -f, eye
    return m


def _rotation_to(direction):
    """A 4x4 rotation whose -Z axis is `direction` (Blender's sun shines along its -Z)."""
    d = direction / np.linalg.norm(direction)
    z = -d
    helper = np.array([0.0, 0.0, 1.0]) if abs(z[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2] = x, y, z
    return m


def _scene(bpy, a):
    """The Blender scene: the welded mesh with its material and adaptive subdivision, the
    camera, the world and the suns."""
    from mathutils import Matrix  # type: ignore[import-not-found]

    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    sc.cycles.device = "CPU"
    sc.cycles.use_adaptive_sampling = False
    sc.cycles.use_denoising = False
    sc.cycles.seed = int(a["seed"])
    sc.cycles.max_bounces = 0
    # back faces a camera ray passes through (counted apart from max_bounces)
    sc.cycles.transparent_max_bounces = 16
    sc.cycles.pixel_filter_type = "BOX"
    # the micro-polygon size is the modifier's pixel size times this scene multiplier
    sc.cycles.dicing_rate = 1.0
    sc.render.film_transparent = True
    sc.render.resolution_x, sc.render.resolution_y = int(a["width"]), int(a["height_px"])
    sc.render.resolution_percentage = 100
    # the diced geometry is kept from the geometry render to the colour render
    sc.render.use_persistent_data = True
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.view_settings.exposure = 0.0
    sc.view_settings.gamma = 1.0
    sc.render.dither_intensity = 0.0
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    sc.render.image_settings.color_mode = "RGBA"
    me = _mesh(bpy, a)
    ob = bpy.data.objects.new("base", me)
    sc.collection.objects.link(ob)
    me.materials.append(_material(bpy, a))
    mod = ob.modifiers.new("subdivision", "SUBSURF")
    mod.subdivision_type = "SIMPLE"
    mod.use_adaptive_subdivision = True
    mod.adaptive_space = "PIXEL"
    mod.adaptive_pixel_size = float(a["dicing"])
    cam_data = bpy.data.cameras.new("cam")
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = float(np.radians(a["fov_y"]))
    cam_data.clip_start = 1e-4
    cam_data.clip_end = 1e6
    cam = bpy.data.objects.new("cam", cam_data)
    cam.matrix_world = Matrix(_look_at(a["eye"], a["target"], a["up"]).tolist())
    sc.collection.objects.link(cam)
    sc.camera = cam
    world = bpy.data.worlds.new("w")
    world.use_nodes = True
    world.cycles_visibility.camera = False
    if not bool(a["shadows"]):
        world.cycles_visibility.shadow = False
    sc.world = world
    for k in range(int(a["lights"])):
        e = np.asarray(a[f"light{k}_irradiance"], np.float64)
        s = float(e.max())
        light = bpy.data.lights.new(f"sun{k}", "SUN")
        light.energy = s
        light.color = tuple((e / s).tolist()) if s > 0 else (1.0, 1.0, 1.0)
        light.angle = float(np.radians(a[f"light{k}_angular_diameter"]))
        light.use_shadow = bool(a["shadows"])
        lo = bpy.data.objects.new(f"sun{k}", light)
        lo.matrix_world = Matrix(_rotation_to(np.asarray(a[f"light{k}_direction"], np.float64)).tolist())
        sc.collection.objects.link(lo)
    return sc, me.materials[0]


def _render(bpy, sc, mat, a, geometry: bool, path: str):
    """One render to an EXR, read back as (H, W, 4) in pomkit's row order."""
    mat.node_tree.nodes["geometry"].outputs["Value"].default_value = 1.0 if geometry else 0.0
    amb = np.zeros(3) if geometry else np.broadcast_to(np.asarray(a["ambient"], np.float64), (3,))
    sc.world.node_tree.nodes["Background"].inputs["Color"].default_value = (float(amb[0]), float(amb[1]), float(amb[2]), 1.0)
    sc.cycles.samples = 1 if geometry else int(a["spp"])
    sc.cycles.filter_width = 0.01 if geometry else 1.0
    sc.render.filepath = path
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(path)
    img.colorspace_settings.name = "Non-Color"
    w, h = img.size
    px = np.empty(w * h * 4, np.float32)
    img.pixels.foreach_get(px)
    return px.reshape(h, w, 4)[::-1].astype(np.float64)


def main(src: str, dst: str) -> None:
    import bpy  # type: ignore[import-not-found]

    a = dict(np.load(src, allow_pickle=False))
    t0 = time.perf_counter()
    sc, mat = _scene(bpy, a)
    t1 = time.perf_counter()
    with tempfile.TemporaryDirectory() as d:
        geo = _render(bpy, sc, mat, a, True, os.path.join(d, "geometry.exr"))
        t2 = time.perf_counter()
        col = _render(bpy, sc, mat, a, False, os.path.join(d, "color.exr"))
    t3 = time.perf_counter()
    mask = geo[..., 3] > 0.5
    # the geometry pass's emission is premultiplied by its coverage (a 0.01-pixel filter: 0 or 1)
    cov = np.where(mask, geo[..., 3], 1.0)
    uv = np.stack([geo[..., 0] / cov, 1.0 - geo[..., 1] / cov], -1)
    uv[~mask] = np.nan
    depth = np.where(mask, geo[..., 2] / cov, np.nan)
    np.savez(dst, color=col[..., :3].astype(np.float32), coverage=col[..., 3].astype(np.float32),
             uv=uv.astype(np.float32), depth=depth.astype(np.float32), mask=mask,
             version=np.array(bpy.app.version_string), seconds=np.array([t1 - t0, t2 - t1, t3 - t2]))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
