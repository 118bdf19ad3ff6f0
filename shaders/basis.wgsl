// basis.wgsl: the base surface's orthonormal tangent basis at a point, and world directions expressed
// in texture space.
//
// Conventions (docs/conventions.md): h = 1 is the base surface, h = 0 lies `depth` below it
// along the base normal. A texture-space ray is (s, h) with s = uv * tiling in height-map uv
// units; a direction is expressed "per unit of world length" so that distances come out in
// world units.
#define_import_path pomkit::basis

#import pomkit::object::G

struct Basis {
    t: vec3<f32>,
    b: vec3<f32>,
    n: vec3<f32>,
    // world length per unit of u and of v
    scale: vec2<f32>,
}

fn make_basis(n_in: vec3<f32>, t_in: vec4<f32>, scale: vec2<f32>) -> Basis {
    var f: Basis;
    f.n = normalize(n_in);
    var t = t_in.xyz - f.n * dot(t_in.xyz, f.n);
    if (dot(t, t) < 1e-12) {
        // degenerate tangent: any vector orthogonal to n
        let a = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 0.0, 1.0), abs(f.n.x) > 0.9);
        t = cross(f.n, a);
    }
    f.t = normalize(t);
    let w = select(1.0, -1.0, t_in.w < 0.0);
    f.b = w * cross(f.n, f.t);
    f.scale = max(scale, vec2<f32>(1e-12));
    return f;
}

// A world direction expressed in texture space per unit of world length: (ds_u, ds_v, dh).
fn to_texture_space(f: Basis, d: vec3<f32>) -> vec3<f32> {
    let tiling = G.tiling;
    let depth = max(G.depth, 1e-12);
    return vec3<f32>(
        tiling * dot(d, f.t) / f.scale.x,
        tiling * dot(d, f.b) / f.scale.y,
        dot(d, f.n) / depth,
    );
}
