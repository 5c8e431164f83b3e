//! pbrt import: the caustic-glass files convert with the settings they ask for and render with photon mapping;
//! pbrt's conventions (left-handed screen, fov of the shorter axis, bounce counts, blackbody spectra, roughness
//! remapping, spot fall-off per version, orientation of emitters, cylinder and partial-disk areas) come out as pbrt
//! defines them; malformed
//! files are one-line `file:line:col` errors.

use crate::common::{app_from_file, data, render_file, scratch, spp};
use prism::lights::{SpotLight, SpotProfile};
use prism::load::parse_scene;
use prism::load::pbrt::{convert_file, roughness_to_alpha_v3, spectrum};
use prism::load::schema::{LightDesc, MaterialDesc, ScalarDesc, SceneDesc};
use prism::settings::Overrides;
use std::path::{Path, PathBuf};

fn write(name: &str, text: &str) -> PathBuf {
    let dir = scratch("pbrt");
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// Convert and parse back; returns the RON text (the descriptor borrows it).
fn ron_of(path: &Path) -> String {
    let c = convert_file(path, path.parent().unwrap()).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    parse_scene(&c.ron, path).unwrap_or_else(|e| panic!("converted RON does not parse: {e}\n{}", c.ron));
    c.ron
}

fn desc(ron: &str) -> SceneDesc<'_> {
    parse_scene(ron, Path::new("x.ron")).unwrap()
}

fn integrator(d: &SceneDesc) -> String {
    d.render.integrator.map(|r| r.get_ron().to_string()).unwrap_or_default()
}

#[test]
fn the_caustic_glass_files_convert_with_the_integrator_iterations_and_crop_they_ask_for() {
    let cases = [
        ("f16-9a.pbrt", "ppm(radius: 0.025, eye_depth: 5, photon_depth: 5)", 10, (700, 1000)),
        ("f16-9b.pbrt", "ppm(radius: 0.075, eye_depth: 5, photon_depth: 5)", 100, (700, 1000)),
        ("f16-9c.pbrt", "ppm(radius: 0.075, eye_depth: 5, photon_depth: 5)", 10000, (700, 1000)),
        ("f16-11a.pbrt", "ppm(radius: 0.075, photons: 100000, eye_depth: 5, photon_depth: 5)", 500, (560, 600)),
        ("f16-11b.pbrt", "ppm(radius: 0.075, photons: 5000000, eye_depth: 5, photon_depth: 5)", 10, (560, 600)),
        // bdpt with maxdepth 20 (bounces) is bidirectional path tracing with 21 segments.
        ("glass.pbrt", "vcm(mode: bdpt, max_depth: 21)", 8192, (1050, 1500)),
    ];
    for (file, integ, n, size) in cases {
        let ron = ron_of(&data(&format!("caustic_glass/{file}")));
        let d = desc(&ron);
        assert_eq!(integrator(&d), integ, "{file}");
        assert_eq!(d.render.spp, Some(n), "{file}: sppm iterations / pixel samples");
        let cam = d.camera.as_ref().unwrap();
        assert_eq!(cam.size, size, "{file}: the crop window's pixels");
        assert!(cam.mirror, "{file}: pbrt's LookAt screen is mirrored relative to Prism's");
        // Film scale 1.5 is an exposure of log2(1.5) stops.
        assert!((d.render.exposure.unwrap() - 1.5f32.log2()).abs() < 1e-6);
        if file.starts_with("f16-11") {
            // cropwindow [.3 .7 .4 .7] of 1400 x 2000, rounded to pbrt's pixel bounds.
            assert_eq!(cam.crop, Some([0.3, 0.4, 0.7, 0.7]));
        }
        // fov 30 of the shorter (horizontal) axis of a portrait image.
        let expect = 2.0 * ((15f64).to_radians().tan() * size.1 as f64 / size.0 as f64).atan().to_degrees();
        let full = if file.starts_with("f16-11") {
            2.0 * ((15f64).to_radians().tan() * 2000.0 / 1400.0).atan().to_degrees()
        } else {
            expect
        };
        assert!((cam.fov as f64 - full).abs() < 1e-3, "{file}: fov {} vs {full}", cam.fov);
    }
}

#[test]
fn pbrt_v3_blackbody_matches_pbrts_own_conversion_in_glass_pbrt() {
    // glass.pbrt's `rgb I [139.81 118.64 105.39]` is the f16 files' `blackbody I [5500 125]` as pbrt-v3 wrote it.
    let rgb = spectrum::blackbody_v3(5500.0, 125.0);
    for (a, b) in rgb.iter().zip([139.8113403320, 118.6366500854, 105.3887557983]) {
        assert!((a - b).abs() / b < 5e-3, "{rgb:?}");
    }
    // pbrt-v4 normalises a blackbody light to luminance 1.
    let v4 = spectrum::blackbody_v4(3000.0);
    assert!((spectrum::luminance(v4) - 1.0).abs() < 1e-3, "{v4:?}");
    assert!(v4[0] > v4[2], "3000 K is reddish: {v4:?}");
}

#[test]
fn the_caustic_glass_scene_renders_with_photon_mapping_and_a_caustic_under_the_glass() {
    let file = data("caustic_glass/f16-9b.pbrt");
    let over = Overrides { size: Some((70, 100)), spp: Some(4), ..Default::default() };
    let mut app = app_from_file(&file, over);
    app.run().unwrap();
    assert_eq!(app.resources.settings.integrator.name, "ppm");
    let img = prism::stages::film_image(&app.resources).unwrap();
    assert!(img.pixels.iter().all(|p| p.is_finite()));
    // The glass's shadow on the floor (below the glass in the image) holds the caustic: light focused through
    // the glass makes parts of the shadow brighter than the open, spot-lit floor beside it.
    let px = |x: u32, y: u32| img.pixels[(y * img.width + x) as usize];
    let lum = |p: glam::Vec3| 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z;
    let shadow_max =
        (40..90).flat_map(|y| (5..40).map(move |x| (x, y))).map(|(x, y)| lum(px(x, y))).fold(0.0, f32::max);
    let lit_floor = (40..60).map(|y| lum(px(65, y))).sum::<f32>() / 20.0;
    assert!(shadow_max > lit_floor, "no caustic brighter than the directly lit floor: {shadow_max} vs {lit_floor}");
}

const HEAD_V4: &str = "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n\
    Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\nColorSpace \"srgb\"\n";

#[test]
fn a_lookat_camera_sees_up_cross_view_on_the_right_as_pbrt_does() {
    // Looking along +z with +y up, pbrt's image-right is up x view = +x: an emitter at +x shows on the right.
    let text = format!(
        "{HEAD_V4}Integrator \"path\" \"integer maxdepth\" 0\nWorldBegin\nAttributeBegin\n\
         AreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"bool twosided\" true\n\
         Shape \"trianglemesh\" \"point3 P\" [0.5 -0.5 0  1.5 -0.5 0  1.5 0.5 0  0.5 0.5 0] \"integer indices\" [0 1 2 0 2 3]\n\
         AttributeEnd\n"
    );
    let img = render_file(&write("handed.pbrt", &text), spp(1));
    let half = |right: bool| {
        (0..16u32)
            .flat_map(|y| (0..8u32).map(move |x| (x, y)))
            .map(|(x, y)| img.pixels[(y * 16 + if right { x + 8 } else { x }) as usize].x)
            .sum::<f32>()
    };
    assert!(half(true) > 10.0 && half(false) == 0.0, "right {} left {}", half(true), half(false));
}

#[test]
fn transforms_objects_instances_and_includes_place_shapes_where_pbrt_does() {
    let dir = scratch("pbrt-include");
    std::fs::write(
        dir.join("part.pbrt"),
        "AttributeBegin\nTranslate 0 0 3\nShape \"sphere\" \"float radius\" 0.25\nAttributeEnd\n",
    )
    .unwrap();
    let text = format!(
        "{HEAD_V4}WorldBegin\nObjectBegin \"ball\"\nTranslate 1 0 0\nShape \"sphere\" \"float radius\" 0.5\nObjectEnd\n\
         AttributeBegin\nTranslate 0 2 0\nObjectInstance \"ball\"\nAttributeEnd\n\
         AttributeBegin\nRotate 90 0 0 1\nObjectInstance \"ball\"\nAttributeEnd\n\
         AttributeBegin\nConcatTransform [2 0 0 0  0 2 0 0  0 0 2 0  0 0 -1 1]\nShape \"sphere\" \"float radius\" 1\nAttributeEnd\n\
         Include \"part.pbrt\"\n"
    );
    let path = dir.join("scene.pbrt");
    std::fs::write(&path, text).unwrap();
    let mut app = app_from_file(&path, spp(1));
    app.run().unwrap();
    let prims = &app.resources.scene.as_ref().unwrap().prims;
    let mut got: Vec<(glam::Vec3, f32)> =
        prims.spheres.iter().map(|s| (glam::Vec3::from(s.center), s.radius)).collect();
    got.sort_by(|a, b| a.0.to_array().partial_cmp(&b.0.to_array()).unwrap());
    let want = [
        (glam::Vec3::new(0.0, 0.0, -1.0), 2.0),
        (glam::Vec3::new(0.0, 0.0, 3.0), 0.25),
        (glam::Vec3::new(0.0, 1.0, 0.0), 0.5),
        (glam::Vec3::new(1.0, 2.0, 0.0), 0.5),
    ];
    assert_eq!(got.len(), 4, "{got:?}");
    for ((c, r), (wc, wr)) in got.iter().zip(want) {
        assert!((*c - wc).length() < 1e-5 && (r - wr).abs() < 1e-5, "{got:?}");
    }
}

fn material<'a>(d: &'a SceneDesc, key: &str) -> &'a MaterialDesc {
    d.materials.get(key).unwrap_or_else(|| panic!("no material {key}: {:?}", d.materials.keys().collect::<Vec<_>>()))
}

#[test]
fn materials_map_to_prism_with_each_versions_roughness_remapping() {
    let v3 = "LookAt 0 0 -5 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\n\
        MakeNamedMaterial \"p\" \"string type\" \"plastic\" \"float roughness\" 0.1 \"color Kd\" [0.2 0.3 0.4]\n\
        MakeNamedMaterial \"m\" \"string type\" \"metal\"\n\
        MakeNamedMaterial \"g\" \"string type\" \"glass\" \"float index\" 1.33\n\
        MakeNamedMaterial \"u\" \"string type\" \"uber\" \"float index\" 1 \"rgb Kd\" [0.5 0.5 0.5]\n\
        MakeNamedMaterial \"x\" \"string type\" \"mix\" \"string namedmaterial1\" \"p\" \"string namedmaterial2\" \"m\" \"float amount\" 0.25\n\
        WorldEnd\n";
    let ron = ron_of(&write("mat3.pbrt", v3));
    let d = desc(&ron);
    match material(&d, "named:p") {
        MaterialDesc::RoughPlastic { alpha: ScalarDesc::Value(a), .. } => {
            assert!((*a as f64 - roughness_to_alpha_v3(0.1)).abs() < 1e-6, "{a}")
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(material(&d, "named:m"), MaterialDesc::RoughConductor { material: Some(m), .. } if m == "Cu"));
    assert!(
        matches!(material(&d, "named:g"), MaterialDesc::RoughDielectric { ior, alpha: ScalarDesc::Value(a), .. } if (*ior - 1.33).abs() < 1e-6 && *a == 0.0)
    );
    assert!(
        matches!(material(&d, "named:u"), MaterialDesc::Lambert { .. }),
        "uber with index 1 reflects nothing specular"
    );
    assert!(matches!(material(&d, "named:x"), MaterialDesc::Blend { weight: ScalarDesc::Value(w), .. } if *w == 0.25));
    let v4 = format!(
        "{HEAD_V4}WorldBegin\nMakeNamedMaterial \"c\" \"string type\" \"coateddiffuse\" \"float roughness\" 0.04 \
         \"integer maxdepth\" 7 \"rgb albedo\" [0.1 0.2 0.3] \"float thickness\" 0.2\n\
         MakeNamedMaterial \"k\" \"string type\" \"coatedconductor\" \"float interface.roughness\" 0.09 \
         \"float interface.eta\" 1.3 \"float conductor.roughness\" 0.16 \"spectrum conductor.eta\" \"metal-Au-eta\" \
         \"spectrum conductor.k\" \"metal-Au-k\"\n"
    );
    let ron = ron_of(&write("mat4.pbrt", &v4));
    let d = desc(&ron);
    match material(&d, "named:c") {
        MaterialDesc::CoatedDiffuse {
            alpha: ScalarDesc::Value(a),
            max_depth: 7,
            samples: 1,
            thickness,
            albedo,
            ior,
            ..
        } => {
            assert!((a - 0.2).abs() < 1e-6, "pbrt-v4: sqrt(0.04), got {a}");
            assert!((thickness - 0.2).abs() < 1e-6 && (ior - 1.5).abs() < 1e-6);
            assert_eq!(*albedo, prism::load::schema::ColorDesc::Rgb([0.1, 0.2, 0.3]));
        }
        other => panic!("{other:?}"),
    }
    match material(&d, "named:k") {
        MaterialDesc::CoatedConductor {
            alpha: ScalarDesc::Value(a),
            conductor_alpha: ScalarDesc::Value(ca),
            ior,
            material: Some(m),
            thickness,
            ..
        } => {
            assert!((a - 0.3).abs() < 1e-6 && (ca - 0.4).abs() < 1e-6, "sqrt of both roughnesses: {a}, {ca}");
            assert!((ior - 1.3).abs() < 1e-6 && m == "Au" && (thickness - 0.01).abs() < 1e-6);
        }
        other => panic!("{other:?}"),
    }
    let v4 = format!(
        "{HEAD_V4}WorldBegin\nMakeNamedMaterial \"t\" \"string type\" \"thindielectric\" \"float eta\" 1.33\n\
         MakeNamedMaterial \"d\" \"string type\" \"diffusetransmission\" \"rgb transmittance\" [0.4 0.2 0.1] \"float scale\" 2\n"
    );
    let ron = ron_of(&write("mat6.pbrt", &v4));
    let d = desc(&ron);
    assert!(matches!(material(&d, "named:t"), MaterialDesc::ThinDielectric { ior, .. } if (*ior - 1.33).abs() < 1e-6));
    match material(&d, "named:d") {
        MaterialDesc::DiffuseTransmission { reflectance, transmittance } => {
            use prism::load::schema::ColorDesc::Rgb;
            assert_eq!((reflectance, transmittance), (&Rgb([0.5; 3]), &Rgb([0.8, 0.4, 0.2])), "times the scale");
        }
        other => panic!("{other:?}"),
    }
    // A walk limit beyond the bound is refused at its line.
    let bad = format!(
        "{HEAD_V4}WorldBegin\nMakeNamedMaterial \"c\" \"string type\" \"coateddiffuse\" \"integer maxdepth\" 100000\n"
    );
    let Err(err) = convert_file(&write("mat5.pbrt", &bad), std::path::Path::new(".")) else {
        panic!("maxdepth 100000 is refused")
    };
    let err = err.to_string();
    assert!(err.contains("maxdepth must be in 1..=100") && err.contains("mat5.pbrt:"), "{err}");
}

#[test]
fn spot_lights_take_their_versions_falloff_and_every_profile_has_its_exact_power() {
    let spot = "LightSource \"spot\" \"point3 from\" [0 5 0] \"point3 to\" [0 0 0] \"float coneangle\" 40 \"float conedeltaangle\" 10\n";
    for (head, want) in [
        (format!("{HEAD_V4}WorldBegin\n"), SpotProfile::Smoothstep),
        (
            format!("{}WorldBegin\n", HEAD_V4.replace("ColorSpace \"srgb\"\n", "").replace("point3", "point"))
                + "WorldEnd\n",
            SpotProfile::Quartic,
        ),
    ] {
        let text =
            format!("{head}{}", spot.replace("point3", if want == SpotProfile::Quartic { "point" } else { "point3" }));
        let ron = ron_of(&write("spot.pbrt", &text));
        let d = desc(&ron);
        let profile = d.entities.iter().find_map(|e| match &e.light {
            Some(LightDesc::Spot { profile, cone_angle, falloff, .. }) => {
                assert_eq!((*cone_angle, *falloff), (40.0, 10.0));
                Some(*profile)
            }
            _ => None,
        });
        assert_eq!(profile, Some(want));
    }
    // Power = intensity x the integral of the fall-off over the sphere, by quadrature in the cosine.
    for profile in [SpotProfile::Smoothstep, SpotProfile::Quartic, SpotProfile::Gltf] {
        let s = SpotLight::new(glam::Vec3A::ZERO, glam::Vec3A::Z, glam::Vec3::ONE, 40.0, 25.0, profile);
        let n = 200_000;
        let integral: f64 = (0..n)
            .map(|i| {
                let c = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
                let w = glam::Vec3A::new((1.0 - c * c).max(0.0).sqrt() as f32, 0.0, c as f32);
                s.falloff(w) as f64
            })
            .sum::<f64>()
            * 2.0
            / n as f64
            * 2.0
            * std::f64::consts::PI;
        let p = s.power().x as f64;
        assert!((p - integral).abs() / integral < 1e-4, "{profile:?}: power {p} vs integral {integral}");
    }
}

#[test]
fn reverse_orientation_and_mirroring_transforms_choose_the_emitting_side_as_pbrt_does() {
    let emit = |extra: &str| {
        let text = format!(
            "{HEAD_V4}Integrator \"path\" \"integer maxdepth\" 0\nWorldBegin\nAttributeBegin\n{extra}\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n\
             Shape \"trianglemesh\" \"point3 P\" [-1 -1 0  1 -1 0  1 1 0  -1 1 0] \"integer indices\" [0 2 1 0 3 2]\nAttributeEnd\n"
        );
        let img = render_file(&write("orient.pbrt", &text), spp(1));
        img.pixels.iter().map(|p| p.x).sum::<f32>()
    };
    // Wound counter-clockwise seen from the camera (at -z): its front faces the camera.
    let plain = emit("");
    let reversed = emit("ReverseOrientation");
    let mirrored = emit("Scale -1 1 1");
    let both = emit("ReverseOrientation\nScale -1 1 1");
    assert!(plain > 10.0, "the front emits towards the camera");
    assert_eq!(reversed, 0.0, "ReverseOrientation turns the emitting side away");
    assert!(mirrored > 10.0, "a mirroring transform keeps pbrt's side (it flips the winding and the side back)");
    assert_eq!(both, 0.0);
}

/// Convert `text`; assert a one-line error at `line:col` containing `needle`.
fn pbrt_error(text: &str, line_col: &str, needle: &str) {
    let p = write("bad.pbrt", text);
    let e = convert_file(&p, p.parent().unwrap()).expect_err("malformed pbrt must fail").to_string();
    assert!(!e.contains('\n'), "one line: {e}");
    assert!(e.contains(&format!("bad.pbrt:{line_col}")), "position {line_col}: {e}");
    assert!(e.contains(needle), "{needle:?}: {e}");
}

#[test]
fn malformed_pbrt_files_are_one_line_errors_with_file_line_and_column() {
    let w = "LookAt 0 0 -5 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\n";
    pbrt_error(
        &format!("{w}Shape \"sphere\"\nShpe \"sphere\"\n"),
        "5:1",
        "unknown directive `Shpe` (did you mean `Shape`?)",
    );
    // A word far from every directive is not quoted: the file may be no pbrt scene at all.
    pbrt_error(&format!("{w}Shape \"sphere\"\nFrobnicate 1 2\n"), "5:1", "expected a pbrt directive here");
    pbrt_error(
        &format!("{w}AttributeBegin\nAttributeEnd\nAttributeEnd\n"),
        "6:1",
        "AttributeEnd without a matching AttributeBegin",
    );
    pbrt_error(&format!("{w}AttributeBegin\n"), "4:1", "AttributeBegin is never closed");
    pbrt_error(&format!("{w}TransformBegin\nAttributeEnd\n"), "5:1", "closes the TransformBegin");
    pbrt_error("LookAt 0 0 -5 0 0 0 0 1\nCamera \"perspective\"\n", "2:1", "LookAt expects 9 numbers");
    pbrt_error("Camera \"perspective\" \"float fov\" \"wide\"\n", "1:34", "expected a number");
    pbrt_error("Camera \"perspective\" \"string fov\" \"wide\"\nWorldBegin\n", "1:22", "should be of type float");
    pbrt_error("Shape \"sphere\"\n", "1:1", "before WorldBegin");
    pbrt_error(&format!("{w}Shape \"plymesh\" \"string filename\" \"missing.ply\"\n"), "4:17", "file not found");
    pbrt_error(
        &format!("{w}Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 3]\n"),
        "4:1",
        "out of range",
    );
    pbrt_error(&format!("{w}NamedMaterial \"nope\"\n"), "4:1", "unknown material \"nope\"");
    pbrt_error(&format!("{w}Shape \"sphere\" \"float radius\" [1\n"), "4:16", "missing `]`");
    pbrt_error(&format!("{w}Material \"matte\" \"string Kd\n"), "4:18", "unterminated string");
    pbrt_error(&format!("{w}Include \"nowhere.pbrt\"\n"), "4:1", "file not found");
    pbrt_error(
        &format!("{w}Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"none.png\"\n"),
        "4:",
        "image not found",
    );
    pbrt_error("LookAt 0 0 -5 0 0 0 0 1 0\nIntegrator \"nonsense\"\nWorldBegin\n", "2:1", "unknown integrator");
}

#[test]
fn a_pbrt_scene_renders_through_the_cli_and_converts_to_a_ron_file_that_loads() {
    let dir = scratch("pbrt-cli");
    let out = dir.join("glass.ron");
    let o = crate::common::prism(&[
        "convert",
        data("caustic_glass/f16-9a.pbrt").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = render_file(&out, Overrides { size: Some((14, 20)), spp: Some(1), ..Default::default() });
    assert!(img.pixels.iter().any(|p| p.x > 0.0));
}

#[test]
fn a_pbrt_v3_environment_map_is_looked_up_in_pbrts_frame_z_up_phi_from_x() {
    // A 16 x 8 equirect map: red around phi = 0 (+x), green around phi = 90 degrees (+y), on the horizon rows.
    let dir = scratch("pbrt-env");
    let (w, h) = (16u32, 8u32);
    let mut px = vec![glam::Vec3::ZERO; (w * h) as usize];
    for y in 3..5 {
        for x in [15, 0] {
            px[(y * w + x) as usize] = glam::Vec3::new(1.0, 0.0, 0.0);
        }
        for x in [3, 4] {
            px[(y * w + x) as usize] = glam::Vec3::new(0.0, 1.0, 0.0);
        }
    }
    prism::io::write_exr(&dir.join("sky.exr"), &prism::io::Image::new(w, h, px)).unwrap();
    let look = |to: &str| {
        let text = format!(
            "LookAt 0 0 0  {to}  0 0 1\nCamera \"perspective\" \"float fov\" 5\nFilm \"image\" \"integer xresolution\" 4 \"integer yresolution\" 4\n\
             Integrator \"path\" \"integer maxdepth\" 1\nWorldBegin\nLightSource \"infinite\" \"string mapname\" \"sky.exr\"\nWorldEnd\n"
        );
        std::fs::write(dir.join("env.pbrt"), text).unwrap();
        render_file(&dir.join("env.pbrt"), spp(4)).mean()
    };
    let (px_, py, nx, ny) = (look("1 0 0"), look("0 1 0"), look("-1 0 0"), look("0 -1 0"));
    assert!(px_.x > 0.4 && px_.y < 0.05, "+x sees red: {px_:?}");
    assert!(py.y > 0.4 && py.x < 0.05, "+y sees green: {py:?}");
    assert!(nx.max_element() < 0.05 && ny.max_element() < 0.05, "-x {nx:?}, -y {ny:?} see nothing");
}

#[test]
fn image_textures_keep_pbrts_orientation_and_uv_scale() {
    // A 2 x 2 texture: top row red, bottom row blue. pbrt's v = 0 is the image's bottom row.
    let dir = scratch("pbrt-tex");
    let px = vec![glam::Vec3::X, glam::Vec3::X, glam::Vec3::Z, glam::Vec3::Z];
    prism::io::write_exr(&dir.join("rb.exr"), &prism::io::Image::new(2, 2, px)).unwrap();
    let text = format!(
        "{HEAD_V4}Integrator \"path\" \"integer maxdepth\" 1\nWorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n\
         Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"rb.exr\" \"string wrap\" \"clamp\"\n\
         Material \"diffuse\" \"texture reflectance\" \"t\"\n\
         Shape \"trianglemesh\" \"point3 P\" [-1 -1 0  1 -1 0  1 1 0  -1 1 0] \"point2 uv\" [0 0  1 0  1 1  0 1] \"integer indices\" [0 2 1 0 3 2]\n"
    );
    std::fs::write(dir.join("tex.pbrt"), text).unwrap();
    let img = render_file(&dir.join("tex.pbrt"), spp(4));
    // The quad covers pixel rows and columns 4 to 11; its top (y = +1, v = 1 in pbrt) shows the image's top row.
    let row = |y: u32| (5..11).map(|x| img.get(x, y)).fold(glam::Vec3::ZERO, |a, b| a + b);
    assert!(row(5).x > 4.0 * row(5).z, "top of the quad is red: {:?}", row(5));
    assert!(row(10).z > 4.0 * row(10).x, "bottom of the quad is blue: {:?}", row(10));
}

/// pbrt-v4's `infinite` `filename`: an equal-area octahedral square (pbrt's `EqualAreaSphereToSquare`: +x at the
/// middle of the right edge, +y at the middle of the bottom edge, +z at the centre), here read from a PFM file,
/// whose rows run from the bottom up.
#[test]
fn a_pbrt_v4_equal_area_map_from_a_pfm_file_is_looked_up_in_pbrts_frame() {
    let dir = scratch("pbrt-env-v4");
    let n = 16usize;
    let mut px = vec![[0f32; 3]; n * n];
    for k in [7, 8] {
        px[k * n + (n - 1)] = [1.0, 0.0, 0.0]; // (1, 0.5): +x
        px[(n - 1) * n + k] = [0.0, 1.0, 0.0]; // (0.5, 1): +y
        for j in [7, 8] {
            px[j * n + k] = [0.0, 0.0, 1.0]; // (0.5, 0.5): +z
        }
    }
    let mut pfm = format!("PF\n{n} {n}\n-1.0\n").into_bytes();
    for row in (0..n).rev() {
        for p in &px[row * n..(row + 1) * n] {
            for c in p {
                pfm.extend(c.to_le_bytes());
            }
        }
    }
    std::fs::write(dir.join("sky.pfm"), pfm).unwrap();
    let look = |to: &str, up: &str| {
        let text = format!(
            "LookAt 0 0 0  {to}  {up}\nCamera \"perspective\" \"float fov\" 5\nFilm \"rgb\" \"integer xresolution\" 4 \"integer yresolution\" 4\n\
             Integrator \"path\" \"integer maxdepth\" 1\nWorldBegin\nLightSource \"infinite\" \"string filename\" \"sky.pfm\" \"float scale\" 2\n"
        );
        std::fs::write(dir.join("env.pbrt"), text).unwrap();
        render_file(&dir.join("env.pbrt"), spp(4)).mean()
    };
    let (x, y, z, nx) =
        (look("1 0 0", "0 0 1"), look("0 1 0", "0 0 1"), look("0 0 1", "0 1 0"), look("-1 0 0", "0 0 1"));
    assert!(x.x > 0.8 && x.y < 0.05 && x.z < 0.05, "+x sees red (times the scale 2): {x:?}");
    assert!(y.y > 0.8 && y.x < 0.05 && y.z < 0.05, "+y sees green: {y:?}");
    assert!(z.z > 0.8 && z.x < 0.05 && z.y < 0.05, "+z sees blue: {z:?}");
    assert!(nx.max_element() < 0.05, "-x sees nothing: {nx:?}");
}

/// pbrt-v3 accepts `AreaLightSource "area"`, the older name of `"diffuse"` (pbrt-v3's own killeroo-simple.pbrt).
#[test]
fn area_light_source_area_is_the_diffuse_area_light() {
    let scene = |ty: &str| {
        format!(
            "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\nFilm \"image\" \"integer xresolution\" 4 \"integer yresolution\" 4\n\
             WorldBegin\nAttributeBegin\nAreaLightSource \"{ty}\" \"rgb L\" [2 2 2]\nShape \"sphere\" \"float radius\" 1\nAttributeEnd\nWorldEnd\n"
        )
    };
    let a = ron_of(&write("area.pbrt", &scene("area")));
    let b = ron_of(&write("diffuse.pbrt", &scene("diffuse")));
    assert_eq!(a.replace("area.pbrt", "X"), b.replace("diffuse.pbrt", "X"));
    assert!(a.contains("Area(radiance: (2"), "{a}");
}

#[test]
fn cylinders_and_partial_disks_have_pbrts_surface_area_and_outward_normals() {
    let text = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\n\
        Film \"image\" \"integer xresolution\" 4 \"integer yresolution\" 4\nWorldBegin\n\
        Shape \"cylinder\" \"float radius\" 0.5 \"float zmin\" -1 \"float zmax\" 1 \"float phimax\" 270\n\
        Shape \"disk\" \"float radius\" 1 \"float innerradius\" 0.5 \"float phimax\" 90 \"float height\" 2\n";
    let path = write("cylinder_disk.pbrt", text);
    let mut app = app_from_file(&path, spp(1));
    app.setup().unwrap();
    let meshes = &app.resources.meshes;
    assert_eq!(meshes.len(), 2);
    let area = |m: &prism::mesh::MeshData| {
        m.indices
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| m.positions[i as usize].as_dvec3());
                0.5 * (b - a).cross(c - a).length()
            })
            .sum::<f64>()
    };
    let (cyl, disk) = (meshes.get(prism::mesh::MeshHandle(0)), meshes.get(prism::mesh::MeshHandle(1)));
    // Lateral area 2 pi r h (phimax / 360) = 2 pi 0.5 2 0.75; annulus sector (r^2 - ri^2) phimax / 2; within what
    // 64 segments a turn lose (the disk's chords: 1 - sin(d) / d = 0.16% for d = 2 pi / 64).
    let (want_cyl, want_disk) = (std::f64::consts::PI * 1.5, 0.75 * std::f64::consts::FRAC_PI_2 / 2.0);
    assert!((area(cyl) / want_cyl - 1.0).abs() < 1e-3, "cylinder area {} vs {want_cyl}", area(cyl));
    assert!((area(disk) / want_disk - 1.0).abs() < 2e-3, "disk sector area {} vs {want_disk}", area(disk));
    // Nothing beyond phimax: every cylinder point has angle in [0, 270] degrees, every disk point in [0, 90].
    let angle = |p: glam::Vec3| p.y.atan2(p.x).to_degrees().rem_euclid(360.0);
    assert!(cyl.positions.iter().all(|p| angle(*p) <= 270.0 + 1e-3 || p.x.hypot(p.y) < 1e-6));
    assert!(disk.positions.iter().all(|p| angle(*p) <= 90.0 + 1e-3));
    // The cylinder's vertex normals and its triangles' winding point outwards.
    assert_eq!(cyl.normals.len(), cyl.positions.len(), "vertex normals");
    for (p, n) in cyl.positions.iter().zip(&cyl.normals) {
        assert!(n.dot(glam::Vec3::new(p.x, p.y, 0.0)) > 0.0, "normal {n} at {p}");
    }
    for t in &cyl.indices {
        let [a, b, c] = t.map(|i| cyl.positions[i as usize]);
        let centre = (a + b + c) / 3.0;
        assert!((b - a).cross(c - a).dot(glam::Vec3::new(centre.x, centre.y, 0.0)) > 0.0, "inward triangle");
    }
}

#[test]
fn curves_become_tubes_of_their_width_around_pbrts_bezier_segments() {
    // A straight cubic Bézier along x (one segment) and a three-segment B-spline, both of width 0.2.
    let text = format!(
        "{HEAD_V4}WorldBegin\nShape \"curve\" \"string type\" \"cylinder\" \"point3 P\" [0 0 0 1 0 0 2 0 0 3 0 0] \"float width\" 0.2\n\
         Shape \"curve\" \"string basis\" \"bspline\" \"point3 P\" [0 0 5 1 0 5 2 0 5 3 0 5 4 0 5 5 0 5] \"float width\" 0.2\n"
    );
    let ron = ron_of(&write("curves.pbrt", &text));
    let d = desc(&ron);
    assert_eq!(d.meshes.len(), 2, "one mesh per curve");
    let per_segment = 2 * 4 * 6;
    let mut counts: Vec<usize> = d.meshes.values().map(|m| m.indices.len()).collect();
    counts.sort();
    assert_eq!(counts, vec![per_segment, 3 * per_segment], "1 and 3 segments (a B-spline of 6 points has 3)");
    for m in d.meshes.values() {
        for (v, n) in m.positions.iter().zip(&m.normals) {
            let radial = (v[1] * v[1] + (v[2] - if v[2] > 2.5 { 5.0 } else { 0.0 }).powi(2)).sqrt();
            assert!((radial - 0.1).abs() < 1e-5, "vertex {v:?} is {radial} from the axis, not half the width");
            assert!(n[0].abs() < 1e-5, "a straight tube's normals are radial: {n:?}");
        }
    }
    // pbrt's B-spline segments end at the knots' averages: the 6-point spline spans x in [1, 4].
    let xs = d.meshes.values().filter(|m| m.positions[0][2] > 2.5).flat_map(|m| m.positions.iter().map(|v| v[0]));
    let (lo, hi) = xs.fold((f32::MAX, f32::MIN), |(a, b), x| (a.min(x), b.max(x)));
    assert!((lo - 1.0).abs() < 1e-5 && (hi - 4.0).abs() < 1e-5, "{lo} {hi}");
    // Control points that make no whole segment are refused at their line.
    let bad = format!("{HEAD_V4}WorldBegin\nShape \"curve\" \"point3 P\" [0 0 0 1 0 0 2 0 0]\n");
    let Err(err) = convert_file(&write("curves2.pbrt", &bad), Path::new(".")) else { panic!("3 points are no cubic") };
    assert!(err.to_string().contains("curves2.pbrt:") && err.to_string().contains("control points"), "{err}");
}

#[test]
fn a_checkerboard_texture_alternates_its_two_values_on_pbrts_cells() {
    let text = format!(
        "{HEAD_V4}WorldBegin\nTexture \"c\" \"spectrum\" \"checkerboard\" \"float uscale\" 4 \"float vscale\" 2 \
         \"float udelta\" 0.25 \"rgb tex1\" [1 0 0] \"rgb tex2\" [0 0 1]\n\
         Texture \"k\" \"spectrum\" \"checkerboard\" \"integer dimension\" 3 \"rgb tex1\" [1 1 1] \"rgb tex2\" [0 0 0]\n\
         MakeNamedMaterial \"m\" \"string type\" \"diffuse\" \"texture reflectance\" \"c\"\n\
         MakeNamedMaterial \"n\" \"string type\" \"diffuse\" \"texture reflectance\" \"k\"\n"
    );
    let ron = ron_of(&write("checker.pbrt", &text));
    let d = desc(&ron);
    let Some(prism::load::schema::TextureDesc::Checker2d { uv_scale, uv_offset }) = d.textures.get("s:c") else {
        panic!("a 2D checkerboard texture: {:?}", d.textures.get("s:c"))
    };
    // Prism's uv is pbrt's (u, 1 - v): the cell parity there must be pbrt's at (u, v).
    let mut rng = prism::sampling::Rng::new(9, 9);
    for _ in 0..2000 {
        let (u, v) = (rng.next_f32(), rng.next_f32());
        let pbrt = ((4.0 * u + 0.25).floor() + (2.0 * v).floor()) as i64 % 2;
        let (x, y) = (u * uv_scale[0] + uv_offset[0], (1.0 - v) * uv_scale[1] + uv_offset[1]);
        let prism = (x.floor() + y.floor()).rem_euclid(2.0) as i64;
        if ((4.0 * u + 0.25).fract() - 0.5).abs() < 0.49 && ((2.0 * v).fract() - 0.5).abs() < 0.49 {
            assert_eq!(pbrt, prism, "pbrt uv ({u}, {v})");
        }
    }
    match material(&d, "named:m") {
        MaterialDesc::Lambert { albedo, .. } => assert_eq!(
            *albedo,
            prism::load::schema::ColorDesc::Texture(prism::load::schema::TextureRef::Mix {
                texture: "s:c".into(),
                a: [1.0, 0.0, 0.0],
                b: [0.0, 0.0, 1.0]
            }),
            "tex1 on the even cells"
        ),
        other => panic!("{other:?}"),
    }
    assert!(matches!(d.textures.get("s:k"), Some(prism::load::schema::TextureDesc::Checker3d { .. })));
}

#[test]
fn an_imagemaps_encoding_is_srgb_linear_or_a_gamma() {
    let png = crate::common::root().join("scenes/assets/checker_f.png");
    let dir = scratch("pbrt_encoding");
    std::fs::copy(&png, dir.join("t.png")).unwrap();
    let head = format!("{HEAD_V4}WorldBegin\n");
    let tex =
        |enc: &str| format!("{head}Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"t.png\" {enc}\n");
    let path = dir.join("enc.pbrt");
    for (enc, raw, gamma) in [
        ("", false, None),
        ("\"string encoding\" \"linear\"", true, None),
        ("\"string encoding\" \"gamma 2.2\"", false, Some(2.2f32)),
    ] {
        std::fs::write(&path, tex(enc)).unwrap();
        let ron = ron_of(&path);
        match desc(&ron).textures.get("s:t") {
            Some(prism::load::schema::TextureDesc::Image { raw: r, gamma: g, .. }) => {
                assert_eq!((*r, *g), (raw, gamma), "{enc}")
            }
            other => panic!("{other:?}"),
        }
    }
    std::fs::write(&path, tex("\"string encoding\" \"log\"")).unwrap();
    let Err(err) = convert_file(&path, Path::new(".")) else { panic!("an unknown encoding is refused") };
    assert!(err.to_string().contains("unknown encoding \"log\"") && err.to_string().contains("enc.pbrt:"), "{err}");
}
