// aov.wgsl: the render targets. They are Rgba32Uint holding float32 bits: exact float32 AOVs on
// every backend (GL cannot render to Rgba32Float).
#define_import_path pomkit::aov

#import pomkit::object::G
#import pomkit::cost::cost_counts

struct FsOut {
    // rgb: linear radiance (float bits), a: steps (low 28 bits) | flags << 28 | HIT_BIT. Only
    // this target is cleared: the others are read where the hit bit is set (src/render/aovs.rs)
    @location(0) color: vec4<u32>,
    // xy: hit uv (mesh space, unwrapped), z: distance eye -> hit, w: mip level used
    @location(1) geo: vec4<u32>,
    // the object's index (AOV `object`)
    @location(2) id: u32,
#ifdef COUNT_FETCHES
    // x: texel fetches, y: bytes read by the search, z: the chain of dependent fetches (AOVs
    // `fetches`, `bytes`, `chain`: cost.wgsl); w: 0
    @location(3) cost: vec4<u32>,
#endif
#ifdef DISPLACED_DEPTH
    // the displaced hit's depth (pixel depth offset): objects meet where their displaced
    // surfaces meet (frames of several objects)
    @builtin(frag_depth) depth: f32,
#endif
}

// flags (AOV `flags`): 1 = the march hit its iteration bound, 2 = NCS early termination,
// 4 = the walk lost the surface away from any silhouette and the base mesh's point covers the
// pixel (NCS, CurvedRelief: FALLBACK_NDV, FALLBACK_UNDER, FALLBACK_OFF_FACE)
const FLAG_BOUND: u32 = 1u;
const FLAG_EARLY: u32 = 2u;
const FLAG_FALLBACK: u32 = 4u;
// a walk that leaves the shell through its top where the view meets the interpolated normal at
// N.V above this (60 degrees from it: a silhouette needs a grazing ray, N.V < sqrt(2 depth / R)
// for depth / R up to 0.18), or on its first step (the normal faces away from the viewer on a
// front face), has lost the surface: the fragment keeps the base mesh's point
const FALLBACK_NDV: f32 = 0.6;
// so has a walk that leaves through the top while its straight view ray still lies more than
// this share of the shell's depth under the plane of the triangle it left from: the mesh's
// faces did not turn away there, its interpolated normals did (normals averaged across a
// low-poly mesh's edges)
const FALLBACK_UNDER: f32 = 0.05;
// so has one that leaves where the interpolated normal lies more than 25 degrees from its
// triangle's face normal (its cosine below this): the walk bends with the normals, and there
// they do not follow the faces (a low-poly box or cylinder whose normals are averaged)
const FALLBACK_OFF_FACE: f32 = 0.9;
// the pixel shows a surface (AOV `mask`): channel 3's bit 31
const HIT_BIT: u32 = 0x80000000u;

// The targets' texels of a hit, as the fragment stage writes them and the compute pipeline
// stores them (visibility.wgsl).
struct Packed {
    color: vec4<u32>,
    geo: vec4<u32>,
    id: u32,
    cost: vec4<u32>,
}

fn pack_aovs(color: vec3<f32>, steps: u32, flags: u32, uv: vec2<f32>, dist: f32, lod: f32) -> Packed {
    var o: Packed;
    let c = bitcast<vec3<u32>>(color);
    o.color = vec4<u32>(c, min(steps, 0x0fffffffu) | (flags << 28u) | HIT_BIT);
    o.geo = bitcast<vec4<u32>>(vec4<f32>(uv, dist, lod));
    o.id = u32(G.object_id);
    o.cost = cost_counts();
    return o;
}

fn write_aovs(p: Packed) -> FsOut {
    var o: FsOut;
    o.color = p.color;
    o.geo = p.geo;
    o.id = p.id;
#ifdef COUNT_FETCHES
    o.cost = p.cost;
#endif
    return o;
}
