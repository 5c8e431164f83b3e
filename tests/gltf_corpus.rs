//! The glTF sample models of `../shared/data/gltf_samples/` as a corpus: every one loads and renders a lit,
//! finite, non-black image (DamagedHelmet, lit only by emissive decals, included); KTX2 textures decode (the
//! AnisotropyBarnLamp's Zstandard RGB8 maps: a normal map's mean normal points out of the surface) or fall back to
//! the factor with one warning (Basis Universal); malformed and hostile KTX2 files are errors, never panics or
//! unbounded work.

use crate::common::{data, forged_ktx2, prism_args, render_file, scratch};
use prism::load::gltf::{Ktx2, decode_ktx2};
use prism::settings::Overrides;

const MODELS: [&str; 18] = [
    "2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
    "AnisotropyBarnLamp/AnisotropyBarnLamp.gltf",
    "BoxAnimated/BoxAnimated.gltf",
    "BoxTextured-glTF-Embedded/BoxTextured.gltf",
    "CesiumMan/glTF-Binary/CesiumMan.glb",
    "ClearCoat-glTF/ClearCoatTest.gltf",
    "CornellBox/CornellBox.glb",
    "DamagedHelmet/DamagedHelmet.glb",
    "DepthOfFieldExample/DepthOfFieldExample.glb",
    "FlightHelmet/FlightHelmet.gltf",
    "Fox.glb",
    "GolfBall/GolfBall.glb",
    "MixedLightingExample/MixedLightingExample.gltf",
    "MorphPrimitivesTest/glTF/MorphPrimitivesTest.gltf",
    "TonemappingTest/TonemappingTest.gltf",
    "cameras/Cameras.gltf",
    "simple_skin/simple_skin.gltf",
    "textureTransform/TextureTransformTest.gltf",
];

#[test]
fn every_sample_model_renders_a_lit_finite_image() {
    for m in MODELS {
        let img = render_file(
            &data(&format!("gltf_samples/{m}")),
            Overrides { size: Some((24, 24)), spp: Some(2), ..Default::default() },
        );
        assert!(img.pixels.iter().all(|p| p.is_finite() && p.min_element() >= 0.0), "{m}: non-finite pixels");
        let lit = img.pixels.iter().filter(|p| p.max_element() > 0.05).count();
        assert!(lit * 10 >= img.pixels.len(), "{m}: only {lit} of {} pixels are lit", img.pixels.len());
    }
}

#[test]
fn the_barn_lamps_ktx2_maps_decode_with_their_meaning_and_without_a_warning() {
    let dir = data("gltf_samples/AnisotropyBarnLamp");
    let normal = std::fs::read(dir.join("AnisotropyBarnLamp_normalbump.ktx2")).unwrap();
    let Ktx2::Image(img) = decode_ktx2(&normal).unwrap() else { panic!("an RGB8 Zstandard map is decoded") };
    assert_eq!((img.width(), img.height()), (1024, 1024));
    // A tangent-space normal map: the mean normal (2 rgb - 1) points out of the surface (+z, blue).
    let rgb = img.to_rgb8();
    let n = rgb.pixels().count() as f64;
    let mean = |c: usize| rgb.pixels().map(|p| 2.0 * p.0[c] as f64 / 255.0 - 1.0).sum::<f64>() / n;
    assert!(
        mean(2) > 0.8 && mean(0).abs() < 0.1 && mean(1).abs() < 0.1,
        "mean normal ({}, {}, {})",
        mean(0),
        mean(1),
        mean(2)
    );
    let orm = std::fs::read(dir.join("AnisotropyBarnLamp_occlusionroughnessmetal.ktx2")).unwrap();
    assert!(matches!(decode_ktx2(&orm).unwrap(), Ktx2::Image(i) if i.width() == 512));
    let out = scratch("gltf_corpus").join("barn.png");
    let run = prism_args(&[
        "render",
        dir.join("AnisotropyBarnLamp.gltf").to_str().unwrap(),
        "--size",
        "8x8",
        "--spp",
        "1",
        "-q",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert!(!run.stderr.contains("KTX2"), "no KTX2 warning once decoded: {}", run.stderr);
}

#[test]
fn forged_ktx2_files_decode_exactly_fall_back_or_fail_cleanly() {
    // R8G8B8A8_UNORM (37), 2 x 1, plain: the texels as written.
    let px = [10, 20, 30, 255, 40, 50, 60, 128];
    let Ktx2::Image(img) = decode_ktx2(&forged_ktx2(37, 2, 1, 0, &px)).unwrap() else { panic!("RGBA8 decodes") };
    assert_eq!(img.to_rgba8().into_raw(), px);
    // B8G8R8_UNORM (30): channels swapped back to RGB.
    let Ktx2::Image(img) = decode_ktx2(&forged_ktx2(30, 1, 1, 0, &[3, 2, 1])).unwrap() else { panic!("BGR8 decodes") };
    assert_eq!(img.to_rgb8().into_raw(), [1, 2, 3]);
    // Zstandard-supercompressed RGB8.
    let rgb: Vec<u8> = (0..4 * 4 * 3).map(|i| i as u8).collect();
    let z = ruzstd::encoding::compress_to_vec(&rgb[..], ruzstd::encoding::CompressionLevel::Fastest);
    let Ktx2::Image(img) = decode_ktx2(&forged_ktx2(23, 4, 4, 2, &z)).unwrap() else { panic!("zstd RGB8 decodes") };
    assert_eq!(img.to_rgb8().into_raw(), rgb);
    // Basis Universal (VK_FORMAT_UNDEFINED) and block formats: not decoded, named.
    assert!(
        matches!(decode_ktx2(&forged_ktx2(0, 4, 4, 1, &[0; 16])).unwrap(), Ktx2::Unsupported(w) if w.contains("Basis"))
    );
    assert!(matches!(decode_ktx2(&forged_ktx2(131, 4, 4, 0, &[0; 8])).unwrap(), Ktx2::Unsupported(_)));
    // Too few texels, too large, and a Zstandard stream far longer than the image: errors or bounded work.
    let e = decode_ktx2(&forged_ktx2(37, 4, 4, 0, &[0; 8])).err().unwrap();
    assert!(e.contains("needs 64"), "{e}");
    let e = decode_ktx2(&forged_ktx2(37, 100_000, 1, 0, &[0; 8])).err().unwrap();
    assert!(e.contains("at most 16384"), "{e}");
    let bomb = ruzstd::encoding::compress_to_vec(&vec![0u8; 64 << 20][..], ruzstd::encoding::CompressionLevel::Fastest);
    let t = std::time::Instant::now();
    let Ktx2::Image(img) = decode_ktx2(&forged_ktx2(23, 2, 2, 2, &bomb)).unwrap() else {
        panic!("decodes its 4 texels")
    };
    assert_eq!(img.width(), 2);
    assert!(t.elapsed().as_secs_f64() < 1.0, "decompression stops at the image's size");
    assert!(decode_ktx2(&[0xAB, b'K', b'T', b'X']).is_err());
}

#[test]
fn mutated_ktx2_files_never_panic() {
    let real = std::fs::read(data("gltf_samples/AnisotropyBarnLamp/AnisotropyBarnLamp_anisotropy.ktx2")).unwrap();
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for _ in 0..300 {
        let mut b = real.clone();
        // Mostly the header, the index and the start of the zstd stream; sometimes a truncation.
        for _ in 0..1 + next() % 4 {
            let at = (next() % 200) as usize;
            b[at] = next() as u8;
        }
        if next().is_multiple_of(5) {
            b.truncate((next() % b.len() as u64) as usize);
        }
        let r = std::panic::catch_unwind(|| decode_ktx2(&b).map(|_| ()));
        assert!(r.is_ok(), "a mutated KTX2 file panicked the decoder");
    }
}

#[test]
fn texture_transform_scales_then_rotates_counter_clockwise_on_the_displayed_image_then_offsets() {
    use glam::Vec2;
    use prism::texture::{ImageMap, TexImage, Wrap};
    let image = std::sync::Arc::new(TexImage::from_texels(1, 1, vec![glam::Vec3::ONE]).unwrap());
    let a = std::f32::consts::FRAC_PI_2;
    let map = |scale: Vec2, rot: f32, offset: Vec2| ImageMap {
        image: image.clone(),
        wrap: Wrap::Repeat,
        uv_scale: scale,
        uv_offset: offset,
        uv_rotation: Vec2::new(rot.cos(), rot.sin()),
    };
    // The u axis turned by 90 degrees points to -v: up on the image as displayed (v grows downwards), a quarter
    // turn counter-clockwise, as KHR_texture_transform describes it and TextureTransformTest's arrow shows it.
    let t = map(Vec2::ONE, a, Vec2::ZERO).transform_uv(Vec2::X);
    assert!((t - Vec2::new(0.0, -1.0)).length() < 1e-6, "{t}");
    // Scale first (2 along u), then rotate, then offset.
    let t = map(Vec2::new(2.0, 1.0), a, Vec2::new(0.5, 0.25)).transform_uv(Vec2::X);
    assert!((t - Vec2::new(0.5, -1.75)).length() < 1e-6, "{t}");
    // No rotation is exactly uv * scale + offset.
    let plain = ImageMap { uv_rotation: ImageMap::NO_ROTATION, ..map(Vec2::new(3.0, 0.5), 0.0, Vec2::new(0.1, 0.2)) };
    let uv = Vec2::new(0.3, 0.7);
    assert_eq!(plain.transform_uv(uv), uv * Vec2::new(3.0, 0.5) + Vec2::new(0.1, 0.2));
}

/// Texture memory: 8-bit images stay 8-bit. NormalTangentTest holds three 2048 x 2048 RGB PNGs (36 MiB decoded as
/// 8-bit); its base colour, metallic-roughness (as metallic, and its roughness as GGX alpha) and normal maps take
/// at most 1.5 times that (as f32 texels they took four times as much).
#[test]
fn eight_bit_textures_are_stored_as_eight_bits() {
    let path = data("gltf").join("NormalTangentTest.glb");
    let mut app = crate::common::app_from_file(&path, Overrides::default());
    app.run_stage(prism::Stage::Load).expect("loads");
    let mut seen: Vec<*const prism::texture::TexImage> = Vec::new();
    let mut bytes = 0usize;
    for t in &app.resources.textures.textures {
        if let prism::texture::Texture::Image(m) = t
            && !seen.contains(&std::sync::Arc::as_ptr(&m.image))
        {
            seen.push(std::sync::Arc::as_ptr(&m.image));
            bytes += m.image.texel_bytes();
        }
    }
    let decoded_8bit = 3 * 2048 * 2048 * 3;
    assert!(!seen.is_empty(), "the model's textures were loaded");
    assert!(
        bytes as f64 <= 1.5 * decoded_8bit as f64,
        "{} images take {bytes} bytes, more than 1.5x the {decoded_8bit} of the decoded 8-bit images",
        seen.len()
    );
}
