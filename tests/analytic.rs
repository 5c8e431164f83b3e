//! Renders compared with closed-form radiance: the inverse-square and cosine laws of a point light, Lambert's
//! polygon formula for a rectangular area light, the irradiance of a spherical light, a Lambertian floor inside a
//! uniformly emitting sphere (E = pi L), emitters seen directly and in mirrors, and a glass sphere in a uniform
//! background (energy conservation of Fresnel reflection + refraction).

use crate::common::{render_ron, spp};
use glam::{DVec3, Vec3};
use prism::io::Image;
use std::f64::consts::PI;

/// Orthographic camera looking straight down at the y = 0 plane, covering [-2,2]^2; returns the world (x, z) of
/// a film position.
const TOP_CAMERA: &str = "camera: (eye: (0, 5, 0), target: (0, 0, 0), up: (0, 0, -1), orthographic: 4, size: (32, 32))";

fn film_to_floor(px: f64, py: f64, size: f64) -> (f64, f64) {
    (4.0 * px / size - 2.0, -(2.0 - 4.0 * py / size))
}

/// Mean of `f(x, z)` over pixel (i, j) of the top camera (16x16 midpoint rule).
fn pixel_average(i: u32, j: u32, size: f64, f: &dyn Fn(f64, f64) -> f64) -> f64 {
    let n = 16;
    let mut acc = 0.0;
    for a in 0..n {
        for b in 0..n {
            let (x, z) =
                film_to_floor(i as f64 + (a as f64 + 0.5) / n as f64, j as f64 + (b as f64 + 0.5) / n as f64, size);
            acc += f(x, z);
        }
    }
    acc / (n * n) as f64
}

/// Compare every pixel whose footprint shows the floor (`floor_visible` at its corners and centre) with the
/// analytic pixel average: each within `tol` (noise allowance, about 5 standard deviations of the per-pixel error
/// measured over many seeds), and the mean signed relative error within `bias_tol` (systematic error).
fn compare_to(
    img: &Image,
    tol: f64,
    bias_tol: f64,
    floor_visible: &dyn Fn(f64, f64) -> bool,
    f: &dyn Fn(f64, f64) -> f64,
) {
    let (mut signed, mut count) = (0.0, 0);
    let size = img.width as f64;
    for j in 0..img.height {
        for i in 0..img.width {
            let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (0.5, 0.5)];
            if !corners.iter().all(|(a, b)| {
                let (x, z) = film_to_floor(i as f64 + a, j as f64 + b, size);
                floor_visible(x, z)
            }) {
                continue;
            }
            let expect = pixel_average(i, j, size, f);
            let got = img.get(i, j).x as f64;
            let err = (got - expect) / expect.max(1e-3);
            signed += err;
            count += 1;
            assert!(err.abs() < tol, "pixel ({i},{j}): rendered {got}, analytic {expect}");
        }
    }
    assert!(count > img.width * img.height / 2, "too few pixels compared");
    let bias = signed / count as f64;
    assert!(bias.abs() < bias_tol, "mean relative error {bias:.2e}: systematic error");
}

fn everywhere(_: f64, _: f64) -> bool {
    true
}

#[test]
fn point_light_follows_inverse_square_and_cosine_laws() {
    // L = rho/pi * I cos(theta) / r^2 on a Lambertian plane below a point light at height h.
    let (rho, intensity, h) = (0.5, 3.0, 1.0);
    let scene = format!(
        "({TOP_CAMERA}, materials: {{\"m\": Lambert(albedo: ({rho}, {rho}, {rho}))}},
          entities: [(shape: Plane(), material: \"m\"), (light: Point(intensity: ({intensity}, {intensity}, {intensity}), position: (0, {h}, 0)))])"
    );
    let img = render_ron(&scene, spp(64));
    compare_to(&img, 5e-3, 3e-4, &everywhere, &|x, z| {
        let r2 = x * x + z * z + h * h;
        rho / PI * intensity * (h / r2.sqrt()) / r2
    });
}

#[test]
fn directional_light_gives_e_cos_alpha_everywhere() {
    let alpha: f64 = 50f64.to_radians();
    let scene = format!(
        "({TOP_CAMERA}, materials: {{\"m\": Lambert(albedo: (0.8, 0.8, 0.8))}},
          entities: [(shape: Plane(), material: \"m\"), (light: Directional(irradiance: (2, 2, 2), direction: ({}, {}, 0)))])",
        alpha.sin(),
        -alpha.cos()
    );
    let img = render_ron(&scene, spp(1));
    compare_to(&img, 1e-5, 1e-6, &everywhere, &|_, _| 0.8 / PI * 2.0 * alpha.cos());
}

/// Irradiance at `x` (normal +y) from a polygon of uniform radiance `l` (Lambert's formula).
fn polygon_irradiance(x: DVec3, verts: &[DVec3], l: f64) -> f64 {
    let n = DVec3::Y;
    let mut sum = 0.0;
    for i in 0..verts.len() {
        let a = (verts[i] - x).normalize();
        let b = (verts[(i + 1) % verts.len()] - x).normalize();
        let theta = a.dot(b).clamp(-1.0, 1.0).acos();
        sum += theta * n.dot(a.cross(b).normalize());
    }
    0.5 * l * sum.abs()
}

#[test]
fn rectangular_area_light_matches_lamberts_polygon_formula() {
    // A 1 x 0.6 light at height 0.8 facing down; stratified light samples make soft shadows converge fast.
    let (l, rho) = (5.0, 0.7);
    let scene = format!(
        "({TOP_CAMERA}, render: (integrator: phong(light_samples: 16)), materials: {{\"m\": Lambert(albedo: ({rho}, {rho}, {rho}))}},
          entities: [(shape: Plane(), material: \"m\"),
                     (shape: Quad(), light: Area(radiance: ({l}, {l}, {l})),
                      transform: [Translate((0.3, 0.8, 0)), Rotate(axis: (1, 0, 0), degrees: 90), Scale((0.5, 0.3, 1))])])"
    );
    let img = render_ron(&scene, spp(64));
    let verts = [
        DVec3::new(-0.2, 0.8, -0.3),
        DVec3::new(0.8, 0.8, -0.3),
        DVec3::new(0.8, 0.8, 0.3),
        DVec3::new(-0.2, 0.8, 0.3),
    ];
    // The camera sees the light's (black) back where it hides the floor.
    let visible = |x: f64, z: f64| !((-0.2..=0.8).contains(&x) && (-0.3..=0.3).contains(&z));
    compare_to(&img, 0.03, 1e-3, &visible, &|x, z| rho / PI * polygon_irradiance(DVec3::new(x, 0.0, z), &verts, l));
}

#[test]
fn spherical_light_irradiance_is_pi_l_sin2_theta_cos_beta() {
    // A sphere light of radius r whose centre is at height d: entirely above the horizon of every floor point,
    // E = pi L (r / dist)^2 cos(beta).
    let (l, r, d) = (4.0, 0.3, 1.0);
    let scene = format!(
        "({TOP_CAMERA}, render: (integrator: phong(light_samples: 4)), materials: {{\"m\": Lambert(albedo: (1, 1, 1))}},
          entities: [(shape: Plane(), material: \"m\"), (shape: Sphere(center: (0, {d}, 0), radius: {r}), light: Area(radiance: ({l}, {l}, {l})))])"
    );
    let img = render_ron(&scene, spp(64));
    let visible = |x: f64, z: f64| x * x + z * z > r * r;
    compare_to(&img, 0.025, 1e-3, &visible, &|x, z| {
        let dist2 = x * x + z * z + d * d;
        1.0 / PI * PI * l * r * r / dist2 * (d / dist2.sqrt())
    });
}

#[test]
fn lambertian_floor_inside_a_uniformly_emitting_sphere_reflects_rho_l() {
    // The floor's whole upper hemisphere sees the sphere of radiance L: E = pi L, so L_out = rho L exactly.
    let scene = "(camera: (eye: (0, 0.5, 0), target: (0, 0, 0), up: (0, 0, -1), size: (16, 16)),
        render: (integrator: phong(light_samples: 4)),
        materials: {\"m\": Lambert(albedo: (0.6, 0.3, 0.9))},
        entities: [(shape: Quad(), material: \"m\", transform: [Rotate(axis: (1, 0, 0), degrees: -90)]),
                   (shape: Sphere(radius: 3), light: Area(radiance: (2, 2, 2), two_sided: true))])";
    let img = render_ron(scene, spp(64));
    let m = img.mean();
    let expect = Vec3::new(0.6, 0.3, 0.9) * 2.0;
    assert!((m - expect).abs().max_element() < 0.01 * expect.max_element(), "mean {m}, expected {expect}");
}

#[test]
fn emitters_seen_directly_return_their_radiance_on_the_front_side_only() {
    let front = "(camera: (eye: (0, 0, 3), size: (8, 8), fov: 10),
        entities: [(shape: Quad(), light: Area(radiance: (1, 2, 3)))])";
    let img = render_ron(front, spp(1));
    assert!(img.pixels.iter().all(|p| *p == Vec3::new(1.0, 2.0, 3.0)), "front: {:?}", img.pixels[0]);
    let back = "(camera: (eye: (0, 0, -3), size: (8, 8), fov: 10),
        entities: [(shape: Quad(), light: Area(radiance: (1, 2, 3)))])";
    assert!(render_ron(back, spp(1)).pixels.iter().all(|p| *p == Vec3::ZERO), "one-sided emitter seen from behind");
}

#[test]
fn a_mirror_reflects_an_emitter_scaled_by_its_reflectance() {
    // Camera looks down at 45 degrees onto a mirror floor; the reflected rays hit a large vertical emitter.
    let scene = "(camera: (eye: (0, 1, 1), target: (0, 0, 0), fov: 5, size: (8, 8)),
        materials: {\"mirror\": Mirror(reflectance: (0.9, 0.5, 0.25))},
        entities: [(shape: Quad(), material: \"mirror\", transform: [Rotate(axis: (1, 0, 0), degrees: -90)]),
                   (shape: Quad(), light: Area(radiance: (2, 2, 2)), transform: [Translate((0, 0, -3)), UniformScale(10)])])";
    let img = render_ron(scene, spp(1));
    for p in &img.pixels {
        assert!((*p - Vec3::new(1.8, 1.0, 0.5)).abs().max_element() < 1e-6, "{p}");
    }
}

#[test]
fn glass_sphere_in_a_uniform_background_conserves_energy() {
    // Fresnel reflection + refraction (with the 1/eta^2 radiance scaling that cancels for a closed object) of a
    // uniform background of radiance 1: every path ends in the background, so every pixel is 1.
    let scene = "(camera: (eye: (0, 0, 4), fov: 35, size: (24, 24)), background: (1, 1, 1),
        render: (integrator: phong(max_depth: 64)),
        materials: {\"glass\": Glass(ior: 1.5)},
        entities: [(shape: Sphere(), material: \"glass\")])";
    let img = render_ron(scene, spp(4));
    for p in &img.pixels {
        assert!((p.x - 1.0).abs() < 1e-3, "pixel {p}: energy not conserved");
    }
    assert!((img.mean().x - 1.0).abs() < 1e-4, "mean {}", img.mean().x);
}

#[test]
fn phong_material_at_the_mirror_direction_gives_kd_over_pi_plus_normalised_ks() {
    // Orthographic camera and directional light both straight down on a Phong plane: wi is the mirror direction
    // of wo, so f = kd/pi + ks (n + 2)/(2 pi), and L = f E. The ambient term adds ka * ambient.
    let (kd, ks, n, e, ka, amb) = (0.3, 0.2, 20.0, 2.0, 0.5, 0.1);
    let scene = format!(
        "({TOP_CAMERA}, ambient: ({amb}, {amb}, {amb}),
          materials: {{\"m\": Phong(ambient: ({ka}, {ka}, {ka}), diffuse: ({kd}, {kd}, {kd}), specular: ({ks}, {ks}, {ks}), exponent: {n})}},
          entities: [(shape: Plane(), material: \"m\"), (light: Directional(irradiance: ({e}, {e}, {e}), direction: (0, -1, 0)))])"
    );
    let img = render_ron(&scene, spp(1));
    let expect = (kd / PI + ks * (n + 2.0) / (2.0 * PI)) * e + ka * amb;
    for p in &img.pixels {
        assert!((p.x as f64 - expect).abs() < 1e-5 * expect, "{} vs {expect}", p.x);
    }
}

#[test]
fn rays_leaving_the_scene_see_the_environment_in_every_integrator() {
    // A camera in an empty scene sees the constant environment; a mirror facing the camera reflects it.
    for integrator in ["phong", "envlight"] {
        let scene = format!(
            "(camera: (size: (8, 8), fov: 20), render: (integrator: {integrator}), background: (9, 9, 9),
              materials: {{\"mirror\": Mirror(reflectance: (0.5, 0.5, 0.5))}},
              entities: [(light: Environment(radiance: (0.3, 0.5, 0.7))),
                         (shape: Quad(), material: \"mirror\", transform: [UniformScale(0.5)])])"
        );
        let img = render_ron(&scene, spp(1));
        let sky = Vec3::new(0.3, 0.5, 0.7);
        assert!((img.get(0, 0) - sky).abs().max_element() < 1e-6, "{integrator}: corner sees {}", img.get(0, 0));
        assert!((img.get(4, 4) - 0.5 * sky).abs().max_element() < 1e-6, "{integrator}: mirror shows {}", img.get(4, 4));
    }
}

/// The semicircle-like B-spline profile of `curves.rs` (radius 1 within 1e-9), as RON control points.
fn sphere_profile_ron(radius: f64) -> String {
    let n = 64;
    let phi = PI / n as f64;
    let rho = radius * 3.0 / (2.0 + phi.cos());
    let pts: Vec<String> = (-1..=n + 1)
        .map(|k| {
            let a = -PI / 2.0 + k as f64 * phi;
            format!("({}, {}, 0)", rho * a.cos(), rho * a.sin())
        })
        .collect();
    format!("BSpline([{}])", pts.join(", "))
}

#[test]
fn lambertian_floor_inside_an_emitting_surface_of_revolution_reflects_rho_l() {
    // A sphere-shaped surface of revolution whose profile runs from the south to the north pole faces inwards:
    // its front (emitting) side surrounds the floor, so E = pi L and L_out = rho L, as for the sphere light.
    let scene = format!(
        "(camera: (eye: (0, 0.5, 0), target: (0, 0, 0), up: (0, 0, -1), size: (16, 16)),
        render: (integrator: phong(light_samples: 4)),
        materials: {{\"m\": Lambert(albedo: (0.6, 0.3, 0.9))}},
        entities: [(shape: Quad(), material: \"m\", transform: [Rotate(axis: (1, 0, 0), degrees: -90)]),
                   (shape: Revolution(profile: {}), light: Area(radiance: (2, 2, 2)))])",
        sphere_profile_ron(3.0)
    );
    let img = render_ron(&scene, spp(64));
    let m = img.mean();
    let expect = Vec3::new(0.6, 0.3, 0.9) * 2.0;
    assert!((m - expect).abs().max_element() < 0.01 * expect.max_element(), "mean {m}, expected {expect}");
}

#[test]
fn a_flat_bezier_patch_light_matches_lamberts_polygon_formula() {
    // The rectangle of the quad-light test as a flat bicubic patch (control points on a regular grid, facing
    // down: S_u x S_v = x x z = -y), sampled through its parameter square.
    let (l, rho) = (5.0, 0.7);
    let pts: Vec<String> =
        (0..16).map(|k| format!("({}, 0.8, {})", -0.2 + (k % 4) as f64 / 3.0, -0.3 + 0.2 * (k / 4) as f64)).collect();
    let scene = format!(
        "({TOP_CAMERA}, render: (integrator: phong(light_samples: 16)), materials: {{\"m\": Lambert(albedo: ({rho}, {rho}, {rho}))}},
          entities: [(shape: Plane(), material: \"m\"),
                     (shape: BezierPatch(points: [{}]), light: Area(radiance: ({l}, {l}, {l})))])",
        pts.join(", ")
    );
    let img = render_ron(&scene, spp(64));
    let verts = [
        DVec3::new(-0.2, 0.8, -0.3),
        DVec3::new(0.8, 0.8, -0.3),
        DVec3::new(0.8, 0.8, 0.3),
        DVec3::new(-0.2, 0.8, 0.3),
    ];
    let visible = |x: f64, z: f64| !((-0.2..=0.8).contains(&x) && (-0.3..=0.3).contains(&z));
    compare_to(&img, 0.03, 1e-3, &visible, &|x, z| rho / PI * polygon_irradiance(DVec3::new(x, 0.0, z), &verts, l));
}
