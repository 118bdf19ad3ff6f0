//! NCS's frame map as the march reads it (src/methods/ncs/frame_map.wgsl): each map texel is two
//! Rgba32Uint texels of float bits, (n, k) and (a, 0), with a = t / S_tangent and
//! k = sign * S_tangent / S_binormal, so that b / S_binormal = k * cross(n, a). Checked against
//! the meshes' analytic frames: the plane exactly, the torus within its chord error.

use pomkit::contract::Resident;
use pomkit::gpu;
use pomkit::heightmap::read_f32_texels;
use pomkit::mesh::Mesh;
use pomkit::methods::{Method, Ncs, PerPixel};
use pomkit::render::test_hooks::resource_scene;
use pomkit::render::Renderer;
use pomkit::scene::HeightMap;
use std::f64::consts::PI;

type V3 = [f64; 3];

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn len(a: V3) -> f64 {
    dot(a, a).sqrt()
}

/// One map texel as the march reads it: (n, a, k) and b / S_binormal.
struct Texel {
    n: V3,
    a: V3,
    k: f64,
    b: V3,
}

/// NCS's own resource for `mesh`, built as a render builds it, read back: (size, texels).
fn frame_map(r: &Renderer, mesh: Mesh) -> ((u32, u32), Vec<Texel>) {
    let map = HeightMap::new(4, 4, vec![0.5; 16]).unwrap();
    let scene = resource_scene(mesh, map).unwrap();
    let m = Method::Ncs(
        Ncs {
            step_scale: 2.5,
            max_steps: 64,
            adaptive: true,
        },
        PerPixel::off(),
    );
    let res = pomkit::render::test_hooks::method_resources(r, &scene, &m).unwrap();
    let [Resident::Texture(view)] = res.as_slice() else {
        panic!("NCS declares one texture, got {res:?}");
    };
    let tex = view.texture().clone();
    let (w, h) = (tex.width(), tex.height());
    assert_eq!(w, 2 * h, "two texels per map texel");
    assert_eq!(
        w as u64 * h as u64 * 16,
        pomkit::methods::NCS_MAP_BYTES,
        "the bytes the docs report"
    );
    // Rgba32Uint holding float bits: read as float32s
    let raw = read_f32_texels(&r.ctx, &tex, 0, (w, h), 4).unwrap();
    let texels = (0..(w / 2 * h) as usize)
        .map(|i| {
            let (x, y) = (i % (w / 2) as usize, i / (w / 2) as usize);
            let at = |k: usize| (y * w as usize + 2 * x + k) * 4;
            let f = |j: usize| raw[j] as f64;
            let (p, q) = (at(0), at(1));
            let n = [f(p), f(p + 1), f(p + 2)];
            let a = [f(q), f(q + 1), f(q + 2)];
            let k = f(p + 3);
            let c = cross(n, a);
            Texel {
                n,
                a,
                k,
                b: [k * c[0], k * c[1], k * c[2]],
            }
        })
        .collect();
    ((w / 2, h), texels)
}

fn renderer() -> Renderer {
    Renderer::new(gpu::shared(None).expect("an adapter (install mesa-vulkan-drivers)")).unwrap()
}

#[test]
fn the_plane_s_frame_map_is_its_analytic_frame() {
    let r = renderer();
    // position ((u - 0.5) size, 0, (v - 0.5) size), normal +Y: t = +X and b = +Z, S = size,
    // and b = -cross(n, t), so k = -S_t / S_b = -1
    let size = 2.0;
    let (_, map) = frame_map(&r, Mesh::plane(size, 1).unwrap());
    for (i, t) in map.iter().enumerate() {
        let close = |a: V3, b: V3| (0..3).all(|j| (a[j] - b[j]).abs() <= 1e-6);
        assert!(close(t.n, [0.0, 1.0, 0.0]), "texel {i}: n = {:?}", t.n);
        assert!(
            close(t.a, [1.0 / size, 0.0, 0.0]),
            "texel {i}: a = {:?}",
            t.a
        );
        assert!((t.k + 1.0).abs() <= 1e-6, "texel {i}: k = {}", t.k);
        assert!(
            close(t.b, [0.0, 0.0, 1.0 / size]),
            "texel {i}: b / S_b = {:?}",
            t.b
        );
    }
}

#[test]
fn the_torus_s_frame_map_follows_its_analytic_frame() {
    let r = renderer();
    let (major, minor) = (1.0, 0.35);
    let ((w, h), map) = frame_map(&r, Mesh::torus(major, minor, 48, 24).unwrap());
    let mut worst = [0.0f64; 4];
    for (i, t) in map.iter().enumerate() {
        let (x, y) = (i as u32 % w, i as u32 / w);
        let (u, v) = ((x as f64 + 0.5) / w as f64, (y as f64 + 0.5) / h as f64);
        let (phi, th) = (2.0 * PI * u, 2.0 * PI * v);
        let radial = [phi.cos(), 0.0, -phi.sin()];
        let n = [radial[0] * th.cos(), th.sin(), radial[2] * th.cos()];
        // dP/du = 2 pi (major + minor cos th) (-sin phi, 0, -cos phi); dP/dv = 2 pi minor (dn/dth)
        let s_t = 2.0 * PI * (major + minor * th.cos());
        let s_b = 2.0 * PI * minor;
        let a = [-phi.sin() / s_t, 0.0, -phi.cos() / s_t];
        let b = [
            -th.sin() * radial[0] / s_b,
            th.cos() / s_b,
            -th.sin() * radial[2] / s_b,
        ];
        // the stored frame is orthonormal as packed: |n| = 1, a and b orthogonal to n
        assert!(
            (len(t.n) - 1.0).abs() <= 1e-5,
            "texel {i}: |n| = {}",
            len(t.n)
        );
        assert!(
            dot(t.n, t.a).abs() <= 1e-5 * len(t.a),
            "texel {i}: n.a = {}",
            dot(t.n, t.a)
        );
        // the texels of the first and last triangle column of the u seam: there the mesh's
        // duplicated seam vertices see triangles on one side only (their tangents and scales
        // are one-sided, off by half a segment), which is the mesh's frame, not the map's
        if !(1.0 / 48.0..=47.0 / 48.0).contains(&u) {
            continue;
        }
        let rel = |p: V3, q: V3| len([p[0] - q[0], p[1] - q[1], p[2] - q[2]]) / len(q);
        worst[0] = worst[0].max(len([t.n[0] - n[0], t.n[1] - n[1], t.n[2] - n[2]]));
        worst[1] = worst[1].max(rel(t.a, a));
        worst[2] = worst[2].max(rel(t.b, b));
        worst[3] = worst[3].max((t.k - s_t / s_b).abs() / (s_t / s_b));
    }
    // the mesh is 48 x 24 flat triangles with interpolated normals and per-vertex scales: its
    // frame is the analytic one within the chord error (the normal turns 7.5 deg across a
    // triangle, the scales are chords)
    eprintln!(
        "torus frame map, worst: n {:.2e}, a {:.2e}, b {:.2e}, k {:.2e}",
        worst[0], worst[1], worst[2], worst[3]
    );
    assert!(worst[0] <= 0.015, "normal off by {}", worst[0]);
    assert!(
        worst[1] <= 0.02,
        "t / S_tangent off by {} (relative)",
        worst[1]
    );
    assert!(
        worst[2] <= 0.01,
        "b / S_binormal off by {} (relative)",
        worst[2]
    );
    assert!(worst[3] <= 0.02, "k off by {} (relative)", worst[3]);
}
