// NCS: normal-based curved silhouettes (Chen & Chang 2008, Algorithm 2). The view ray is
// marched from the rasterised point in texture space (u, v, h), and at every step the local
// basis is the base mesh's at the ray's point, so the ray follows the curved base surface: P_{i+1} = P_i + c * delta * S * TBN * V with delta = depth / max_steps (world
// length) and c = step_scale. Leaving the shell through its top discards the pixel (that makes
// the silhouette); falling below the height field refines between the last two steps; still
// inside after max_steps is an early termination (flags & 2; the paper's fig. 7 shows them red).
//
// On any mesh: the march walks across the base mesh's triangles (walk.wgsl), so that a ray
// crossing a seam continues in the neighbouring chart, one crossing a mirror axis reflects, and
// the basis at each step is the one the mesh interpolates there (the paper's basis maps at full
// resolution; a texture-space map cannot hold two bases where mirrored charts share texels).
// A ray that walks out through an open border has left the displaced surface: the pixel is
// discarded, as the reference mesh ends there; through a crack (an open border that another
// one of the mesh runs along) it has lost it, and takes the fallback below. A ray that rises out through the top on its first
// step (the interpolated normal faces away from the viewer on a front face) or where the view is
// far from grazing (FALLBACK_NDV), where the interpolated normal lies far from its face
// (FALLBACK_OFF_FACE), or while the straight view ray still lies under the plane of the
// triangle it leaves from (FALLBACK_UNDER: the interpolated normals curved the walk, the faces
// did not), has lost the surface, not found a silhouette: the fragment keeps the base
// mesh's point (flags & 4), so that NCS never covers less than the base mesh.

#define_import_path pomkit::methods::ncs

#import pomkit::object::G
#import pomkit::cost::chained
#import pomkit::aov::{FLAG_EARLY, FLAG_FALLBACK, FALLBACK_NDV, FALLBACK_UNDER}
#import pomkit::basis::{Basis, make_basis}
#import pomkit::height::height_at
#import pomkit::march::{Ray, Hit, pom_sample_count}
#import pomkit::walk::{walk_point, walk_move, walk_basis, walk_start, walk_above, walk_turned_by_normals, walk_into_crack}

fn ncs_hit(r: Ray, uv: vec2<f32>, h: f32, len: f32, steps: f32, flags: u32, f: Basis) -> Hit {
    var hit: Hit;
    hit.s = uv * G.tiling;
    hit.h = h;
    hit.len = len;
    hit.steps = steps;
    hit.flags = flags;
    hit.lod = r.lod;
    hit.f = f;
    hit.exited = false;
    return hit;
}

// adaptive steps: the fewest layers per shell height (head-on), as POM's default min_steps
const MIN_LAYERS: f32 = 8.0;

// The world length of a step whose view ray meets the base surface at N.V = ndv: the paper's
// c * delta, or (adaptive) at least POM's layer density: each step descends one of the shell's
// pom_sample_count(N.V, 8, N) layers (N.V local), and at most one shell depth along the ray, so
// that the step still follows the surface's curvature.
fn ncs_step_length(ndv_in: f32, n: f32, dl0: f32) -> f32 {
    if (params.adaptive > 0.5) {
        let ndv = max(ndv_in, 1e-3);
        let layers = pom_sample_count(ndv, MIN_LAYERS, n, true);
        return clamp(G.depth / (ndv * layers), dl0, max(G.depth, dl0));
    }
    return dl0;
}

// One step along the view in the basis f, in (u, v, h), and its world length.
fn basis_step(f: Basis, view: vec3<f32>, n: f32, dl0: f32, inv_depth: f32) -> vec4<f32> {
    let dl = ncs_step_length(-dot(view, f.n), n, dl0);
    return vec4<f32>(vec3<f32>(dot(view, f.t) / f.scale.x, dot(view, f.b) / f.scale.y, dot(view, f.n) * inv_depth) * dl, dl);
}

fn march(r: Ray) -> Hit {
    let n = max(params.max_steps, 1.0);
    // the paper's step: c * delta, delta = depth / N (world length)
    let dl0 = params.step_scale * G.depth / n;
    let tiling = G.tiling;
    let view = r.view;
    // the march's point on the base mesh (its triangle, uv and barycentrics)
    var p = walk_point(walk_start(r.extra), r.uv);
    var h = 1.0;
    var len = 0.0;
    var d = h - height_at(p.uv * tiling, r.lod);
    var steps = 1.0;
    if (d <= 0.0) {
        return ncs_hit(r, p.uv, h, 0.0, steps, 0u, r.f);
    }
    let inv_depth = 1.0 / max(G.depth, 1e-12);
    // the first step goes along the rasterised basis
    var st = basis_step(r.f, view, n, dl0, inv_depth);
    // the point the ray falls below the height field at (the crossing between it and the last
    // point above is taken after the loop)
    var h1 = h;
    var d1 = d;
    var flags = FLAG_EARLY;
    var exited = false;
    var lost = false;
    let uv0 = p.uv;
    let ni = i32(n);
    for (var i = 0; i < ni; i = i + 1) {
        // each step bends along the basis the last step read
        chained();
        let w = walk_move(p.tri, p.uv, st.xy, 1.0);
        h1 = h + st.z;
        steps = steps + 1.0;
        if (h1 > 1.0 || !w.on) {
            exited = true;
            // out through the top on the first step, far from any silhouette (FALLBACK_NDV),
            // where the normals lie far from their face (FALLBACK_OFF_FACE) or with the straight
            // ray still under the mesh (FALLBACK_UNDER), or out through a crack (an open border
            // that another runs along) with the straight ray under the plane across it (the
            // surface goes on where the walk cannot follow): the walk lost the surface; out
            // through an open border: it left it
            let x = r.p + view * (len + st.w);
            lost = (w.on && (i == 0 || -dot(view, r.f.n) > FALLBACK_NDV || walk_turned_by_normals(w, x, G.depth, walk_start(r.extra))
                || walk_above(p.tri, x) < -FALLBACK_UNDER * G.depth)) || walk_into_crack(w, x);
            break;
        }
        d1 = h1 - height_at(w.uv * tiling, r.lod);
        if (d1 <= 0.0) {
            flags = 0u;
            break;
        }
        p = w;
        h = h1;
        len = len + st.w;
        d = d1;
        st = basis_step(walk_basis(p), view, n, dl0, inv_depth);
    }
    if (lost) {
        // the stated fallback: the base mesh's point at the fragment (never worse than the base)
        return ncs_hit(r, uv0, 1.0, 0.0, steps, FLAG_FALLBACK, r.f);
    }
    if (exited) {
        var out: Hit;
        out.exited = true;
        out.steps = steps;
        return out;
    }
    if (flags == 0u) {
        // the crossing between the last two points
        let t = d / max(d - d1, 1e-12);
        p = walk_move(p.tri, p.uv, st.xy, t);
        h = mix(h, h1, t);
        len = len + st.w * t;
    }
    return ncs_hit(r, p.uv, h, len, steps, flags, walk_basis(p));
}
