//! 6.837 scene files: every assignment 1-5 scene renders; converting to RON and loading that gives the same
//! scene; the course's conventions come out as the course's formulas (diffuse `kd c cos`, ambient `ka kd`,
//! Blinn-Phong specular, point-light attenuation, refraction without Fresnel, flat colours without lights,
//! orthographic rays from behind the camera); transforms and `MaterialIndex` compose as in the course parser;
//! malformed files give one-line `file:line:col` errors, never a panic; course command lines run. Assignments 6
//! and 7 (solid textures, TGA output): `tests/mit6837_solid.rs`.

use crate::common::{app_from_file, data, prism, render_file, scratch};
use glam::{Vec3, Vec3A};
use prism::settings::Overrides;
use std::path::{Path, PathBuf};

/// Every `.txt` scene of assignments `from..=to`.
pub fn scenes(from: u32, to: u32) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for a in from..=to {
        let dir = data(&format!("mit6837/assignment{a}"));
        let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "txt") && p.file_name().unwrap() != "parse_code.txt")
            .collect();
        v.sort();
        out.extend(v);
    }
    out
}

fn small(spp: u32) -> Overrides {
    Overrides { size: Some((64, 64)), spp: Some(spp), ..Default::default() }
}

#[test]
fn every_assignment_1_to_5_scene_renders_at_64x64() {
    let all = scenes(1, 5);
    assert_eq!(all.len(), 7 + 16 + 12 + 14 + 12, "scene count");
    for path in all {
        let img = render_file(&path, small(1));
        assert_eq!((img.width, img.height), (64, 64));
        assert!(img.pixels.iter().all(|p| p.is_finite()), "{}", path.display());
        // Something other than the background is visible.
        let first = img.pixels[0];
        assert!(img.pixels.iter().any(|p| (*p - first).abs().max_element() > 1e-3), "{} is flat", path.display());
    }
}

fn scene_of(path: &Path) -> prism::App {
    let mut app = app_from_file(path, Overrides::default());
    app.setup().unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    app
}

#[test]
fn converting_to_ron_then_loading_gives_the_same_primitives_lights_and_camera() {
    let dir = scratch("convert");
    for path in scenes(1, 5) {
        let out = dir.join(path.with_extension("ron").file_name().unwrap());
        let o = prism(&["convert", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        assert!(o.status.success(), "{}: {}", path.display(), String::from_utf8_lossy(&o.stderr));
        let (a, b) = (scene_of(&path), scene_of(&out));
        let (sa, sb) = (a.resources.scene.as_ref().unwrap(), b.resources.scene.as_ref().unwrap());
        let name = path.display();
        assert_eq!(sa.prims.tris, sb.prims.tris, "{name}: triangles");
        assert_eq!(sa.prims.spheres.len(), sb.prims.spheres.len(), "{name}: spheres");
        for (x, y) in sa.prims.spheres.iter().zip(&sb.prims.spheres) {
            assert_eq!((x.center, x.radius, x.material), (y.center, y.radius, y.material), "{name}: sphere");
        }
        assert_eq!(sa.prims.planes.len(), sb.prims.planes.len(), "{name}: planes");
        assert_eq!(sa.materials, sb.materials, "{name}: materials");
        assert_eq!(format!("{:?}", sa.lights), format!("{:?}", sb.lights), "{name}: lights");
        assert_eq!(format!("{:?}", sa.camera), format!("{:?}", sb.camera), "{name}: camera");
        assert_eq!(sa.globals, sb.globals, "{name}: background and ambient");
    }
    // Wrong extensions are one-line errors.
    let txt = scenes(1, 1)[0].clone();
    for (input, output, needle) in
        [(txt.to_str().unwrap(), "out.obj", "must be a .ron"), ("scene.ron", "out.ron", "expected a 6.837 scene")]
    {
        let o = prism(&["convert", input, "-o", dir.join(output).to_str().unwrap()]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.starts_with("error:") && err.contains(needle), "{err}");
    }
}

/// Write a 6.837 scene into a scratch folder (with a one-triangle `tri.obj` beside it).
fn write_txt(name: &str, text: &str) -> PathBuf {
    // One folder per file name: tests run in parallel and rewrite their own files only.
    let dir = scratch(&format!("txt-{}", name.trim_end_matches(".txt")));
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// Radiance at the centre pixel of a small render (1 sample; the centre pixel of a 5x5 image sees the axis).
fn centre_radiance(path: &Path, integrator: &str) -> Vec3 {
    let mut app = app_from_file(
        path,
        Overrides { size: Some((5, 5)), spp: Some(1), integrator: Some(integrator.into()), ..Default::default() },
    );
    app.run().unwrap_or_else(|e| panic!("{e}"));
    let f = app.resources.film.as_ref().unwrap();
    f.pixel(2, 2)
}

/// A big square facing +z at z = 0 seen head-on from z = 10 by an orthographic camera.
fn square_scene(lights: &str, material: &str, background: &str) -> String {
    format!(
        "OrthographicCamera {{ center 0 0 10 direction 0 0 -1 up 0 1 0 size 1 }}
         {lights}
         Background {{ {background} }}
         Materials {{ numMaterials 1 {material} }}
         Group {{ numObjects 2
           MaterialIndex 0
           Triangle {{ vertex0 -9 -9 0 vertex1 9 -9 0 vertex2 9 9 0 }}
           Triangle {{ vertex0 -9 -9 0 vertex1 9 9 0 vertex2 -9 9 0 }}
         }}"
    )
}

#[test]
fn course_shading_formulas_come_out_exactly() {
    let rel = |a: Vec3, b: Vec3| ((a - b).abs() / b.abs().max(Vec3::splat(1e-6))).max_element();
    // Diffuse: kd * c * cos, plus ambient * kd.
    // The light travels along (0, -0.6, -0.8): cos = 0.8 on the square facing +z.
    let cos = 0.8;
    let p = write_txt(
        "diffuse.txt",
        &square_scene(
            "Lights { numLights 1 DirectionalLight { direction 0 -0.6 -0.8 color 0.9 0.5 0.25 } }",
            "Material { diffuseColor 0.5 0.4 1 }",
            "color 0 0 0 ambientLight 0.1 0.2 0.3",
        ),
    );
    let got = centre_radiance(&p, "phong");
    let want = Vec3::new(0.5, 0.4, 1.0) * Vec3::new(0.9, 0.5, 0.25) * cos
        + Vec3::new(0.1, 0.2, 0.3) * Vec3::new(0.5, 0.4, 1.0);
    assert!(rel(got, want) < 1e-4, "diffuse + ambient: {got} vs {want}");
    // Blinn-Phong specular: ks (n.h)^e c (viewer along +z, light from direction (0, 0.6, 0.8)).
    let p = write_txt(
        "specular.txt",
        &square_scene(
            "Lights { numLights 1 DirectionalLight { direction 0 -0.6 -0.8 color 1 1 1 } }",
            "PhongMaterial { diffuseColor 0 0 0 specularColor 0.5 0.5 0.5 exponent 8 }",
            "color 0 0 0",
        ),
    );
    let h = (Vec3::Z + Vec3::new(0.0, 0.6, 0.8)).normalize();
    let want = Vec3::splat(0.5 * h.z.powf(8.0));
    let got = centre_radiance(&p, "phong");
    assert!(rel(got, want) < 1e-4, "specular: {got} vs {want}");
    // Point light attenuation: c / (a0 + a1 d + a2 d^2) * kd * cos, light on the axis at distance 2.
    let p = write_txt(
        "point.txt",
        &square_scene(
            "Lights { numLights 1 PointLight { position 0 0 2 color 1 1 1 attenuation 0.5 0.25 0.125 } }",
            "Material { diffuseColor 1 1 1 }",
            "color 0 0 0",
        ),
    );
    let want = Vec3::splat(1.0 / (0.5 + 0.25 * 2.0 + 0.125 * 4.0));
    let got = centre_radiance(&p, "phong");
    assert!(rel(got, want) < 1e-3, "point light: {got} vs {want}");
    // Without lights the ambient light is white: flat diffuse colours.
    let p = write_txt("flat.txt", &square_scene("", "Material { diffuseColor 0.3 0.6 0.9 }", "color 0 0 0"));
    let got = centre_radiance(&p, "phong");
    assert!(rel(got, Vec3::new(0.3, 0.6, 0.9)) < 1e-5, "flat: {got}");
}

#[test]
fn refraction_has_no_fresnel_and_orthographic_rays_start_behind_the_camera() {
    // A transparent sphere (ior 1.5) around the camera's centre, seen head-on: the background through it is
    // weighted by the transparent colour once per interface only (no Fresnel loss, no 1/eta^2 scaling).
    let dir = scratch("refract");
    let p = dir.join("glass.txt");
    std::fs::write(
        &p,
        "OrthographicCamera { center 0 0 0 direction 0 0 -1 up 0 1 0 size 0.01 }
         Background { color 0.8 0.6 0.4 }
         Materials { numMaterials 1
           PhongMaterial { diffuseColor 0 0 0 transparentColor 0.5 0.25 1 indexOfRefraction 1.5 } }
         Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1 } }",
    )
    .unwrap();
    // The camera centre is inside the sphere: the course's orthographic rays start at -inf, so they enter and
    // leave the sphere (two interfaces, both head-on).
    let got = centre_radiance(&p, "phong(max_depth: 4, shade_back: true)");
    let want = Vec3::new(0.8, 0.6, 0.4) * Vec3::new(0.5, 0.25, 1.0) * Vec3::new(0.5, 0.25, 1.0);
    assert!((got - want).abs().max_element() < 1e-4, "{got} vs {want}");
}

#[test]
fn transforms_nest_and_material_index_applies_in_file_order() {
    let p = write_txt(
        "nest.txt",
        "PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 angle 30 }
         Materials { numMaterials 3 Material { diffuseColor 1 0 0 } Material { diffuseColor 0 1 0 }
                     PhongMaterial { diffuseColor 0 0 1 } }
         Group { numObjects 3
           MaterialIndex 1
           Transform { Translate 1 2 3 Scale 2 2 2
             Group { numObjects 1
               Transform { ZRotate 90 MaterialIndex 2 TriangleMesh { obj_file tri.obj } } } }
           Triangle { vertex0 0 0 0 vertex1 1 0 0 vertex2 0 1 0 }
           Transform { Translate 5 0 0 Matrix { 1 0 0 10  0 1 0 20  0 0 1 30  0 0 0 1 } UniformScale 3
             Triangle { vertex0 0 0 0 vertex1 1 0 0 vertex2 0 1 0 } }
         }",
    );
    let err = {
        let mut app = app_from_file(&p, Overrides::default());
        app.setup().err().map(|e| e.to_string())
    };
    // `MaterialIndex` is not an object: inside a Transform it is an error (the course parser would read it as one).
    assert!(err.as_deref().is_some_and(|e| e.contains("nest.txt:8:") && e.contains("MaterialIndex")), "{err:?}");
    let p = write_txt(
        "nest.txt",
        "PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 angle 30 }
         Materials { numMaterials 3 Material { diffuseColor 1 0 0 } Material { diffuseColor 0 1 0 }
                     PhongMaterial { diffuseColor 0 0 1 } }
         Group { numObjects 3
           MaterialIndex 1
           Transform { Translate 1 2 3 Scale 2 2 2
             Group { numObjects 1
               MaterialIndex 2
               Transform { ZRotate 90 TriangleMesh { obj_file tri.obj } } } }
           Triangle { vertex0 0 0 0 vertex1 1 0 0 vertex2 0 1 0 }
           Transform { Translate 5 0 0 Matrix { 1 0 0 10  0 1 0 20  0 0 1 30  0 0 0 1 } UniformScale 3
             Triangle { vertex0 0 0 0 vertex1 1 0 0 vertex2 0 1 0 } }
         }",
    );
    let app = scene_of(&p);
    let s = app.resources.scene.as_ref().unwrap();
    let close = |a: Vec3A, b: [f32; 3]| (a - Vec3A::from(b)).abs().max_element() < 1e-5;
    // Mesh: p -> T(1,2,3) S(2) Rz(90) p: (1,0,0) -> (0,1,0) -> (0,2,0) -> (1,4,3).
    let t0 = s.prims.tris[0];
    assert!(close(t0[0], [1.0, 2.0, 3.0]) && close(t0[1], [1.0, 4.0, 3.0]) && close(t0[2], [-1.0, 2.0, 3.0]), "{t0:?}");
    // The triangle after the nested group still has material 2 (file order, not tree scope).
    let mat = |i: usize| s.materials[s.prims.tri_shading[i].material as usize].phong_params().unwrap().diffuse;
    assert_eq!(mat(0), prism::texture::ColorParam::Const(Vec3::Z));
    assert_eq!(mat(1), prism::texture::ColorParam::Const(Vec3::Z));
    // Matrix is pre-multiplied as in the course: M T(5,0,0) S(3): (1,0,0) -> (3,0,0) -> (8,0,0) -> (18,20,30).
    let t2 = s.prims.tris[2];
    assert!(close(t2[0], [15.0, 20.0, 30.0]) && close(t2[1], [18.0, 20.0, 30.0]), "{t2:?}");
}

/// Run `prism render` on 6.837 text; the first stderr line must be an error naming `bad.txt:LINE:`.
fn assert_txt_error(text: &str, line: usize, needle: &str) {
    let p = write_txt("bad.txt", text);
    let o = prism(&["render", p.to_str().unwrap(), "-q", "-o", p.with_extension("png").to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "accepted: {text}");
    assert!(!err.contains("panicked"), "panic: {err}");
    let first = err.lines().next().unwrap_or("");
    assert!(first.starts_with("error:") && first.contains(&format!("bad.txt:{line}:")), "{first}");
    assert!(first.contains(needle), "`{needle}` not in: {first}");
    assert_eq!(err.lines().count(), 1, "more than one line: {err}");
}

const CAM: &str = "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 5 }\n";
const MATS: &str = "Materials { numMaterials 1 Material { diffuseColor 1 0 0 } }\n";

#[test]
fn malformed_files_give_one_line_errors_with_file_and_line() {
    let sphere = "Sphere { center 0 0 0 radius 1 }";
    let group = |body: &str| format!("{CAM}{MATS}Group {{ numObjects 1 MaterialIndex 0\n{body} }}");
    let cases: Vec<(String, usize, &str)> = vec![
        // Missing braces.
        (format!("{CAM}{MATS}Group {{ numObjects 1\nMaterialIndex 0\n{sphere}\n"), 5, "end of file"),
        (group("Sphere center 0 0 0 radius 1 }"), 4, "expected `{`"),
        (
            format!("{CAM}Materials {{ numMaterials 1 Material {{ diffuseColor 1 0 0 }}\nGroup {{ }}"),
            3,
            "`Group` in Materials",
        ),
        // Wrong counts.
        (format!("{CAM}{MATS}Group {{ numObjects 2 MaterialIndex 0\n{sphere}\n}}"), 5, "numObjects 2 but contains 1"),
        (group(&format!("{sphere} {sphere}")), 4, "numObjects 1 but contains more"),
        (
            format!("{CAM}Materials {{ numMaterials 2\nMaterial {{ diffuseColor 1 0 0 }} }}"),
            3,
            "numMaterials 2 but lists 1",
        ),
        (
            format!("{CAM}Lights {{ numLights 0\nDirectionalLight {{ direction 0 0 -1 color 1 1 1 }} }}"),
            3,
            "numLights 0 but lists more",
        ),
        // Unknown keywords.
        (group("Cylinder { }"), 4, "unknown object `Cylinder`"),
        (format!("{CAM}\nMaterials {{ numMaterials 1 Material {{ shininess 3 }} }}"), 3, "unknown keyword `shininess`"),
        (format!("{CAM}Background {{ colour 1 1 1 }}"), 2, "unknown keyword `colour`"),
        ("Camera { }".into(), 1, "unknown keyword `Camera`"),
        // Missing obj_file, missing mesh.
        (group("TriangleMesh { }"), 4, "expected `obj_file`"),
        (group("TriangleMesh { obj_file nope.obj }"), 4, "not found"),
        // Non-numeric tokens.
        (group("Sphere { center 0 zero 0 radius 1 }"), 4, "`zero`"),
        (format!("{CAM}{MATS}Group {{ numObjects one }}"), 3, "`one`"),
        ("OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size five }".into(), 1, "`five`"),
        // Material indices, degenerate geometry, no camera.
        (
            format!("{CAM}{MATS}Group {{ numObjects 1 MaterialIndex 3\n{sphere} }}"),
            3,
            "MaterialIndex 3 is out of range",
        ),
        (format!("{CAM}{MATS}Group {{ numObjects 1\n{sphere} }}"), 4, "before any MaterialIndex"),
        (group("Sphere { center 0 0 0 radius -1 }"), 4, "radius"),
        (group(&format!("Transform {{ Scale 1 0 1 {sphere} }}")), 4, "singular"),
        (group("Triangle { vertex0 0 0 0 vertex1 1 1 1 vertex2 2 2 2 }"), 4, "zero area"),
        (format!("{MATS}Group {{ numObjects 0 }}"), 1, "no camera"),
    ];
    for (text, line, needle) in cases {
        assert_txt_error(&text, line, needle);
    }
}

#[test]
fn course_command_lines_of_assignment_5_run_through_prism_raytracer() {
    let commands = std::fs::read_to_string(data("mit6837/COMMANDS.txt")).unwrap();
    let section = commands.split("## assignment5").nth(1).unwrap().split("## assignment6").next().unwrap();
    let dir = scratch("raytracer");
    let mut ran = 0;
    for line in section.lines().filter(|l| l.starts_with("raytracer ")) {
        let mut args: Vec<String> = line.split_whitespace().skip(1).map(String::from).collect();
        // Smaller images, paths into the data folder and the scratch folder.
        for i in 0..args.len() {
            match args[i].as_str() {
                "-input" => args[i + 1] = data(&format!("mit6837/assignment5/{}", args[i + 1])).display().to_string(),
                "-output" => args[i + 1] = dir.join(&args[i + 1]).display().to_string(),
                "-size" => {
                    args[i + 1] = "32".into();
                    args[i + 2] = "32".into();
                }
                _ => {}
            }
        }
        let mut full = vec!["raytracer".to_string()];
        full.extend(args.iter().cloned());
        let refs: Vec<&str> = full.iter().map(String::as_str).collect();
        let o = prism(&refs);
        assert!(o.status.success(), "{line}: {}", String::from_utf8_lossy(&o.stderr));
        if let Some(i) = args.iter().position(|a| a == "-output") {
            // Written where the course asks, in the course's format.
            let tga = PathBuf::from(&args[i + 1]);
            let bytes = std::fs::read(&tga).unwrap_or_else(|_| panic!("{line}: {} not written", tga.display()));
            assert_eq!(bytes.len(), 18 + 32 * 32 * 3, "{line}: a 32x32 24-bit TGA");
        }
        ran += 1;
    }
    assert!(ran >= 20, "only {ran} command lines");
}
