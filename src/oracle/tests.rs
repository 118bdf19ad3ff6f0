use super::*;
use crate::scene::HeightMap;
use glam::DVec2;

#[test]
fn constant_height_analytic() {
    // ray at angle theta from the normal descends (1 - c) * depth before hitting h = c
    for c in [0.0, 0.3, 0.75, 1.0] {
        let hm = HeightMap::new(4, 4, vec![c as f32; 16]).unwrap();
        let depth = 0.1;
        let theta: f64 = 60f64.to_radians();
        // per unit world length: horizontal sin(theta) (1 world unit = 0.5 uv on a size-2 plane)
        let ds = DVec2::new(theta.sin() * 0.5, 0.0);
        let dh = -theta.cos() / depth;
        let (lam, _) = march_height_field(&Field::new(&hm), DVec2::new(0.3, 0.4), ds, dh).unwrap();
        let expect = (1.0 - c as f32 as f64) * depth / theta.cos();
        assert!((lam - expect).abs() < 1e-9, "c={c}: {lam} vs {expect}");
    }
}

#[test]
fn finds_a_thin_spike() {
    // a single raised texel in a flat floor: a ray passing just over its neighbour must hit it
    let mut data = vec![0.0f32; 64 * 64];
    data[32 * 64 + 40] = 1.0;
    let hm = HeightMap::new(64, 64, data).unwrap();
    let s0 = DVec2::new(30.5 / 64.0, 32.5 / 64.0);
    // horizontal 10 texels per unit height drop: reaches texel 40 at h = 0.0
    let ds = DVec2::new(10.0 / 64.0, 0.0);
    let (lam, _) = march_height_field(&Field::new(&hm), s0, ds, -1.0).unwrap();
    let s = s0.x + ds.x * lam;
    assert!(
        s * 64.0 - 0.5 > 38.9 && s * 64.0 - 0.5 < 40.0,
        "hit at texel {}",
        s * 64.0 - 0.5
    );
}

#[test]
fn light_rays_at_the_top_and_behind_a_wall() {
    // a plateau at exactly h = 1 is lit: its light rays start at the top of the shell
    let hm = HeightMap::new(8, 8, vec![1.0; 64]).unwrap();
    assert!(light_ray_free(
        &Field::new(&hm),
        DVec2::new(0.3, 0.6),
        1.0,
        DVec2::new(0.5, 0.0),
        0.2,
        0.0
    ));
    // a floor at 0 with a full-height wall at columns 8..16 of 32, lit from +x by a light
    // that rises one shell height per 4 texels. In texel space (x = s * 32 - 0.5) the ramp
    // rises from h = 0 at x = 7 to h = 1 at x = 8; the ray from the floor at x0 is at height
    // (x - x0) / 4, so it clears the ramp's top iff x0 <= 4: the shadow spans (4, 7].
    let mut data = vec![0.0f32; 32 * 32];
    for r in 0..32 {
        for c in 8..16 {
            data[r * 32 + c] = 1.0;
        }
    }
    let hm = HeightMap::new(32, 32, data).unwrap();
    let ds = DVec2::new(4.0 / 32.0, 0.0);
    let field = Field::new(&hm);
    // the ray from the floor at texel-space x (s.x * 32 - 0.5), `b` the bias
    let biased =
        |x: f64, b: f64| light_ray_free(&field, DVec2::new((x + 0.5) / 32.0, 0.5), 0.0, ds, 1.0, b);
    let free = |x: f64| biased(x, 0.0);
    assert!(free(3.9));
    assert!(!free(4.1));
    assert!(!free(6.9));
    // on the wall's top (h = 1) it is lit
    assert!(light_ray_free(
        &field,
        DVec2::new(10.5 / 32.0, 0.5),
        1.0,
        ds,
        1.0,
        0.0
    ));
    // with a bias, a floor point whose ray clears the ramp's top by less than it is also
    // lit: x0 = 4.0002 passes 5e-5 below the top (blocked exactly, free with 1e-4)
    assert!(!biased(4.0002, 0.0));
    assert!(biased(4.0002, 1e-4));
}
