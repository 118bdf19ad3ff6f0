//! Camera rays' candidates: the camera's image plane cut into tiles, each listing the triangles
//! whose entry region (the top, front-facing from the eye; a prism with a wall whole) projects
//! onto it, clipped to the part in front of the eye (1e-9 of its distance from it). A camera
//! ray tests its tile's few triangles instead of walking the bounding volumes.

use super::prism::Prism;
use crate::scene::Camera;
use glam::DVec3;

/// What the grid reads of one object's shell: its prisms, which of them have a wall, the
/// shell's depth, and the maps between the object's space and the world.
pub(super) struct Entries<'a> {
    pub(super) prisms: &'a [Option<Prism>],
    pub(super) walled: &'a [bool],
    pub(super) depth: f64,
    pub(super) to_obj: glam::DMat4,
    pub(super) to_world: glam::DMat4,
}

/// Tiles over the camera's full image plane, as (object, triangle) lists.
pub(super) struct Grid {
    eye: DVec3,
    forward: DVec3,
    right: DVec3,
    up: DVec3,
    /// the plane's corner (x, y = tangents along right and up) and tiles per unit
    x0: f64,
    y0: f64,
    scale: f64,
    nx: usize,
    ny: usize,
    /// tile k's candidates: items[starts[k]..starts[k + 1]]
    starts: Vec<u32>,
    items: Vec<(u32, u32)>,
}

impl Grid {
    pub(super) fn new(camera: &Camera, objects: &[Entries<'_>]) -> Grid {
        let b = camera.basis();
        let ((fw, fh), _) = camera.full();
        let (tx, ty) = (b.tan_half_y * b.aspect, b.tan_half_y);
        // about two pixels a tile
        let nx = (fw as usize / 2).clamp(1, 256);
        let ny = (fh as usize / 2).clamp(1, 256);
        let scale = (nx as f64 / (2.0 * tx)).min(ny as f64 / (2.0 * ty));
        let (nx, ny) = (
            ((2.0 * tx * scale).ceil() as usize).max(1),
            ((2.0 * ty * scale).ceil() as usize).max(1),
        );
        let mut g = Grid {
            eye: b.eye,
            forward: b.forward,
            right: b.right,
            up: b.up,
            x0: -tx,
            y0: -ty,
            scale,
            nx,
            ny,
            starts: vec![0; nx * ny + 1],
            items: Vec::new(),
        };
        // each candidate's tile range
        let mut spans: Vec<((u32, u32), [usize; 4])> = Vec::new();
        for (oi, ob) in objects.iter().enumerate() {
            let eye = ob.to_obj.transform_point3(b.eye);
            for (t, p) in ob.prisms.iter().enumerate() {
                let Some(p) = p else { continue };
                let walled = ob.walled[t];
                // a top seen from behind is entered by no camera ray
                if !walled && (p.p[0] - eye).dot(p.ng) >= 0.0 {
                    continue;
                }
                let id = (oi as u32, t as u32);
                // the entry region's corners in camera space (the region lies in their hull)
                let floor = if walled { 2.0 * ob.depth } else { 0.0 };
                let mut pts = [DVec3::ZERO; 6];
                for k in 0..3 {
                    for (m, q) in [p.p[k], p.p[k] - p.n[k] * floor].into_iter().enumerate() {
                        let v = ob.to_world.transform_point3(q) - b.eye;
                        pts[2 * k + m] = DVec3::new(v.dot(b.right), v.dot(b.up), v.dot(b.forward));
                    }
                }
                // the hull's part in front of the eye: its corners there, and where the
                // segments between a corner in front and one behind cross z = near
                let near = 1e-9 * (1.0 + pts.iter().map(|v| v.length()).fold(0.0, f64::max));
                let mut lo = (f64::INFINITY, f64::INFINITY);
                let mut hi = (f64::NEG_INFINITY, f64::NEG_INFINITY);
                let mut put = |v: DVec3| {
                    let (x, y) = (v.x / v.z, v.y / v.z);
                    lo = (lo.0.min(x), lo.1.min(y));
                    hi = (hi.0.max(x), hi.1.max(y));
                };
                for &f in pts.iter().filter(|v| v.z >= near) {
                    put(f);
                    for &r in pts.iter().filter(|v| v.z < near) {
                        put(f + (r - f) * ((f.z - near) / (f.z - r.z)));
                    }
                }
                // (nothing in front: no camera ray meets it)
                if !(lo.0.is_finite() && hi.0.is_finite() && lo.1.is_finite() && hi.1.is_finite()) {
                    continue;
                }
                let Some(span) = g.tiles(lo, hi) else {
                    continue;
                };
                spans.push((id, span));
            }
        }
        for (_, [i0, i1, j0, j1]) in &spans {
            for j in *j0..=*j1 {
                for i in *i0..=*i1 {
                    g.starts[j * nx + i + 1] += 1;
                }
            }
        }
        for k in 0..nx * ny {
            g.starts[k + 1] += g.starts[k];
        }
        g.items = vec![(0, 0); g.starts[nx * ny] as usize];
        let mut fill = g.starts.clone();
        for (id, [i0, i1, j0, j1]) in spans {
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let k = j * nx + i;
                    g.items[fill[k] as usize] = id;
                    fill[k] += 1;
                }
            }
        }
        g
    }

    /// The tiles a box of the plane meets: (first, last column, first, last row); None where
    /// it lies outside the grid.
    fn tiles(&self, lo: (f64, f64), hi: (f64, f64)) -> Option<[usize; 4]> {
        // one tile's margin against rounding
        let (x0, x1) = (
            (lo.0 - self.x0) * self.scale - 1.0,
            (hi.0 - self.x0) * self.scale + 1.0,
        );
        let (y0, y1) = (
            (lo.1 - self.y0) * self.scale - 1.0,
            (hi.1 - self.y0) * self.scale + 1.0,
        );
        if x1 < 0.0 || y1 < 0.0 || x0 >= self.nx as f64 || y0 >= self.ny as f64 {
            return None;
        }
        let c = |v: f64, n: usize| (v.max(0.0) as usize).min(n - 1);
        Some([
            c(x0, self.nx),
            c(x1, self.nx),
            c(y0, self.ny),
            c(y1, self.ny),
        ])
    }

    /// A camera ray's candidates (those of its tile), or None where the ray is not from the eye
    /// or leaves the grid.
    pub(super) fn candidates(&self, eye: DVec3, dir: DVec3) -> Option<&[(u32, u32)]> {
        if eye != self.eye {
            return None;
        }
        let z = dir.dot(self.forward);
        if !(z > 0.0) {
            return None;
        }
        let x = ((dir.dot(self.right) / z - self.x0) * self.scale).floor();
        let y = ((dir.dot(self.up) / z - self.y0) * self.scale).floor();
        if !(x >= 0.0 && y >= 0.0 && x < self.nx as f64 && y < self.ny as f64) {
            return None;
        }
        let k = y as usize * self.nx + x as usize;
        Some(&self.items[self.starts[k] as usize..self.starts[k + 1] as usize])
    }
}
