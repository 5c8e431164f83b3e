//! Adaptive sampling (`--adaptive`): the samples after a uniform pilot pass go to pixels in proportion to their
//! neighbourhood's noise. Checked against Mitsuba 3's independent Cornell box reference: the image stays unbiased
//! (channel means), the total sample count is the uniform one, and the error at equal samples drops because the
//! emitter's edges (where a pixel straddles radiance 18 and 0.3) get the samples.

use crate::common::{app_from_file, downsample, prism, refs, scene_path};
use prism::settings::Overrides;

/// Render the Cornell box at 64x64; the image and the film's per-pixel sample counts.
fn cornell(spp: u32, adaptive: bool) -> (prism::io::Image, Vec<u64>) {
    let o = Overrides {
        size: Some((64, 64)),
        spp: Some(spp),
        seed: Some(5),
        adaptive: Some(adaptive),
        ..Default::default()
    };
    let mut app = app_from_file(&scene_path("cornell_box.ron"), o);
    app.run().unwrap();
    let img = prism::render::film_image(&app.resources).unwrap();
    let counts = app.resources.film.as_ref().unwrap().parts().1.to_vec();
    (img, counts)
}

#[test]
fn adaptive_sampling_is_unbiased_and_lowers_the_cornell_error_at_equal_samples() {
    // The 256x256 reference, box-filtered down to 64x64: what a 64x64 box-filter render converges to.
    let reference = downsample(&prism::io::read_exr(&refs("cornell.exr")).unwrap(), 4);
    let spp = 32;
    let (uniform, uniform_counts) = cornell(spp, false);
    let (adaptive, counts) = cornell(spp, true);
    assert!(uniform_counts.iter().all(|&c| c == spp as u64));
    // The budget: spp x pixels to within the rounding dither; the pilot (pass 0: 32 / 16 passes = 2 spp) is uniform.
    let total: u64 = counts.iter().sum();
    let budget = spp as u64 * counts.len() as u64;
    assert!((total as f64 - budget as f64).abs() < 0.01 * budget as f64, "{total} samples for a budget of {budget}");
    let pilot = spp as u64 / 16;
    assert!(counts.iter().all(|&c| c >= pilot), "every pixel keeps its pilot samples");
    let most = *counts.iter().max().unwrap();
    assert!(most > 3 * spp as u64, "the noisiest pixels get several times the uniform rate (most: {most})");
    // Where the samples went: the pixel with the most lies on the emitter's edge (rows 7-11 of 64 hold the light).
    let busiest = counts.iter().position(|&c| c == most).unwrap();
    let row = busiest / 64;
    assert!((6..=12).contains(&row), "busiest pixel in row {row}, not at the emitter");
    let u = prism::compare::compare(&uniform, &reference).unwrap();
    let a = prism::compare::compare(&adaptive, &reference).unwrap();
    for c in 0..3 {
        let rel = (a.mean_test[c] - a.mean_reference[c]).abs() / a.mean_reference[c];
        assert!(rel < 0.01, "adaptive channel {c} mean {} vs reference {}", a.mean_test[c], a.mean_reference[c]);
    }
    eprintln!("Cornell 64x64 at {spp} spp: RMSE uniform {:.5}, adaptive {:.5}", u.rmse, a.rmse);
    assert!(a.rmse < 0.85 * u.rmse, "adaptive RMSE {} not below uniform {}", a.rmse, u.rmse);
}

#[test]
fn adaptive_sampling_with_a_photon_mapper_is_a_warning_not_an_effect() {
    let dir = crate::common::scratch("adaptive-ppm");
    let out = dir.join("ppm.png");
    let scene = scene_path("cornell_caustic.ron");
    let args = ["render", scene.to_str().unwrap(), "--size", "16x16", "--spp", "1", "-q", "--integrator", "ppm"];
    let o = prism(&[&args[..], &["--adaptive", "-o", out.to_str().unwrap()]].concat());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && err.contains("adaptive sampling has no effect with the `ppm` integrator"), "{err}");
}
