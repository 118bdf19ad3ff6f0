// Distance mapping (Donnelly 2005, GPU Gems 2 ch. 8): sphere tracing through a 3-D distance
// texture over the shell (distance_volume.wgsl). From the entry the ray advances by the distance
// stored for its voxel, less the voxel's half diagonal (a step that cannot reach the surface);
// where that leaves nothing (within about a voxel of the bounding columns) it tests the height
// field itself and steps half a texel; the first sample below the surface is refined by
// `binary_steps` bisections. `max_steps` bounds the walk (flagged).
#define_import_path pomkit::methods::distance_mapping

#import pomkit::cost::{fetched, chained}
#import pomkit::object::G
#import pomkit::aov::FLAG_BOUND
#import pomkit::march::{Ray, Hit, planar_hit}
#import pomkit::height::height_at

// the method's own resource (group 2, binding 1): the header (size x, size y, slices, level),
// then the distances, x fastest
@group(2) @binding(1) var<storage, read> dist_buf: array<f32>;

fn wrap_f(a: f32, n: f32) -> f32 {
    return a - floor(a / n) * n;
}

fn march(r: Ray) -> Hit {
    let wv = dist_buf[0];
    let hv = dist_buf[1];
    let slices = dist_buf[2];
    let node = exp2(dist_buf[3]);
    // voxel space along the view segment (s0 + dsdh u, 1 - u), u in [0, 1]
    let x0 = (r.s.x * G.map_size.x - 0.5) / node;
    let y0 = (r.s.y * G.map_size.y - 0.5) / node;
    let dx = r.dsdh.x * G.map_size.x / node;
    let dy = r.dsdh.y * G.map_size.y / node;
    let len = length(vec3<f32>(dx, dy, slices));
    // the near-surface step: half a texel along the ray, at most 1/64 of the shell's height
    let texels = length(r.dsdh * G.map_size);
    let du_near = min(0.5 / max(texels, 1e-6), 1.0 / 64.0);
    var u = 0.0;
    var u_prev = 0.0;
    var steps = 0.0;
    var found = false;
    var flags = 0u;
    let n = i32(params.max_steps);
    var it = 0;
    loop {
        if (it >= n) {
            flags = FLAG_BOUND;
            break;
        }
        it = it + 1;
        // sphere tracing: each step's length is the last distance read
        chained();
        let x = wrap_f(x0 + dx * u, wv);
        let y = wrap_f(y0 + dy * u, hv);
        let z = clamp(slices * (1.0 - u), 0.0, slices - 0.5);
        let idx = (u32(z) * u32(hv) + u32(y)) * u32(wv) + u32(x);
        fetched(1u, 4u);
        let dd = dist_buf[4u + idx] - 0.8660254;
        steps = steps + 1.0;
        if (dd > 0.0) {
            u_prev = u;
            u = u + dd / len;
        } else {
            let hs = height_at(r.s + r.dsdh * u, r.lod);
            steps = steps + 1.0;
            if (1.0 - u <= hs) {
                found = true;
                break;
            }
            u_prev = u;
            u = u + du_near;
        }
        if (u >= 1.0) {
            u = 1.0;
            found = true;
            break;
        }
    }
    var lo = u_prev;
    var hi = u;
    if (found) {
        let nb = i32(params.binary_steps);
        for (var k = 0; k < nb; k = k + 1) {
            let mid = 0.5 * (lo + hi);
            steps = steps + 1.0;
            chained();
            if (1.0 - mid <= height_at(r.s + r.dsdh * mid, r.lod)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
    }
    return planar_hit(r, r.s + r.dsdh * hi, 1.0 - hi, steps, flags);
}
