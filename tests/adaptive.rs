//! Adaptive sampling (`--adaptive`): the samples after a uniform pilot pass go to pixels in proportion to their
//! neighbourhood's noise. Checked against Mitsuba 3's independent Cornell box reference: the image stays unbiased
//! (channel means), the total sample count is the uniform one, and the error at equal samples drops because the
//! emitter's edges (where a pixel straddles radiance 18 and 0.3) get the samples.

use crate::common::{app_from_file, downsample, prism, refs, scene_path};
use glam::Vec3;
use prism::integrator::{MAX_RATE, MIN_ADAPTIVE_PIXELS, MIN_RATE, SampleAllocation};
use prism::settings::Overrides;

/// Render the Cornell box at 64x64; the image and the film's per-pixel sample counts.
fn cornell(spp: u32, adaptive: bool) -> (prism::io::Image, Vec<u64>) {
    cornell_in_passes(spp, adaptive, None)
}

/// [`cornell`] in `passes` passes (`None`: the default layout).
fn cornell_in_passes(spp: u32, adaptive: bool, passes: Option<u32>) -> (prism::io::Image, Vec<u64>) {
    let o = Overrides {
        size: Some((64, 64)),
        spp: Some(spp),
        seed: Some(5),
        adaptive: Some(adaptive),
        passes,
        ..Default::default()
    };
    let mut app = app_from_file(&scene_path("cornell_box.ron"), o);
    app.run().unwrap();
    let img = prism::stages::film_image(&app.resources).unwrap();
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
    // The budget: spp x pixels to within the rounding dither; the pilot (pass 0: 32 / 16 = 2 spp) is uniform.
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
fn the_default_pass_layout_renders_every_sample_once_and_keeps_the_pilot() {
    use prism::settings::{MIN_PASS_SPP, RenderSettings, default_pass_layout};
    for spp in [1, 2, 3, 15, 16, 17, 31, 32, 33, 64, 100, 255, 256, 257, 1000, 4096, 65_537] {
        for adaptive in [false, true] {
            for shards in [1, 2, 3, 8] {
                let (passes, pilot_spp) = default_pass_layout(spp, adaptive, shards);
                let s = RenderSettings { spp: Some(spp), passes, pilot_spp, adaptive, ..Default::default() };
                s.validate().unwrap_or_else(|e| panic!("spp {spp} adaptive {adaptive} shards {shards}: {e}"));
                let what = format!("spp {spp}, adaptive {adaptive}, {shards} shards: {passes} passes, {pilot_spp:?}");
                // The passes cover the samples 0..spp of every pixel exactly once, in order.
                let counts: Vec<u32> = (0..passes).map(|p| s.samples_in_pass(p)).collect();
                assert!(counts.iter().all(|&c| c >= 1), "{what}: an empty pass in {counts:?}");
                assert_eq!(counts.iter().map(|&c| c as u64).sum::<u64>(), spp as u64, "{what}: {counts:?}");
                for p in 0..passes {
                    assert_eq!(s.samples_before_pass(p + 1), s.samples_before_pass(p) + counts[p as usize] as u64);
                }
                // The adaptive pilot keeps its share of the budget (spp / 16, at least 1) whatever the layout.
                if adaptive && spp > 1 {
                    assert_eq!(counts[0], (spp / 16).max(1), "{what}: the pilot");
                }
                // Passes after the pilot hold a packet's worth of samples per pixel where there are enough samples
                // and no shards ask for more passes; shards get a pass each where the samples allow.
                let later = &counts[if pilot_spp.is_some() { 1 } else { 0 }..];
                if shards == 1 && spp >= 2 * MIN_PASS_SPP {
                    assert!(later.iter().all(|&c| c >= MIN_PASS_SPP), "{what}: {counts:?}");
                }
                assert!(passes >= shards.min(spp), "{what}: fewer passes than shards");
                assert!(passes <= 16, "{what}");
            }
        }
    }
}

#[test]
fn the_pass_layout_does_not_change_which_samples_a_pixel_gets() {
    // The same pilot (2 of 32 spp) in 16 even passes and in the default layout (a pilot pass, then one of 30): every
    // pixel gets the same number of samples, the same ones, so the images agree up to the rounding of the f32 sums
    // each pass hands the film.
    let (even, even_counts) = cornell_in_passes(32, true, Some(16));
    let (default, counts) = cornell_in_passes(32, true, None);
    assert_eq!(counts, even_counts, "per-pixel sample counts");
    let d = prism::compare::compare(&default, &even).unwrap();
    assert!(d.rmse < 1e-6, "RMSE between the two layouts {}", d.rmse);
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

// The allocation itself: rates, counts, and what a pixel's own samples may change.
#[test]
fn rates_average_one_and_respect_the_clamp() {
    // A 40x40 pilot (1 sample per pixel): a few very noisy neighbourhoods among mildly noisy ones, and a flat band
    // (the first ten rows).
    let n = 40 * 40;
    let value = |i: usize| match i {
        _ if i < 400 => 1.0,
        _ if i.is_multiple_of(97) => 60.0,
        _ => (i % 7) as f32 * 0.1,
    };
    let sums: Vec<Vec3> = (0..n).map(|i| Vec3::splat(value(i))).collect();
    let squares: Vec<Vec3> = sums.iter().map(|s| *s * *s).collect();
    let a = SampleAllocation::from_pilot(40, 40, 1, &sums, &squares, 3);
    let r = a.rates();
    let mean = r.iter().map(|&x| x as f64).sum::<f64>() / r.len() as f64;
    assert!((mean - 1.0).abs() < 1e-5, "mean rate {mean}");
    assert!(r.iter().all(|&x| (MIN_RATE * 0.99..=MAX_RATE * 1.01).contains(&x)));
    assert!(r.iter().any(|&x| x > 0.9 * MAX_RATE) && r.iter().any(|&x| x < 1.1 * MIN_RATE), "both clamps reached");
    // A flat image samples uniformly.
    let flat = SampleAllocation::from_pilot(40, 40, 1, &vec![Vec3::ONE; n], &vec![Vec3::ONE; n], 3);
    assert!(flat.rates().iter().all(|&x| x == 1.0));
}

#[test]
fn rates_follow_the_square_root_of_the_noise() {
    // A 64x64 pilot of 4 samples per pixel, mean 1 everywhere: one sample's deviation 0.5 in the left half, 2 in the
    // right. Rates go as the square root of the deviation (`NOISE_EXPONENT`), so the right half gets 2x the left's
    // (away from the seam, where the neighbourhoods mix), and the two halves' rates average 1.
    let (w, h) = (64u32, 64u32);
    let n = (w * h) as usize;
    let sigma = |i: usize| if (i % 64) < 32 { 0.5f32 } else { 2.0 };
    let sums = vec![Vec3::splat(4.0); n];
    let squares: Vec<Vec3> = (0..n).map(|i| Vec3::splat(4.0 * (1.0 + sigma(i) * sigma(i)))).collect();
    let a = SampleAllocation::from_pilot(w, h, 4, &sums, &squares, 7);
    let (left, right) = (a.rates()[20 * 64 + 10], a.rates()[20 * 64 + 50]);
    assert!((right / left - 2.0).abs() < 1e-3, "rate ratio {} for a 4x deviation ratio", right / left);
    assert!((left - 2.0 / 3.0).abs() < 0.02 && (right - 4.0 / 3.0).abs() < 0.04, "rates {left} and {right}");
}

#[test]
fn counts_are_monotone_and_total_the_budget() {
    // A 32x32 pilot of 4 samples per pixel: a noisy column (samples 0 and 2: mean 1, E[v^2] 2) in a flat image.
    let (w, h) = (32u32, 32u32);
    let n = (w * h) as usize;
    let noisy = |i: usize| i % 32 == 16;
    let sums: Vec<Vec3> = (0..n).map(|_| Vec3::splat(4.0)).collect();
    let squares: Vec<Vec3> = (0..n).map(|i| Vec3::splat(if noisy(i) { 8.0 } else { 4.0 })).collect();
    let a = SampleAllocation::from_pilot(w, h, 4, &sums, &squares, 7);
    for p in 0..n {
        let mut last = 0;
        for s in 0..200 {
            let c = a.samples_before(p, s);
            assert!(c >= last);
            last = c;
        }
        assert_eq!(a.samples_before(p, 3), 3, "the pilot is uniform");
    }
    assert!((0..n).all(|p| a.samples_before(p, u32::MAX as u64) <= u32::MAX as u64), "indices stay in u32");
    let total: u64 = (0..n).map(|p| a.samples_before(p, 260)).sum();
    let expect = 260 * n as u64;
    assert!((total as f64 - expect as f64).abs() < 0.01 * expect as f64, "{total} vs {expect}");
    // Pixels beside the column see its variance in their neighbourhood and get more samples than flat ones.
    assert!(a.samples_before(15, 260) > 2 * a.samples_before(5, 260));
}

#[test]
fn a_pixel_rate_depends_on_its_own_pilot_samples_only_through_the_image_wide_normalisation() {
    // A 40x40 pilot of 4 samples per pixel with smoothly varying noise (E[v^2] - E[v]^2 = 0.1 + x/40).
    let (w, h) = (40u32, 40u32);
    let n = (w * h) as usize;
    let mut sums = vec![Vec3::splat(4.0); n];
    let mut squares: Vec<Vec3> = (0..n).map(|i| Vec3::splat(4.0 * (1.1 + (i % 40) as f32 / 40.0))).collect();
    let a = SampleAllocation::from_pilot(w, h, 4, &sums, &squares, 1);
    // Change only pixel c's samples, by a lot: its neighbours' rates jump, its own moves by O(8 / pixels).
    let c = 20 * 40 + 20;
    sums[c] = Vec3::splat(40.0);
    squares[c] = Vec3::splat(400.0);
    let b = SampleAllocation::from_pilot(w, h, 4, &sums, &squares, 1);
    // (Their deviation grows about 4x; rates follow its square root.)
    assert!(b.rates()[c - 1] > 1.5 * a.rates()[c - 1], "the neighbours see the change");
    let own = (b.rates()[c] / a.rates()[c] - 1.0).abs();
    assert!(own < 8.0 * 20.0 / n as f32, "own rate moved by {own}");
    // A pixel far away in the same column (the same noise) gets exactly the same rate: the changed pixel's
    // own rate has no link to its samples beyond the normalisation every pixel shares.
    let far = 5 * 40 + 20;
    assert_eq!(b.rates()[c], b.rates()[far]);
    assert!(own > 0.0, "the normalisation does move");
}

#[test]
fn small_images_and_overflowing_samples_do_not_mislead_the_allocation() {
    // Below MIN_ADAPTIVE_PIXELS the allocation is uniform.
    let side = (MIN_ADAPTIVE_PIXELS as f64).sqrt() as u32 - 1;
    let m = (side * side) as usize;
    let pilot = |m: usize| -> (Vec<Vec3>, Vec<Vec3>) {
        let sums: Vec<Vec3> = (0..m).map(|i| Vec3::splat((i % 5) as f32)).collect();
        let squares = sums.iter().map(|s| *s * *s * 2.0 + Vec3::ONE).collect();
        (sums, squares)
    };
    let (sums, squares) = pilot(m);
    let small = SampleAllocation::from_pilot(side, side, 2, &sums, &squares, 0);
    assert!(small.rates().iter().all(|&r| r == 1.0));
    // The same kind of pilot on an image just large enough is allocated unevenly.
    let (sums, squares) = pilot(((side + 1) * (side + 1)) as usize);
    let large = SampleAllocation::from_pilot(side + 1, side + 1, 2, &sums, &squares, 0);
    assert!(large.rates().iter().any(|&r| r != 1.0));
    // A sample whose square overflows marks its neighbourhood as the noisiest, not the smoothest.
    let n = 32 * 32;
    let sums: Vec<Vec3> = (0..n).map(|i| Vec3::splat(1.0 + (i % 3) as f32)).collect();
    let mut squares: Vec<Vec3> = sums.iter().map(|s| *s * *s * 1.5).collect();
    squares[500] = Vec3::splat(f32::INFINITY);
    let a = SampleAllocation::from_pilot(32, 32, 1, &sums, &squares, 0);
    let max = a.rates().iter().cloned().fold(0.0f32, f32::max);
    assert_eq!(a.rates()[501], max);
}
