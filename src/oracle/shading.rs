//! The reference shading (docs/conventions.md) the oracle shades its hits with: the base mesh's basis
//! at a point of the mesh, and the shading normal the height field's gradient tilts it to. The
//! tessellated mesh (`methods::tessellated`) takes its vertex normals from here, and
//! `pk.reference`'s ray casts their hits' normals (`shading_normals`).

use crate::scene::Material;
use glam::{DVec2, DVec3};

/// The reference shading normal (docs/conventions.md) at texture point `s` (mesh uv times the
/// tiling): the base mesh's basis (unit normal `n`, tangent `t` and bitangent `bt` orthonormal, `scale`
/// the mesh's uv per unit length along them) tilted by the height field's gradient, taken as
/// central differences one texel apart of the bilinear field at level 0. The tessellated mesh's
/// vertex normals, and the normal at a hit found by a ray cast on that mesh (`pk.reference`).
pub fn displaced_normal(
    mat: &Material,
    s: DVec2,
    n: DVec3,
    t: DVec3,
    bt: DVec3,
    scale: DVec2,
) -> DVec3 {
    let hm = &mat.height;
    let tiling = mat.tiling as f64;
    let ex = 1.0 / hm.width as f64;
    let ey = 1.0 / hm.height as f64;
    let hx = hm.sample(s.x + ex, s.y) - hm.sample(s.x - ex, s.y);
    let hy = hm.sample(s.x, s.y + ey) - hm.sample(s.x, s.y - ey);
    let gx = mat.depth as f64 * hx / (2.0 * ex) * tiling / scale.x.max(1e-12);
    let gy = mat.depth as f64 * hy / (2.0 * ey) * tiling / scale.y.max(1e-12);
    (n - t * gx - bt * gy).normalize_or_zero()
}

/// The base mesh's basis from a unit normal `n` and a tangent `t` (the bitangent's sign in `w`),
/// orthonormalised as the shader does: (n, t, bt).
pub fn basis(n: DVec3, t: DVec3, w: f64) -> (DVec3, DVec3, DVec3) {
    let mut t = t - n * n.dot(t);
    if t.length_squared() < 1e-24 {
        t = if n.x.abs() > 0.9 {
            n.cross(DVec3::Z)
        } else {
            n.cross(DVec3::X)
        };
    }
    let t = t.normalize();
    (n, t, n.cross(t) * if w < 0.0 { -1.0 } else { 1.0 })
}

/// `displaced_normal` at many points of one material: texture points from mesh `uvs` (times
/// the tiling), each with the base normal, tangent (bitangent sign in w) and uv scale
/// interpolated there.
pub fn shading_normals(
    mat: &Material,
    uvs: &[[f64; 2]],
    base_normals: &[[f64; 3]],
    tangents: &[[f64; 4]],
    uv_scale: &[[f64; 2]],
) -> Vec<DVec3> {
    let tiling = mat.tiling as f64;
    (0..uvs.len())
        .map(|i| {
            let nb = DVec3::from(base_normals[i]).normalize_or_zero();
            let tg = tangents[i];
            let (n, t, bt) = basis(nb, DVec3::new(tg[0], tg[1], tg[2]), tg[3]);
            displaced_normal(mat, DVec2::from(uvs[i]) * tiling, n, t, bt, DVec2::from(uv_scale[i]))
        })
        .collect()
}
