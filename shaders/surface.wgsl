// surface.wgsl: the rasterised base mesh and the per-pixel methods. One pipeline per
// (METHOD, SHADOWS, FILTERING); the branches below on override constants are resolved when the
// pipeline is created.

@vertex
fn vs_main(v: VsIn) -> VsOut {
    var o: VsOut;
    o.clip = G.view_proj * vec4<f32>(v.position, 1.0);
    o.world = v.position;
    o.normal = v.normal;
    o.uv = v.uv;
    o.tangent = v.tangent;
    o.uv_scale = v.uv_scale;
    return o;
}

struct Shaded {
    color: vec3<f32>,
    steps: f32,
}

// Lambertian shading with the shared light model (DESIGN.md, Shading):
// L = albedo/pi * sum(E * max(0, N.L) * visibility) + albedo * ambient * ao
fn shade(f: Frame, s: vec2<f32>, h: f32, p: vec3<f32>, n: vec3<f32>, lod: f32, with_shadows: bool) -> Shaded {
    var o: Shaded;
    o.steps = 0.0;
    let albedo = albedo_at(s, lod);
    var sum = vec3<f32>(0.0);
    let nl = u32(G.eye.w);
    for (var i = 0u; i < min(nl, MAX_LIGHTS); i = i + 1u) {
        let ls = light_sample(i, p);
        let ndl = dot(n, ls.dir);
        if (ndl <= 0.0) {
            continue;
        }
        var vis = 1.0;
        if (SHADOWS != 0u && with_shadows) {
            if (METHOD == 6u) {
                vis = shadow_map_visibility(i, p, n);
            } else {
                let sr = shadow_march(f, s, h, ls, lod);
                vis = sr.visibility;
                o.steps = o.steps + sr.steps;
            }
        }
        sum = sum + ls.e * ndl * vis;
    }
    o.color = albedo / PI * sum + albedo * G.ambient.rgb;
    return o;
}

@fragment
fn fs_main(in: VsOut) -> FsOut {
    let f = make_frame(in.normal, in.tangent, in.uv_scale);
    let tiling = G.tex.z;
    let s0 = in.uv * tiling;
    // explicit LOD, from derivatives taken here in uniform control flow
    let lod = compute_lod(s0);
    let to_p = in.world - G.eye.xyz;
    let base_dist = length(to_p);
    let view = to_p / max(base_dist, 1e-20);
    let v_ts = to_texture_space(f, view);
    let ndotv = -dot(view, f.n);

    var color = vec3<f32>(0.0);
    var steps = 0.0;
    var s_hit = s0;
    var dist = base_dist;

    if (METHOD == 0u) {
        // Flat: texture at the rasterised uv, base normal
        let sh = shade(f, s0, 1.0, in.world, f.n, lod, false);
        color = sh.color;
    } else if (METHOD == 1u) {
        // Bump (Blinn 1978): normal from the height field, uv unchanged
        let sh = shade(f, s0, 1.0, in.world, height_normal(f, s0, lod), lod, false);
        color = sh.color;
    } else if (METHOD == 2u) {
        // POM (Tatarchuk 2006) with LOD blending toward bump mapping
        let w_bump = lod_bump_weight(lod);
        var c_pom = vec3<f32>(0.0);
        if (w_bump < 1.0) {
            let hl = height_lod(lod);
            let hit = pom_march(s0, v_ts, ndotv, hl);
            let lam = (1.0 - hit.h) / max(-v_ts.z, 1e-12);
            let p = in.world + view * lam;
            let sh = shade(f, hit.s, hit.h, p, height_normal(f, hit.s, hl), hl, true);
            c_pom = sh.color;
            steps = hit.steps + sh.steps;
            s_hit = hit.s;
            dist = base_dist + lam;
        }
        var c_bump = vec3<f32>(0.0);
        if (w_bump > 0.0) {
            let sh = shade(f, s0, 1.0, in.world, height_normal(f, s0, lod), lod, false);
            c_bump = sh.color;
        }
        color = mix(c_pom, c_bump, w_bump);
    } else if (METHOD == 6u) {
        // Tessellated: the displaced mesh itself, shaded like the per-pixel methods (base frame,
        // height-field normal at the rasterised uv, level 0: this is the true surface)
        let sh = shade(f, s0, 1.0, in.world, height_normal(f, s0, 0.0), lod, true);
        color = sh.color;
    }

    return write_aovs(color, steps, s_hit / tiling, dist, lod);
}
