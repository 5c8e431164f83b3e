//! Curved surfaces against ground truth: curve evaluation, derivatives and basis conversion against their
//! definitions; a straight profile parallel to the axis against the analytic cylinder and a semicircle-like
//! B-spline against the analytic sphere over 10^5 random rays each (distance and normal); tessellations lie on the
//! surface and wind about its normal; RON shapes, 6.837 spline files and scenes; every malformed spline file and
//! shape gives a one-line error.

use crate::common::{app_from_ron, data, prism, render_ron, scratch, spp};
use glam::{DAffine3, DVec3, Vec3A};
use prism::geometry::Ray;
use prism::primitives::{NO_LIGHT, to_f64};
use prism::sampling::{Rng, warp};
use prism::settings::Overrides;
use prism::shapes::curve::{bezier_to_bspline, bspline_to_bezier};
use prism::shapes::tessellate::{patch_tessellation, revolution_tessellation};
use prism::shapes::{AnalyticShape, Curve, CurveKind, Revolution};

fn curve(kind: CurveKind, pts: &[[f64; 3]]) -> Curve {
    Curve::new(kind, pts.iter().map(|p| DVec3::from_array(*p)).collect()).unwrap()
}

#[test]
fn curve_derivatives_match_finite_differences_and_bases_convert_exactly() {
    let b = curve(
        CurveKind::BSpline,
        &[[0., 0., 0.], [1., 2., 0.], [3., 3., 0.], [4., 0., 0.], [6., 1., 0.], [7., 3., 0.]],
    );
    assert_eq!(b.num_segments(), 3);
    for k in 1..60 {
        let s = k as f64 * 0.05;
        let h = 1e-6;
        let fd = (b.eval(s + h) - b.eval(s - h)) / (2.0 * h);
        assert!((fd - b.derivative(s)).length() < 1e-6, "derivative at {s}");
        let fd2 = (b.derivative(s + h) - b.derivative(s - h)) / (2.0 * h);
        if (s - s.round()).abs() > 1e-3 {
            assert!((fd2 - b.second_derivative(s)).length() < 1e-5, "second derivative at {s}");
        }
    }
    // A uniform B-spline is C2 across knots.
    for k in [1.0, 2.0] {
        assert!((b.eval(k - 1e-12) - b.eval(k + 1e-12)).length() < 1e-9);
        assert!((b.derivative(k - 1e-9) - b.derivative(k + 1e-9)).length() < 1e-6);
    }
    // Conversions round trip exactly and describe the same curve.
    let z = b.to_bezier();
    assert_eq!(z.points.len(), 10);
    let back = z.to_bspline().unwrap();
    for (p, q) in back.points.iter().zip(&b.points) {
        assert!((*p - *q).length() < 1e-12);
    }
    for k in 0..=30 {
        let s = k as f64 * 0.1;
        assert!((z.eval(s) - b.eval(s)).length() < 1e-12);
    }
    let seg = [DVec3::new(1., 2., 0.), DVec3::new(-1., 4., 0.), DVec3::new(3., 5., 0.), DVec3::new(2., 0., 0.)];
    let there = bspline_to_bezier(&bezier_to_bspline(&seg));
    assert!(there.iter().zip(&seg).all(|(a, b)| (*a - *b).length() < 1e-12));
    // Two Bézier pieces joined only with C0 have no B-spline form.
    let c0 = curve(
        CurveKind::Bezier,
        &[[0., 0., 0.], [1., 1., 0.], [2., 1., 0.], [3., 0., 0.], [3., 5., 0.], [4., 5., 0.], [5., 0., 0.]],
    );
    let err = c0.to_bspline().unwrap_err();
    assert!(err.contains("C2"), "{err}");
    // The course's tessellation counts: n segments per piece.
    assert_eq!(b.tessellate(10).len(), 31);
    assert_eq!(c0.tessellate(4).len(), 9);
}

#[test]
fn a_repeated_control_point_makes_a_b_spline_pass_through_it_with_zero_speed() {
    let c = curve(
        CurveKind::BSpline,
        &[[0., 0., 0.], [1., 1., 0.], [2., 2., 0.], [2., 2., 0.], [2., 2., 0.], [4., 0., 0.], [5., 1., 0.]],
    );
    // The knot between segments 1 and 2 sits at the triple point.
    assert!((c.eval(2.0) - DVec3::new(2., 2., 0.)).length() < 1e-12);
    assert!(c.derivative(2.0).length() < 1e-12);
}

/// Random rays around a box of half-size `r` centred at the origin: half aimed at random points inside it.
fn random_rays(n: usize, r: f32, seed: u64) -> Vec<Ray> {
    let mut rng = Rng::new(seed, 3);
    (0..n)
        .map(|i| {
            let o = warp::uniform_sphere(rng.next_2d()) * (3.0 * r);
            let d = if i % 2 == 0 {
                let target = (Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0) * r;
                (target - o).normalize()
            } else {
                warp::uniform_sphere(rng.next_2d())
            };
            Ray::new(o, d)
        })
        .collect()
}

/// Compare a revolution with an analytic answer `truth(o, d) -> Option<(t, normal)>` (object = world, f64):
/// returns (rays compared, hits, max distance error, max normal angle). Rays within `1e-4` of grazing or of the
/// surface's rim (`rim(p)`) are ties and left out.
fn compare_with_truth(
    shape: &Revolution,
    rays: &[Ray],
    truth: impl Fn(DVec3, DVec3) -> Option<(f64, DVec3)>,
    rim: impl Fn(DVec3) -> bool,
) -> (usize, usize, f64, f64) {
    let (mut n, mut hits, mut dist, mut angle) = (0, 0, 0.0f64, 0.0f64);
    for ray in rays {
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let expected = truth(o, d);
        let got = shape.intersect(ray);
        let tie = expected.is_some_and(|(t, nrm)| nrm.dot(d).abs() < 1e-4 || rim(o + d * t))
            || got.is_some_and(|h| {
                let q = shape.surface(ray, &h);
                q.n.dot(ray.dir).abs() < 1e-4 || rim(q.p.as_dvec3())
            });
        if tie {
            continue;
        }
        n += 1;
        match (got, expected) {
            (None, None) => {}
            (Some(h), Some((t, nrm))) => {
                hits += 1;
                dist = dist.max((h.t as f64 - t).abs());
                let q = shape.surface(ray, &h);
                // The angle between the normals, from the cross product (acos loses half the digits near 0).
                let n = q.n.as_dvec3().normalize();
                angle = angle.max(n.cross(nrm).length().atan2(n.dot(nrm)));
            }
            (g, e) => panic!("ray {ray:?}: exact {g:?}, analytic {e:?}"),
        }
    }
    (n, hits, dist, angle)
}

#[test]
fn a_straight_profile_parallel_to_the_axis_is_the_analytic_cylinder_over_100k_rays() {
    let profile = curve(CurveKind::Bezier, &[[1., -1., 0.], [1., -1. / 3., 0.], [1., 1. / 3., 0.], [1., 1., 0.]]);
    let shape = Revolution::new(profile, DAffine3::IDENTITY, 0, NO_LIGHT);
    let cylinder = |o: DVec3, d: DVec3| -> Option<(f64, DVec3)> {
        let (a, b, c) = (d.x * d.x + d.z * d.z, o.x * d.x + o.z * d.z, o.x * o.x + o.z * o.z - 1.0);
        let disc = b * b - a * c;
        if a == 0.0 || disc < 0.0 {
            return None;
        }
        let s = disc.sqrt();
        [(-b - s) / a, (-b + s) / a].into_iter().filter(|&t| t > 0.0).find_map(|t| {
            let p = o + d * t;
            // The profile runs upwards at x = 1: its left normal faces the axis.
            (p.y.abs() <= 1.0).then(|| (t, -DVec3::new(p.x, 0.0, p.z).normalize()))
        })
    };
    let rim = |p: DVec3| (p.y.abs() - 1.0).abs() < 1e-4;
    let rays = random_rays(100_000, 1.2, 5);
    let (n, hits, dist, angle) = compare_with_truth(&shape, &rays, cylinder, rim);
    eprintln!("cylinder: {n} rays, {hits} hits, max distance error {dist:.2e}, max normal error {angle:.2e} rad");
    assert!(hits > 30_000, "{hits} hits: a weak test");
    assert!(dist < 1e-5, "distance error {dist}");
    assert!(angle < 1e-5, "normal error {angle}");
}

#[test]
fn a_semicircle_like_b_spline_profile_is_the_analytic_sphere_over_100k_rays() {
    // Control points on a circle of radius rho at angles -pi/2 + k phi (one beyond each pole, mirrored through
    // the axis): the uniform B-spline passes through radius rho (2 + cos phi) / 3 = 1 at its knots, the poles
    // included, and stays within 1e-9 of the unit circle between them (256 pieces).
    let n = 256;
    let phi = std::f64::consts::PI / n as f64;
    let rho = 3.0 / (2.0 + phi.cos());
    let pts: Vec<[f64; 3]> = (-1..=n + 1)
        .map(|k| {
            let a = -std::f64::consts::FRAC_PI_2 + k as f64 * phi;
            [rho * a.cos(), rho * a.sin(), 0.0]
        })
        .collect();
    let profile = curve(CurveKind::BSpline, &pts);
    let deviation = (0..=100_000)
        .map(|k| (profile.eval(profile.num_segments() as f64 * k as f64 / 100_000.0).length() - 1.0).abs())
        .fold(0.0, f64::max);
    eprintln!("the profile is within {deviation:.1e} of the unit circle");
    assert!(deviation < 1e-9, "the profile is {deviation} from the unit circle");
    // Under a similarity transform the sphere stays a sphere: radius 2 at (1, 2, 3).
    let m = glam::Affine3A::from_scale_rotation_translation(
        glam::Vec3::splat(2.0),
        glam::Quat::from_axis_angle(glam::Vec3::new(1.0, 2.0, 0.5).normalize(), 0.7),
        glam::Vec3::new(1.0, 2.0, 3.0),
    );
    let shape = Revolution::new(profile, to_f64(&m), 0, NO_LIGHT);
    let c = DVec3::new(1.0, 2.0, 3.0);
    let sphere = |o: DVec3, d: DVec3| -> Option<(f64, DVec3)> {
        let f = o - c;
        let (a, b, cc) = (d.dot(d), f.dot(d), f.dot(f) - 4.0);
        let disc = b * b - a * cc;
        if disc < 0.0 {
            return None;
        }
        let s = disc.sqrt();
        // The profile runs from the south pole to the north pole on the +x side: its left normal faces the centre.
        [(-b - s) / a, (-b + s) / a].into_iter().find(|&t| t > 0.0).map(|t| (t, -(o + d * t - c).normalize()))
    };
    let rays: Vec<Ray> = random_rays(100_000, 2.4, 9)
        .into_iter()
        .map(|r| Ray::new(r.origin + Vec3A::new(1.0, 2.0, 3.0), r.dir))
        .collect();
    let (n, hits, dist, angle) = compare_with_truth(&shape, &rays, sphere, |_| false);
    eprintln!("sphere: {n} rays, {hits} hits, max distance error {dist:.2e}, max normal error {angle:.2e} rad");
    assert!(hits > 30_000, "{hits} hits: a weak test");
    assert!(dist < 1e-5, "distance error {dist}");
    assert!(angle < 1e-4, "normal error {angle}");
}

#[test]
fn tessellations_lie_on_the_surface_and_wind_about_its_normal() {
    let dir = data("mit6837/assignment8");
    let items = prism::load::mit6837::spline::parse_spline_file(&dir.join("spline8_09_teapot.txt")).unwrap();
    use prism::load::mit6837::spline::SplineTxt;
    for item in &items {
        let mesh = match item {
            SplineTxt::Revolution { profile, .. } => {
                let m = revolution_tessellation(profile, 8, 24).unwrap();
                // Vertices: (pieces * 8 + 1) rows of 25 (the seam duplicated).
                assert_eq!(m.positions.len(), (profile.num_segments() * 8 + 1) * 25);
                m
            }
            SplineTxt::Patch { points, .. } => {
                let m = patch_tessellation(points, 6).unwrap();
                assert_eq!(m.positions.len(), 49);
                assert_eq!(m.indices.len(), 72);
                m
            }
            SplineTxt::Curve { .. } => continue,
        };
        assert_eq!(mesh.normals.len(), mesh.positions.len());
        assert_eq!(mesh.uvs.len(), mesh.positions.len());
        // Counter-clockwise about the vertex normals.
        let mut agree = 0;
        for t in &mesh.indices {
            let p = t.map(|i| mesh.positions[i as usize]);
            let ng = (p[1] - p[0]).cross(p[2] - p[0]);
            let ns = mesh.normals[t[0] as usize] + mesh.normals[t[1] as usize] + mesh.normals[t[2] as usize];
            if ng.dot(ns) > 0.0 {
                agree += 1;
            }
        }
        assert!(
            agree * 100 >= mesh.indices.len() * 99,
            "{agree} of {} triangles wind about the normal",
            mesh.indices.len()
        );
    }
    // Revolution vertices are exact surface points: at the profile's tessellation, revolved.
    let (_, profile) = crate::curve_stability::profiles().remove(0);
    let m = revolution_tessellation(&profile, 5, 12).unwrap();
    for (k, p) in profile.tessellate(5).iter().enumerate() {
        let v = m.positions[k * 13 + 3].as_dvec3();
        let a = std::f64::consts::TAU * 3.0 / 12.0;
        assert!((v - DVec3::new(p.x * a.cos(), p.y, p.x * a.sin())).length() < 1e-5);
    }
}

#[test]
fn bad_tessellation_resolutions_are_one_line_errors() {
    let (_, profile) = crate::curve_stability::profiles().remove(0);
    for (c, r) in [(0, 10), (10, 0), (1_000_000, 10), (60_000, 60_000)] {
        let e = revolution_tessellation(&profile, c, r).unwrap_err();
        assert!(
            !e.contains('\n') && (e.contains("at least 1") || e.contains("absurd") || e.contains("more than")),
            "{e}"
        );
    }
    let pts = [DVec3::ZERO; 16];
    assert!(patch_tessellation(&pts, 0).unwrap_err().contains("at least 1"));
    assert!(patch_tessellation(&pts, 200_000).unwrap_err().contains("absurd"));
}

/// The vase, torus and a patch as RON, exact and tessellated, rendered small.
fn curved_scene(tess: &str) -> String {
    format!(
        r#"(camera: (eye: (0, 6, 12), target: (0, 0, 0), fov: 45, size: (48, 48)),
        render: (integrator: phong, spp: 1),
        materials: {{"red": Lambert(albedo: (0.8, 0.1, 0.1))}},
        entities: [
            (light: Directional(irradiance: (3, 3, 3), direction: (-0.2, -1, -0.5))),
            (material: "red", transform: [Translate((-3, 0, 0)), Scale((1, 0.8, 1))],
             shape: Revolution(profile: BSpline([(0, -3, 0), (0, -3, 0), (0, -3, 0), (1.5, -3, 0), (2.5, 4, 0),
                 (3, 4, 0), (2, -4, 0), (0, -4, 0), (0, -4, 0), (0, -4, 0)]), tessellation: {tess})),
            (material: "red", transform: [Translate((3, 0, 0))],
             shape: Splines(path: "{}", tessellation: {tess})),
        ])"#,
        data("mit6837/assignment8/spline8_09_teapot.txt").display()
    )
}

#[test]
fn exact_surfaces_and_fine_tessellations_render_the_same_image() {
    let exact = render_ron(&curved_scene("None"), spp(1));
    let fine = render_ron(&curved_scene("Some((curve: 40, revolution: 160, patch: 40))"), spp(1));
    let coarse = render_ron(&curved_scene("Some((curve: 2, revolution: 6, patch: 2))"), spp(1));
    let e_fine = prism::compare::compare(&fine, &exact).unwrap().rmse;
    let e_coarse = prism::compare::compare(&coarse, &exact).unwrap().rmse;
    eprintln!("RMSE vs exact: fine {e_fine:.4}, coarse {e_coarse:.4}");
    assert!(exact.pixels.iter().any(|v| v.x > 0.1), "the exact render is black");
    assert!(e_fine < 0.25 * e_coarse, "fine tessellation {e_fine} vs coarse {e_coarse}");
}

#[test]
fn curved_shapes_in_ron_reject_bad_control_points_with_the_entity_named() {
    let cases = [
        ("Revolution(profile: Bezier([(1, 0, 0), (1, 1, 0), (1, 2, 0)]))", "3k + 1"),
        ("Revolution(profile: BSpline([(1, 0, 0), (1, 1, 0), (1, 2, 0)]))", "at least 4"),
        ("Revolution(profile: BSpline([(1, 0, 0), (1, 1, 0.5), (1, 2, 0), (1, 3, 0)]))", "leaves the xy-plane"),
        (
            "Revolution(profile: BSpline([(1, 0, 0), (1, 1, 0), (1, 2, 0), (1, 3, 0)]), tessellation: Some((curve: 0)))",
            "at least 1",
        ),
        ("BezierPatch(points: [(0, 0, 0), (1, 0, 0)])", "16 control points"),
        ("Splines(path: \"no/such/spline.txt\")", "not found"),
    ];
    for (shape, expected) in cases {
        let text = format!("(camera: (), entities: [(name: \"thing\", shape: {shape})])");
        let err = app_from_ron(&text, Overrides::default()).run().err().map(|e| e.to_string()).unwrap_or_default();
        assert!(err.contains(expected) && err.contains("thing") && !err.contains('\n'), "{shape}: {err}");
    }
    // NaN cannot be written in RON as a number, but an infinity can.
    let text = "(camera: (), entities: [(name: \"thing\", shape: Revolution(profile: BSpline([(1, 0, 0), (1, 1, 0), (inf, 2, 0), (1, 3, 0)])))])";
    let err = app_from_ron(text, Overrides::default()).run().unwrap_err().to_string();
    assert!(err.contains("not finite"), "{err}");
}

/// Every malformed spline file: one line with the file and the line number.
#[test]
fn malformed_spline_files_are_one_line_errors_with_file_and_line() {
    use prism::load::mit6837::spline::parse_splines;
    let cases: &[(&str, &str, usize)] = &[
        ("num_splines 2\nbezier\nnum_vertices 4\n0 0 0\n1 1 0\n2 1 0\n3 0 0\n", "num_splines 2", 7),
        ("num_splines 1\nbezier\nnum_vertices 5\n0 0 0\n1 1 0\n2 1 0\n3 0 0\n", "end of file", 7),
        ("num_splines 1\nbezier\nnum_vertices 3\n0 0 0\n1 1 0\n2 1 0\n", "3k + 1", 2),
        ("num_splines 1\nbspline\nnum_vertices 2\n0 0 0\n1 1 0\n", "at least 4", 2),
        ("num_splines 1\nbspline\nnum_vertices 4\n0 0 0\n1 nan 0\n2 1 0\n3 0 0\n", "not finite", 5),
        ("num_splines 1\nbspline\nnum_vertices 4\n0 0 0\n1 x 0\n2 1 0\n3 0 0\n", "expected a coordinate", 5),
        (
            "num_splines 1\nsurface_of_revolution\nbspline\nnum_vertices 4\n0 0 0\n1 1 0.5\n2 1 0\n3 0 0\n",
            "leaves the xy-plane",
            6,
        ),
        ("num_splines 1\nbspline\nnum_vertices 4\n0 0 0\n1 1 0\n2 1 0\n3 0 0\n4 4 0\n", "more control points", 8),
        ("num_splines 1\nbezier_patch\n0 0 0\n1 0 0\n", "end of file", 4),
        ("num_splines 1\nbezier_patch\n0 0 0\n1 0 0\nbezier\n", "16 control points", 5),
        ("num_splines 1\ncircle\n", "unknown spline", 2),
        ("num_splines x\n", "non-negative integer", 1),
        ("num_splines 1\nbspline\nnum_vertices 99999999999\n", "absurd", 2),
        ("", "end of file", 1),
    ];
    for (text, expected, line) in cases {
        let err = parse_splines(text, std::path::Path::new("bad.txt")).unwrap_err().to_string();
        assert!(
            err.contains(expected) && err.starts_with(&format!("bad.txt:{line}:")) && !err.contains('\n'),
            "{text:?}: {err}"
        );
    }
}

#[test]
fn the_course_spline_files_parse_and_convert_between_bases_as_the_curve_editor_does() {
    use prism::load::mit6837::spline::{SplineTxt, parse_spline_file, write_splines};
    let dir = data("mit6837/assignment8");
    let counts = [(1, 2), (2, 2), (3, 1), (4, 1), (5, 1), (6, 1), (7, 1), (8, 1), (9, 10)];
    for (i, n) in counts {
        let name = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().to_string())
            .find(|f| f.starts_with(&format!("spline8_0{i}")))
            .unwrap();
        let items = parse_spline_file(&dir.join(&name)).unwrap();
        assert_eq!(items.len(), n, "{name}");
        // -output_bezier then reading back gives the same curves.
        let text = write_splines(&items, CurveKind::Bezier).unwrap();
        let again = prism::load::mit6837::spline::parse_splines(&text, std::path::Path::new("x.txt")).unwrap();
        for (a, b) in items.iter().zip(&again) {
            if let (SplineTxt::Curve { curve: a, .. }, SplineTxt::Curve { curve: b, .. }) = (a, b) {
                for k in 0..=20 {
                    let s = a.num_segments() as f64 * k as f64 / 20.0;
                    assert!((a.eval(s) - b.eval(s)).length() < 1e-9, "{name}");
                }
            }
        }
    }
    // spline8_01 (Bézier) as a B-spline: 4 points each, the same curves.
    let items = parse_spline_file(&dir.join("spline8_01_bezier.txt")).unwrap();
    let text = write_splines(&items, CurveKind::BSpline).unwrap();
    assert_eq!(text.matches("bspline").count(), 2);
}

#[test]
fn prism_tessellate_writes_the_meshes_the_assignment_8_scenes_name() {
    let dir = scratch("tessellate");
    let spline = data("mit6837/assignment8/spline8_06_torus.txt");
    let out = dir.join("torus_high.obj");
    let o = prism(&[
        "tessellate",
        spline.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--curve",
        "30",
        "--revolution",
        "60",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let parts = prism::load::load_obj(&out).unwrap();
    let tris: usize = parts.iter().map(|p| p.mesh.indices.len()).sum();
    assert_eq!(tris, 2 * 60 * 60, "2 pieces x 30 segments x 60 steps x 2 triangles");
    // The course's own command line does the same.
    let out2 = dir.join("torus_low.obj");
    let o = prism(&[
        "curve_editor",
        "-input",
        spline.to_str().unwrap(),
        "-curve_tessellation",
        "4",
        "-revolution_tessellation",
        "10",
        "-output",
        out2.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let tris: usize = prism::load::load_obj(&out2).unwrap().iter().map(|p| p.mesh.indices.len()).sum();
    assert_eq!(tris, 2 * 8 * 10);
    // Bad resolutions and files are one-line errors.
    for args in [
        vec!["tessellate", spline.to_str().unwrap(), "-o", out.to_str().unwrap(), "--curve", "0"],
        vec!["tessellate", "no_such_spline.txt", "-o", out.to_str().unwrap()],
    ] {
        let o = prism(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.trim().lines().count() == 1, "{args:?}: {err}");
    }
}

#[test]
fn every_assignment_8_scene_renders_with_its_course_mesh_and_with_exact_surfaces() {
    let dir = data("mit6837/assignment8");
    let mut scenes: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.file_name().unwrap().to_string_lossy().starts_with("scene8_"))
        .collect();
    scenes.sort();
    assert_eq!(scenes.len(), 11);
    for path in scenes {
        for exact in [false, true] {
            let o = Overrides { size: Some((32, 32)), spp: Some(1), exact_curves: exact, ..Default::default() };
            let img = crate::common::render_file(&path, o);
            // The course's background is (0.2, 0, 0.6): count the pixels showing something else.
            let background = glam::Vec3::new(0.2, 0.0, 0.6);
            let object = img.pixels.iter().filter(|p| (**p - background).abs().max_element() > 0.1).count();
            assert!(object > 100, "{} (exact: {exact}): {object} object pixels", path.display());
        }
    }
}

#[test]
fn curved_area_lights_sample_by_area_with_the_pdf_a_ray_hitting_the_sample_reports() {
    // The teapot's body, lid and a spout patch as emitters seen from outside.
    let text = format!(
        "(camera: (), entities: [(shape: Splines(path: \"{}\"), light: Area(radiance: (1, 1, 1), two_sided: true))])",
        data("mit6837/assignment8/spline8_09_teapot.txt").display()
    );
    let mut app = app_from_ron(&text, Overrides::default());
    app.setup().unwrap();
    let scene = app.resources.scene.as_ref().unwrap();
    assert_eq!(scene.lights.lights.len(), 10);
    let p = Vec3A::new(0.5, 5.0, 6.0);
    let mut rng = Rng::new(3, 1);
    for (slot, light) in scene.lights.lights.iter().enumerate() {
        let prism::lights::LightSource::Area(a) = light else { panic!("an area light") };
        let (mut inv_pdf_area, mut n) = (0.0f64, 0);
        let mut checked = 0;
        for _ in 0..4000 {
            let Some(ls) = a.sample(&scene.prims, p, rng.next_2d()) else { continue };
            // Convert back to area measure: the Monte Carlo mean of 1 / pdf_area is the area.
            let cos = ls.wi.dot(ls.n).abs() as f64;
            inv_pdf_area += (ls.dist as f64).powi(2) / (ls.pdf as f64 * cos);
            n += 1;
            // The ray towards the sample hits the light there, and the light's pdf for that hit is the sample's
            // within 1% (away from grazing views, where the pdf's 1 / cos magnifies the hit's rounding).
            let ray = Ray::with_tmax(p, ls.wi, ls.dist * 1.001);
            if cos > 0.05
                && let Some(hit) = scene.trace(&ray)
                && hit.light as usize == slot
                && (hit.p - ls.p).length() < 1e-4
            {
                let pdf = a.pdf(&scene.prims, p, &hit);
                assert!(
                    (pdf - ls.pdf).abs() <= 1e-2 * ls.pdf,
                    "pdf {pdf} at the hit, {} sampled (slot {slot}, hit {hit:?}, sample {ls:?})",
                    ls.pdf
                );
                checked += 1;
            }
        }
        assert!(checked > 100, "only {checked} samples visible");
        let area = inv_pdf_area / 4000.0;
        let expected = a.area(&scene.prims) as f64;
        assert!(
            (area - expected).abs() < 0.05 * expected,
            "Monte Carlo area {area}, quadrature {expected} ({n} samples)"
        );
    }
}

#[test]
fn prism_convert_writes_assignment_8_meshes_as_spline_shapes_tessellated_or_exact() {
    let dir = scratch("convert8");
    let scene = data("mit6837/assignment8/scene8_09_teapot_high.txt");
    for (exact, expect) in [(false, "Some((curve: 30, revolution: 100, patch: 30))"), (true, "tessellation: None")] {
        let out = dir.join(format!("teapot_{exact}.ron"));
        let mut args = vec!["convert", scene.to_str().unwrap(), "-o", out.to_str().unwrap()];
        if exact {
            args.push("--exact-curves");
        }
        let o = prism(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let text = std::fs::read_to_string(&out).unwrap();
        assert!(text.contains("Splines(path:") && text.contains(expect), "{text}");
        // The written scene loads (the spline path is relative to it).
        let mut app = crate::common::app_from_file(&out, Overrides { size: Some((8, 8)), ..Default::default() });
        app.setup().unwrap();
        let prims = &app.resources.scene.as_ref().unwrap().prims;
        if exact {
            assert_eq!((prims.revolutions.len(), prims.patches.len(), prims.num_tris()), (2, 8, 0));
        } else {
            assert!(prims.num_tris() > 10_000 && prims.analytic.is_empty());
        }
    }
}

#[test]
fn degenerate_and_extreme_curved_shapes_render_without_panics() {
    let cases = [
        // A profile collapsed to a point, one lying on the axis (zero area), a flat disc, a huge and a tiny vase.
        "Revolution(profile: BSpline([(1, 1, 0), (1, 1, 0), (1, 1, 0), (1, 1, 0)]))",
        "Revolution(profile: Bezier([(0, -1, 0), (0, 0, 0), (0, 0.5, 0), (0, 1, 0)]))",
        "Revolution(profile: Bezier([(0, 0, 0), (0.3, 0, 0), (0.6, 0, 0), (1, 0, 0)]))",
        "Revolution(profile: BSpline([(0, -3e17, 0), (1.5e17, -3e17, 0), (2.5e17, 4e17, 0), (2e17, -4e17, 0)]))",
        "Revolution(profile: BSpline([(0, -3e-20, 0), (1.5e-20, -3e-20, 0), (2.5e-20, 4e-20, 0), (2e-20, -4e-20, 0)]))",
        // A patch collapsed to a point, and one collapsed to a line.
        "BezierPatch(points: [(1,1,1),(1,1,1),(1,1,1),(1,1,1),(1,1,1),(1,1,1),(1,1,1),(1,1,1),(1,1,1),(1,1,1),(1,1,1),(1,1,1),(1,1,1),(1,1,1),(1,1,1),(1,1,1)])",
        "BezierPatch(points: [(0,0,0),(1,0,0),(2,0,0),(3,0,0),(0,0,0),(1,0,0),(2,0,0),(3,0,0),(0,0,0),(1,0,0),(2,0,0),(3,0,0),(0,0,0),(1,0,0),(2,0,0),(3,0,0)])",
    ];
    for shape in cases {
        for accel in ["bvh", "kdtree", "grid", "brute"] {
            let text = format!(
                "(camera: (eye: (0, 1, 6), size: (12, 12)), render: (accel: {accel}, spp: 1, integrator: envlight(max_depth: 3)),
                  entities: [(shape: {shape}), (light: Environment(radiance: (1, 1, 1)))])"
            );
            let img = render_ron(&text, spp(1));
            assert!(img.pixels.iter().all(|p| p.is_finite()), "{shape} with {accel}");
        }
    }
}

/// Beyond the world-coordinate limit (`docs/guide/reliability.md`: products of coordinates must stay finite in f32) a
/// curved shape is refused by name, as spheres and triangles are, instead of failing later in some other guise.
#[test]
fn curved_shapes_beyond_the_coordinate_limit_are_errors_naming_them() {
    for (shape, what) in [
        (
            "Revolution(profile: BSpline([(0, -3e20, 0), (1.5e20, -3e20, 0), (2.5e20, 4e20, 0), (2e20, -4e20, 0)]))",
            "surface of revolution",
        ),
        (
            "BezierPatch(points: [(0,0,0),(1,0,0),(2,0,0),(3e20,0,0),(0,1,0),(1,1,0),(2,1,0),(3,1,0),(0,2,0),(1,2,0),(2,2,0),(3,2,0),(0,3,0),(1,3,0),(2,3,0),(3,3,0)])",
            "Bézier patch",
        ),
    ] {
        let text = format!(
            "(camera: (eye: (0, 1, 6), size: (12, 12)), entities: [(name: \"far\", shape: {shape}), (light: Environment())])"
        );
        let err = crate::common::app_from_ron(&text, spp(1)).run().unwrap_err().to_string();
        assert!(err.contains("far") && err.contains(what) && err.contains("limit"), "{err}");
    }
}
