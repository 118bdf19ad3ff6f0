//! One object of the shell: its mesh and material with the geometry its mesh and depth make
//! (prisms, adjacency, bounding volumes), built once per (mesh content, depth) and kept in the
//! caller's `Shells`, and the queries a ray's walk asks of it.

use super::bvh::Bvh;
use super::prism::{Local, Prism};
use crate::error::{Error, Result};
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use crate::oracle::field::Field;
use crate::scene::Material;
use glam::{DMat3, DMat4, DVec2, DVec3};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::{Arc, Mutex};

/// A point of the ray's path in a prism: texture point s = uv * tiling, height h.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sample {
    pub(super) lam: f64,
    pub(super) at: Local,
    pub(super) s: DVec2,
    pub(super) h: f64,
    /// s in cells (for bounds and deviations)
    pub(super) c: DVec2,
}

/// `Object::overhung`'s answers, kept per triangle
const UNKNOWN: u8 = 0;
const NO: u8 = 1;
const YES: u8 = 2;


pub(super) struct Object<'a> {
    pub(super) mesh: &'a Mesh,
    pub(super) mat: &'a Material,
    pub(super) field: Field<'a>,
    /// what the mesh and the depth give, built once per (mesh content, depth) and kept
    pub(super) geo: Arc<Geometry>,
    pub(super) to_obj: DMat4,
    pub(super) to_world: DMat4,
    pub(super) normal_to_world: DMat3,
    /// 1 / depth (heights are offsets times it)
    pub(super) per_depth: f64,
    pub(super) tiling: f64,
}

impl std::ops::Deref for Object<'_> {
    type Target = Geometry;
    fn deref(&self) -> &Geometry {
        &self.geo
    }
}

/// An object's shell as its mesh and depth make it: prisms, adjacency, bounding volumes. Kept in
/// the caller's `Shells` by (mesh content, depth), so that later calls on the same asset pay per
/// pixel only.
pub(super) struct Geometry {
    pub(super) prisms: Vec<Option<Prism>>,
    /// per triangle and side k (corners k, k+1): the triangle across it where the two shells
    /// share the side (the same positions and normals); None at a wall (an open border, a hard
    /// edge), where a ray may enter the shell from the side
    pub(super) across: Vec<[Option<u32>; 3]>,
    /// the triangles with a wall
    pub(super) walled: Vec<bool>,
    /// whether no triangle has one (the shell closes round a solid)
    pub(super) closed: bool,
    /// per triangle: whether any part of the object's shell where a ray can enter it (a top,
    /// a wall) lies above the triangle's plane, by more than 1e-6 of the object's size (the
    /// rounding of float32 positions: a quad's two triangles are one plane). Where none does,
    /// a ray that leaves through the triangle's top, and so is above that plane from then on,
    /// does not meet this object again (`Object::overhung`, answered on first use)
    pub(super) overhung: Vec<AtomicU8>,
    /// welded id per vertex (the same position)
    pub(super) weld: Vec<u32>,
    /// per triangle: whether every triangle that shares a corner with it has the same uv there
    /// (no uv seam meets it), so that texture space goes on smoothly around it
    pub(super) seam_free: Vec<bool>,
    pub(super) bvh: Bvh,
    pub(super) depth: f64,
    /// object-space size of the whole mesh (for tolerances)
    pub(super) extent: f64,
}

/// The shells built lately, by (mesh key, depth bits): the most recent `KEPT` of them. Owned by
/// the oracle's caller (pk.oracle holds one for the process; a test, its own), so that what is
/// kept, and for how long, is the caller's to say.
#[derive(Default)]
pub struct Shells {
    kept: Mutex<Vec<((u64, u64), Arc<Geometry>)>>,
}

/// How many shells `Shells` keeps.
const KEPT: usize = 4;

impl Shells {
    /// The shell of (mesh, depth), built where it is not kept.
    fn get(&self, mesh: &Mesh, key: u64, depth: f64) -> Result<Arc<Geometry>> {
        let id = (key, depth.to_bits());
        let kept = self
            .kept
            .lock()
            .ok()
            .and_then(|g| g.iter().find(|(k, _)| *k == id).map(|(_, v)| v.clone()));
        if let Some(g) = kept {
            return Ok(g);
        }
        let g = Arc::new(Geometry::new(mesh, depth)?);
        if let Ok(mut kept) = self.kept.lock() {
            kept.retain(|(k, _)| *k != id);
            kept.push((id, g.clone()));
            let over = kept.len().saturating_sub(KEPT);
            kept.drain(..over);
        }
        Ok(g)
    }

    /// How many shells are kept.
    pub fn len(&self) -> usize {
        self.kept.lock().map(|k| k.len()).unwrap_or(0)
    }

    /// Whether none is.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl<'a> Object<'a> {
    pub(super) fn new(
        mesh: &'a Mesh,
        mat: &'a Material,
        key: u64,
        m: DMat4,
        shells: &Shells,
    ) -> Result<Object<'a>> {
        let depth = mat.depth as f64;
        let geo = shells.get(mesh, key, depth)?;
        let lin = DMat3::from_mat4(m);
        Ok(Object {
            mesh,
            mat,
            field: Field::new(&mat.height),
            geo,
            to_obj: m.inverse(),
            to_world: m,
            normal_to_world: lin.inverse().transpose(),
            per_depth: 1.0 / depth,
            tiling: mat.tiling as f64,
        })
    }
}

impl Geometry {
    fn new(mesh: &Mesh, depth: f64) -> Result<Geometry> {
        let n = mesh.indices.len() / 3;
        crate::parallel::init();
        let prisms: Vec<Option<Prism>> = (0..n).into_par_iter().map(|t| Prism::new(mesh, t)).collect();
        if prisms.iter().all(Option::is_none) {
            return Err(Error::arg(
                "mesh",
                "no triangle with usable positions and uvs",
            ));
        }
        let topo = Topology::quantised(mesh);
        let across: Vec<[Option<u32>; 3]> = (0..n)
            .into_par_iter()
            .map(|t| {
                std::array::from_fn(|k| {
                    let e = topo.tri_edges[t][k] as usize;
                    let p = prisms[t].as_ref()?;
                    // (a triangle without area, as at a sphere's poles, is looked through)
                    let other = topo.edges[e]
                        .1
                        .iter()
                        .find(|s| s.tri as usize != t && prisms[s.tri as usize].is_some())?;
                    let q = prisms[other.tri as usize].as_ref()?;
                    // the same side only where both ends carry the same normal on both
                    let same = [k, (k + 1) % 3].iter().all(|&c| {
                        (0..3).any(|j| {
                            topo.weld[q.v[j] as usize] == topo.weld[p.v[c] as usize]
                                && (q.n[j] - p.n[c]).length() <= 1e-5
                        })
                    });
                    same.then_some(other.tri)
                })
            })
            .collect();
        let walled: Vec<bool> = (0..n)
            .map(|t| prisms[t].is_some() && across[t].iter().any(Option::is_none))
            .collect();
        let (lo, hi) = mesh.bounds();
        let extent = (hi - lo).max_element().max(1e-30);
        // each item's box: where a ray can enter the prism. That is its top (the base
        // triangle); with a wall, the whole prism: its top and its floor (depth along each
        // corner's normal, and as much again for the floor's bulge between corners, where
        // |n(b)| < 1)
        let boxes: Vec<Option<(DVec3, DVec3)>> = prisms
            .par_iter()
            .enumerate()
            .map(|(t, p)| {
                let p = p.as_ref()?;
                let floor = if walled[t] { 2.0 * depth } else { 0.0 };
                let (mut lo, mut hi) = (p.p[0], p.p[0]);
                for k in 0..3 {
                    for x in [p.p[k], p.p[k] - p.n[k] * floor] {
                        lo = lo.min(x);
                        hi = hi.max(x);
                    }
                }
                let pad = DVec3::splat(1e-9 * extent);
                Some((lo - pad, hi + pad))
            })
            .collect();
        // a ray enters a prism through its top against its normal; through a wall, any way
        let facing: Vec<Option<DVec3>> = (0..n)
            .map(|t| prisms[t].as_ref().filter(|_| !walled[t]).map(|p| p.ng))
            .collect();
        let bvh = Bvh::new(&boxes, &facing);
        let overhung = (0..n).map(|_| AtomicU8::new(UNKNOWN)).collect();
        // the welded corners where uvs differ
        let mut first_uv: Vec<Option<DVec2>> = vec![None; mesh.positions.len()];
        let mut seam = vec![false; mesh.positions.len()];
        for &v in &mesh.indices {
            let (w, uv) = (topo.weld[v as usize] as usize, mesh.uv_f64(v));
            match first_uv[w] {
                None => first_uv[w] = Some(uv),
                Some(u) => seam[w] |= (u - uv).length() > 1e-9,
            }
        }
        let seam_free: Vec<bool> = (0..n)
            .map(|t| {
                prisms[t]
                    .as_ref()
                    .is_some_and(|p| p.v.iter().all(|&v| !seam[topo.weld[v as usize] as usize]))
            })
            .collect();
        Ok(Geometry {
            prisms,
            across,
            closed: !walled.iter().any(|&w| w),
            walled,
            overhung,
            seam_free,
            weld: topo.weld,
            bvh,
            depth,
            extent,
        })
    }
}

impl Object<'_> {
    /// Whether any part of the object's shell where a ray can enter it (a top, a wall) lies above
    /// triangle `t`'s plane (see the field `overhung`): a query of the bounding volumes, made on
    /// the first call for the triangle and kept (a frame asks it of the few triangles its rays
    /// leave by, so a large mesh pays for those only).
    pub(super) fn overhung(&self, t: usize) -> bool {
        match self.overhung[t].load(Ordering::Relaxed) {
            YES => return true,
            NO => return false,
            _ => {}
        }
        let Some(p) = &self.prisms[t] else {
            return false;
        };
        let depth = self.depth;
        let (ng, base) = (p.ng, p.ng.dot(p.p[0]) + 1e-6 * self.extent);
        let answer = self.bvh.any(
            // the box's highest point along ng
            |lo, hi| 0.5 * ((lo + hi).dot(ng) + (hi - lo).dot(ng.abs())) > base,
            |i| {
                let q = self.prisms[i as usize]
                    .as_ref()
                    .expect("an item has a prism");
                (0..3).any(|k| {
                    q.p[k].dot(ng) > base
                        || (self.walled[i as usize]
                            && (q.p[k] - q.n[k] * (2.0 * depth)).dot(ng) > base)
                })
            },
        );
        self.overhung[t].store(if answer { YES } else { NO }, Ordering::Relaxed);
        answer
    }

    /// Whether a point of prism `p` lies above the surface.
    pub(super) fn above(&self, p: &Prism, at: Local) -> bool {
        let s = p.uv(at.b) * self.tiling;
        1.0 + p.offset(at) * self.per_depth > self.mat.height.sample(s.x, s.y)
    }

    pub(super) fn sample(&self, p: &Prism, lam: f64, at: Local, lift: f64) -> Sample {
        let s = p.uv(at.b) * self.tiling;
        let hm = &self.mat.height;
        Sample {
            lam,
            at,
            s,
            h: 1.0 + p.offset(at) * self.per_depth + lift,
            c: DVec2::new(s.x * hm.width as f64, s.y * hm.height as f64),
        }
    }
}
