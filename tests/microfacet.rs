//! GGX microfacet lobes (rough conductor, rough dielectric, rough plastic): sampling against the BSDF's own pdf
//! (chi-square, several roughness values and incident angles down to grazing, reflection and transmission),
//! the values against an independent transcription of the formulas of `../shared/refs/cornell_rough.md`, the
//! white furnace (a reflectance-1 conductor loses exactly the energy single scattering loses, computed here by
//! quadrature), reciprocity, the transport-mode rules (1/eta^2 for radiance only), and the rough plastic against
//! Mitsuba 3's `roughplastic` (`tests/data/mitsuba_roughplastic.csv`, made by the script beside it).

use crate::common::chi_square;
use glam::{Vec3, Vec3A};
use prism::bsdf::{Bsdf, ConductorFresnel, Lobe, TransportMode};
use prism::math::Frame;
use prism::sampling::Rng;
use std::f64::consts::PI;

const S_BINS: usize = 24;
const PHI_BINS: usize = 24;

/// The rough coat's tables for index `eta` at `alpha`.
fn coat(eta: f32, alpha: f32) -> prism::bsdf::rough_interface::InterfaceAt {
    prism::bsdf::rough_interface::RoughInterface::get(eta, Some(alpha)).at(alpha)
}

fn dir(theta_deg: f32, phi_deg: f32) -> Vec3A {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3A::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

/// Bins on each hemisphere around a lobe axis (reflection direction above, refraction direction below): `s =
/// sqrt((1 - cos(angle to axis)) / 2)` in [0, 1] (fine near the peak) times the angle around the axis.
struct LobeBins {
    up: Frame,
    down: Frame,
}

impl LobeBins {
    fn frame(&self, side: usize) -> &Frame {
        if side == 0 { &self.up } else { &self.down }
    }

    fn bin(&self, d: Vec3A) -> usize {
        let side = if d.z > 0.0 { 0 } else { 1 };
        let l = self.frame(side).to_local(d);
        let s = ((1.0 - l.z.clamp(-1.0, 1.0) as f64) / 2.0).sqrt();
        let si = ((s * S_BINS as f64) as usize).min(S_BINS - 1);
        let phi = (l.y as f64).atan2(l.x as f64).rem_euclid(2.0 * PI);
        let pi = ((phi / (2.0 * PI) * PHI_BINS as f64) as usize).min(PHI_BINS - 1);
        (side * S_BINS + si) * PHI_BINS + pi
    }

    /// Expected counts of `n` samples from `pdf` (midpoint rule on sub-cells; each side only integrates its own
    /// hemisphere). dω = 4 s ds dφ.
    fn expected(&self, pdf: &dyn Fn(Vec3A) -> f64, n: usize) -> Vec<f64> {
        let sub = 40;
        let mut out = vec![0.0; 2 * S_BINS * PHI_BINS];
        for side in 0..2 {
            let f = self.frame(side);
            for si in 0..S_BINS {
                for pi in 0..PHI_BINS {
                    let mut acc = 0.0;
                    for a in 0..sub {
                        for b in 0..sub {
                            let s = (si as f64 + (a as f64 + 0.5) / sub as f64) / S_BINS as f64;
                            let phi = 2.0 * PI * (pi as f64 + (b as f64 + 0.5) / sub as f64) / PHI_BINS as f64;
                            let z = 1.0 - 2.0 * s * s;
                            let r = (1.0 - z * z).max(0.0).sqrt();
                            let d = f.to_world(Vec3A::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32));
                            if (d.z > 0.0) != (side == 0) {
                                continue;
                            }
                            let ds = 1.0 / (S_BINS * sub) as f64;
                            let dphi = 2.0 * PI / (PHI_BINS * sub) as f64;
                            acc += pdf(d) * 4.0 * s * ds * dphi;
                        }
                    }
                    out[(side * S_BINS + si) * PHI_BINS + pi] = acc * n as f64;
                }
            }
        }
        out
    }
}

/// Sample `bsdf` n times; chi-square of the directions against `bsdf.pdf`, and the pdf's integral against the
/// fraction of samples returned; each weight must equal `f |cos| / pdf`.
fn check_lobe(name: &str, bsdf: &Bsdf, wo: Vec3A, eta: f32) {
    let up = Frame::from_normal(Vec3A::new(-wo.x, -wo.y, wo.z));
    let down = match prism::math::refract(wo, Vec3A::Z, eta) {
        Some(t) => Frame::from_normal(t.normalize()),
        None => Frame::from_normal(-Vec3A::Z),
    };
    let bins = LobeBins { up, down };
    let n = 200_000;
    let mut rng = Rng::new(0xface, name.len() as u64);
    let mut observed = vec![0.0; 2 * S_BINS * PHI_BINS];
    let mut accepted = 0usize;
    for _ in 0..n {
        let Some(s) = bsdf.sample(rng.next_f32(), rng.next_2d()) else { continue };
        assert!(!s.delta);
        let expect = bsdf.eval(s.wi) * s.wi.z.abs() / bsdf.pdf(s.wi);
        assert!(
            (s.weight - expect).abs().max_element() <= 1e-3 * expect.max_element().max(1e-4),
            "{name}: weight {} vs f cos / pdf {expect}",
            s.weight
        );
        observed[bins.bin(s.wi)] += 1.0;
        accepted += 1;
    }
    let exp = bins.expected(&|d| bsdf.pdf(d) as f64, n);
    let total = exp.iter().sum::<f64>() / n as f64;
    let frac = accepted as f64 / n as f64;
    assert!((total - frac).abs() < 0.01, "{name}: pdf integrates to {total}, {frac} of the samples were returned");
    let (stat, df, p) = chi_square(&observed, &exp);
    if p <= 1e-3 {
        let mut v: Vec<(f64, usize)> =
            (0..exp.len()).map(|i| ((observed[i] - exp[i]).powi(2) / exp[i].max(1.0), i)).collect();
        v.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (c, i) in v.iter().take(12) {
            eprintln!(
                "bin side {} s {} phi {}: obs {} exp {:.1} ({c:.1})",
                i / (S_BINS * PHI_BINS),
                (i / PHI_BINS) % S_BINS,
                i % PHI_BINS,
                observed[*i],
                exp[*i]
            );
        }
    }
    assert!(p > 1e-3, "{name}: chi-square {stat:.1} with {df} dof, p = {p:.2e}");
}

const AU_ETA: Vec3 = Vec3::new(0.143_036, 0.375_307, 1.442_045);
const AU_K: Vec3 = Vec3::new(3.982_997, 2.385_557, 1.603_359);

#[test]
fn rough_conductor_sampling_follows_its_pdf() {
    for alpha in [0.05f32, 0.2, 0.5, 1.0] {
        for theta in [0.0f32, 45.0, 80.0, 89.0] {
            let wo = dir(theta, 30.0);
            let lobe = Lobe::Conductor {
                alpha,
                fresnel: ConductorFresnel::Complex { eta: AU_ETA, k: AU_K },
                scale: Vec3::ONE,
            };
            let bsdf = Bsdf::from_lobes(Vec3A::Z, wo, &[lobe]).unwrap();
            check_lobe(&format!("conductor alpha {alpha} theta {theta}"), &bsdf, wo, 1.0);
        }
    }
}

#[test]
fn rough_dielectric_sampling_follows_its_pdf_in_reflection_and_transmission() {
    for (alpha, eta) in [(0.1f32, 1.5f32), (0.5, 1.5), (0.15, 1.0 / 1.5), (1.0, 1.33)] {
        for theta in [0.0f32, 30.0, 60.0, 85.0] {
            let wo = dir(theta, 110.0);
            let lobe = Lobe::RoughDielectric { alpha, r: Vec3::ONE, t: Vec3::ONE, eta };
            let bsdf = Bsdf::from_lobes(Vec3A::Z, wo, &[lobe]).unwrap();
            check_lobe(&format!("dielectric alpha {alpha} eta {eta} theta {theta}"), &bsdf, wo, eta);
        }
    }
}

#[test]
fn rough_plastic_and_mixtures_sample_their_pdf() {
    for (alpha, theta) in [(0.05f32, 20.0f32), (0.3, 60.0), (0.7, 88.0)] {
        let wo = dir(theta, 200.0);
        let plastic = Lobe::Plastic {
            alpha,
            eta: 1.5,
            diffuse: Vec3::new(0.6, 0.3, 0.2),
            specular: Vec3::ONE,
            coat: coat(1.5, alpha),
        };
        let bsdf = Bsdf::from_lobes(Vec3A::Z, wo, &[plastic]).unwrap();
        check_lobe(&format!("plastic alpha {alpha} theta {theta}"), &bsdf, wo, 1.5);
        // A blend of a conductor and a diffuse lobe (glTF's metallic factor) samples the mixture pdf.
        let metal =
            Lobe::Conductor { alpha, fresnel: ConductorFresnel::Schlick(Vec3::splat(0.9)), scale: Vec3::splat(0.4) };
        let bsdf = Bsdf::from_lobes(Vec3A::Z, wo, &[metal, Lobe::Diffuse { albedo: Vec3::splat(0.3) }]).unwrap();
        check_lobe(&format!("metal+diffuse alpha {alpha} theta {theta}"), &bsdf, wo, 1.0);
    }
}

// An independent transcription of ../shared/refs/cornell_rough.md (f64).
fn d_ref(m: [f64; 3], a: f64) -> f64 {
    if m[2] <= 0.0 {
        return 0.0;
    }
    let t = (m[0] * m[0] + m[1] * m[1]) / (a * a) + m[2] * m[2];
    1.0 / (PI * a * a * t * t)
}

fn g1_ref(v: [f64; 3], m: [f64; 3], a: f64) -> f64 {
    let vm = v[0] * m[0] + v[1] * m[1] + v[2] * m[2];
    if vm * v[2] <= 0.0 {
        return 0.0;
    }
    let xy = v[0] * v[0] + v[1] * v[1];
    if xy == 0.0 {
        return 1.0;
    }
    2.0 / (1.0 + (1.0 + a * a * xy / (v[2] * v[2])).sqrt())
}

fn norm(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / l, v[1] / l, v[2] / l]
}

/// `f cos` of a conductor with F = 1, for the camera-side direction `wi` and light-side `wo` (the md's names).
fn conductor_fcos_ref(wi: [f64; 3], wo: [f64; 3], a: f64) -> f64 {
    if wi[2] <= 0.0 || wo[2] <= 0.0 {
        return 0.0;
    }
    let h = norm([wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]]);
    d_ref(h, a) * g1_ref(wi, h, a) * g1_ref(wo, h, a) / (4.0 * wi[2])
}

/// Directional albedo `int f cos dwo` by quadrature on a (cos theta, phi) grid refined near the mirror direction.
fn albedo_quadrature(wi: [f64; 3], a: f64) -> f64 {
    let (nt, np) = (1500, 720);
    let mut sum = 0.0;
    for i in 0..nt {
        // cos theta = 1 - t^2 puts more nodes near the pole, where narrow lobes at normal incidence sit.
        let t0 = i as f64 / nt as f64;
        let t1 = (i + 1) as f64 / nt as f64;
        let tm = 0.5 * (t0 + t1);
        let z = 1.0 - tm * tm;
        let dz = (1.0 - t0 * t0) - (1.0 - t1 * t1);
        let r = (1.0 - z * z).max(0.0).sqrt();
        for j in 0..np {
            let phi = 2.0 * PI * (j as f64 + 0.5) / np as f64;
            sum += conductor_fcos_ref(wi, [r * phi.cos(), r * phi.sin(), z], a) * dz * (2.0 * PI / np as f64);
        }
    }
    sum
}

#[test]
fn conductor_and_dielectric_values_match_the_reference_formulas() {
    let mut rng = Rng::new(5, 6);
    for a in [0.1f32, 0.2, 0.6] {
        for _ in 0..500 {
            let wo = prism::sampling::warp::uniform_hemisphere(rng.next_2d());
            let wi = prism::sampling::warp::uniform_hemisphere(rng.next_2d());
            let lobe = Lobe::Conductor { alpha: a, fresnel: ConductorFresnel::Schlick(Vec3::ONE), scale: Vec3::ONE };
            let f = lobe.eval(wo, wi, TransportMode::Radiance).x as f64 * wi.z as f64;
            let c = |v: Vec3A| [v.x as f64, v.y as f64, v.z as f64];
            let r = conductor_fcos_ref(c(wo), c(wi), a as f64);
            assert!((f - r).abs() <= 1e-4 * r.max(1e-3), "alpha {a}: {f} vs {r}");
        }
    }
    // Au at normal incidence: the md's F = (0.966679, 0.802010, 0.324121).
    let f = ConductorFresnel::Complex { eta: AU_ETA, k: AU_K }.eval(1.0);
    assert!((f - Vec3::new(0.966_679, 0.802_010, 0.324_121)).abs().max_element() < 2e-5, "{f}");
}

#[test]
fn a_white_rough_conductor_in_a_furnace_loses_only_the_single_scattering_energy() {
    // F = 1: the directional albedo is int D G1 G1 / (4 cos) dwo, below 1 by the energy of the light that would
    // scatter more than once between microfacets. Sampling estimates it as the mean sample weight; quadrature of the
    // reference formulas gives the exact number.
    for (a, theta) in [(0.2f32, 0.0f32), (0.2, 70.0), (0.5, 45.0), (1.0, 0.0), (1.0, 80.0)] {
        let wo = dir(theta, 0.0);
        let lobe = Lobe::Conductor { alpha: a, fresnel: ConductorFresnel::Schlick(Vec3::ONE), scale: Vec3::ONE };
        let bsdf = Bsdf::from_lobes(Vec3A::Z, wo, &[lobe]).unwrap();
        let mut rng = Rng::new(11, theta.to_bits() as u64);
        let n = 200_000;
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let w = bsdf.sample(rng.next_f32(), rng.next_2d()).map_or(0.0, |s| s.weight.x as f64);
            sum += w;
            sum2 += w * w;
        }
        let mean = sum / n as f64;
        let sigma = ((sum2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
        let exact = albedo_quadrature([wo.x as f64, wo.y as f64, wo.z as f64], a as f64);
        assert!(exact < 1.0 && exact > 0.2, "alpha {a} theta {theta}: albedo {exact}");
        assert!((mean - exact).abs() < 4.0 * sigma + 2e-3, "alpha {a} theta {theta}: sampled {mean} vs {exact}");
        // At normal incidence every microfacet tilted by more than 45 degrees reflects below the horizon: GGX's
        // slope distribution puts the fraction a^2 / (1 + a^2) of the projected area there (P(tan^2 < x) =
        // x / (a^2 + x)), a loss that masking adds to.
        if theta == 0.0 {
            let tail = (a * a / (1.0 + a * a)) as f64;
            assert!(1.0 - exact > tail, "alpha {a}: loss {} below the tail {tail}", 1.0 - exact);
        }
        if a == 0.2 && theta == 0.0 {
            assert!(1.0 - exact < 0.0385 + 0.02, "alpha 0.2 loses {}", 1.0 - exact);
        }
        // alpha = 1: D = 1/pi and G1 = 2 cos / (1 + cos), so the albedo at normal incidence is
        // 2 int_0^{pi/4} (2 cos^2 t - 1) tan t dt = 1 - ln 2 in closed form.
        if a == 1.0 && theta == 0.0 {
            let closed = 1.0 - std::f64::consts::LN_2;
            assert!((exact - closed).abs() < 2e-4, "alpha 1: quadrature {exact} vs 1 - ln 2 = {closed}");
            assert!((mean - closed).abs() < 4.0 * sigma + 1e-3, "alpha 1: sampled {mean} vs 1 - ln 2");
        }
    }
}

#[test]
fn microfacet_lobes_are_reciprocal() {
    let mut rng = Rng::new(21, 22);
    let lobes = [
        Lobe::Conductor { alpha: 0.3, fresnel: ConductorFresnel::Complex { eta: AU_ETA, k: AU_K }, scale: Vec3::ONE },
        Lobe::Plastic { alpha: 0.2, eta: 1.5, diffuse: Vec3::splat(0.5), specular: Vec3::ONE, coat: coat(1.5, 0.2) },
        Lobe::RoughDielectric { alpha: 0.25, r: Vec3::ONE, t: Vec3::ONE, eta: 1.5 },
    ];
    let rad = TransportMode::Radiance;
    for _ in 0..2000 {
        let a = prism::sampling::warp::uniform_hemisphere(rng.next_2d());
        let b = prism::sampling::warp::uniform_hemisphere(rng.next_2d());
        for l in &lobes {
            let (f1, f2) = (l.eval(a, b, rad), l.eval(b, a, rad));
            assert!((f1 - f2).abs().max_element() <= 1e-4 * f1.max_element().max(1e-3), "{l:?}: {f1} vs {f2}");
        }
        // Transmission: f(wo, wi) / eta_wo^2 = f(wi, wo) / eta_wi^2 (radiance). From inside, the frame faces the
        // inside viewer (z negated) and the relative index is 1/1.5.
        let below = Vec3A::new(b.x, b.y, -b.z);
        let out = Lobe::RoughDielectric { alpha: 0.25, r: Vec3::ONE, t: Vec3::ONE, eta: 1.5 }.eval(a, below, rad).x;
        let flip = |v: Vec3A| Vec3A::new(v.x, v.y, -v.z);
        let inside = Lobe::RoughDielectric { alpha: 0.25, r: Vec3::ONE, t: Vec3::ONE, eta: 1.0 / 1.5 }
            .eval(flip(below), flip(a), rad)
            .x;
        assert!((out - inside / 2.25).abs() <= 1e-3 * out.max(1e-3), "{out} vs {inside} / 1.5^2");
    }
}

#[test]
fn refraction_scales_radiance_by_one_over_eta_squared_but_not_importance() {
    let wo = dir(30.0, 0.0);
    let glass = Bsdf::from_lobes(Vec3A::Z, wo, &[Lobe::Dielectric { r: Vec3::ONE, t: Vec3::ONE, eta: 1.5 }]).unwrap();
    let mut rng = Rng::new(1, 2);
    for _ in 0..200 {
        let (ul, u) = (rng.next_f32(), rng.next_2d());
        let (r, i) = (glass.sample(ul, u).unwrap(), glass.sample_mode(ul, u, TransportMode::Importance).unwrap());
        if r.wi.z < 0.0 {
            assert!((r.weight.x * 2.25 - i.weight.x).abs() < 1e-5, "{} vs {}", r.weight.x, i.weight.x);
        } else {
            assert_eq!(r.weight, i.weight);
        }
    }
    // Rough glass: the importance value is eta^2 times the radiance value for transmission.
    let lobe = Lobe::RoughDielectric { alpha: 0.3, r: Vec3::ONE, t: Vec3::ONE, eta: 1.5 };
    let wi = dir(160.0, 180.0);
    let (fr, fi) = (lobe.eval(wo, wi, TransportMode::Radiance).x, lobe.eval(wo, wi, TransportMode::Importance).x);
    assert!(fr > 0.0 && (fi - 2.25 * fr).abs() < 1e-4 * fi, "{fr} {fi}");
    // Shading-normal correction (Veach): with a shading normal tilted from the geometric one, importance values are
    // f |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|).
    let ns = Vec3A::new(0.3, 0.0, 1.0).normalize();
    let mut b = Bsdf::new(Frame::from_normal(ns), Vec3A::Z, wo);
    b.push(Lobe::Diffuse { albedo: Vec3::splat(0.5) });
    let b = b.finish().unwrap();
    let wi = dir(40.0, 90.0);
    let (fr, fi) = (b.eval(wi).x, b.eval_mode(wi, TransportMode::Importance).x);
    let c = wo.dot(ns).abs() * wi.z.abs() / (wo.z.abs() * wi.dot(ns).abs());
    assert!((fi - fr * c).abs() < 1e-6, "{fi} vs {fr} x {c}");
}

/// `Lobe::eval_pdf` (what next-event estimation and BSDF sampling call, sharing the half vector, `D` and `G1(wo)`
/// between value and density) must return exactly `(eval, pdf)`: the same numbers bit for bit, for every lobe, on
/// random direction pairs above, below and across the surface and on directions the lobes sample, grazing ones and
/// `wo` from inside included, in both transport modes.
#[test]
fn fused_microfacet_value_and_density_equal_eval_and_pdf_bit_for_bit() {
    let lobes = [
        Lobe::Conductor {
            alpha: 0.2,
            fresnel: ConductorFresnel::Complex { eta: Vec3::new(0.14, 0.37, 1.44), k: Vec3::new(3.98, 2.38, 1.6) },
            scale: Vec3::ONE,
        },
        Lobe::Conductor { alpha: 0.02, fresnel: ConductorFresnel::Schlick(Vec3::splat(0.9)), scale: Vec3::ONE },
        Lobe::RoughDielectric { alpha: 0.15, r: Vec3::ONE, t: Vec3::ONE, eta: 1.5 },
        Lobe::RoughDielectric { alpha: 0.6, r: Vec3::splat(0.8), t: Vec3::splat(0.9), eta: 1.0 / 1.33 },
        Lobe::Diffuse { albedo: Vec3::splat(0.5) },
        Lobe::Plastic { alpha: 0.1, eta: 1.5, diffuse: Vec3::splat(0.5), specular: Vec3::ONE, coat: coat(1.5, 0.1) },
    ];
    let mut rng = Rng::new(17, 3);
    let mut nonzero = [0usize; 2];
    for lobe in &lobes {
        for k in 0..20000 {
            let random_dir = |rng: &mut Rng| {
                let (z, phi) = (2.0 * rng.next_f32() - 1.0, 2.0 * std::f32::consts::PI * rng.next_f32());
                let r = (1.0 - z * z).max(0.0).sqrt();
                Vec3A::new(r * phi.cos(), r * phi.sin(), z)
            };
            let mut wo = random_dir(&mut rng);
            let mut wi = random_dir(&mut rng);
            if k % 10 == 0 {
                wo.z *= 1e-4; // grazing
                wo = wo.normalize();
            }
            if k % 7 == 0 {
                wi = Vec3A::new(-wo.x, -wo.y, wo.z); // the mirror direction: the half vector is the normal
            } else if k % 3 == 0 {
                // A direction the lobe itself samples (where transmission has its density).
                let u = glam::Vec2::new(rng.next_f32(), rng.next_f32());
                if let Some(s) =
                    lobe.sample(wo.z.abs() * Vec3A::Z + wo.with_z(0.0), rng.next_f32(), u, TransportMode::Radiance)
                {
                    wo.z = wo.z.abs();
                    wi = s.wi;
                }
            }
            for mode in [TransportMode::Radiance, TransportMode::Importance] {
                let (f, p) = lobe.eval_pdf(wo, wi, mode);
                let (fe, pe) = (lobe.eval(wo, wi, mode), lobe.pdf(wo, wi));
                let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                assert_eq!(
                    (bits(f), p.to_bits()),
                    (bits(fe), pe.to_bits()),
                    "{lobe:?} wo {wo} wi {wi} {mode:?}: fused ({f}, {p}) vs ({fe}, {pe})"
                );
                nonzero[(wi.z < 0.0) as usize] += (p > 0.0) as usize;
            }
        }
    }
    assert!(nonzero[0] > 10000 && nonzero[1] > 5000, "too few directions with a density: {nonzero:?}");
}

/// Mitsuba 3's `roughplastic` (GGX, `nonlinear: false`, `diffuse_reflectance` (0.8, 0.5, 0.2),
/// `specular_reflectance` 0 or 1, `ext_ior` 1) at five direction pairs for three widths and three indices, as
/// `tests/data/mitsuba_roughplastic.py` evaluated it: the rough coat's transmittance and internal reflectance
/// make the diffuse base (and the whole lobe) agree within 1%.
#[test]
fn rough_plastic_matches_mitsuba_3s_roughplastic_within_one_percent() {
    let text = std::fs::read_to_string(crate::common::root().join("tests/data/mitsuba_roughplastic.csv")).unwrap();
    let mut worst = (0.0f32, String::new());
    let mut rows = 0;
    for line in text.lines().skip(1) {
        let v: Vec<f32> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let (alpha, eta, spec) = (v[0], v[1], v[2]);
        let wi = Vec3A::new(v[3], v[4], v[5]).normalize();
        let wo = Vec3A::new(v[6], v[7], v[8]).normalize();
        let want = Vec3::new(v[9], v[10], v[11]);
        let lobe = Lobe::Plastic {
            alpha,
            eta,
            diffuse: Vec3::new(0.8, 0.5, 0.2),
            specular: Vec3::splat(spec),
            coat: coat(eta, alpha),
        };
        let got = lobe.eval(wi, wo, TransportMode::Radiance);
        let err = ((got - want).abs() / want.max(Vec3::splat(1e-6))).max_element();
        if err > worst.0 {
            worst = (err, format!("alpha {alpha} eta {eta} specular {spec} wi {wi} wo {wo}: {got} vs {want}"));
        }
        rows += 1;
    }
    assert_eq!(rows, 90);
    assert!(worst.0 < 0.01, "largest relative difference {:.4}: {}", worst.0, worst.1);
}

/// A textured width reads a 16-row table in sqrt(alpha): on a row it equals the constant width's table (R_int by
/// the coarser rule within 0.1%), between rows it stays within 1% of the exact table.
#[test]
fn the_textured_width_table_agrees_with_the_constant_width_tables() {
    use prism::bsdf::rough_interface::RoughInterface;
    let grid = RoughInterface::get(1.5, None);
    for alpha in [(5.0f32 / 15.0).powi(2), 0.2, 0.55, 0.9] {
        let (g, c) = (grid.at(alpha), coat(1.5, alpha));
        let on_row = alpha == (5.0f32 / 15.0).powi(2);
        let tol = if on_row { 1e-3 } else { 1e-2 };
        let r = (g.internal_reflectance() - c.internal_reflectance()).abs() / c.internal_reflectance();
        assert!(r < tol, "alpha {alpha}: R_int {} vs {}", g.internal_reflectance(), c.internal_reflectance());
        for mu in [0.05f32, 0.3, 0.7, 1.0] {
            let (tg, tc) = (g.transmittance(mu), c.transmittance(mu));
            assert!((tg - tc).abs() / tc < tol, "alpha {alpha} mu {mu}: T {tg} vs {tc}");
        }
    }
}
