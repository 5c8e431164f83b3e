//! The same scene and seed give a bit-identical image whatever the thread count (uniform and adaptive sampling),
//! and the same EXR file byte for byte.

use crate::common::{prism, root, scratch};
use prism::io::read_exr;

#[test]
fn exr_is_bit_identical_for_one_and_two_threads() {
    for adaptive in ["false", "true"] {
        bit_identical_for_one_and_two_threads(adaptive);
    }
}

fn bit_identical_for_one_and_two_threads(adaptive: &str) {
    let dir = scratch("determinism");
    let scene = root().join("scenes/cornell_box.ron");
    let (mut images, mut files) = (vec![], vec![]);
    for threads in ["1", "2"] {
        let out = dir.join(format!("t{threads}-{adaptive}.exr"));
        let o = prism(&[
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--size",
            "64x64",
            "--spp",
            "8",
            "--threads",
            threads,
            "--adaptive",
            adaptive,
            "-q",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        images.push(read_exr(&out).unwrap());
        files.push(std::fs::read(&out).unwrap());
    }
    let bits = |img: &prism::io::Image| -> Vec<u32> {
        img.pixels.iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect()
    };
    assert_eq!(bits(&images[0]), bits(&images[1]), "thread count changed the image (adaptive: {adaptive})");
    assert!(files[0] == files[1], "same pixels, but the EXR files differ (adaptive: {adaptive})");
    assert!(images[0].mean().x > 0.05, "the image is not black");
}

#[test]
fn same_seed_same_image_different_seed_different_noise() {
    use crate::common::{app_from_file, scene_path};
    use prism::settings::Overrides;
    let render = |seed| {
        let mut app = app_from_file(
            &scene_path("cornell_box.ron"),
            Overrides { size: Some((32, 32)), spp: Some(2), seed: Some(seed), ..Default::default() },
        );
        app.run().unwrap();
        prism::stages::film_image(&app.resources).unwrap()
    };
    assert_eq!(render(1), render(1));
    assert_ne!(render(1), render(2));
}
