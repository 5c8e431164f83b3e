//! 6.837 assignments 6 and 7: every scene renders and converts; the solid textures (checkerboard, Perlin noise,
//! marble, wood) follow their formulas; `prism raytracer` runs the course's command lines and writes TGA images at
//! exactly the asked path with the course's linear quantisation `int(255 c)`; malformed solid materials give
//! one-line `file:line` errors.

use crate::common::{data, prism, render_file, scratch};
use crate::mit6837::scenes;
use glam::{Affine3A, Vec3, Vec3A};
use prism::settings::Overrides;
use prism::texture::{Solid, SolidKind, perlin};
use std::path::PathBuf;

#[test]
fn every_assignment_6_and_7_scene_renders_and_converts() {
    let all = scenes(6, 7);
    assert_eq!(all.len(), 18 + 6, "scene count");
    let dir = scratch("a67");
    for path in all {
        let img = render_file(&path, Overrides { size: Some((48, 48)), spp: Some(1), ..Default::default() });
        assert!(img.pixels.iter().all(|p| p.is_finite()), "{}", path.display());
        let first = img.pixels[0];
        assert!(img.pixels.iter().any(|p| (*p - first).abs().max_element() > 1e-3), "{} is flat", path.display());
        let out = dir.join(path.with_extension("ron").file_name().unwrap());
        let o = prism(&["convert", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        assert!(o.status.success(), "{}: {}", path.display(), String::from_utf8_lossy(&o.stderr));
    }
}

fn solid(kind: SolidKind, octaves: u32, frequency: f32, amplitude: f32) -> Solid {
    Solid { kind, transform: Affine3A::IDENTITY, octaves, frequency, amplitude }
}

#[test]
fn solid_textures_follow_the_course_formulas() {
    // Checkerboard: parity of floor(x) + floor(y) + floor(z), 0 on the cell of the origin, negative cells too.
    let c = solid(SolidKind::Checker3d, 0, 1.0, 1.0);
    assert_eq!(c.eval(Vec3A::new(0.5, 0.5, 0.5)), 0.0);
    assert_eq!(c.eval(Vec3A::new(1.5, 0.5, 0.5)), 1.0);
    assert_eq!(c.eval(Vec3A::new(-0.5, 0.5, 0.5)), 1.0);
    assert_eq!(c.eval(Vec3A::new(-0.5, -0.5, 0.5)), 0.0);
    // Perlin's improved noise vanishes on the integer lattice and stays within [-1, 1].
    let mut rng = prism::sampling::Rng::new(7, 7);
    for _ in 0..2000 {
        let p = (rng.next_2d() * 40.0 - 20.0, rng.next_f32() * 40.0 - 20.0);
        let n = perlin::noise(p.0.x as f64, p.0.y as f64, p.1 as f64);
        assert!(n.abs() <= 1.0, "{n}");
        let (i, j, k) = (p.0.x.floor() as f64, p.0.y.floor() as f64, p.1.floor() as f64);
        assert_eq!(perlin::noise(i, j, k), 0.0);
    }
    // Octaves: N = sum noise(2^i p) / 2^i.
    let q = [0.3, 1.7, -2.2];
    let n3 = perlin::octave_sum(q, 3);
    let by_hand =
        perlin::noise(0.3, 1.7, -2.2) + perlin::noise(0.6, 3.4, -4.4) / 2.0 + perlin::noise(1.2, 6.8, -8.8) / 4.0;
    assert!((n3 - by_hand).abs() < 1e-12);
    let p = Vec3A::new(0.3, 1.7, -2.2);
    let noise = solid(SolidKind::Noise, 3, 1.0, 1.0).eval(p) as f64;
    assert!((noise - (n3 + 1.0) / 2.0).abs() < 1e-6);
    // Marble with 0 octaves is a pure sine of x; wood of the distance to the y axis.
    let marble = solid(SolidKind::Marble, 0, 3.0, 2.0).eval(p) as f64;
    assert!((marble - ((3.0f64 * 0.3).sin() + 1.0) / 2.0).abs() < 1e-6);
    let wood = solid(SolidKind::Wood, 2, 7.0, 2.0).eval(p) as f64;
    let r = (0.3f64 * 0.3 + 2.2 * 2.2).sqrt();
    let expect = ((7.0 * r + 2.0 * perlin::octave_sum(q, 2)).sin() + 1.0) / 2.0;
    assert!((wood - expect).abs() < 1e-5, "{wood} vs {expect}");
}

/// A square facing the camera, no lights (the course's flat colours: ambient white), with `material`.
fn flat_scene(materials: &str) -> String {
    format!(
        "OrthographicCamera {{ center 0 0 10 direction 0 0 -1 up 0 1 0 size 4 }}
         Background {{ color 0 0 0 }}
         Materials {{ {materials} }}
         Group {{ numObjects 1 MaterialIndex 0
           Triangle {{ vertex0 -3 -3 0 vertex1 3 -3 0 vertex2 0 3 0 }} }}"
    )
}

#[test]
fn raytracer_writes_the_course_tga_with_linear_int_255_values() {
    let dir = scratch("tga");
    let scene = dir.join("flat.txt");
    std::fs::write(&scene, flat_scene("numMaterials 1 Material { diffuseColor 0.5 0.25 1 }")).unwrap();
    let out = dir.join("out.tga");
    let o =
        prism(&["raytracer", "-input", scene.to_str().unwrap(), "-size", "8", "8", "-output", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let b = std::fs::read(&out).expect("the TGA at exactly the -output path");
    assert_eq!(&b[..3], &[0, 0, 2], "uncompressed true-colour");
    assert_eq!((u16::from_le_bytes([b[12], b[13]]), u16::from_le_bytes([b[14], b[15]]), b[16]), (8, 8, 24));
    // Pixel (4, 4) sits on the triangle: colour (0.5, 0.25, 1) as int(255 c) = (127, 63, 255), stored BGR.
    let i = 18 + (4 * 8 + 4) * 3;
    assert_eq!(&b[i..i + 3], &[255, 63, 127]);
    // -normals: |n| = (0, 0, 1) written raw.
    let normals = dir.join("normals.tga");
    let o = prism(&[
        "raytracer",
        "-input",
        scene.to_str().unwrap(),
        "-size",
        "8",
        "8",
        "-normals",
        normals.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let b = std::fs::read(&normals).unwrap();
    assert_eq!(&b[i..i + 3], &[255, 0, 0]);
}

#[test]
fn a_checkerboard_of_two_materials_shows_each_in_its_cells() {
    let dir = scratch("checker");
    let scene = dir.join("checker.txt");
    let mats = "numMaterials 3 Material { diffuseColor 1 0 0 } Material { diffuseColor 0 0 1 }
                Checkerboard { Transform { UniformScale 0.5 } materialIndex 0 materialIndex 1 }";
    std::fs::write(&scene, flat_scene(mats).replace("MaterialIndex 0", "MaterialIndex 2")).unwrap();
    // 4 world units across 8 pixels; the texture scale 0.5 makes 2-unit cells: pixel columns 0-3 lie in x in
    // [-2, 0) (cell -1), 4-7 in [0, 2) (cell 0); z = 0 and y in [0, 2) or [-2, 0).
    let img = render_file(&scene, Overrides { size: Some((8, 8)), spp: Some(1), ..Default::default() });
    let at = |x: u32, y: u32| img.get(x, y);
    assert!((at(5, 4) - Vec3::new(0.0, 0.0, 1.0)).abs().max_element() < 1e-6, "{}", at(5, 4)); // x>0, y<0: odd
    assert!((at(5, 2) - Vec3::new(1.0, 0.0, 0.0)).abs().max_element() < 1e-6, "{}", at(5, 2)); // x>0, y>0: even
    assert!((at(2, 4) - Vec3::new(1.0, 0.0, 0.0)).abs().max_element() < 1e-6, "{}", at(2, 4)); // both negative
}

#[test]
fn course_command_lines_of_assignments_6_and_7_run_through_prism_raytracer() {
    let commands = std::fs::read_to_string(data("mit6837/COMMANDS.txt")).unwrap();
    let dir = scratch("raytracer67");
    let mut ran = 0;
    for (a, section) in [(6, "## assignment6"), (7, "## assignment7")] {
        let text = commands.split(section).nth(1).unwrap().split("\n## ").next().unwrap();
        // Every line, sample patterns and pixel filters (and their visualisations) included.
        for line in text.lines().filter(|l| l.starts_with("raytracer ")) {
            let mut args: Vec<String> = line.split_whitespace().skip(1).map(String::from).collect();
            for i in 0..args.len() {
                match args[i].as_str() {
                    "-input" => {
                        args[i + 1] = data(&format!("mit6837/assignment{a}/{}", args[i + 1])).display().to_string()
                    }
                    "-output" | "-render_samples" | "-render_filter" => {
                        args[i + 1] = dir.join(&args[i + 1]).display().to_string()
                    }
                    "-size" => {
                        args[i + 1] = "24".into();
                        args[i + 2] = "24".into();
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
                let tga = PathBuf::from(&args[i + 1]);
                let len = std::fs::metadata(&tga).unwrap_or_else(|_| panic!("{line}: no {}", tga.display())).len();
                assert_eq!(len, 18 + 24 * 24 * 3, "{line}");
            }
            // The visualisations are (24 zoom)^2 TGAs.
            for opt in ["-render_samples", "-render_filter"] {
                if let Some(i) = args.iter().position(|a| a == opt) {
                    let zoom: u64 = args[i + 2].parse().unwrap();
                    let len = std::fs::metadata(&args[i + 1]).unwrap_or_else(|_| panic!("{line}: no {opt}")).len();
                    assert_eq!(len, 18 + 24 * 24 * zoom * zoom * 3, "{line}");
                }
            }
            ran += 1;
        }
    }
    assert!(ran >= 90, "only {ran} command lines");
}

#[test]
fn malformed_solid_materials_are_one_line_errors_with_their_line() {
    let dir = scratch("badsolid");
    let cases = [
        ("numMaterials 2 Material { diffuseColor 1 0 0 }\nCheckerboard { materialIndex 0 }", "two materialIndex"),
        (
            "numMaterials 2 Material { diffuseColor 1 0 0 }\nNoise { materialIndex 0 materialIndex 5 }",
            "materialIndex 5",
        ),
        (
            "numMaterials 2 Material { diffuseColor 1 0 0 }\nMarble { materialIndex 0 materialIndex 1 }",
            "contain itself",
        ),
        (
            "numMaterials 2 Material { diffuseColor 1 0 0 }\nWood { Transform { Sphere } materialIndex 0 materialIndex 0 }",
            "transformation",
        ),
        (
            "numMaterials 2 Material { diffuseColor 1 0 0 }\nNoise { frequency 2 materialIndex 0 materialIndex 0 }",
            "frequency",
        ),
    ];
    for (mats, needle) in cases {
        let path = dir.join("bad.txt");
        std::fs::write(&path, flat_scene(mats)).unwrap();
        let o = prism(&["render", path.to_str().unwrap(), "-o", dir.join("o.png").to_str().unwrap(), "-q"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(needle) && err.contains("bad.txt:"), "{mats}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
}
