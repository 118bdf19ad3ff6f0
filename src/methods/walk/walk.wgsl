// walk.wgsl: a texture-space ray walking across the base mesh (src/methods/walk/mod.rs). A walk
// point is a triangle and a uv in that triangle's chart. A move by a uv displacement follows the
// segment out of the triangle through the side it crosses, into the triangle across it, whose
// chart may be another one (a seam: the rest of the move is mapped into it) or a mirrored one (a
// mirror axis: the move reflects); through an open border the walk ends: the ray has left the
// surface. The basis at a walk point is its triangle's corner bases interpolated, as the
// rasteriser interpolates them for the fragment.
#define_import_path pomkit::walk

#import pomkit::cost::{fetched, chained}
#import pomkit::basis::{Basis, make_basis}
#import pomkit::aov::{FALLBACK_UNDER, FALLBACK_OFF_FACE}

// the walk data (group 2, binding 1): 14 texels per triangle, triangle i's at column
// (i mod per_row) * 14 and row i div per_row, per_row a power of two (mod.rs's `texels`). A
// texture, not a storage buffer: on lavapipe a storage read at an index that differs across the
// lanes of a SIMD vector is a scalar loop over them (prism.wgsl reads its prisms so too).
//   0, 1:          uv -> b1 and b2 (rows of an affine map)
//   2 + 2k, 3 + 2k: side k (corners k, k+1): uv -> the neighbour's uv (rows), neighbour in .w of
//                   the first row (-1 on an open border)
//   .w of 0, 1, 3, 5: the triangle's plane n . x = d (n.x, n.y, n.z, d; object space)
//   8 + 2c, 9 + 2c: corner c's (normal, S_tangent) and (tangent, sign * S_binormal)
@group(2) @binding(1) var walk_tex: texture_2d<f32>;

const RECORDS: u32 = 14u;

// record k of triangle tri
fn walk_rec(tri: u32, k: u32) -> vec4<f32> {
    let per_row = textureDimensions(walk_tex).x / RECORDS;
    let shift = countTrailingZeros(per_row);
    return textureLoad(walk_tex, vec2<u32>((tri & (per_row - 1u)) * RECORDS + k, tri >> shift), 0);
}
// sides crossed in one move at most (a move spans a few texels; triangles are larger)
const MAX_CROSSINGS: i32 = 16;

struct WalkPoint {
    tri: u32,
    uv: vec2<f32>,
    // the move's direction in the chart it ended in (crossings map it)
    dir: vec2<f32>,
    // false when the walk left the surface through an open border
    on: bool,
    // (where !on) the border was a crack: another open border runs along it, and the surface
    // goes on in a triangle the walk cannot reach (walk/mod.rs), whose plane (unit normal,
    // offset; object space) is crack_plane
    crack: bool,
    crack_plane: vec4<f32>,
    // (b0, b1, b2) of uv in tri (walk_basis's weights; where on)
    b: vec3<f32>,
}

fn walk_row(r: vec4<f32>, p: vec2<f32>) -> f32 {
    return r.x * p.x + r.y * p.y + r.z;
}

// (b0, b1, b2) of uv in triangle tri
fn walk_bary(tri: u32, uv: vec2<f32>) -> vec3<f32> {
    fetched(2u, 32u);
    let b1 = walk_row(walk_rec(tri, 0u), uv);
    let b2 = walk_row(walk_rec(tri, 1u), uv);
    return vec3<f32>(1.0 - b1 - b2, b1, b2);
}

// The walk point at uv in triangle tri (no direction yet).
fn walk_point(tri: u32, uv: vec2<f32>) -> WalkPoint {
    return WalkPoint(tri, uv, vec2<f32>(0.0), true, false, vec4<f32>(0.0), walk_bary(tri, uv));
}

// Move from (tri, uv) by dir * len (dir in tri's chart).
fn walk_move(tri_in: u32, uv_in: vec2<f32>, dir: vec2<f32>, len: f32) -> WalkPoint {
    var w = WalkPoint(tri_in, uv_in, dir, true, false, vec4<f32>(0.0), vec3<f32>(0.0));
    var rest = dir * len;
    for (var i = 0; i < MAX_CROSSINGS; i = i + 1) {
        let e = w.uv + rest;
        let be = walk_bary(w.tri, e);
        if (all(be >= vec3<f32>(-1e-6))) {
            w.uv = e;
            w.b = be;
            return w;
        }
        // the side the segment leaves through: the first corner whose barycentric reaches 0
        // (side (c + 1) % 3 lies opposite corner c)
        let bs = walk_bary(w.tri, w.uv);
        var s = 2.0;
        var side = 0u;
        for (var c = 0u; c < 3u; c = c + 1u) {
            if (be[c] < -1e-6) {
                let sc = clamp(bs[c] / max(bs[c] - be[c], 1e-30), 0.0, 1.0);
                if (sc < s) {
                    s = sc;
                    side = (c + 1u) % 3u;
                }
            }
        }
        let x = w.uv + rest * s;
        rest = rest * (1.0 - s);
        // the triangle across is named by the record read here
        chained();
        fetched(2u, 32u);
        let r0 = walk_rec(w.tri, 2u + 2u * side);
        let r1 = walk_rec(w.tri, 3u + 2u * side);
        if (r0.w < 0.0) {
            w.uv = x;
            w.on = false;
            w.crack = r0.w < -1.5;
            w.crack_plane = vec4<f32>(r0.xyz, r1.x);
            return w;
        }
        // the point and the rest of the move, in the neighbour's chart
        w.uv = vec2<f32>(walk_row(r0, x), walk_row(r1, x));
        rest = vec2<f32>(dot(r0.xy, rest), dot(r1.xy, rest));
        w.dir = vec2<f32>(dot(r0.xy, w.dir), dot(r1.xy, w.dir));
        w.tri = u32(r0.w);
    }
    w.uv = w.uv + rest;
    w.b = walk_bary(w.tri, w.uv);
    return w;
}

// The mesh's basis at a walk point: the corners' normals, tangents and uv scales interpolated.
fn walk_basis(w: WalkPoint) -> Basis {
    let tri = w.tri;
    let b = clamp(w.b, vec3<f32>(0.0), vec3<f32>(1.0));
    fetched(6u, 96u);
    let t0 = walk_rec(tri, 9u);
    let n = walk_rec(tri, 8u) * b.x + walk_rec(tri, 10u) * b.y + walk_rec(tri, 12u) * b.z;
    let t = t0 * b.x + walk_rec(tri, 11u) * b.y + walk_rec(tri, 13u) * b.z;
    // the handedness is the triangle's (its corners agree in a chart)
    let sign = select(1.0, -1.0, t0.w < 0.0);
    return make_basis(n.xyz, vec4<f32>(t.xyz, sign), vec2<f32>(n.w, abs(t.w)));
}

// Triangle tri's unit face normal (0 on a triangle without area).
fn walk_face_normal(tri: u32) -> vec3<f32> {
    fetched(3u, 48u);
    return vec3<f32>(walk_rec(tri, 0u).w, walk_rec(tri, 1u).w, walk_rec(tri, 3u).w);
}

// How far the object-space point x lies above triangle tri's plane (0 on a triangle without
// area).
fn walk_above(tri: u32, x: vec3<f32>) -> f32 {
    fetched(1u, 16u);
    return dot(walk_face_normal(tri), x) - walk_rec(tri, 5u).w;
}

// Whether a walk that left through a crack at w, its straight view ray at x (object space),
// has lost the surface there: x lies under the plane of the triangle across the crack, where
// the surface goes on (the ray heads into it); above it, the ray has left the surface (a crack
// on the outline, where two faces meet at a corner without a shared edge).
fn walk_into_crack(w: WalkPoint, x: vec3<f32>) -> bool {
    return !w.on && w.crack && dot(w.crack_plane.xyz, x) - w.crack_plane.w < 0.0;
}

// Whether triangles a and b lie in one plane (within a hundredth of the shell's depth).
fn walk_coplanar(a: u32, b: u32, depth: f32) -> bool {
    if (a == b) {
        return true;
    }
    fetched(2u, 32u);
    return dot(walk_face_normal(a), walk_face_normal(b)) > 1.0 - 1e-6
        && abs(walk_rec(a, 5u).w - walk_rec(b, 5u).w) < 0.01 * depth;
}

// Whether a walk from triangle `start` that left the shell's top at w, its straight view ray at
// x (object space), was turned out by the interpolated normals rather than by the mesh: the
// normal at w lies far from its face (FALLBACK_OFF_FACE), x lies under w's triangle
// (FALLBACK_UNDER, a share of the shell's depth), or at all under it where w's triangle lies in
// the start's plane (the faces did not turn between the entry and the exit: a box's flat face
// under averaged normals). aov.wgsl gives the reasons.
fn walk_turned_by_normals(w: WalkPoint, x: vec3<f32>, depth: f32, start: u32) -> bool {
    let under = walk_above(w.tri, x);
    return dot(walk_basis(w).n, walk_face_normal(w.tri)) < FALLBACK_OFF_FACE
        || under < -FALLBACK_UNDER * depth
        || (under < 0.0 && walk_coplanar(start, w.tri, depth));
}

// The triangle a fragment starts in (the method's geometry carries it in Ray::extra.z).
fn walk_start(extra: vec4<f32>) -> u32 {
    return u32(round(extra.z));
}
