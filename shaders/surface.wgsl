// surface.wgsl: the rasterised mesh and the per-pixel methods. One pipeline per
// (METHOD, SHADOWS, FILTERING); the branches on override constants are resolved when the
// pipeline is created. The methods share the tangent-space set-up (common.wgsl), the search
// (pom.wgsl, relief.wgsl, exact.wgsl), the shadows (shadows.wgsl, horizon.wgsl, exact.wgsl),
// the LOD (lod.wgsl), the shading and the AOV output below.

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

fn light_visibility(f: Frame, s: vec2<f32>, h: f32, p: vec3<f32>, n: vec3<f32>, i: u32, ls: LightSample, lod: f32) -> ShadowResult {
    var r: ShadowResult;
    r.visibility = 1.0;
    r.steps = 0.0;
    if (METHOD == 6u) {
        r.visibility = shadow_map_visibility(i, p, n);
    } else if (SHADOWS == 3u) {
        r = horizon_shadow(f, s, h, ls);
    } else if (SHADOWS == 4u) {
        r = exact_shadow(f, s, h, ls);
    } else {
        r = shadow_march(f, s, h, ls, lod);
    }
    return r;
}

// Lambertian shading with the shared light model (DESIGN.md, Shading):
// L = albedo/pi * sum(E * max(0, N.L) * visibility) + albedo * ambient * ao
fn shade(f: Frame, s: vec2<f32>, h: f32, p: vec3<f32>, n: vec3<f32>, lod: f32, with_shadows: bool, px: vec2<f32>) -> Shaded {
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
            let r = light_visibility(f, s, h, p, n, i, ls, lod);
            vis = r.visibility;
            o.steps = o.steps + r.steps;
        }
        sum = sum + ls.e * ndl * vis;
    }
    var ao = 1.0;
    if (METHOD != 6u && with_shadows && G.extra.z > 0.0 && any(G.ambient.rgb > vec3<f32>(0.0))) {
        let a = horizon_ao(f, s, h, px);
        ao = a.x;
        o.steps = o.steps + a.y;
    }
    o.color = albedo / PI * sum + albedo * G.ambient.rgb * ao;
    return o;
}

// The view ray's hit for the per-pixel methods (METHOD 2..5, 7).
fn method_hit(s0: vec2<f32>, dsdh: vec2<f32>, ndotv: f32, hl: f32) -> Hit {
    if (METHOD == 3u) {
        return parallax_offset(s0, dsdh, ndotv, hl);
    } else if (METHOD == 4u) {
        return steep_march(s0, dsdh, hl);
    } else if (METHOD == 5u) {
        return relief_march(s0, dsdh, ndotv, hl);
    } else if (METHOD == 7u) {
        return exact_march(s0, dsdh);
    }
    return pom_march(s0, dsdh, ndotv, hl);
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
    let px = in.clip.xy;

    var color = vec3<f32>(0.0);
    var steps = 0.0;
    var flags = 0u;
    var s_hit = s0;
    var dist = base_dist;

    if (METHOD == 0u) {
        // Flat: texture at the rasterised uv, base normal
        color = shade(f, s0, 1.0, in.world, f.n, lod, false, px).color;
    } else if (METHOD == 1u) {
        // Bump (Blinn 1978): normal from the height field, uv unchanged
        color = shade(f, s0, 1.0, in.world, height_normal(f, s0, lod), lod, false, px).color;
    } else if (METHOD == 8u) {
        // NCS: the march follows the curved base surface; leaving the shell is a silhouette
        let hl = height_lod(lod);
        let r = ncs_march(in.uv, view, hl);
        if (r.exited) {
            discard;
        }
        let p = in.world + view * r.len;
        let sh = shade(r.f, r.uv * tiling, r.h, p, height_normal(r.f, r.uv * tiling, hl), hl, true, px);
        color = sh.color;
        steps = r.steps + sh.steps;
        flags = r.flags;
        s_hit = r.uv * tiling;
        dist = base_dist + r.len;
    } else if (METHOD == 6u) {
        // Tessellated: the displaced mesh itself, shaded like the per-pixel methods (base frame,
        // height-field normal at the rasterised uv, level 0: this is the true surface)
        let sh = shade(f, s0, 1.0, in.world, height_normal(f, s0, 0.0), lod, true, px);
        color = sh.color;
        steps = sh.steps;
    } else {
        // per-pixel displacement; POM blends toward bump mapping by the LOD (lod.wgsl)
        var w_bump = 0.0;
        if (METHOD == 2u) {
            w_bump = lod_bump_weight(lod);
        }
        // Exact reads level 0 (the exact field); the others the footprint's level by default
        var hl = height_lod(lod);
        if (METHOD == 7u) {
            hl = 0.0;
        }
        var c_march = vec3<f32>(0.0);
        if (w_bump < 1.0) {
            let dsdh = v_ts.xy / max(-v_ts.z, 1e-6);
            let hit = method_hit(s0, dsdh, ndotv, hl);
            let lam = (1.0 - hit.h) / max(-v_ts.z, 1e-12);
            let p = in.world + view * lam;
            let sh = shade(f, hit.s, hit.h, p, height_normal(f, hit.s, hl), hl, true, px);
            c_march = sh.color;
            steps = hit.steps + sh.steps;
            flags = hit.flags;
            s_hit = hit.s;
            dist = base_dist + lam;
        }
        var c_bump = vec3<f32>(0.0);
        if (w_bump > 0.0) {
            c_bump = shade(f, s0, 1.0, in.world, height_normal(f, s0, lod), lod, false, px).color;
        }
        color = mix(c_march, c_bump, w_bump);
    }
    return write_aovs(color, u32(steps), flags, s_hit / tiling, dist, lod);
}
