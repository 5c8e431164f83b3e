//! Near-specular lobes under estimators without multiple importance sampling (`prism::bsdf::NEAR_SPECULAR_ALPHA`): a
//! plastic sphere with a GGX coat of width 0.001 in a white furnace against Mitsuba 3's render of it
//! (`tests/data/mitsuba_furnace_plastic.csv`, made by the script beside it), for `envlight` with and without MIS,
//! `ppm`, `vcm` and `vcm(mode: bdpt)`; and the split itself: the near-specular and wide parts add up to the BSDF, the
//! lobe number selects the near-specular part with its probability, and the near-specular estimate
//! (`Bsdf::near_specular_weight` on that part's samples) and the share of the mixture estimate
//! (`Bsdf::near_specular_share`) converge to the same integral.

use crate::common::{render_ron, spp};
use glam::{Vec2, Vec3, Vec3A};
use prism::bsdf::{Bsdf, BsdfPart, ConductorFresnel, Lobe};
use prism::sampling::Rng;

const FURNACE: &str = "(
    camera: (eye: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0), fov: 40, size: (64, 64)),
    render: (filter: Box()),
    materials: { \"p\": RoughPlastic(alpha: 0.001, ior: 1.5, diffuse: (0.2, 0.5, 0.8)) },
    entities: [(shape: Sphere(), material: \"p\"), (light: Environment(radiance: (1, 1, 1)))],
)";

/// Mitsuba 3's mean over the pixels fully on the sphere (`tests/data/mitsuba_furnace_plastic.csv`).
fn mitsuba_mean() -> Vec3 {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/mitsuba_furnace_plastic.csv"))
        .expect("tests/data/mitsuba_furnace_plastic.csv");
    let row: Vec<f32> = text.lines().nth(1).unwrap().split(',').map(|v| v.parse().unwrap()).collect();
    Vec3::new(row[2], row[3], row[4])
}

#[test]
fn a_nearly_smooth_plastic_coat_reflects_the_white_furnace_under_every_integrator() {
    let reference = mitsuba_mean();
    let r = (0.25f64.asin().tan() / 20f64.to_radians().tan()) * 32.0;
    for integrator in [
        "envlight",
        "envlight(mis: false)",
        "envlight(mis: false, max_depth: 2)",
        "ppm",
        "ppm(glossy: gather)",
        "vcm",
        "vcm(mode: bdpt)",
    ] {
        let mut o = spp(256);
        o.integrator = Some(integrator.into());
        let img = render_ron(FURNACE, o);
        let (mut sum, mut n) = (Vec3::ZERO.as_dvec3(), 0);
        for y in 0..64 {
            for x in 0..64 {
                if ((x as f64 + 0.5 - 32.0).powi(2) + (y as f64 + 0.5 - 32.0).powi(2)).sqrt() <= r - 0.75 {
                    sum += img.pixels[y * 64 + x].as_dvec3();
                    n += 1;
                }
            }
        }
        assert_eq!(n, 1512, "pixels on the sphere, as the Mitsuba script counts them");
        let mean = (sum / n as f64).as_vec3();
        let rel = ((mean - reference) / reference).abs().max_element();
        // Without the split, light sampling alone lost the coat: -26% in red under envlight(mis: false), -15% ppm.
        assert!(rel < 0.005, "{integrator}: sphere mean {mean}, Mitsuba 3 {reference} ({:.2}% off)", rel * 100.0);
    }
}

/// A BSDF seen from 50 degrees off the normal.
fn bsdf(lobes: &[Lobe]) -> Bsdf {
    let wo = Vec3A::new(50f32.to_radians().sin(), 0.0, 50f32.to_radians().cos());
    Bsdf::from_lobes(Vec3A::Z, wo, lobes).expect("a BSDF")
}

fn coat(alpha: f32) -> prism::bsdf::rough_interface::InterfaceAt {
    prism::bsdf::rough_interface::RoughInterface::get(1.5, Some(alpha)).at(alpha)
}

fn cases() -> Vec<(&'static str, Vec<Lobe>)> {
    let plastic = |alpha| Lobe::Plastic {
        alpha,
        eta: 1.5,
        diffuse: Vec3::new(0.2, 0.5, 0.8),
        specular: Vec3::ONE,
        coat: coat(alpha),
    };
    let gold = ConductorFresnel::Schlick(Vec3::new(1.0, 0.78, 0.34));
    vec![
        ("plastic, coat alpha 0.005", vec![plastic(0.005)]),
        (
            "conductor alpha 0.008 over a diffuse lobe",
            vec![
                Lobe::Conductor { alpha: 0.008, fresnel: gold, scale: Vec3::ONE },
                Lobe::Diffuse { albedo: Vec3::splat(0.4) },
            ],
        ),
        ("Phong exponent 50000", vec![Lobe::Phong { ks: Vec3::splat(0.6), exponent: 50000.0 }]),
    ]
}

#[test]
fn the_near_specular_and_wide_parts_add_up_to_the_bsdf() {
    let mut rng = Rng::new(7, 1);
    for (name, lobes) in cases() {
        let b = bsdf(&lobes);
        assert!(b.has_near_specular(), "{name}");
        for _ in 0..2000 {
            let wi = prism::sampling::warp::uniform_sphere(rng.next_2d());
            let (f, ns, wide) = (b.eval(wi), b.eval_near_specular(wi).0, b.eval_wide(wi));
            assert!(
                (ns + wide - f).abs().max_element() <= 1e-4 * f.max_element().max(1.0),
                "{name}: {ns} + {wide} != {f}"
            );
        }
    }
    // A wide lobe has no near-specular part, and eval_wide is eval.
    let b = bsdf(&[Lobe::Conductor { alpha: 0.02, fresnel: ConductorFresnel::Schlick(Vec3::ONE), scale: Vec3::ONE }]);
    assert!(!b.has_near_specular());
    assert_eq!(b.near_specular_probability(), 0.0);
}

#[test]
fn the_near_specular_estimate_and_the_share_of_the_mixture_estimate_agree() {
    // Both estimate the integral of f_ns |cos| over the sphere: E[1{part = near-specular} w_ns] (what `ppm`'s eye
    // chain counts) and E[share(wi) f |cos| / pdf] (what `envlight(mis: false)` counts). The lobe number's
    // frequency of choosing the near-specular part is its probability.
    let n = 400_000;
    for (name, lobes) in cases() {
        let b = bsdf(&lobes);
        let mut rng = Rng::new(11, 3);
        let (mut a, mut a2, mut s, mut s2, mut picks) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0u32);
        for _ in 0..n {
            let (u_lobe, u) = (rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32()));
            let Some(bs) = b.sample(u_lobe, u) else { continue };
            let share = (b.near_specular_share(bs.wi) * bs.weight).y as f64;
            s += share;
            s2 += share * share;
            if b.part(u_lobe) == BsdfPart::NearSpecular {
                picks += 1;
                let w = b.near_specular_weight(bs.wi).map_or(0.0, |w| w.y as f64);
                a += w;
                a2 += w * w;
            }
        }
        let nf = n as f64;
        let (ma, ms) = (a / nf, s / nf);
        let se = ((a2 / nf - ma * ma) / nf + (s2 / nf - ms * ms) / nf).sqrt();
        assert!(ma > 0.01, "{name}: near-specular albedo {ma}");
        assert!((ma - ms).abs() < 4.0 * se + 1e-4, "{name}: {ma} vs {ms} (standard error {se})");
        let p = b.near_specular_probability() as f64;
        let freq = picks as f64 / nf;
        assert!((freq - p).abs() < 4.0 * (p * (1.0 - p) / nf).sqrt() + 1e-6, "{name}: chosen {freq}, probability {p}");
    }
}
