//! Hostile images: forged EXR and HDR headers (sizes the file cannot hold, beyond the cap, zero, negative windows),
//! real images truncated and with flipped header bytes, each used as `compare` input, environment map and texture.

use super::{Case, Expect, dir, path_str};
use crate::common::{data, forged_exr, forged_hdr, refs};
use std::path::{Path, PathBuf};

/// An environment-map scene and a texture scene for `image` (the only difference between good and bad cases).
fn uses(d: &Path, image: &Path, tag: &str, expect: Expect) -> Vec<Case> {
    let env = d.join(format!("{tag}_env.ron"));
    std::fs::write(
        &env,
        format!(
            "(camera: (size: (8, 8)), entities: [(light: Environment(map: {:?}, layout: Equirect)), (shape: Sphere())])",
            path_str(image)
        ),
    )
    .unwrap();
    let tex = d.join(format!("{tag}_tex.ron"));
    std::fs::write(
        &tex,
        format!(
            "(camera: (size: (8, 8)), textures: {{\"t\": Image(path: {:?})}}, materials: {{\"m\": Lambert(albedo: \
             Texture(\"t\"))}}, entities: [(shape: Sphere(), material: \"m\")])",
            path_str(image)
        ),
    )
    .unwrap();
    let out = d.join("out.png");
    let mut v = vec![
        Case::new("images", format!("{tag} as environment map"), &[&"render", &env, &"-o", &out, &"-q"], expect),
        Case::new("images", format!("{tag} as texture"), &[&"render", &tex, &"-o", &out, &"-q"], expect),
    ];
    // compare reads EXR and HDR; a cross-size comparison is an error even for good images.
    if expect != Expect::Ok {
        v.push(Case::new("images", format!("{tag} in compare"), &[&"compare", &image, &image], expect));
    }
    v
}

fn write(d: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = d.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

pub fn cases() -> Vec<Case> {
    let d = dir("images");
    let mut v = Vec::new();
    // Forged headers.
    let forged: Vec<(&str, Vec<u8>)> = vec![
        ("exr 100000x50000", forged_exr(100_000, 50_000, false, 16)),
        ("exr 65537x1", forged_exr(65_537, 1, false, 16)),
        ("exr 8000x4000 thin", forged_exr(8000, 4000, false, 64)),
        ("exr 8000x4000 zip thin", forged_exr(8000, 4000, true, 64)),
        ("exr 16384x4096 zip thin", forged_exr(16384, 4096, true, 4096)),
        ("exr 0x0", forged_exr(0, 0, false, 16)),
        ("exr -5x-5", forged_exr(-5, -5, false, 16)),
        ("exr 2147483647x1", forged_exr(i32::MAX, 1, false, 16)),
        ("exr 1x1 no data", forged_exr(1, 1, false, 0)),
        ("exr 4x4 zip garbage", forged_exr(4, 4, true, 200)),
    ];
    for (i, (tag, bytes)) in forged.iter().enumerate() {
        let p = write(&d, &format!("forged{i}.exr"), bytes);
        v.extend(uses(&d, &p, tag, Expect::Error));
    }
    let hdr: Vec<(&str, Vec<u8>)> = vec![
        ("hdr 100000x50000", forged_hdr(100_000, 50_000, &[2, 2, 0, 0])),
        ("hdr 8000x4000 thin", forged_hdr(8000, 4000, &[0; 64])),
        ("hdr 0x0", forged_hdr(0, 0, &[])),
        ("hdr 4294967295 square", forged_hdr(u32::MAX, u32::MAX, &[])),
        ("hdr 4x4 truncated", forged_hdr(4, 4, &[1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16])),
        ("hdr run past the row", forged_hdr(16, 2, &[2, 2, 0, 16, 255, 1, 255, 1, 255, 1, 255, 1])),
        ("hdr old rle marker first", forged_hdr(8, 8, &[1, 1, 1, 200, 1, 1, 1, 200])),
    ];
    for (i, (tag, bytes)) in hdr.iter().enumerate() {
        let p = write(&d, &format!("forged{i}.hdr"), bytes);
        v.extend(uses(&d, &p, tag, Expect::Error));
    }
    // Real files, truncated at several lengths and with bytes flipped in the header.
    let real_hdr = std::fs::read(data("envmaps/equirect/probulator_grace_256x128.hdr")).unwrap();
    let real_exr = std::fs::read(refs("furnace.exr")).unwrap();
    for (ext, real) in [("hdr", &real_hdr), ("exr", &real_exr)] {
        let good = write(&d, &format!("good.{ext}"), real);
        v.extend(uses(&d, &good, &format!("intact {ext}"), Expect::Ok));
        for frac in [0usize, 1, 5, 20, 50, 90, 99] {
            let n = real.len() * frac / 100 + if frac == 0 { 7 } else { 0 };
            let p = write(&d, &format!("trunc{frac}.{ext}"), &real[..n.min(real.len() - 1)]);
            v.extend(uses(&d, &p, &format!("{ext} truncated to {frac}%"), Expect::Error));
        }
        for (k, at) in [3usize, 9, 20, 40, 70, 120, 200, 333].iter().enumerate() {
            let mut b = real.clone();
            b[*at] ^= 0x5a;
            let p = write(&d, &format!("flip{k}.{ext}"), &b);
            v.extend(uses(&d, &p, &format!("{ext} byte {at} flipped"), Expect::Either));
        }
    }
    v
}
