//! The float64 oracle on any mesh: the exact first hit of a ray with the displaced surface
//! S = P + depth (h - 1) N of every object of a scene (curved, several, transformed), P and N
//! interpolated over each base triangle as the tessellator and the shaders define them (N the
//! normalised interpolated vertex normal).
//!
//! A ray enters the shell through its top, the base mesh (a bounding volume hierarchy finds the
//! triangles it crosses going in), and walks from prism to prism (prism.rs): through a side
//! into the triangle across it (the same side where positions and normals agree, across uv
//! seams too), out through the top, or out through an open border's side. In each prism the
//! ray's path in texture space, (uv(b) * tiling, h), is a smooth curve: it is cut into chords,
//! each bounded by its deviation from the curve at its middle, and a chord whose box of cells
//! lies under the ray (the max pyramid's bound) holds no hit; elsewhere chords are halved until
//! they deviate by at most `TOL_TEXELS` from the curve, and then walked exactly by the planar
//! oracle's cell walk (field.rs). Hits are therefore exact to within `TOL_TEXELS` along the
//! surface (in height, to what that distance along the ray makes).
//!
//! Light rays are the same walk from the hit: a light is visible where its ray leaves the shell
//! without meeting the surface and meets no object's shell again (every object occludes, as in
//! the world and in Mitsuba's reference).

mod bundle;
mod bundle_shows;
mod bvh;
mod grid;
mod object;
pub(crate) mod prism;
mod walk;

use super::field::walk_cells;
use super::trace::{Hit, Tracer};
use crate::error::{Error, Result};
use crate::scene::{Material, Scene};
use bundle_shows::Bundle;
use glam::{DVec2, DVec3};
pub use object::Shells;
use object::{Object, Sample};
use prism::{Crossing, Local, Place, Prism};

/// The largest deviation, in texels, of a walked chord from the ray's path in texture space
/// (the hit it finds is then moved onto the path itself).
pub const TOL_TEXELS: f64 = 1e-2;

/// A hit's place: its object-space point and where in which prism.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShellAt {
    tri: u32,
    at: Local,
    x: DVec3,
}

/// A search's nearest hit: the object and the ray's place in its shell, and the cells its walks
/// took (every walk the search began, the ones that missed too).
#[derive(Clone, Copy, Debug)]
struct Found {
    object: usize,
    place: Place,
    cells: u32,
}

/// A triangle of one of the scene's objects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct TriangleOf {
    object: usize,
    tri: u32,
}

/// A ray's walk through one object's shell: a hit, or where it left.
enum Walk {
    Hit {
        tri: u32,
        lam: f64,
        at: Local,
        cells: u32,
    },
    Left {
        lam: f64,
        cells: u32,
        /// the triangle through whose top it left, where it did
        top: Option<u32>,
    },
}

/// What a ray's walk must answer of its hit.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Want {
    /// the first hit, on the path itself (a camera ray)
    Exact,
    /// whether it has one, and where: the chord's first hit, or where the path lies below the
    /// field's lowest texel (a bundle's axis, which `Object::all_blocked` looks past)
    Near,
    /// only whether it has one (a light or ambient ray): any point of the path at or under the
    /// field answers
    Any,
}

/// A ray o + lam d in an object's space, walked `lift` above the field (a light or ambient ray
/// leaving a hit), answering what `want` says. `part` > 0 makes it the axis
/// of a bundle of rays from o whose directions differ from d by at most `part` (bundle.rs):
/// its chords' boxes are widened by as far as the rays part, and a chord that its box does
/// not clear counts as a hit (the bundle then shows nothing).
struct Ray {
    o: DVec3,
    d: DVec3,
    lift: f64,
    want: Want,
    part: f64,
}

/// What a chord knows of the path's middle: nothing, the point, or how far it deviates from
/// the chord there (in cells, in height), where a chord is half of one whose middle was found.
#[derive(Clone, Copy)]
enum Middle<'s> {
    Unknown,
    Known(&'s Sample),
    Deviates((f64, f64)),
}

/// The scene's objects, ready for exact rays on any mesh.
pub(crate) struct Shell<'a> {
    objects: Vec<Object<'a>>,
    /// the camera rays' candidates
    grid: grid::Grid,
}

impl<'a> Shell<'a> {
    /// The scene's shell, its objects' geometry taken from `shells` or built and kept there.
    pub(crate) fn new(scene: &'a Scene, shells: &Shells) -> Result<Shell<'a>> {
        scene.validate()?;
        let mut objects = Vec::new();
        for o in &scene.objects {
            objects.push(Object::new(
                &o.mesh,
                &o.material,
                o.mesh.key,
                o.transform.m,
                shells,
            )?);
        }
        if objects.is_empty() {
            return Err(Error::arg("scene", "has no objects; add one"));
        }
        let entries: Vec<grid::Entries<'_>> = objects
            .iter()
            .map(|ob| grid::Entries {
                prisms: &ob.prisms,
                walled: &ob.walled,
                depth: ob.depth,
                to_obj: ob.to_obj,
                to_world: ob.to_world,
            })
            .collect();
        let grid = grid::Grid::new(&scene.camera, &entries);
        Ok(Shell { objects, grid })
    }

    /// The first hit of the ray eye + lam dir over lam > lam_min with any object's displaced
    /// surface (with `any`, the first found). Each
    /// start of a walk (where the ray enters a shell) is walked as the camera's tile or the
    /// bounding volumes give it, nearer first; a hit bounds the rest of the search.
    fn first(
        &self,
        eye: DVec3,
        dir: DVec3,
        lam_min: f64,
        any: bool,
        skip: Option<usize>,
    ) -> Option<Found> {
        if !any && lam_min == 0.0 && skip.is_none() {
            if let Some(tile) = self.grid.candidates(eye, dir) {
                return self.first_of(tile, eye, dir);
            }
        }
        self.search(eye, dir, lam_min, any, skip, None)
    }

    /// `first` through the bounding volumes; `from`: the triangle the ray starts in or left by,
    /// whose boxes up to the root hold its start or lie about it (bvh.rs: `visit_from`; any
    /// triangle gives the same answer, this one the fewest boxes to test).
    fn search(
        &self,
        eye: DVec3,
        dir: DVec3,
        lam_min: f64,
        any: bool,
        skip: Option<usize>,
        from: Option<TriangleOf>,
    ) -> Option<Found> {
        let mut best: Option<Found> = None;
        let mut cells = 0u32;
        let mut bound = f64::INFINITY;
        for (oi, ob) in self.objects.iter().enumerate() {
            if skip == Some(oi) {
                continue;
            }
            let o = ob.to_obj.transform_point3(eye);
            let d = ob.to_obj.transform_vector3(dir);
            // a start of the walk: walked unless a hit already lies before it; false to stop
            let mut start = |t: u32, lam: f64, at: Local, bound: &mut f64| -> bool {
                if !(lam > lam_min) || lam >= *bound {
                    return true;
                }
                let ray = Ray {
                    o,
                    d,
                    lift: 0.0,
                    want: if any { Want::Any } else { Want::Exact },
                    part: 0.0,
                };
                let hit = ob.walk_start(oi, &ray, Place { tri: t, lam, at }, &mut best, &mut cells);
                if let Some(b) = best {
                    *bound = bound.min(b.place.lam);
                }
                !(any && hit)
            };
            let mut go_on = true;
            let each = |t: u32, lam_max: &mut f64| {
                go_on = ob.starts(t, o, d, |lam, at| start(t, lam, at, lam_max));
                go_on
            };
            match from {
                Some(f) if f.object == oi => ob.bvh.visit_from(f.tri, o, d, lam_min, bound, each),
                _ => ob.bvh.visit(o, d, lam_min, bound, each),
            }
            if let Some(b) = best {
                bound = bound.min(b.place.lam);
            }
            if !go_on {
                break;
            }
        }
        best.map(|b| Found { cells, ..b })
    }
}

impl Shell<'_> {
    /// A camera ray's first hit among the starts of the triangles `candidates`, walked nearer
    /// first until a hit bounds the rest.
    fn first_of(&self, candidates: &[(u32, u32)], eye: DVec3, dir: DVec3) -> Option<Found> {
        let mut starts: smallvec::SmallVec<[(f64, u32, u32, Local); 8]> = smallvec::SmallVec::new();
        for &(oi, t) in candidates {
            let ob = &self.objects[oi as usize];
            let (o, d) = (
                ob.to_obj.transform_point3(eye),
                ob.to_obj.transform_vector3(dir),
            );
            ob.starts(t, o, d, |lam, at| {
                if lam > 0.0 {
                    starts.push((lam, oi, t, at));
                }
                true
            });
        }
        starts.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let (mut best, mut cells): (Option<Found>, u32) = (None, 0);
        for (lam, oi, t, at) in starts {
            if best.is_some_and(|b| lam >= b.place.lam) {
                break;
            }
            let ob = &self.objects[oi as usize];
            let ray = Ray {
                o: ob.to_obj.transform_point3(eye),
                d: ob.to_obj.transform_vector3(dir),
                lift: 0.0,
                want: Want::Exact,
                part: 0.0,
            };
            ob.walk_start(
                oi as usize,
                &ray,
                Place { tri: t, lam, at },
                &mut best,
                &mut cells,
            );
        }
        best.map(|b| Found { cells, ..b })
    }
}

impl Object<'_> {
    /// The walk of object `oi`'s `ray` from a start: its hit kept in `best` where nearer, its
    /// cells added; whether it hit.
    fn walk_start(
        &self,
        oi: usize,
        ray: &Ray,
        start: Place,
        best: &mut Option<Found>,
        cells: &mut u32,
    ) -> bool {
        match self.walk(ray, start.tri, start.lam, start.at) {
            Walk::Hit {
                tri,
                lam,
                at,
                cells: c,
            } => {
                *cells += c;
                if best.is_none_or(|b| lam < b.place.lam) {
                    *best = Some(Found {
                        object: oi,
                        place: Place { tri, lam, at },
                        cells: 0,
                    });
                }
                true
            }
            Walk::Left { cells: c, .. } => {
                *cells += c;
                false
            }
        }
    }

    /// The starts of a walk in triangle `t` along the ray o + lam d (object space): where it
    /// enters through the top, and through a wall, into the shell above the surface. `f` is
    /// called with each (lam, point) until it returns false; false when it did.
    fn starts(&self, t: u32, o: DVec3, d: DVec3, mut f: impl FnMut(f64, Local) -> bool) -> bool {
        let Some(p) = self.prisms[t as usize].as_ref() else {
            return true;
        };
        if let Some((lam, b)) = p.entry(o, d) {
            if !f(lam, entry_at(b)) {
                return false;
            }
        }
        if !self.walled[t as usize] {
            return true;
        }
        let mut walls: [Option<Crossing>; 6] = [None; 6];
        let mut i = 0;
        for k in 0..3 {
            if self.across[t as usize][k].is_none() {
                p.crossings(o, d, k, false, &mut |c: Crossing| {
                    let off = p.offset(c.at);
                    if off <= 0.0 && off >= -self.depth && self.above(p, c.at) {
                        walls[i] = Some(c);
                        i += 1;
                    }
                });
            }
        }
        walls.iter().flatten().all(|c| f(c.lam, c.at))
    }
}

/// A ray's point on a prism's top where it enters.
fn entry_at(b: DVec2) -> Local {
    Local {
        b: b.clamp(DVec2::ZERO, DVec2::ONE),
        s: 0.0,
    }
}

impl Tracer for Shell<'_> {
    type At = ShellAt;

    fn trace(&self, eye: DVec3, dir: DVec3) -> Option<Hit<ShellAt>> {
        let Found {
            object: oi,
            place: Place { tri, lam, at },
            cells,
        } = self.first(eye, dir, 0.0, false, None)?;
        let ob = &self.objects[oi];
        let p = ob.prisms[tri as usize].as_ref().expect("a hit's prism");
        let uv = p.uv(at.b);
        let h = if ob.depth > 0.0 {
            (1.0 + p.offset(at) / ob.depth).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let x = ob.to_obj.transform_point3(eye + dir * lam);
        Some(Hit {
            uv,
            dist: lam,
            cells,
            object: oi,
            s: uv * ob.tiling,
            h,
            at: ShellAt { tri, at, x },
        })
    }

    fn reaches(&self, hit: &Hit<ShellAt>, l: DVec3, bias: f64) -> bool {
        self.reaches_from(hit, l, bias, None)
    }

    fn reaches_all(&self, hit: &Hit<ShellAt>, axis: DVec3, dirs: &[DVec3], bias: f64) -> usize {
        let bundle = if dirs.len() > 1 {
            self.bundle(hit, axis, dirs, bias.max(1e-9))
        } else {
            None
        };
        let search_own = match bundle {
            None => return dirs.iter().filter(|l| self.reaches(hit, **l, bias)).count(),
            Some(Bundle::Blocked) => return 0,
            Some(Bundle::Left(search)) => search,
            Some(Bundle::Cleared(place)) => {
                return dirs
                    .iter()
                    .filter(|l| self.reaches_from(hit, **l, bias, Some(place)))
                    .count()
            }
        };
        // every ray left the object's shell unblocked: the other objects' shells remain, and
        // this one's where anything of it lies above where the rays left (searched from the
        // start: a ray inside the shell enters no top or wall of it)
        if self.objects.len() == 1 && !search_own {
            return dirs.len();
        }
        let eye = self.objects[hit.object].to_world.transform_point3(hit.at.x);
        let skip = (!search_own).then_some(hit.object);
        let from = Some(TriangleOf {
            object: hit.object,
            tri: hit.at.tri,
        });
        dirs.iter()
            .filter(|l| self.search(eye, **l, 1e-9, true, skip, from).is_none())
            .count()
    }

    fn normal(&self, hit: &Hit<ShellAt>) -> DVec3 {
        let ob = &self.objects[hit.object];
        let p = ob.prisms[hit.at.tri as usize]
            .as_ref()
            .expect("a hit's prism");
        let m = ob.mesh;
        let w = Prism::weights(hit.at.at.b);
        let (mut n, mut t, mut sc) = (DVec3::ZERO, DVec3::ZERO, DVec2::ZERO);
        for (k, &v) in p.v.iter().enumerate() {
            let tg = m.tangents[v as usize];
            n += p.n[k] * w[k];
            t += DVec3::new(tg[0] as f64, tg[1] as f64, tg[2] as f64) * w[k];
            sc += DVec2::new(
                m.uv_scale[v as usize][0] as f64,
                m.uv_scale[v as usize][1] as f64,
            ) * w[k];
        }
        use crate::oracle::shading::{basis, displaced_normal};
        let (n, t, bt) = basis(
            n.normalize_or_zero(),
            t,
            m.tangents[p.v[0] as usize][3] as f64,
        );
        let sn = displaced_normal(ob.mat, hit.s, n, t, bt, sc);
        (ob.normal_to_world * sn).normalize_or_zero()
    }

    fn material(&self, object: usize) -> &Material {
        self.objects[object].mat
    }
}

impl Shell<'_> {
    /// `reaches`, its walk begun at `from` (the bundle's axis's place) where given:
    /// a bundle showed that no ray meets the surface before that lam. The ray's own point is
    /// located there; where it lies outside the prism (beside the triangle, or above its top,
    /// where the ray may have left the shell on the way), the walk begins at the hit.
    fn reaches_from(&self, hit: &Hit<ShellAt>, l: DVec3, bias: f64, from: Option<Place>) -> bool {
        let ob = &self.objects[hit.object];
        let d = ob.to_obj.transform_vector3(l);
        let lift = bias.max(1e-9);
        let ray = Ray {
            o: hit.at.x,
            d,
            lift,
            want: Want::Any,
            part: 0.0,
        };
        let start = from
            .and_then(|f| {
                let p = ob.prisms[f.tri as usize].as_ref()?;
                let at = p.locate(ray.o + d * f.lam, f.at)?;
                (Prism::inside(at.b, 0.0) && at.s <= 0.0).then_some(Place { at, ..f })
            })
            .unwrap_or(Place {
                tri: hit.at.tri,
                lam: 0.0,
                at: hit.at.at,
            });
        match ob.walk(&ray, start.tri, start.lam, start.at) {
            Walk::Hit { .. } => false,
            Walk::Left { lam, top, .. } => {
                // where it left, in the world: the rest of the ray meets no shell again (this
                // object's, where it left above all of it, is not looked for)
                let clear = top.is_some_and(|t| !ob.overhung(t as usize));
                if clear && self.objects.len() == 1 {
                    return true;
                }
                let eye = ob.to_world.transform_point3(hit.at.x);
                let eps = 1e-9 * (1.0 + lam.abs());
                let from = top.map(|tri| TriangleOf {
                    object: hit.object,
                    tri,
                });
                self.search(eye, l, lam + eps, true, clear.then_some(hit.object), from)
                    .is_none()
            }
        }
    }
}

#[cfg(test)]
mod tests;
