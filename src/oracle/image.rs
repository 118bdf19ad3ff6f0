//! The exact image: a noise-free reference for colour (`pk.reference.render_exact`). Every
//! sample's hit is the float64 oracle's (oracle/mod.rs), shaded in float64 with the reference shading
//! of docs/conventions.md:
//!
//! - normal: of the displaced surface S(u, v) = P + depth (h - 1) N, with the derivatives of h
//!   taken as central differences one texel apart of the bilinear field at level 0, at the hit;
//! - albedo: bilinear at level 0 (repeating), at the hit;
//! - a light: E max(0, N.L) times the fraction of its disk whose rays leave the shell unblocked
//!   (64 stratified directions over the disk of a directional light's `angular_diameter`, or of
//!   a sphere light's apparent radius; one direction for a point); a sphere light's E is I / r²;
//! - ambient: albedo * ambient * ao, ao the fraction of 64 cosine-weighted directions about the
//!   shading normal that leave the shell (a direction below the base plane is blocked).
//!
//! Samples: k x k per pixel on the grid of `render(spp=)` (the pixel centres of a k-times finer
//! camera); colour is their mean (a miss is black), coverage the fraction that hit. A pixel's
//! samples share the direction sets: sample q traces the directions d with d mod k² = q, so
//! that each pixel averages every direction once however many samples it has.

use super::rows::{interrupted, par_rows};
use super::trace::{
    disk_directions, hits_of, perpendiculars, stratified_disk, Hit, OracleHits, Tracer,
};
use crate::error::{Error, Result};
use crate::scene::{Albedo, Light, Scene};
use glam::{DVec2, DVec3};

/// Directions in a light's disk set and in the ambient set.
pub const DIRECTIONS: usize = 64;

/// The exact image: per pixel, colour (RGB) and coverage from the samples.
#[derive(Clone, Debug)]
pub struct OracleImage {
    pub width: u32,
    pub height: u32,
    pub color: Vec<f32>,
    pub coverage: Vec<f32>,
    /// the oracle's frame at the pixel centres (`hits` at light bias 0)
    pub centres: OracleHits,
}

/// 64 cosine-weighted directions about +z: the stratified disk lifted to the hemisphere
/// (Malley's method).
fn cosine_directions() -> Vec<DVec3> {
    stratified_disk()
        .into_iter()
        .map(|d| DVec3::new(d.x, d.y, (1.0 - d.length_squared()).max(0.0).sqrt()))
        .collect()
}

fn albedo_at(a: &Option<crate::scene::Shared<Albedo>>, s: DVec2) -> DVec3 {
    let Some(a) = a else {
        return DVec3::splat(0.5);
    };
    let (w, h) = (a.width as i64, a.height as i64);
    let x = s.x * w as f64 - 0.5;
    let y = s.y * h as f64 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |i: i64, j: i64| {
        let t = a.data[(j.rem_euclid(h) * w + i.rem_euclid(w)) as usize];
        DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64)
    };
    let (i, j) = (x0 as i64, y0 as i64);
    (at(i, j) * (1.0 - fx) + at(i + 1, j) * fx) * (1.0 - fy)
        + (at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx) * fy
}

/// The directions sample q of n traces from a set: those with index = q mod n (every one when
/// n = 1; one, cycling, when n > the set's size).
fn share(set: &[DVec3], q: usize, n: usize) -> impl Iterator<Item = &DVec3> {
    let len = set.len();
    let (start, step) = if n >= len { (q % len, len) } else { (q, n) };
    set.iter().skip(start).step_by(step.max(1))
}

/// The directions sample `q` of `n` traces for hits found elsewhere (a ray cast on the displaced
/// mesh, `pk.reference` on curved meshes and in Mitsuba): with `tan_r` > 0 its share of the 64
/// over the disk of angular radius atan(tan_r) about the unit `axis` (a light), with `tan_r` = 0
/// the axis alone (a point or a sharp light), and with `tan_r` < 0 its share of the 64
/// cosine-weighted directions about the unit normal `axis` (ambient). Exactly the sets and the
/// sharing of `render`.
pub fn sample_directions(axis: DVec3, tan_r: f64, q: usize, n: usize) -> Vec<DVec3> {
    if tan_r < 0.0 {
        let (t, b) = perpendiculars(axis, axis.x.abs() >= 0.9);
        share(&cosine_directions(), q, n)
            .map(|d| t * d.x + b * d.y + axis * d.z)
            .collect()
    } else if tan_r > 0.0 {
        share(&disk_directions(axis, tan_r), q, n)
            .copied()
            .collect()
    } else {
        vec![axis]
    }
}

/// `sample_directions` for many samples: sample i about `axes[i]` with `tan_r[i]`, its share
/// as sample `q[i]` of `n`. Every direction, and the sample each belongs to.
pub fn sample_directions_of(
    axes: &[[f64; 3]],
    tan_r: &[f64],
    q: &[u32],
    n: usize,
) -> (Vec<DVec3>, Vec<u32>) {
    let (mut dirs, mut owner) = (Vec::new(), Vec::new());
    for i in 0..axes.len() {
        for d in sample_directions(DVec3::from(axes[i]), tan_r[i], q[i] as usize, n) {
            dirs.push(d);
            owner.push(i as u32);
        }
    }
    (dirs, owner)
}

/// The exact image of a scene at `spp` samples per pixel (a square, 1 to 256).
/// `shadows` false leaves out the light and ambient rays (every light fully visible, ao = 1):
/// the colour of the displacement alone, for methods measured without shadows. `shells` keeps
/// the objects' shells for later calls.
pub fn render(
    scene: &Scene,
    spp: u32,
    shadows: bool,
    shells: &super::Shells,
) -> Result<OracleImage> {
    let k = (spp as f64).sqrt().round() as u32;
    if spp == 0 || k * k != spp || k > 16 {
        return Err(Error::arg(
            "spp",
            format!("must be a square number of samples per pixel from 1 to 256, got {spp}"),
        ));
    }
    let out = image(scene, &super::tracer(scene, shells)?, k, shadows);
    interrupted()?;
    Ok(out)
}

fn image<T: Tracer>(scene: &Scene, oracle: &T, k: u32, shadows: bool) -> OracleImage {
    let cam = &scene.camera;
    let (w, h) = (cam.width, cam.height);
    let mut fine = cam.clone();
    (fine.width, fine.height, fine.window) = (w * k, h * k, None);
    let basis = fine.basis();
    let cosines = cosine_directions();
    // a directional light's disk is the same at every hit: its directions once
    let disks: Vec<Option<Vec<DVec3>>> = scene
        .lights
        .iter()
        .map(|l| match l {
            Light::Directional(l) if l.angular_diameter > 0.0 => Some(disk_directions(
                -DVec3::from(l.direction).normalize(),
                (0.5 * l.angular_diameter).to_radians().tan(),
            )),
            _ => None,
        })
        .collect();
    let ambient = DVec3::from(scene.ambient.map(|x| x as f64));
    let n = (k * k) as usize;
    // per pixel of each row: the mean colour of its samples and the fraction that hit
    let rows = par_rows(h as usize, |i| {
        (0..w as usize)
            .map(|j| {
                let mut sum = DVec3::ZERO;
                let mut hits = 0;
                for q in 0..n {
                    let si = (i * k as usize + q / k as usize) as u32;
                    let sj = (j * k as usize + q % k as usize) as u32;
                    let dir = fine.ray_dir(&basis, si, sj);
                    let Some(hit) = oracle.trace(basis.eye, dir) else {
                        continue;
                    };
                    hits += 1;
                    let p = basis.eye + dir * hit.dist;
                    sum += shade(
                        scene,
                        oracle,
                        &hit,
                        p,
                        ambient,
                        (&cosines, &disks),
                        (q, n),
                        shadows,
                    );
                }
                (sum / n as f64, hits as f32 / n as f32)
            })
            .collect::<Vec<_>>()
    });
    let (mut color, mut coverage) = (Vec::with_capacity((w * h * 3) as usize), Vec::new());
    for (c, cov) in rows.into_iter().flatten() {
        color.extend([c.x as f32, c.y as f32, c.z as f32]);
        coverage.push(cov);
    }
    OracleImage {
        width: w,
        height: h,
        color,
        coverage,
        centres: hits_of(scene, oracle, 0.0),
    }
}

/// The reference shading of one sample's hit (world point `p`): sample `q` of `n` traces its
/// share of each direction set (none without `shadows`).
#[allow(clippy::too_many_arguments)]
fn shade<T: Tracer>(
    scene: &Scene,
    o: &T,
    hit: &Hit<T::At>,
    p: DVec3,
    ambient: DVec3,
    (cosines, disks): (&[DVec3], &[Option<Vec<DVec3>>]),
    (q, n): (usize, usize),
    shadows: bool,
) -> DVec3 {
    let nrm = o.normal(hit);
    let albedo = albedo_at(&o.material(hit.object).albedo, hit.s);
    let mut direct = DVec3::ZERO;
    for (light, disk) in scene.lights.iter().zip(disks) {
        let (to_light, e, tan_r) = match light {
            Light::Directional(l) => (
                -DVec3::from(l.direction).normalize(),
                DVec3::from(light.power().map(|x| x as f64)),
                (0.5 * l.angular_diameter).to_radians().tan(),
            ),
            Light::Sphere(l) => {
                let d = DVec3::from(l.position) - p;
                let r2 = d.length_squared().max(1e-24);
                (
                    d / r2.sqrt(),
                    DVec3::from(light.power().map(|x| x as f64)) / r2,
                    l.radius / (r2 - l.radius * l.radius).max(1e-24).sqrt(),
                )
            }
        };
        let ndl = nrm.dot(to_light);
        if ndl <= 0.0 {
            continue;
        }
        if !shadows {
            direct += e * ndl;
            continue;
        }
        let own;
        let set: &[DVec3] = match disk {
            Some(d) => d,
            None if tan_r > 0.0 => {
                own = disk_directions(to_light, tan_r);
                &own
            }
            None => std::slice::from_ref(&to_light),
        };
        let mut dirs = [DVec3::ZERO; DIRECTIONS];
        let mut all = 0;
        for (slot, d) in dirs.iter_mut().zip(share(set, q, n)) {
            *slot = *d;
            all += 1;
        }
        let lit = o.reaches_all(hit, to_light, &dirs[..all], 0.0);
        direct += e * ndl * (lit as f64 / all.max(1) as f64);
    }
    let mut ao = 1.0;
    if shadows && ambient.max_element() > 0.0 {
        // the cosine set about the shading normal
        let (t, b) = perpendiculars(nrm, nrm.x.abs() >= 0.9);
        let (mut open, mut all) = (0usize, 0usize);
        for d in share(cosines, q, n) {
            all += 1;
            let wd = t * d.x + b * d.y + nrm * d.z;
            open += o.reaches(hit, wd, 0.0) as usize;
        }
        ao = open as f64 / all.max(1) as f64;
    }
    albedo / std::f64::consts::PI * direct + albedo * ambient * ao
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_direction_once_per_pixel() {
        let set: Vec<DVec3> = (0..64).map(|i| DVec3::new(i as f64, 0.0, 0.0)).collect();
        for n in [1usize, 4, 16, 64, 256] {
            let mut seen = vec![0; 64];
            for q in 0..n {
                for d in share(&set, q, n) {
                    seen[d.x as usize] += 1;
                }
            }
            let want = (n / 64).max(1);
            assert!(seen.iter().all(|&c| c == want), "n = {n}: {seen:?}");
        }
    }

    #[test]
    fn cosine_directions_are_unit_and_cosine_weighted() {
        let c = cosine_directions();
        assert_eq!(c.len(), DIRECTIONS);
        assert!(c
            .iter()
            .all(|d| (d.length() - 1.0).abs() < 1e-12 && d.z > 0.0));
        // E[cos] under a cosine-weighted density is 2/3 (uniform over the hemisphere: 1/2); the
        // 8 x 8 grid's cell centres give 0.692
        let mean = c.iter().map(|d| d.z).sum::<f64>() / c.len() as f64;
        assert!((mean - 2.0 / 3.0).abs() < 0.03, "{mean}");
    }
}
