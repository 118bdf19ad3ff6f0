// march.wgsl: the interface between the surface pass and a method's view-ray search, and the
// one segment-based linear search that SteepParallax, POM, Relief and Prism share.
//
// A method module (src/methods/*.wgsl, or a user's `pk.Custom`) defines
//     fn march(r: Ray) -> Hit
// The surface pass (surface.wgsl) builds the Ray, calls it, and shades the Hit: docs/custom_methods.md.
#define_import_path pomkit::march

#import pomkit::basis::Basis
#import pomkit::height::height_at

// The view ray at a rasterised fragment of the base mesh.
struct Ray {
    // entry point on the base surface (h = 1), in tiled texture units (uv * tiling)
    s: vec2<f32>,
    // texture units travelled per unit of height descended: the ray meets the floor (h = 0) at
    // s + dsdh (0 where the ray does not descend: does_not_descend)
    dsdh: vec2<f32>,
    // cosine between the view ray and the base normal (1 head-on, 0 grazing)
    ndotv: f32,
    // the mip level to sample the height field at (the footprint's, or 0 with mip_filtering=False)
    lod: f32,
    // mesh uv at the entry (not tiled)
    uv: vec2<f32>,
    // world direction of the view ray (unit)
    view: vec3<f32>,
    // the fragment's point on the base mesh (object space; the view ray starts there)
    p: vec3<f32>,
    // the view direction in texture space per unit of world length (ds_u, ds_v, dh)
    v_ts: vec3<f32>,
    // the base mesh's basis at the entry
    f: Basis,
    // the method's per-vertex attribute at the entry (its geometry's, with VERTEX_EXTRA; else 0)
    extra: vec4<f32>,
    // the window of the shell the surface lies in: the ray enters at height `top` (at `s`) and
    // the field lies above `floor` along it. [0, 1] but for Hybrid's fine method (shader def
    // WINDOW: the coarse mesh's per-vertex window), whose search marches the window alone.
    top: f32,
    floor: f32,
    // world length from the rasterised fragment to the entry (s, top) along the view ray: 0 but
    // for Hybrid's fine method, whose entry starts where the ray reaches h = 1 (planar_hit adds it)
    lead: f32,
}

// What a method returns. `planar_hit` fills every field from (s, h) for methods that march in
// the entry's tangent basis.
struct Hit {
    // texture coordinate of the hit (tiled units) and its height in [0, 1]
    s: vec2<f32>,
    h: f32,
    // height-map samples (or node fetches) taken: AOV `steps`
    steps: f32,
    // AOV `flags`: FLAG_BOUND (1) the search hit its bound, FLAG_EARLY (2) ended inside the shell
    flags: u32,
    // the mip level the hit is shaded with
    lod: f32,
    // world length from the entry to the hit
    len: f32,
    // the base mesh's basis at the hit (shading and shadows)
    f: Basis,
    // the ray left the shell without a hit: nothing is drawn (a silhouette)
    exited: bool,
}

// A ray that does not descend into the shell in its fragment's basis (v_ts.z >= -GRAZING: on
// a curved mesh, a silhouette fragment whose interpolated normal faces away from the view): no
// walk can find the field along it, so its dsdh is 0 (make_ray): the linear searches (Parallax,
// SteepParallax, POM, Relief) fall straight down at the entry, where a slope clamped to 1e6
// texture units per height sampled texels anywhere in the map (POM's uv p95 48 million texels
// on a box with averaged normals, TexturedCube_ImageGlob_248.blend), and the traversals (Exact,
// ConeStep) end at the entry, as Flat shows it, instead of walking to their iteration bound
// (measured on a torus: 48 pixels at 4096 iterations held a 256² frame at 43 ms against POM's 5).
const GRAZING: f32 = 0.0;

fn does_not_descend(r: Ray) -> bool {
    return r.v_ts.z >= -GRAZING;
}

fn planar_hit(r: Ray, s: vec2<f32>, h: f32, steps: f32, flags: u32) -> Hit {
    var hit: Hit;
    hit.s = s;
    hit.h = h;
    hit.steps = steps;
    hit.flags = flags;
    hit.lod = r.lod;
    hit.len = r.lead + (r.top - h) / max(-r.v_ts.z, 1e-12);
    hit.f = r.f;
    hit.exited = false;
    return hit;
}

// A straight segment through the height field: (s + ds t, h + dh t) for t in [0, 1].
struct Segment {
    s: vec2<f32>,
    ds: vec2<f32>,
    h: f32,
    dh: f32,
}

// The view ray from its entry down to the floor (the window's: the shell's top and floor but
// for Hybrid's fine method).
fn view_segment(r: Ray) -> Segment {
    let span = r.top - r.floor;
    return Segment(r.s, r.dsdh * span, r.top, -span);
}

fn segment_s(g: Segment, t: f32) -> vec2<f32> {
    return g.s + g.ds * t;
}

fn segment_h(g: Segment, t: f32) -> f32 {
    return g.h + g.dh * t;
}

struct Bracket {
    // the last sample above the surface and the first one at or below it (parameters along the
    // segment and ray height minus surface height there)
    t_prev: f32,
    d_prev: f32,
    t_cur: f32,
    d_cur: f32, // <= 0 when the bracket holds an intersection
    steps: f32,
}

// Linear search along the segment in n equal steps with an early out at the first sample at or
// below the surface. The start point is sampled too, so a surface at the start is hit there.
fn linear_search(g: Segment, n: f32, lod: f32) -> Bracket {
    return linear_search_from(g, n, lod, g.h - height_at(g.s, lod), 1.0);
}

// The linear search with the start's sample given (`d0`: ray height minus surface height there,
// counted as `steps0` steps): a walk through segments (Prism) samples their shared ends once.
fn linear_search_from(g: Segment, n: f32, lod: f32, d0: f32, steps0: f32) -> Bracket {
    let dt = 1.0 / n;
    var b: Bracket;
    b.steps = steps0;
    b.t_cur = 0.0;
    b.d_cur = d0;
    b.t_prev = b.t_cur;
    b.d_prev = b.d_cur;
    let ni = i32(n);
    for (var i = 1; i <= ni && b.d_cur > 0.0; i = i + 1) {
        b.t_prev = b.t_cur;
        b.d_prev = b.d_cur;
        // computed from i, not accumulated, and the last one at the end itself: f32(n) * (1 / n)
        // falls short of 1 for some n (41, 47, ...), and more often where the adapter's division
        // is approximate, so that a ray ending on a floor at height 0 would stop a hair above it
        b.t_cur = select(f32(i) * dt, 1.0, i == ni);
        b.d_cur = segment_h(g, b.t_cur) - height_at(segment_s(g, b.t_cur), lod);
        b.steps = b.steps + 1.0;
    }
    return b;
}

// The shell's lattice in a window from `top` down `span` (heights), for a search that takes `n`
// steps over [0, 1] alone: heights 1 - k d, with d = 1 / (n m) and m = floor(1 / span) (so that
// the window holds at most n of them), and the first k whose height lies strictly below `top`.
// Its heights are the search alone's that fall in the window, and the ones between them a
// narrower window adds. Returns (d, k).
fn window_lattice(top: f32, span: f32, n: f32) -> vec2<f32> {
    let d = 1.0 / (max(n, 1.0) * max(floor(1.0 / max(span, 1e-6)), 1.0));
    return vec2<f32>(d, floor((1.0 - top) / d) + 1.0);
}

// The linear search of a window narrower than the shell (Hybrid's fine method: WINDOW) on the
// shell's lattice (`window_lattice`): the segment's start (the window's top), every lattice
// height strictly inside the window, and its end (the floor). A window that holds the field
// then never finds its first sample below the surface farther along the ray than the search
// alone would (issue 74: never worse). At most n + 2 samples; over [0, 1] with a whole n,
// `linear_search`'s.
fn window_search(g: Segment, n: f32, lod: f32) -> Bracket {
    var b: Bracket;
    b.steps = 1.0;
    b.t_cur = 0.0;
    b.d_cur = g.h - height_at(g.s, lod);
    b.t_prev = b.t_cur;
    b.d_prev = b.d_cur;
    let span = -g.dh;
    if (!(span > 0.0)) {
        return b;
    }
    let top = g.h;
    let bottom = g.h + g.dh;
    let lattice = window_lattice(top, span, n);
    var k = lattice.y;
    let ni = i32(ceil(max(n, 1.0))) + 2;
    var done = false;
    for (var i = 0; i < ni && b.d_cur > 0.0 && !done; i = i + 1) {
        b.t_prev = b.t_cur;
        b.d_prev = b.d_cur;
        let h = 1.0 - k * lattice.x;
        done = h <= bottom;
        b.t_cur = select((top - h) / span, 1.0, done);
        b.d_cur = segment_h(g, b.t_cur) - height_at(segment_s(g, b.t_cur), lod);
        b.steps = b.steps + 1.0;
        k = k + 1.0;
    }
    return b;
}

// The linear search of the view segment in n steps: over a window (WINDOW) on its lattice
// (`window_search`), else in n equal steps (`linear_search`).
fn view_search(g: Segment, n: f32, lod: f32) -> Bracket {
#ifdef WINDOW
    return window_search(g, n, lod);
#else
    return linear_search(g, n, lod);
#endif
}

// POM's refinement: the parameter where the ray meets the piecewise-linear height profile
// between the bracket's two samples (a line-line intersection at full float precision); the
// last sample when the bracket holds no crossing.
fn refine_linear(b: Bracket) -> f32 {
    let denom = b.d_prev - b.d_cur;
    if (b.d_cur <= 0.0 && denom > 1e-12) {
        return b.t_prev + (b.t_cur - b.t_prev) * (b.d_prev / denom);
    }
    return b.t_cur;
}

// POM's sample count: n = n_max + (N.V)(n_min - n_max), i.e. n_max at grazing angles and
// n_min head-on. Tatarchuk 2006 prints eq. 1 with the operands swapped, but the text ("we
// increase the sampling rate along the steep viewing angles") and Figure 4 need this form.
// `adaptive` false: the fixed-count profile (Brawley & Tatarchuk 2004), always n_max.
fn pom_sample_count(ndotv: f32, n_min: f32, n_max: f32, adaptive: bool) -> f32 {
    if (!adaptive) {
        return n_max;
    }
    return max(round(n_max + clamp(ndotv, 0.0, 1.0) * (n_min - n_max)), 1.0);
}
