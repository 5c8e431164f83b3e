//! Noise targets (`--noise REL`, `prism_core::film::noise`): the film's own estimate of the image's relMSE against
//! the true error — against Mitsuba 3's Cornell box reference for `envlight` (the reference's own noise, measured
//! here, taken off), against the spread between two seeds for `ppm` (whose estimate leaves its bias out) — and the
//! render stopping at the first pass that meets the target, with the same image as the fixed-sample render of those
//! passes; resumes, shards and the film file keep the halves the estimate is made from.

use crate::common::{app_from_file, downsample, refs, scene_path, scratch};
use prism::io::Image;
use prism::sampling::SamplerKind;
use prism::settings::Overrides;

/// A 128 x 128 Cornell box render: its image, its noise estimate and the samples per pixel it took.
fn cornell(o: Overrides) -> (Image, Option<f64>, u64) {
    let o = Overrides { size: Some((128, 128)), ..o };
    let mut app = app_from_file(&scene_path("cornell_box.ron"), o);
    app.run().unwrap();
    let p = &app.resources.progress;
    (prism::stages::film_image(&app.resources).unwrap(), p.noise, p.spp_done)
}

/// Overrides asking for `spp` samples and an estimate (a target no render meets).
fn budget(spp: u32, integrator: Option<&str>, seed: u64) -> Overrides {
    Overrides {
        spp: Some(spp),
        noise: Some(1e-12),
        seed: Some(seed),
        integrator: integrator.map(str::to_string),
        ..Default::default()
    }
}

#[test]
fn the_envlight_estimate_is_within_a_quarter_of_the_error_against_mitsubas_reference() {
    // The 256 x 256 reference box-filtered to 128 x 128: each of its pixels is the mean of 4 x 8192 independent
    // samples, so its own relMSE is an independent-sample render's estimate scaled by n / (4 x 8192) (independent
    // samples make the estimate exact in expectation).
    let reference = downsample(&prism::io::read_exr(&refs("cornell.exr")).unwrap(), 2);
    let (_, independent, _) = cornell(Overrides { sampler: Some(SamplerKind::Independent), ..budget(256, None, 1) });
    let reference_noise = independent.unwrap() * 256.0 / (4.0 * 8192.0);
    for spp in [64, 256, 1024] {
        let (img, estimate, done) = cornell(budget(spp, None, 1));
        assert_eq!(done, spp as u64);
        let truth = prism::compare::compare(&img, &reference).unwrap().relmse - reference_noise;
        let estimate = estimate.expect("an estimate after two passes");
        eprintln!(
            "envlight {spp} spp: estimated relMSE {estimate:.3e}, true {truth:.3e} (reference's own {reference_noise:.1e})"
        );
        assert!((estimate / truth - 1.0).abs() < 0.25, "{spp} spp: estimate {estimate:.3e}, true {truth:.3e}");
    }
}

#[test]
fn the_ppm_estimate_is_its_variance_within_a_quarter() {
    // Two seeds differ by their noise alone (the bias is the same): relMSE(a, b) = var(a) + var(b).
    for spp in [64, 256] {
        let (a, ea, _) = cornell(budget(spp, Some("ppm(max_depth: 8)"), 1));
        let (b, eb, _) = cornell(budget(spp, Some("ppm(max_depth: 8)"), 2));
        let spread = prism::compare::compare(&a, &b).unwrap().relmse;
        let sum = ea.unwrap() + eb.unwrap();
        eprintln!(
            "ppm {spp} iterations: estimates {:.3e} + {:.3e}, two seeds' relMSE {spread:.3e}",
            ea.unwrap(),
            eb.unwrap()
        );
        assert!((sum / spread - 1.0).abs() < 0.25, "{spp}: estimates sum {sum:.3e}, spread {spread:.3e}");
    }
}

#[test]
fn a_noise_target_stops_at_the_first_pass_that_meets_it_with_the_image_of_those_passes() {
    let target = 2e-3;
    let unlimited = Overrides { noise: Some(target as f32), spp_unlimited: true, ..Default::default() };
    let (img, estimate, done) = cornell(unlimited.clone());
    let passes = done / 16;
    assert_eq!(done % 16, 0, "passes of 16 samples");
    assert!(estimate.unwrap() <= target, "stopped at {estimate:?} above the target");
    assert!(passes >= 3, "the target is not met by the first estimate ({done} spp)");
    // One pass fewer is above the target, and the fixed-sample render of the same passes is the same image.
    let o = |spp: u64| Overrides {
        spp: Some(spp as u32),
        passes: Some((spp / 16) as u32),
        noise: Some(1e-12),
        ..Default::default()
    };
    let (_, before, _) = cornell(o(done - 16));
    assert!(before.unwrap() > target, "{} spp already met the target: {before:?}", done - 16);
    let (same, _, _) = cornell(Overrides { noise: None, ..o(done) });
    assert!(img.pixels == same.pixels, "the noise-target render differs from the {done}-spp render of its passes");
    // With adaptive sampling and with ppm the target stops the render too.
    for o in [
        Overrides { adaptive: Some(true), ..unlimited.clone() },
        Overrides { integrator: Some("ppm(max_depth: 8)".into()), ..unlimited.clone() },
    ] {
        let (_, estimate, done) = cornell(o.clone());
        assert!(estimate.unwrap() <= target && done < 4096, "{o:?}: {estimate:?} at {done} spp");
    }
}

#[test]
fn shards_each_stop_at_the_target_and_merge() {
    let dir = scratch("noise_shards");
    let scene = scene_path("cornell_box.ron");
    let mut parts = vec![];
    for k in 0..2 {
        let film = dir.join(format!("part{k}.prism-film"));
        let out = crate::common::prism(&[
            "render",
            scene.to_str().unwrap(),
            "--size",
            "64x64",
            "--spp",
            "4096",
            "--noise",
            "0.002",
            "--shard",
            &format!("{k}/2"),
            "-q",
            "-o",
            film.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let f = prism::film::read_film(&film).unwrap();
        assert!(f.header.passes_done == f.header.passes, "a shard the target stopped is complete");
        assert!(f.header.spp_done < 4096 / 2, "shard {k} took {} spp", f.header.spp_done);
        let halves = f.noise.expect("the film keeps its noise halves");
        assert_eq!(halves.passes, f.header.spp_done / 16);
        parts.push(film);
    }
    let merged = dir.join("merged.exr");
    let out = crate::common::prism(&[
        "merge",
        parts[0].to_str().unwrap(),
        parts[1].to_str().unwrap(),
        "-o",
        merged.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn film_files_keep_the_noise_halves_exactly_and_refuse_forged_ones() {
    let dir = scratch("noise_film");
    let film = dir.join("cornell.prism-film");
    let scene = scene_path("cornell_box.ron");
    let out = crate::common::prism(&[
        "render",
        scene.to_str().unwrap(),
        "--size",
        "16x16",
        "--spp",
        "80",
        "--noise",
        "1e-9",
        "-q",
        "-o",
        film.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let f = prism::film::read_film(&film).unwrap();
    let h = f.noise.as_ref().expect("halves");
    assert_eq!((h.passes, h.first_passes), (5, 4));
    // Written again, the same bytes.
    let again = dir.join("again.prism-film");
    prism::film::write_film(
        &again,
        &f.header,
        &{
            let mut film = f.film.clone();
            film.track_noise(f.noise.clone());
            film
        },
        &f.state,
    )
    .unwrap();
    assert_eq!(std::fs::read(&film).unwrap(), std::fs::read(&again).unwrap());
    // A negative half sum (forged), with the checksum fixed up, is a one-line error.
    let mut bytes = std::fs::read(&film).unwrap();
    let at = bytes.len() - 8 - 8 - prism::film::NoiseHalves::byte_len(256) + 16;
    bytes[at..at + 8].copy_from_slice(&(-1.0f64).to_le_bytes());
    let n = bytes.len() - 8;
    let sum = prism::film::checksum(&bytes[..n]);
    bytes[n..].copy_from_slice(&sum.to_le_bytes());
    let err = prism::film::parse_film(&bytes, &film).err().expect("refused").to_string();
    assert!(err.contains("noise halves"), "{err}");
}
