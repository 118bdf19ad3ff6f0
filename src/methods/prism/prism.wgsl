// Prism POM (Dachsbacher & Tatarchuk 2007), one walk per shell entry. Each base triangle is
// extruded into a prism; the rasteriser draws only the shell's boundary faces (every top and
// bottom, and the sides that no neighbouring prism shares), so a fragment is where a view ray
// enters the shell. From there the ray walks through the prisms: in each, its entry and exit are
// the nearest and farthest of the prism's eight boundary triangles, the segment between them is
// marched with a constant texture gradient (march.wgsl's segment search and POM's refinement, or
// the max-mip traversal with `exact`), and a ray leaving through a side enters the prism across
// it (adjacency from geometry::prisms). Leaving through the top (or an unshared side) leaves the
// shell: no hit, discard; a later entry of the same ray is a fragment of its own. Walls (a
// side no neighbouring prism shares: an open border, or a crease where two prisms with other
// normals meet): the displaced surface ends at the mesh's open border (as the reference mesh
// does), so a ray entering the shell through a wall below the height field passes under the
// surface and is no hit, at a crease as at a border, as `pk.oracle.hits` does. Prisms whose
// highest height lies below the ray's lowest point in them are crossed without a march.
//
// Parameterisation: a point of a prism is (b1, b2, h): barycentrics of the base triangle and
// the height in the field's units (0 on the bottom; on the top, each corner's top height: 1 on
// the paper's full shell, the highest height beside the corner's edge on the tight shell,
// prisms.rs). The boundary triangles interpolate it linearly from their corners; uv, the tangent
// basis and the height interpolate linearly in it, so the march between entry and exit is linear
// in texture space, as in the paper. The basis at the hit is interpolated from the triangle's
// corners.
//
// The method's own pass (a top-level shader, not a `march` module): its geometry is the prisms
// (geometry::prisms). Outward shells (the paper's set-up) put h = 0 on the base mesh and h = 1
// `depth` above it. With several objects the hit's depth is the fragment depth
// (DISPLACED_DEPTH); with one, the entries' rasterised depth orders the fragments (a ray's later
// entry lies behind its earlier one's whole walk), which keeps the early depth test.

#import pomkit::cost::{fetched, chained, count_fragment}
#import pomkit::view::V
#import pomkit::object::G
#import pomkit::vertex::{VertexIn, VertexOut, pass_through}
#import pomkit::aov::{FsOut, write_aovs, pack_aovs, FLAG_BOUND}
#import pomkit::basis::{Basis, make_basis}
#import pomkit::height::{height_at, height_normal, height_lod, compute_lod}
#import pomkit::march::{Segment, linear_search_from, refine_linear, pom_sample_count}
#import pomkit::maxmip::{maxmip_traverse, positive_start}
#import pomkit::shading::shade
#import pomkit::object::{is_transformed, to_world, to_clip, normal_to_world, stretch, clip_depth, shadow_depth, shadow_light_object}

const NONE: u32 = 0xffffffffu;
// the bit of a boundary face's prism index that marks a wall (prisms.rs's WALL)
const WALL: u32 = 0x80000000u;
// (prisms.rs's BOTTOM: a prism's bottom face)
const BOTTOM: u32 = 0x40000000u;
// the most prisms one ray walks through (a grazing ray crosses a handful)
const MAX_PRISMS: u32 = 64u;

// The method's own resource (group 2, binding 1): the per-prism data as rgba32uint texels
// (prisms.rs's `texels`), PRISM_TEXELS a prism, a power-of-two number of prisms a row:
//   0-2 top corners, 3-5 bottom corners (xyz, f32 bits). In their w, what the walk needs at
//   every prism it crosses: 0.w the highest height under the prism (f32), 1.w the diagonal bits
//   (bit k: side k's split), the plateau bit (3: the lowest height equals the highest) and corner
//   2's top height (unorm16, bits 16-31), 2.w corners 0 and 1's top heights (unorm16 x 2),
//   3.w-5.w the prism across side k (f32, -1: the shell's boundary). A span reads these six.
//   6: uv0, uv1; 7: uv2 (f32 bits): a candidate's segment reads these two.
//   8-10: corner k's basis: normal and tangent (octahedral snorm16), uv scale (f32 bits; corner
//   0's x carries the tangent's handedness in its sign bit): the hit's three texels (nine when
//   they were rgba32float; a fetch costs lavapipe about the same whatever the format).
// A texture, not a storage buffer: on lavapipe a storage read at an index that differs across
// the lanes of a SIMD vector is a scalar loop over them, and the walk reads a prism's corners
// at every prism it crosses.
const PRISM_TEXELS: u32 = 11u;
@group(2) @binding(1) var prism_tex: texture_2d<u32>;

fn prism_word(p: u32, k: u32) -> vec4<u32> {
    let per_row = textureDimensions(prism_tex).x / PRISM_TEXELS;
    let shift = countTrailingZeros(per_row);
    return textureLoad(prism_tex, vec2<u32>((p & (per_row - 1u)) * PRISM_TEXELS + k, p >> shift), 0);
}

fn prism_texel(p: u32, k: u32) -> vec4<f32> {
    return bitcast<vec4<f32>>(prism_word(p, k));
}

// prisms.rs's `oct_decode`: an octahedral snorm16 code's unit direction.
fn oct_decode(c: u32) -> vec3<f32> {
    let e = unpack2x16snorm(c);
    var v = vec3<f32>(e, 1.0 - abs(e.x) - abs(e.y));
    let t = max(-v.z, 0.0);
    v.x = v.x + select(t, -t, v.x >= 0.0);
    v.y = v.y + select(t, -t, v.y >= 0.0);
    return normalize(v);
}

// The prism across `side` (0-2) from the adjacency `adj` (the bottom corners' w), or NONE (the
// shell's boundary, or side 3: the top or the bottom).
fn prism_across(adj: vec3<f32>, side: u32) -> u32 {
    let a = select(select(adj.z, adj.y, side == 1u), adj.x, side == 0u);
    return select(NONE, u32(max(a, 0.0)), side <= 2u && a >= 0.0);
}

// A boundary-face corner seen through `clip_from_world` (the camera's or the light's), with its
// face's centre; the faces are drawn unindexed, three vertices each, so `vi % 3` is the
// corner's place in its face.
fn prism_vertex(v: VertexIn, vi: u32, prism: u32, centre: vec3<f32>, clip_from_world: mat4x4<f32>) -> VertexOut {
    // (the prism's index with WALL where the face is a wall)
    var o = pass_through(v, to_clip(v.position, clip_from_world));
    o.prism = prism;
    let c = vi % 3u;
    o.corner = vec3<f32>(f32(c == 0u), f32(c == 1u), f32(c == 2u));
    o.from_centre = v.position - centre;
    return o;
}

@vertex
fn vs_prism(v: VertexIn, @builtin(vertex_index) vi: u32, @location(5) prism: u32,
            @location(6) centre: vec3<f32>) -> VertexOut {
    return prism_vertex(v, vi, prism, centre, V.view_proj);
}

// The least barycentric a walk starts at in its boundary face (walk_origin).
const EDGE_MARGIN: f32 = 1e-5;

// The point a boundary fragment walks from: its interpolated position, moved toward its face's
// centre where it lies within EDGE_MARGIN (barycentric) of an edge, until it lies that far
// inside. There the rasteriser (exact, fixed point) and the interpolated position (float) can
// disagree: a pixel the rasteriser gives this face can lie just outside it, the ray from there
// misses the fragment's prism, its span finds no entry, and the pixel was a pinhole (about one a
// basis on smooth content, both shells). Elsewhere the point is the fragment's own.
fn walk_origin(in: VertexOut) -> vec3<f32> {
    let b = in.corner;
    let m = min(b.x, min(b.y, b.z));
    // the least barycentric grows linearly toward the centre, where all are 1/3
    let f = (EDGE_MARGIN - m) / max(1.0 / 3.0 - m, 1e-6);
    return select(in.world, in.world - in.from_centre * f, m < EDGE_MARGIN);
}

// The ray's way through one prism: entry and exit (t and (b1, b2, h)) and the side it leaves
// through (3: the top or the bottom).
struct Span {
    t_in: f32,
    st_in: vec3<f32>,
    t_out: f32,
    st_out: vec3<f32>,
    side: u32,
    ok: bool,
    // the prism across each side (prism_across)
    adj: vec3<f32>,
    // the highest height under the prism, and whether the lowest equals it (a plateau)
    max_h: f32,
    plateau: bool,
    // the corners' extrusions (top - bottom: the normal times the shell's depth and the
    // corner's top height)
    e0: vec3<f32>,
    e1: vec3<f32>,
    e2: vec3<f32>,
}

// The span's running entry and exit while it tests the prism's eight boundary triangles: each
// as a fraction (numerator, denominator > 0) of t and of (b1, b2, h), divided once at the end.
struct SpanAcc {
    in_num: f32,
    in_den: f32,
    st_in: vec3<f32>,
    out_num: f32,
    out_den: f32,
    st_out: vec3<f32>,
    side: u32,
    ok: bool,
}

// A corner of the prism as the ray sees it: r = corner - o, m = r x d (the edge function of
// edge (a, b) is dot(r_b, m_a): d . (r_b x r_a)), and dt = dot(r, d) (t at the corner's foot).
struct RayCorner {
    r: vec3<f32>,
    m: vec3<f32>,
    dt: f32,
}

fn ray_corner(c: vec3<f32>, o: vec3<f32>, d: vec3<f32>) -> RayCorner {
    let r = c - o;
    return RayCorner(r, cross(r, d), dot(r, d));
}

// The edge function of edge (a, b), antisymmetric in its corners: each edge of the prism is
// computed once and shared, negated, by the two triangles on it, so that the eight triangles
// close up: a ray that leaves one enters its neighbour, with no gap between them.
fn edge(a: RayCorner, b: RayCorner) -> f32 {
    return dot(b.r, a.m);
}

// One boundary triangle (a, b, c) into the span, from its three edge functions e_ab, e_bc,
// e_ca: the ray meets it where they share a sign (within 1e-5 of their sum, as the barycentric
// test it replaces); the barycentrics are (e_bc, e_ca, e_ab) / their sum, and so is t, of the
// corners' dt. Straight-line code (selects, no early return): a SIMD group on lavapipe runs every
// path any of its lanes takes, and the span calls this eight times a prism crossed.
fn consider(acc: ptr<function, SpanAcc>, dt_a: f32, dt_b: f32, dt_c: f32, e_ab: f32, e_bc: f32, e_ca: f32,
            sa: vec3<f32>, sb: vec3<f32>, sc: vec3<f32>, side: u32) {
    let sum = e_ab + e_bc + e_ca;
    let neg = sum < 0.0;
    let den = abs(sum);
    let wa = select(e_bc, -e_bc, neg);
    let wb = select(e_ca, -e_ca, neg);
    let wc = select(e_ab, -e_ab, neg);
    let tol = -1e-5 * den;
    let hit = den >= 1e-12 && wa >= tol && wb >= tol && wc >= tol;
    let num = wa * dt_a + wb * dt_b + wc * dt_c;
    let st = sa * wa + sb * wb + sc * wc;
    (*acc).ok = (*acc).ok || hit;
    // num / den against the running entry's and exit's fractions (denominators > 0)
    let nearer = hit && num * (*acc).in_den < (*acc).in_num * den;
    let farther = hit && num * (*acc).out_den > (*acc).out_num * den;
    (*acc).in_num = select((*acc).in_num, num, nearer);
    (*acc).in_den = select((*acc).in_den, den, nearer);
    (*acc).st_in = select((*acc).st_in, st, nearer);
    (*acc).out_num = select((*acc).out_num, num, farther);
    (*acc).out_den = select((*acc).out_den, den, farther);
    (*acc).st_out = select((*acc).st_out, st, farther);
    (*acc).side = select((*acc).side, side, farther);
}

// Side k of a prism (corners k, j = k + 1; top edge e_t = edge(T_k, T_j), bottom edge e_b =
// edge(B_k, B_j), verticals v_k = edge(T_k, B_k), v_j): its two triangles, split along
// top(k)-bottom(j), or along top(j)-bottom(k) when `flip` (the same split as the neighbour's).
fn consider_side(acc: ptr<function, SpanAcc>, tk: RayCorner, tj: RayCorner, bk: RayCorner, bj: RayCorner,
                 e_t: f32, e_b: f32, v_k: f32, v_j: f32, sk: vec2<f32>, sj: vec2<f32>, mk: f32, mj: f32,
                 flip: bool, side: u32) {
    let stk = vec3<f32>(sk, mk);
    let stj = vec3<f32>(sj, mj);
    let sbk = vec3<f32>(sk, 0.0);
    let sbj = vec3<f32>(sj, 0.0);
    // flip: (T_k, T_j, B_k) and (T_j, B_j, B_k), diagonal g = T_j-B_k; else (T_k, T_j, B_j) and
    // (T_k, B_j, B_k), diagonal g = T_k-B_j (selects, not a branch: neighbouring lanes differ)
    let g = select(edge(tk, bj), edge(tj, bk), flip);
    consider(acc, tk.dt, tj.dt, select(bj.dt, bk.dt, flip), e_t, select(v_j, g, flip), select(-g, -v_k, flip),
             stk, stj, select(sbj, sbk, flip), side);
    consider(acc, select(tk.dt, tj.dt, flip), bj.dt, bk.dt, select(g, v_j, flip), -e_b, select(-v_k, -g, flip),
             select(stk, stj, flip), sbj, sbk, side);
}

fn prism_span(p: u32, o: vec3<f32>, d: vec3<f32>) -> Span {
    // the prism's corners, with its highest height, diagonals, plateau bit, tops' heights and
    // adjacency in their w (no texels: bytes only)
    fetched(0u, 96u);
    let q0 = prism_texel(p, 0u);
    let q1 = prism_texel(p, 1u);
    let q2 = prism_texel(p, 2u);
    let q3 = prism_texel(p, 3u);
    let q4 = prism_texel(p, 4u);
    let q5 = prism_texel(p, 5u);
    var sp: Span;
    sp.adj = vec3<f32>(q3.w, q4.w, q5.w);
    sp.max_h = q0.w;
    let w1 = bitcast<u32>(q1.w);
    sp.plateau = (w1 & 8u) != 0u;
    // the tops' heights (the tight shell)
    let m01 = unpack2x16unorm(bitcast<u32>(q2.w));
    let m = vec3<f32>(m01, unpack2x16unorm(w1).y);
    sp.e0 = q0.xyz - q3.xyz;
    sp.e1 = q1.xyz - q4.xyz;
    sp.e2 = q2.xyz - q5.xyz;
    let diag = w1 & 7u;
    let t0 = ray_corner(q0.xyz, o, d);
    let t1 = ray_corner(q1.xyz, o, d);
    let t2 = ray_corner(q2.xyz, o, d);
    let b0 = ray_corner(q3.xyz, o, d);
    let b1 = ray_corner(q4.xyz, o, d);
    let b2 = ray_corner(q5.xyz, o, d);
    // the nine edges of top, bottom and verticals, each once
    let et01 = edge(t0, t1);
    let et12 = edge(t1, t2);
    let et20 = edge(t2, t0);
    let eb01 = edge(b0, b1);
    let eb12 = edge(b1, b2);
    let eb20 = edge(b2, b0);
    let v0 = edge(t0, b0);
    let v1 = edge(t1, b1);
    let v2 = edge(t2, b2);
    var acc: SpanAcc;
    // no entry yet (+inf: 1 / 0) and no exit (-inf: -1 / 0)
    acc.in_num = 1.0;
    acc.in_den = 0.0;
    acc.out_num = -1.0;
    acc.out_den = 0.0;
    acc.st_in = vec3<f32>(0.0);
    acc.st_out = vec3<f32>(0.0);
    acc.side = 3u;
    acc.ok = false;
    // barycentrics (b1, b2) of the corners
    let s0 = vec2<f32>(0.0, 0.0);
    let s1 = vec2<f32>(1.0, 0.0);
    let s2 = vec2<f32>(0.0, 1.0);
    consider(&acc, t0.dt, t1.dt, t2.dt, et01, et12, et20, vec3<f32>(s0, m.x), vec3<f32>(s1, m.y), vec3<f32>(s2, m.z), 3u);
    consider(&acc, b0.dt, b1.dt, b2.dt, eb01, eb12, eb20, vec3<f32>(s0, 0.0), vec3<f32>(s1, 0.0), vec3<f32>(s2, 0.0), 3u);
    consider_side(&acc, t0, t1, b0, b1, et01, eb01, v0, v1, s0, s1, m.x, m.y, (diag & 1u) != 0u, 0u);
    consider_side(&acc, t1, t2, b1, b2, et12, eb12, v1, v2, s1, s2, m.y, m.z, (diag & 2u) != 0u, 1u);
    consider_side(&acc, t2, t0, b2, b0, et20, eb20, v2, v0, s2, s0, m.z, m.x, (diag & 4u) != 0u, 2u);
    sp.ok = acc.ok;
    sp.side = acc.side;
    let inv_in = 1.0 / max(acc.in_den, 1e-30);
    let inv_out = 1.0 / max(acc.out_den, 1e-30);
    sp.t_in = select(3.4e38, acc.in_num * inv_in, acc.ok);
    sp.st_in = acc.st_in * inv_in;
    sp.t_out = select(-3.4e38, acc.out_num * inv_out, acc.ok);
    sp.st_out = acc.st_out * inv_out;
    return sp;
}

// Base-triangle quantities at barycentrics (b1, b2).
fn bary(b: vec2<f32>) -> vec3<f32> {
    return vec3<f32>(1.0 - b.x - b.y, b.x, b.y);
}

// The uv at two points of one prism (a segment's entry and exit), its corners read once.
fn prism_uv2(p: u32, b0: vec2<f32>, b1: vec2<f32>) -> array<vec2<f32>, 2> {
    let q6 = prism_texel(p, 6u);
    let u2 = prism_texel(p, 7u).xy;
    let w0 = bary(b0);
    let w1 = bary(b1);
    return array<vec2<f32>, 2>(q6.xy * w0.x + q6.zw * w0.y + u2 * w0.z, q6.xy * w1.x + q6.zw * w1.y + u2 * w1.z);
}

fn prism_basis(p: u32, b: vec2<f32>) -> Basis {
    let w = bary(b);
    let f0 = prism_word(p, 8u);
    let f1 = prism_word(p, 9u);
    let f2 = prism_word(p, 10u);
    let n = oct_decode(f0.x) * w.x + oct_decode(f1.x) * w.y + oct_decode(f2.x) * w.z;
    let t = oct_decode(f0.y) * w.x + oct_decode(f1.y) * w.y + oct_decode(f2.y) * w.z;
    let sc = abs(bitcast<vec2<f32>>(f0.zw)) * w.x + abs(bitcast<vec2<f32>>(f1.zw)) * w.y
        + abs(bitcast<vec2<f32>>(f2.zw)) * w.z;
    return make_basis(n, vec4<f32>(t, select(1.0, -1.0, (f0.z >> 31u) != 0u)), sc);
}

// The walk of a ray from `o` (a point of prism `first`'s boundary) along `view` (object space,
// unit): whether it hits, the hit's distance from `o`, its texture point, height and basis, the
// level sampled, the steps taken (samples, plus one per prism crossed) and the flags.
struct PrismHit {
    ok: bool,
    t: f32,
    s: vec2<f32>,
    h: f32,
    f: Basis,
    hl: f32,
    steps: f32,
    flags: u32,
}

fn prism_walk(face_prism: u32, o: vec3<f32>, view: vec3<f32>, lod: f32) -> PrismHit {
    let first = face_prism & ~(WALL | BOTTOM);
    let wall = (face_prism & WALL) != 0u;
    var out: PrismHit;
    out.ok = false;
    out.flags = 0u;
    let tiling = G.tiling;
    // exact=True is the variant compiled with PRISM_EXACT: the other variant holds no max-mip
    // code (lavapipe would run its straight-line part at every candidate prism)
#ifdef PRISM_EXACT
    let exact = true;
    let hl = 0.0;
#else
    let exact = false;
    let hl = height_lod(lod);
#endif
    out.hl = hl;
    var steps = 0.0;
    var p = first;
    var t0 = 0.0;
    // the sample at the walk's point t0 (ray height minus surface height), when taken
    var d0 = 0.0;
    var have_d0 = false;
    var st_hit = vec2<f32>(0.0);
    var k = 0u;
    // Two loops, as in maxmip.wgsl: the inner one walks from prism to prism (the span, and the
    // test of the ray's lowest point against the prism's highest height) until a prism the ray
    // dips into, the candidate; the outer one marches the candidate's segment. On a SIMD machine
    // that runs every branch any lane of a group takes (lavapipe), the march's code then runs
    // once per candidate, not at every prism crossed.
    // What the walk keeps from a span across the loops, not the span itself: its entry, its exit
    // and the prism across the exit (loop-carried state is dear on lavapipe: carrying the six
    // corners of the shared side, to read three texels a prism instead of six, made Prism slower,
    // docs/cost_journal_2026.md).
    var t_in = 0.0;
    var st_in = vec3<f32>(0.0);
    var t_out = 0.0;
    var st_out = vec3<f32>(0.0);
    var next = first;
    var bound = false;
    var h_e = 0.0;
    var h_x = 0.0;
    // the candidate's plateau: its height where the field under it is flat (lowest = highest
    // height), or -1
    var plateau = -1.0;
    // the candidate's normal at its entry (the extrusions interpolated), for its layer count
    var n_cand = vec3<f32>(0.0, 0.0, 1.0);
    loop {
        var cand = false;
        loop {
            if (next == NONE) {
                break;
            }
            if (k > 0u) {
                t0 = t_out;
            }
            p = next;
            if (k >= MAX_PRISMS) {
                bound = true;
                break;
            }
            k = k + 1u;
            // the next prism is the one the last prism's record names across its exit side
            chained();
            let sp = prism_span(p, o, view);
            steps = steps + 1.0;
            if (!sp.ok || sp.t_out <= t0) {
                next = NONE;
                break;
            }
            next = prism_across(sp.adj, sp.side);
            t_out = sp.t_out;
            st_out = sp.st_out;
            // the walk's entry is the previous exit (the first prism's: the fragment itself)
            t_in = sp.t_in;
            st_in = sp.st_in;
            if (t_in < t0) {
                // entered before t0 (the first prism, or rounding at a shared side): start at t0
                // on the segment entry -> exit
                let a = (t0 - t_in) / max(t_out - t_in, 1e-30);
                st_in = mix(st_in, st_out, a);
                t_in = t0;
            }
            h_e = clamp(st_in.z, 0.0, 1.0);
            h_x = clamp(st_out.z, 0.0, 1.0);
            // a march only where the ray's lowest point in the prism is below its highest height
            if (min(h_e, h_x) <= sp.max_h) {
                cand = true;
                plateau = select(-1.0, sp.max_h, sp.plateau);
                let w = bary(st_in.xy);
                n_cand = sp.e0 * w.x + sp.e1 * w.y + sp.e2 * w.z;
                break;
            }
            // crossed without a march: no sample carries to the next prism
            have_d0 = false;
        }
        if (!cand) {
            break;
        }
        let uvs = prism_uv2(p, st_in.xy, st_out.xy);
        let s_e = uvs[0] * tiling;
        let s_x = uvs[1] * tiling;
        let dh_seg = h_x - h_e;
        var hit = -1.0;
        if (wall && k == 1u) {
            // entered through a wall: the displaced surface ends at an open border, and a crease's
            // wall is passed under as the oracle passes it, so a ray that enters below the height
            // field passes under the surface (no hit here)
            if (h_e - height_at(s_e, hl) <= 0.0) {
                break;
            }
        }
        if (plateau >= 0.0 && hl == 0.0) {
            // a plateau (every texel a sample under the prism reads has one height): the ray meets
            // it where its height reaches the plateau's, or at once if it entered below it (the
            // field the march samples, without the samples)
            hit = select(0.0, (h_e - plateau) / (h_e - h_x), h_e > plateau);
        } else {
#ifdef PRISM_EXACT
            if (abs(dh_seg) > 1e-4) {
                // exact=True: the max-mip traversal along the segment, parameterised by height
                let slope = (s_x - s_e) / abs(dh_seg) * G.map_size;
                let p0 = positive_start(s_e, slope);
                let tr = maxmip_traverse(p0, h_e, slope.x, slope.y, sign(dh_seg), abs(dh_seg), G.max_iterations);
                steps = steps + tr.iters;
                if (tr.hit) {
                    hit = tr.t / abs(dh_seg);
                }
            } else {
#else
            {
#endif
                // the shared linear search from entry to exit, at POM's layer density: a segment
                // spanning dh of the shell's height gets n * dh layers (>= 1); the entry's sample
                // is the previous prism's last one
                let ndotv = -dot(view, normalize(n_cand));
                let n = max(ceil(pom_sample_count(ndotv, params.min_steps, params.max_steps, true) * abs(dh_seg)), 2.0);
                if (!have_d0) {
                    d0 = h_e - height_at(s_e, hl);
                    steps = steps + 1.0;
                }
                let b = linear_search_from(Segment(s_e, s_x - s_e, h_e, dh_seg), n, hl, d0, 0.0);
                steps = steps + b.steps;
                d0 = b.d_cur;
                if (b.d_cur <= 0.0) {
                    hit = refine_linear(b);
                }
            }
        }
        if (hit >= 0.0) {
            // the basis is interpolated after the loop, once (see below)
            st_hit = mix(st_in, st_out, hit).xy;
            out.ok = true;
            out.t = mix(t_in, t_out, hit);
            out.s = mix(s_e, s_x, hit);
            out.h = mix(h_e, h_x, hit);
            break;
        }
        // the exit's sample carries to the next prism (not after the max-mip traversal); the
        // inner loop moves on to it
        have_d0 = !exact;
    }
    out.steps = steps;
    if (out.ok) {
        // the hit's basis, outside the loop: inside it, a SIMD group would interpolate it at
        // every prism where one of its lanes hits
        out.f = prism_basis(p, st_hit);
    } else if (bound) {
        out.flags = FLAG_BOUND;
    }
    return out;
}

@fragment
fn fs_prism(in: VertexOut, @builtin(front_facing) front: bool) -> FsOut {
    count_fragment(in.clip.xy);
    if ((in.prism & BOTTOM) != 0u) {
        // the ray enters the shell from behind the surface: nothing shows from that side, and a
        // later entry of the same ray (another part's top) is a fragment of its own
        discard;
    }
    let tiling = G.tiling;
    let lod = compute_lod(in.uv * tiling);
    // object space, as in surface.wgsl
    let to_p = in.world - G.eye_object;
    let view = to_p / max(length(to_p), 1e-20);
    let px = in.clip.xy;
    let start = walk_origin(in);
    var ph: PrismHit;
    if (G.depth <= 0.0) {
        // depth 0: the displaced surface is the base mesh, the shell's top (prisms.rs's
        // FLAT_SHELL): a top fragment seen from above is its own hit, as Flat draws it, and a
        // wall lies under it
        if ((in.prism & WALL) != 0u || !front) {
            discard;
        }
        ph.ok = true;
        ph.t = 0.0;
        ph.s = in.uv * tiling;
        ph.h = 1.0;
        ph.f = make_basis(in.normal, in.tangent, in.uv_scale);
#ifdef PRISM_EXACT
        ph.hl = 0.0;
#else
        ph.hl = height_lod(lod);
#endif
        ph.steps = 0.0;
        ph.flags = 0u;
    } else {
        ph = prism_walk(in.prism, start, view, lod);
    }
    if (!ph.ok) {
        discard;
    }
    let p_obj = start + view * ph.t;
    let p = to_world(p_obj);
    let sh = shade(ph.f, ph.s, ph.h, p, normal_to_world(height_normal(ph.f, ph.s, ph.hl)), ph.hl, true, px);
    var dist = length(p - V.eye);
    if (is_transformed()) {
        dist = length(p_obj - G.eye_object) * stretch(view);
    }
    var o = write_aovs(pack_aovs(sh.color, u32(ph.steps + sh.steps), ph.flags, ph.s / tiling, dist, lod));
#ifdef DISPLACED_DEPTH
    o.depth = clip_depth(p);
#endif
    return o;
}

// The shadow-map pass: the shell's boundary seen from the light, each fragment walked along the
// light's direction; the hit's depth in the light's projection.
@vertex
fn vs_prism_shadow(v: VertexIn, @builtin(vertex_index) vi: u32, @location(5) prism: u32,
                   @location(6) centre: vec3<f32>) -> VertexOut {
    return prism_vertex(v, vi, prism, centre, V.shadow_vp);
}

@fragment
fn fs_prism_shadow(in: VertexOut) -> @builtin(frag_depth) f32 {
    let lod = compute_lod(in.uv * G.tiling);
    let view = shadow_light_object();
    let start = walk_origin(in);
    let ph = prism_walk(in.prism, start, view, lod);
    if (!ph.ok) {
        discard;
    }
    return shadow_depth(to_world(start + view * ph.t));
}
