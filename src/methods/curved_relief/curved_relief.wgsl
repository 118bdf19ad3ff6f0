// Curved relief mapping (Oliveira & Policarpo 2005): relief mapping whose reference surface is
// not the tangent plane but the quadric that approximates the base mesh around the fragment,
// z = a x² + b y² in its basis (a, b per vertex, fitted on the CPU, interpolated: Ray::extra).
// Along the view ray the base surface falls away by q t² (q = a vx² + b vy²), so the ray's depth
// below the curved base at world distance t is d(t) = q t² + c t (c = -V.N): the search runs in
// [0, t_end], t_end where d reaches the shell's depth (the floor) or, where the surface curves
// away faster than the ray descends, where d returns to 0: the ray leaves the shell through its
// top without a hit and the fragment is discarded (the silhouette). A linear search of
// `linear_steps`, then `binary_steps` bisections. The search's uv walks across the base mesh's
// triangles (walk.wgsl): across a seam it continues in the neighbouring chart, and a ray that
// walks out through an open border has left the surface (discarded); one that walks out
// through a crack (an open border that another of the mesh runs along) has lost it, and takes
// the fallback below. A fragment whose
// interpolated normal faces away from the viewer, or whose ray leaves through the top far from
// grazing (FALLBACK_NDV), where the normals lie far from their face (FALLBACK_OFF_FACE), or
// while the straight ray still lies under the mesh (FALLBACK_UNDER, or at all within the plane
// of the face it entered),
// keeps the base mesh's point (flags & 4): never less than the base mesh.
// The hit is shaded in the mesh's basis at the hit.
#define_import_path pomkit::methods::curved_relief

#import pomkit::object::G
#import pomkit::march::{Ray, Hit}
#import pomkit::aov::{FLAG_FALLBACK, FALLBACK_NDV}
#import pomkit::height::height_at
#import pomkit::cost::chained
#import pomkit::walk::{walk_point, walk_move, walk_basis, walk_start, walk_turned_by_normals, walk_into_crack}

// the ray's height in the shell (1 at the curved base, 0 at the floor) at world distance t
fn ray_h(q: f32, c: f32, depth: f32, t: f32) -> f32 {
    return 1.0 - (q * t * t + c * t) / depth;
}

fn march(r: Ray) -> Hit {
    var hit: Hit;
    hit.f = r.f;
    hit.lod = r.lod;
    hit.flags = 0u;
    hit.exited = false;
    let depth = max(G.depth, 1e-12);
    let vx = dot(r.view, r.f.t);
    let vy = dot(r.view, r.f.b);
    let c = -dot(r.view, r.f.n);
    let q = r.extra.x * vx * vx + r.extra.y * vy * vy;
    // the smallest positive root of q t² + c t = depth (the floor), rationalised so that q -> 0
    // gives depth / c; none where the surface falls away too fast: the ray leaves at t = c / -q
    let disc = c * c + 4.0 * q * depth;
    var t_end = 0.0;
    var exits = false;
    if (c <= 0.0) {
        // the interpolated normal faces away from the viewer on a front face: the quadric has no
        // way in. The stated fallback: the base mesh's point at the fragment (flags & 4)
        hit.s = r.uv * G.tiling;
        hit.h = 1.0;
        hit.len = 0.0;
        hit.steps = 0.0;
        hit.flags = FLAG_FALLBACK;
        return hit;
    }
    if (disc >= 0.0) {
        t_end = 2.0 * depth / (c + sqrt(disc));
    } else {
        t_end = c / (-q);
        exits = true;
    }
    let n = max(params.linear_steps, 1.0);
    let dt = t_end / n;
    let tiling = G.tiling;
    // the last point above the height field (lo) and the first below (hi), each a walk point
    // at world distance t along the view; dir: uv per world length in the point's chart
    var lo = walk_point(walk_start(r.extra), r.uv);
    lo.dir = r.v_ts.xy / tiling;
    var hi = lo;
    var t_lo = 0.0;
    var t_hi = 0.0;
    var found = false;
    var lost = false;
    var steps = 0.0;
    let ni = i32(n);
    for (var i = 1; i <= ni; i = i + 1) {
        t_hi = dt * f32(i);
        hi = walk_move(lo.tri, lo.uv, lo.dir, dt);
        steps = steps + 1.0;
        if (walk_into_crack(hi, r.p + r.view * t_hi)) {
            // out through a crack (an open border that another of the mesh runs along), the
            // straight ray under the plane across it: the surface goes on where the walk cannot
            // follow (the fallback below)
            lost = true;
            break;
        }
        if (!hi.on) {
            // out through an open border: off the surface
            hit.exited = true;
            hit.steps = steps;
            return hit;
        }
        if (ray_h(q, c, depth, t_hi) <= height_at(hi.uv * tiling, r.lod)) {
            found = true;
            break;
        }
        lo = hi;
        t_lo = t_hi;
    }
    if (lost || (!found && exits && (c > FALLBACK_NDV || walk_turned_by_normals(lo, r.p + r.view * t_end, depth, walk_start(r.extra))))) {
        // out through the top far from any silhouette, where the normals lie far from their
        // face, or with the straight ray still under the mesh, or into a crack: the quadric
        // lost the surface; the base mesh's point at the fragment covers the pixel (flags & 4)
        hit.s = r.uv * G.tiling;
        hit.h = 1.0;
        hit.len = 0.0;
        hit.steps = steps;
        hit.flags = FLAG_FALLBACK;
        return hit;
    }
    if (!found) {
        // only a ray that leaves through the top gets here (at the floor h_ray = 0 <= any height)
        hit.exited = exits;
        hit.steps = steps;
        hit.s = hi.uv * tiling;
        hit.h = 0.0;
        hit.len = t_end;
        return hit;
    }
    let nb = i32(params.binary_steps);
    for (var k = 0; k < nb; k = k + 1) {
        let mid = 0.5 * (t_lo + t_hi);
        // each midpoint follows from the last verdict
        chained();
        let w = walk_move(lo.tri, lo.uv, lo.dir, mid - t_lo);
        steps = steps + 1.0;
        if (ray_h(q, c, depth, mid) <= height_at(w.uv * tiling, r.lod)) {
            hi = w;
            t_hi = mid;
        } else {
            lo = w;
            t_lo = mid;
        }
    }
    hit.s = hi.uv * tiling;
    hit.h = clamp(ray_h(q, c, depth, t_hi), 0.0, 1.0);
    hit.len = t_hi;
    hit.steps = steps;
    hit.f = walk_basis(hi);
    return hit;
}
