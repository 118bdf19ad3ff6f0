use super::*;

#[test]
fn every_aov_decodes_to_its_declared_type_and_size() {
    let (w, h) = (3u32, 2u32);
    let n = 6;
    let color = [
        1.0f32.to_bits(),
        0.5f32.to_bits(),
        0.25f32.to_bits(),
        7 | (2 << 28),
    ];
    // pixel 0 misses (no hit bit)
    let colors: Vec<u32> = (0..n)
        .flat_map(|i| {
            let mut c = color;
            c[3] |= if i == 0 { 0 } else { HIT_BIT };
            c
        })
        .collect();
    let t = Texels(
        [
            Some(colors),
            // pixel 0 misses (distance -1)
            Some(
                (0..n)
                    .flat_map(|i| {
                        [0.1f32, 0.2, if i == 0 { -1.0 } else { 2.0 }, 0.5].map(f32::to_bits)
                    })
                    .collect(),
            ),
            Some(vec![4; n]),
            Some([9, 36, 0, 0].repeat(n)),
        ],
        Some((0..n as u32).collect()),
    );
    let f = Frame::decode(w, h, Aovs::ALL, &t, None, 0.0);
    for (a, d) in AOVS.iter().zip(&f.data) {
        let d = d.as_ref().expect("every AOV");
        let (len, ty) = match d {
            AovData::F32(v) => (v.len(), Dtype::F32),
            AovData::U32(v) => (v.len(), Dtype::U32),
            AovData::U8(v) => (v.len(), Dtype::U8),
            AovData::I32(v) => (v.len(), Dtype::I32),
            AovData::Bool(v) => (v.len(), Dtype::Bool),
        };
        assert_eq!((len, ty), (n * a.comps, a.dtype), "{}", a.name);
    }
    assert_eq!(f.mask(), &[false, true, true, true, true, true]);
    assert!(f.f32s("depth")[0].is_nan() && f.f32s("depth")[1] == 2.0);
    assert_eq!(f.get("steps"), Some(&AovData::U32(vec![0, 7, 7, 7, 7, 7])));
    assert_eq!(f.get("flags"), Some(&AovData::U8(vec![0, 2, 2, 2, 2, 2])));
    assert_eq!(
        f.get("object"),
        Some(&AovData::I32(vec![-1, 4, 4, 4, 4, 4]))
    );
    assert_eq!(&f.f32s("color")[..3], &[1.0, 0.5, 0.25]);
    assert_eq!(
        f.get("fetches"),
        Some(&AovData::U32(vec![0, 9, 9, 9, 9, 9]))
    );
    assert_eq!(f.f32s("coverage"), &[0.0, 1.0, 1.0, 1.0, 1.0, 1.0]);
    assert_eq!(
        f.get("bytes"),
        Some(&AovData::U32(vec![0, 36, 36, 36, 36, 36]))
    );
    assert_eq!(
        Aovs::parse(&["color"]).unwrap().targets(),
        [true, false, false, false]
    );
    assert_eq!(
        Aovs::parse(&["fetches"]).unwrap().targets(),
        [true, false, false, true]
    );
    assert_eq!(
        written([true, false, true, false], false),
        [true, true, true, false]
    );
    assert_eq!(
        written([true, false, true, false], true),
        [true, false, true, false]
    );
    let all = Aovs::STANDARD;
    assert_eq!(all.targets_for(1), [true, true, false, false]);
    assert_eq!(all.targets_for(2), [true, true, true, false]);
    // one object: the id is 0 wherever hit without its target
    let t1 = Texels(
        [
            Some([0, 0, 0, HIT_BIT, 0, 0, 0, 0].to_vec()),
            None,
            None,
            None,
        ],
        None,
    );
    let f1 = Frame::decode(2, 1, Aovs::parse(&["object"]).unwrap(), &t1, None, 0.0);
    assert_eq!(f1.get("object"), Some(&AovData::I32(vec![0, -1])));
}

#[test]
fn supersampling_box_filters_colour_and_takes_the_rest_from_the_plain_frame() {
    // a 4 x 2 frame of 2 x 2 samples per pixel -> 2 x 1; pixel 0's samples: one miss
    let (w, h, n) = (4u32, 2u32, 8usize);
    let color: Vec<u32> = (0..n)
        .flat_map(|i| {
            let mut c = [i as f32, 0.0, 1.0, 0.0].map(f32::to_bits);
            c[3] = if i == 0 { 0 } else { HIT_BIT };
            c
        })
        .collect();
    let geo = |n: usize, miss: usize| -> Vec<u32> {
        (0..n)
            .flat_map(|i| {
                [i as f32, 0.0, if i == miss { -1.0 } else { 2.0 }, 0.0].map(f32::to_bits)
            })
            .collect()
    };
    let t = Texels([Some(color), Some(geo(n, 0)), None, None], None);
    let (ss, rest) = Aovs::parse(&["color", "coverage", "uv", "object"])
        .unwrap()
        .split_supersampled();
    let big = Frame::decode(w, h, ss.unwrap(), &t, Some(1.5), 2.0);
    let t1 = Texels(
        [
            Some([0, 0, 0, HIT_BIT].repeat(2)),
            Some(geo(2, 9)),
            Some(vec![5, 7]),
            None,
        ],
        None,
    );
    let plain = Frame::decode(2, 1, rest.unwrap(), &t1, Some(0.5), 1.0);
    let f = Frame::supersampled(big, 2, Some(plain));
    assert_eq!((f.width, f.height), (2, 1));
    assert!(f.aovs.has("uv") && f.aovs.has("color") && !f.aovs.has("depth"));
    // samples of pixel 0: 0, 1, 4, 5; of pixel 1: 2, 3, 6, 7
    assert_eq!(f.f32s("color"), &[2.5, 0.0, 1.0, 4.5, 0.0, 1.0]);
    assert_eq!(f.f32s("coverage"), &[0.75, 1.0]);
    // the plain frame's
    assert_eq!(f.f32s("uv"), &[0.0, 0.0, 1.0, 0.0]);
    assert_eq!(f.get("object"), Some(&AovData::I32(vec![5, 7])));
    assert_eq!((f.gpu_ms, f.wall_ms), (Some(2.0), 3.0));
}
