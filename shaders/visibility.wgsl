// visibility.wgsl: the compute pipeline's two steps (`pk.Renderer(pipeline="compute")`).
//
// 1. The visibility pass rasterises the mesh the surface pass would draw, with the same clip
//    positions, culling and depth test, and writes only the index of the nearest triangle (+1;
//    0: nothing) into an R32Uint target: a small write per pixel, cheap on a GPU's graphics
//    slice. Its vertex stage reads the mesh from storage (`vertex_at`), so that every adapter
//    can draw it without the primitive-index feature.
// 2. The surface pass runs in compute, one invocation per pixel: `rasterise` rebuilds what the
//    rasteriser would have interpolated at the pixel's centre (the same attributes, perspective
//    correct) and the footprint that the fragment stage takes from derivatives (the attributes'
//    exact differences one pixel right and one pixel down), and the pass stores the method's
//    AOVs into the targets as storage textures.
//
// The mesh is its vertex buffer read as float32 words (VERTEX_FLOATS a vertex: mesh::Vertex, 14,
// or, with VERTEX_EXTRA, a method's vertex with its `extra` vec4, 18: render::pipelines checks) and its index buffer; an index array of one word
// stands for a non-indexed mesh (triangle t's corners are vertices 3t, 3t + 1, 3t + 2).
#define_import_path pomkit::visibility

#import pomkit::view::V
#import pomkit::vertex::{VertexIn, VertexOut, pass_through}
#import pomkit::object::{G, to_clip}
#import pomkit::basis::{make_basis, to_texture_space}

@group(3) @binding(0) var<storage, read> mesh_vertices: array<f32>;
@group(3) @binding(1) var<storage, read> mesh_indices: array<u32>;
@group(3) @binding(2) var visibility_tex: texture_2d<u32>;
@group(3) @binding(3) var out_color: texture_storage_2d<rgba32uint, write>;
@group(3) @binding(4) var out_geo: texture_storage_2d<rgba32uint, write>;
@group(3) @binding(5) var out_id: texture_storage_2d<r32uint, write>;
@group(3) @binding(6) var out_cost: texture_storage_2d<rgba32uint, write>;

#ifdef VERTEX_EXTRA
const VERTEX_FLOATS: u32 = 18u;
#else
const VERTEX_FLOATS: u32 = 14u;
#endif

struct VisibilityOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) triangle: u32,
}

fn corner_index(tri: u32, k: u32) -> u32 {
    if (arrayLength(&mesh_indices) <= 1u) {
        return 3u * tri + k;
    }
    return mesh_indices[3u * tri + k];
}

fn vertex_at(i: u32) -> VertexIn {
    let b = i * VERTEX_FLOATS;
    var v: VertexIn;
    v.position = vec3<f32>(mesh_vertices[b], mesh_vertices[b + 1u], mesh_vertices[b + 2u]);
    v.normal = vec3<f32>(mesh_vertices[b + 3u], mesh_vertices[b + 4u], mesh_vertices[b + 5u]);
    v.uv = vec2<f32>(mesh_vertices[b + 6u], mesh_vertices[b + 7u]);
    v.tangent = vec4<f32>(mesh_vertices[b + 8u], mesh_vertices[b + 9u], mesh_vertices[b + 10u], mesh_vertices[b + 11u]);
    v.uv_scale = vec2<f32>(mesh_vertices[b + 12u], mesh_vertices[b + 13u]);
#ifdef VERTEX_EXTRA
    v.extra = vec4<f32>(mesh_vertices[b + 14u], mesh_vertices[b + 15u], mesh_vertices[b + 16u], mesh_vertices[b + 17u]);
#endif
    return v;
}

// The visibility pass's vertex: corner `vi % 3` of triangle `vi / 3` (a non-indexed draw of
// three vertices a triangle).
fn visibility_vertex(vi: u32) -> VisibilityOut {
    let tri = vi / 3u;
    let v = vertex_at(corner_index(tri, vi % 3u));
    var o: VisibilityOut;
    o.clip = to_clip(v.position, V.view_proj);
    o.triangle = tri + 1u;
    return o;
}

// A pixel's rebuilt fragment: the interpolated vertex, and the differences of the tiled texture
// coordinate one pixel right and one pixel down (the fragment stage's dpdx, dpdy).
struct Rasterised {
    covered: bool,
    v: VertexOut,
    ds_dx: vec2<f32>,
    ds_dy: vec2<f32>,
}

fn lerp3(b: vec3<f32>, x0: VertexIn, x1: VertexIn, x2: VertexIn) -> VertexOut {
    var o = pass_through(x0, vec4<f32>(0.0));
    o.world = b.x * x0.position + b.y * x1.position + b.z * x2.position;
    o.normal = b.x * x0.normal + b.y * x1.normal + b.z * x2.normal;
    o.uv = b.x * x0.uv + b.y * x1.uv + b.z * x2.uv;
    o.tangent = b.x * x0.tangent + b.y * x1.tangent + b.z * x2.tangent;
    o.uv_scale = b.x * x0.uv_scale + b.y * x1.uv_scale + b.z * x2.uv_scale;
#ifdef VERTEX_EXTRA
    o.extra = b.x * x0.extra + b.y * x1.extra + b.z * x2.extra;
#endif
    return o;
}

// The perspective-correct barycentrics of the point at `ndc` on the triangle whose clip-space
// (x, y, w) are the columns c0, c1, c2 (2-D homogeneous rasterisation, Olano & Greer 1997: valid
// whatever side of the eye a corner lies; the rows of the adjugate are the edge functions).
fn barycentrics(c0: vec3<f32>, c1: vec3<f32>, c2: vec3<f32>, ndc: vec3<f32>) -> vec3<f32> {
    let e = vec3<f32>(dot(cross(c1, c2), ndc), dot(cross(c2, c0), ndc), dot(cross(c0, c1), ndc));
    return e / (e.x + e.y + e.z);
}

// A pixel position (pixel units, y down) in normalised device coordinates, homogeneous.
fn to_ndc(p: vec2<f32>, size: vec2<f32>) -> vec3<f32> {
    return vec3<f32>(p.x / size.x * 2.0 - 1.0, 1.0 - p.y / size.y * 2.0, 1.0);
}

fn uv_at(b: vec3<f32>, x0: VertexIn, x1: VertexIn, x2: VertexIn) -> vec2<f32> {
    return b.x * x0.uv + b.y * x1.uv + b.z * x2.uv;
}

// The texture point whose footprint sets a fragment's mip level (and so LOD_BLEND's fade to
// bump mapping): its own; with a window (WINDOW: Hybrid's coarse mesh, drawn at the window's
// top), where its view ray crosses h = 1, the base mesh's point the method alone is drawn at
// (on a plane, the same point), so that a coarse face's tilt does not change the level.
fn footprint_point(v: VertexOut, tiling: f32) -> vec2<f32> {
    let s = v.uv * tiling;
#ifdef WINDOW
    let f = make_basis(v.normal, v.tangent, v.uv_scale);
    let t = to_texture_space(f, normalize(v.world - G.eye_object));
    if (t.z < 0.0 && v.extra.w > 0.0) {
        return s - t.xy / max(-t.z, 1e-6) * (1.0 - v.extra.y);
    }
#endif
    return s;
}

// The fragment the rasteriser would have made at pixel `px` of a `dims` frame, from the
// visibility target; `tiling` scales uv into the height map's texture coordinate.
fn rasterise(px: vec2<u32>, dims: vec2<u32>, tiling: f32) -> Rasterised {
    var r: Rasterised;
    let id = textureLoad(visibility_tex, vec2<i32>(px), 0).r;
    r.covered = id != 0u;
    if (!r.covered) {
        return r;
    }
    let tri = id - 1u;
    let x0 = vertex_at(corner_index(tri, 0u));
    let x1 = vertex_at(corner_index(tri, 1u));
    let x2 = vertex_at(corner_index(tri, 2u));
    let k0 = to_clip(x0.position, V.view_proj);
    let k1 = to_clip(x1.position, V.view_proj);
    let k2 = to_clip(x2.position, V.view_proj);
    let c0 = k0.xyw;
    let c1 = k1.xyw;
    let c2 = k2.xyw;
    let size = vec2<f32>(dims);
    let centre = vec2<f32>(px) + 0.5;
    let b = barycentrics(c0, c1, c2, to_ndc(centre, size));
    r.v = lerp3(b, x0, x1, x2);
    let z = b.x * k0.z + b.y * k1.z + b.z * k2.z;
    let w = b.x * k0.w + b.y * k1.w + b.z * k2.w;
    r.v.clip = vec4<f32>(centre, z / w, w);
    // the fragment stage's (fine) derivatives: differences across the pixel's 2 x 2 quad, on
    // this triangle's plane
    let q = vec2<f32>(vec2<u32>(px.x & ~1u, px.y & ~1u)) + 0.5;
    let b00 = barycentrics(c0, c1, c2, to_ndc(vec2<f32>(q.x, centre.y), size));
    let b10 = barycentrics(c0, c1, c2, to_ndc(vec2<f32>(q.x + 1.0, centre.y), size));
    let b01 = barycentrics(c0, c1, c2, to_ndc(vec2<f32>(centre.x, q.y), size));
    let b11 = barycentrics(c0, c1, c2, to_ndc(vec2<f32>(centre.x, q.y + 1.0), size));
#ifdef WINDOW
    r.ds_dx = footprint_point(lerp3(b10, x0, x1, x2), tiling) - footprint_point(lerp3(b00, x0, x1, x2), tiling);
    r.ds_dy = footprint_point(lerp3(b11, x0, x1, x2), tiling) - footprint_point(lerp3(b01, x0, x1, x2), tiling);
#else
    r.ds_dx = (uv_at(b10, x0, x1, x2) - uv_at(b00, x0, x1, x2)) * tiling;
    r.ds_dy = (uv_at(b11, x0, x1, x2) - uv_at(b01, x0, x1, x2)) * tiling;
#endif
    return r;
}

// Pixel of invocation `li` (0..63) of workgroup `wg`, which covers an 8 x 8 tile: each run of
// eight invocations (a SIMD group on a CPU adapter, a quarter of a GPU's) covers a 4 x 2 block,
// as a fragment stage's lanes do, so that neighbours march together.
fn tile_pixel(wg: vec2<u32>, li: u32) -> vec2<u32> {
    let k = li >> 3u;
    let j = li & 7u;
    return wg * 8u + vec2<u32>((k & 1u) * 4u + (j & 3u), (k >> 1u) * 2u + (j >> 2u));
}

// The targets' texels at pixel `px` (the fragment stage's colour attachments; aov.wgsl's Packed).
fn store_color(px: vec2<u32>, c: vec4<u32>) {
    textureStore(out_color, vec2<i32>(px), c);
}

fn store_geo(px: vec2<u32>, g: vec4<u32>) {
    textureStore(out_geo, vec2<i32>(px), g);
}

fn store_id(px: vec2<u32>, id: u32) {
    textureStore(out_id, vec2<i32>(px), vec4<u32>(id, 0u, 0u, 0u));
}

fn store_cost(px: vec2<u32>, c: vec4<u32>) {
    textureStore(out_cost, vec2<i32>(px), c);
}
