//! Textures and normal maps: the two appearance scenes against their Mitsuba 3 references, texture lookups at
//! known uvs (texel centres, every wrap mode, bilinear weights, sRGB decoded per texel), normal maps (a flat map
//! changes nothing, a map of known slope tilts the normal by that slope, mirrored uvs through MikkTSpace), bump
//! maps of known slope, which colours count as zero, and every bad appearance input.

use crate::common::{app_from_ron, prism, rmse_against_reference, scratch};
use glam::{Vec2, Vec3, Vec3A};
use prism::geometry::Ray;
use prism::io::srgb_to_linear;
use prism::settings::Overrides;
use prism::texture::{ColorParam, TexImage, Wrap};

#[test]
fn cornell_rough_matches_the_mitsuba_reference() {
    // GGX conductor (Au) and GGX dielectric exactly as Mitsuba 3 evaluates them: the image mean within 1% at every
    // sample count and the RMSE falling like 1/sqrt(spp) (x4 samples: about /2).
    let rmse = rmse_against_reference("cornell_rough.ron", "cornell_rough.exr", &[4, 16, 64], 0.01);
    for k in 0..2 {
        let ratio = rmse[k] / rmse[k + 1];
        assert!((1.6..3.5).contains(&ratio), "RMSE ratio {ratio:.2} between {rmse:?}");
    }
}

#[test]
fn textured_matches_the_mitsuba_reference() {
    // An sRGB texture decoded per texel with Mitsuba's uv conventions and a normal-mapped floor.
    let rmse = rmse_against_reference("textured.ron", "textured.exr", &[4, 16, 64], 0.01);
    for k in 0..2 {
        let ratio = rmse[k] / rmse[k + 1];
        assert!((1.6..3.5).contains(&ratio), "RMSE ratio {ratio:.2} between {rmse:?}");
    }
}

/// A 4x3 image whose texel (row r, column c) is (c, r, 10 r + c).
fn grid_image() -> TexImage {
    let (w, h) = (4u32, 3u32);
    let texels = (0..h).flat_map(|r| (0..w).map(move |c| Vec3::new(c as f32, r as f32, (10 * r + c) as f32))).collect();
    TexImage::from_texels(w, h, texels).unwrap()
}

#[test]
fn texture_lookup_at_a_texel_centre_returns_that_texel() {
    // Texel (row r, column c) has its centre at ((c + 0.5) / W, (r + 0.5) / H), v downwards, no flip.
    let img = grid_image();
    for wrap in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
        for r in 0..3 {
            for c in 0..4 {
                let uv = Vec2::new((c as f32 + 0.5) / 4.0, (r as f32 + 0.5) / 3.0);
                let v = img.bilinear(uv, wrap);
                assert!(
                    (v - Vec3::new(c as f32, r as f32, (10 * r + c) as f32)).abs().max_element() < 1e-5,
                    "{wrap:?} {r} {c}: {v}"
                );
            }
        }
    }
}

#[test]
fn bilinear_weights_and_wrap_modes_follow_the_mitsuba_rules() {
    let img = grid_image();
    // Between the centres of columns 1 and 2 at 30%, row 1 exactly: x = u W - 0.5 = 1.3.
    let uv = Vec2::new(1.8 / 4.0, 1.5 / 3.0);
    let v = img.bilinear(uv, Wrap::Repeat);
    assert!((v.x - 1.3).abs() < 1e-5 && (v.y - 1.0).abs() < 1e-5, "{v}");
    // Both directions: x = 2.25, y = 0.75: weights (0.75, 0.25) x (0.25, 0.75).
    let uv = Vec2::new(2.75 / 4.0, 1.25 / 3.0);
    let v = img.bilinear(uv, Wrap::Repeat);
    assert!((v.z - (10.0 * 0.75 + 2.25)).abs() < 1e-4, "{v}");
    // u = 0: halfway between column -1 and 0.
    let at_edge = |wrap| img.bilinear(Vec2::new(0.0, 0.5 / 3.0), wrap).x;
    assert!((at_edge(Wrap::Repeat) - 1.5).abs() < 1e-5, "repeat blends column 3 with 0");
    assert!((at_edge(Wrap::Clamp) - 0.0).abs() < 1e-5, "clamp repeats column 0");
    assert!((at_edge(Wrap::Mirror) - 0.0).abs() < 1e-5, "mirror reflects column 0 onto -1");
    // Far outside: repeat tiles with period W, mirror with period 2W (column 1 mirrored at u in (1, 2) is column 2).
    let col = |u: f32, wrap| img.bilinear(Vec2::new(u, 0.5 / 3.0), wrap).x;
    assert!((col(1.0 + 1.5 / 4.0, Wrap::Repeat) - 1.0).abs() < 1e-5);
    assert!((col(1.0 + 1.5 / 4.0, Wrap::Mirror) - 2.0).abs() < 1e-5);
    assert!((col(7.3, Wrap::Clamp) - 3.0).abs() < 1e-5);
    assert!((col(-5.0 + 2.5 / 4.0, Wrap::Repeat) - 2.0).abs() < 1e-5);
}

/// A bilinear lookup's pair of neighbouring indices (`Wrap::index_pair`, which skips the division where both lie
/// inside the image) is the two indices wrapped one at a time, in every mode, for sizes 1 to 9 and indices far
/// outside on both sides, the edges included.
#[test]
fn wrapped_index_pairs_equal_the_indices_wrapped_one_at_a_time() {
    for wrap in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
        for n in 1u32..10 {
            for i in -40i64..40 {
                assert_eq!(wrap.index_pair(i, n), (wrap.index(i, n), wrap.index(i + 1, n)), "{wrap:?} n {n} i {i}");
            }
            for i in [-1_000_000_000, 1_000_000_000, i64::from(n) - 1, -i64::from(n)] {
                assert_eq!(wrap.index_pair(i, n), (wrap.index(i, n), wrap.index(i + 1, n)), "{wrap:?} n {n} i {i}");
            }
        }
    }
}

#[test]
fn srgb_textures_are_decoded_per_texel_before_interpolation() {
    let path = crate::common::root().join("scenes/assets/checker_f.png");
    let bytes = image::open(&path).unwrap().to_rgb8();
    let img = TexImage::load(&path, false).unwrap();
    let raw = TexImage::load(&path, true).unwrap();
    let dec = |b: u8| srgb_to_linear(b as f32 / 255.0);
    // Texel (row 20, column 7) and (row 20, column 8) straddle an orange/teal edge of the checkerboard.
    let (a, b) = (bytes.get_pixel(7, 20), bytes.get_pixel(8, 20));
    assert!((img.texel_at(20 * 64 + 7).x - dec(a[0])).abs() < 1e-6);
    assert!((raw.texel_at(20 * 64 + 7).x - a[0] as f32 / 255.0).abs() < 1e-6, "raw keeps byte / 255");
    let gamma = TexImage::load_decoded(&path, prism::texture::ByteDecoding::Gamma(2.2)).unwrap();
    assert!((gamma.texel_at(20 * 64 + 7).x - (a[0] as f32 / 255.0).powf(2.2)).abs() < 1e-6, "gamma: c^2.2");
    let mid = img.bilinear(Vec2::new(8.0 / 64.0, 20.5 / 64.0), Wrap::Repeat);
    let expect = 0.5 * (dec(a[0]) + dec(b[0]));
    let wrong = srgb_to_linear(0.5 * (a[0] as f32 + b[0] as f32) / 255.0);
    assert!((mid.x - expect).abs() < 1e-5, "mean of decoded texels {expect}, got {} (decoded mean: {wrong})", mid.x);
    assert!((expect - wrong).abs() > 0.01);
}

/// The BSDF's shading normal at the centre-ish of a quad facing +z (camera on +z), for a material definition.
fn shading_normal(textures: &str, materials: &str, shape: &str) -> (Vec3A, prism::bsdf::Bsdf) {
    let text = format!(
        "(camera: (eye: (0, 0, 5)), textures: {{ {textures} }}, materials: {{ {materials} }},
          entities: [(shape: {shape}, material: \"m\")])"
    );
    let mut app = app_from_ron(&text, Overrides::default());
    app.setup().unwrap_or_else(|e| panic!("{e}"));
    let scene = app.resources.scene.as_ref().unwrap();
    let ray = Ray::new(Vec3A::new(0.13, -0.21, 5.0), Vec3A::new(0.0, 0.0, -1.0));
    let hit = scene.trace(&ray).expect("hits the quad");
    let b = scene.bsdf(&hit, -ray.dir).expect("a BSDF");
    (b.normal(), b)
}

/// Write a constant-valued float normal map (EXR, exact values) and return its path.
fn constant_map(name: &str, c: Vec3) -> String {
    let dir = scratch("normalmaps");
    let path = dir.join(format!("{name}.exr"));
    prism::io::write_exr(&path, &prism::io::Image::new(2, 2, vec![c; 4])).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn a_flat_normal_map_changes_nothing() {
    let p = constant_map("flat", Vec3::new(0.5, 0.5, 1.0));
    let (n_plain, plain) = shading_normal("", "\"m\": Lambert(albedo: 0.7)", "Quad()");
    let (n_map, mapped) = shading_normal(
        &format!("\"n\": Image(path: {p:?}, raw: true)"),
        "\"base\": Lambert(albedo: 0.7), \"m\": NormalMap(material: \"base\", texture: \"n\")",
        "Quad()",
    );
    assert!((n_plain - n_map).abs().max_element() < 1e-6, "{n_plain} vs {n_map}");
    let mut rng = prism::sampling::Rng::new(3, 4);
    for _ in 0..100 {
        let wi = prism::sampling::warp::uniform_sphere(rng.next_2d());
        let (a, b) = (plain.eval(wi), mapped.eval(wi));
        assert!((a - b).abs().max_element() < 1e-6, "{wi}: {a} vs {b}");
    }
}

#[test]
fn a_normal_map_of_known_slope_tilts_the_shading_normal_by_that_slope() {
    // c = (0.75, 0.5, 1): n = (0.5, 0, 1) in (tangent, bitangent, normal); the quad's tangent (dp/du) is +x.
    let p = constant_map("slope", Vec3::new(0.75, 0.5, 1.0));
    let tex = format!("\"n\": Image(path: {p:?}, raw: true)");
    let (n, _) = shading_normal(&tex, "\"b\": Lambert(), \"m\": NormalMap(material: \"b\", texture: \"n\")", "Quad()");
    let expect = Vec3A::new(0.5, 0.0, 1.0).normalize();
    assert!((n - expect).abs().max_element() < 1e-5, "{n} vs {expect}");
    // Strength scales the slope: 2 x 0.5 = 1, a 45-degree tilt.
    let (n, _) = shading_normal(
        &tex,
        "\"b\": Lambert(), \"m\": NormalMap(material: \"b\", texture: \"n\", strength: 2)",
        "Quad()",
    );
    assert!((n - Vec3A::new(1.0, 0.0, 1.0).normalize()).abs().max_element() < 1e-5, "{n}");
    // Green along +v: c = (0.5, 0.75, 1) tilts towards dp/dv, which is +y on the default quad.
    let p = constant_map("slope_v", Vec3::new(0.5, 0.75, 1.0));
    let tex = format!("\"n\": Image(path: {p:?}, raw: true)");
    let (n, _) = shading_normal(&tex, "\"b\": Lambert(), \"m\": NormalMap(material: \"b\", texture: \"n\")", "Quad()");
    assert!((n - Vec3A::new(0.0, 0.5, 1.0).normalize()).abs().max_element() < 1e-5, "{n}");
    let (n, _) = shading_normal(
        &tex,
        "\"b\": Lambert(), \"m\": NormalMap(material: \"b\", texture: \"n\", flip_green: true)",
        "Quad()",
    );
    assert!((n - Vec3A::new(0.0, -0.5, 1.0).normalize()).abs().max_element() < 1e-5, "{n}");
}

#[test]
fn mirrored_uvs_tilt_the_normal_towards_increasing_u_through_mikktspace() {
    // An OBJ quad whose u grows towards -x (mirrored): MikkTSpace's tangent points along -x, so the same map
    // tilts the normal towards -x.
    let dir = scratch("mirrored");
    let obj = dir.join("mirrored.obj");
    std::fs::write(
        &obj,
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 1 0\nvt 0 0\nvt 0 1\nvt 1 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n",
    )
    .unwrap();
    let p = constant_map("slope_m", Vec3::new(0.75, 0.5, 1.0));
    let tex = format!("\"n\": Image(path: {p:?}, raw: true)");
    let shape = format!("Mesh(path: {:?})", obj.to_string_lossy());
    let (n, _) = shading_normal(&tex, "\"b\": Lambert(), \"m\": NormalMap(material: \"b\", texture: \"n\")", &shape);
    assert!((n - Vec3A::new(-0.5, 0.0, 1.0).normalize()).abs().max_element() < 1e-4, "{n}");
}

#[test]
fn a_bump_map_of_known_slope_tilts_the_normal_by_its_gradient() {
    // Height h(u) = 0.1 (texture value) with the value growing linearly in u between the two texel centres of a
    // 2x1 image (0 at u = 0.25, 1 at u = 0.75): dh/du = 0.2; dp/du = (2, 0, 0) on the default quad, so the normal
    // is normalize(-0.2 / 2, 0, 1).
    let dir = scratch("bump");
    let path = dir.join("ramp.exr");
    prism::io::write_exr(&path, &prism::io::Image::new(2, 1, vec![Vec3::ZERO, Vec3::ONE])).unwrap();
    let tex = format!("\"h\": Image(path: {:?}, wrap: clamp)", path.to_string_lossy());
    let (n, _) = shading_normal(
        &tex,
        "\"b\": Lambert(), \"m\": Bump(material: \"b\", height: Map(texture: \"h\", channel: R, scale: 0.1))",
        "Quad()",
    );
    let expect = Vec3A::new(-0.1, 0.0, 1.0).normalize();
    assert!((n - expect).abs().max_element() < 1e-3, "{n} vs {expect}");
}

/// Render a one-line scene through the CLI; it must fail with one line containing `needle`.
fn fails_with(scene: &str, needle: &str) {
    let dir = scratch("badappearance");
    let path = dir.join("bad.ron");
    std::fs::write(&path, scene).unwrap();
    let o = prism(&["render", path.to_str().unwrap(), "-o", dir.join("o.png").to_str().unwrap(), "-q"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{scene}: should fail");
    assert!(err.contains(needle), "{scene}: error should mention {needle:?}: {err}");
    assert_eq!(err.trim().lines().count(), 1, "one-line error: {err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_textures_and_materials_are_one_line_errors_naming_them() {
    let dir = scratch("badappearance");
    std::fs::write(dir.join("garbage.png"), b"this is not a png").unwrap();
    let grey = image::GrayImage::from_pixel(2, 2, image::Luma([128u8]));
    grey.save(dir.join("grey.png")).unwrap();
    let rgb = image::RgbImage::from_pixel(2, 2, image::Rgb([128u8, 128, 255]));
    rgb.save(dir.join("rgb.png")).unwrap();
    let scene = |textures: &str, materials: &str| {
        format!(
            "(camera: (), textures: {{ {textures} }}, materials: {{ {materials} }}, entities: [(shape: Sphere(), material: \"m\")])"
        )
    };
    fails_with(&scene("\"t\": Image(path: \"missing.png\")", "\"m\": Lambert(albedo: Texture(\"t\"))"), "missing.png");
    fails_with(&scene("\"t\": Image(path: \"garbage.png\")", "\"m\": Lambert(albedo: Texture(\"t\"))"), "garbage.png");
    fails_with(&scene("\"t\": Marble()", "\"m\": Lambert(albedo: Texture(\"t\"))"), "material 'm'");
    fails_with(&scene("\"t\": Image(path: \"rgb.png\")", "\"m\": RoughConductor(alpha: Texture(\"t\"))"), "channel");
    fails_with(&scene("", "\"m\": RoughConductor(alpha: 1.5)"), "alpha");
    fails_with(&scene("", "\"m\": RoughDielectric(alpha: NaN)"), "material 'm'");
    fails_with(&scene("", "\"m\": Lambert(albedo: (NaN, 0, 0))"), "albedo");
    fails_with(&scene("", "\"m\": RoughConductor(material: \"Unobtainium\")"), "Unobtainium");
    fails_with(&scene("", "\"m\": Lambert(albedo: Texture(\"nope\"))"), "unknown texture 'nope'");
    fails_with(&scene("", "\"m\": Blend(a: \"m\", b: \"m\", weight: 0.5)"), "refers to itself");
    fails_with(
        &scene(
            "\"t\": Image(path: \"grey.png\", raw: true)",
            "\"b\": Lambert(), \"m\": NormalMap(material: \"b\", texture: \"t\")",
        ),
        "zero-length normal",
    );
    fails_with(
        &scene(
            "\"t\": Image(path: \"rgb.png\", raw: true)",
            "\"b\": Lambert(), \"n\": NormalMap(material: \"b\", texture: \"t\"), \"m\": Blend(a: \"n\", b: \"b\", weight: 0.5)",
        ),
        "outermost",
    );
}

#[test]
fn extreme_texture_values_never_make_nan_pixels() {
    // Huge HDR texels, a grazing normal map and out-of-range textured roughness (clamped to [0, 1]) still give
    // finite pixels.
    let dir = scratch("extreme");
    let big = dir.join("big.exr");
    prism::io::write_exr(
        &big,
        &prism::io::Image::new(2, 2, vec![Vec3::splat(1e30), Vec3::ZERO, Vec3::splat(5.0), Vec3::ONE]),
    )
    .unwrap();
    let steep = constant_map("steep", Vec3::new(1.0, 0.5, 0.5005));
    let text = format!(
        "(camera: (eye: (0, 0, 4), size: (32, 32)), render: (integrator: envlight(max_depth: 4)),
          textures: {{\"big\": Image(path: {:?}), \"steep\": Image(path: {steep:?}, raw: true)}},
          materials: {{
            \"metal\": RoughConductor(alpha: Map(texture: \"big\", channel: R), reflectance: 0.9),
            \"base\": Lambert(albedo: 0.5), \"m\": NormalMap(material: \"base\", texture: \"steep\"),
          }},
          entities: [(shape: Sphere(center: (-0.6, 0, 0), radius: 0.5), material: \"metal\"),
                     (shape: Quad(), material: \"m\", transform: [Translate((0.6, 0, 0)), UniformScale(0.5)]),
                     (light: Environment())])",
        big.to_string_lossy()
    );
    let img = crate::common::render_ron(&text, crate::common::spp(4));
    assert!(img.pixels.iter().all(|p| p.is_finite()), "non-finite pixels");
}

#[test]
fn sphere_texture_coordinates_are_computed_only_where_a_material_or_light_reads_them() {
    // A sphere's (u, v) and dp/du, dp/dv cost an atan2 and an acos per hit; only textures, normal and bump maps
    // and emitters (textured radiance, sampling density) read them, so plain materials get zeros instead.
    let text = r#"(camera: (),
      textures: { "t": Image(path: "assets/checker_f.png"), "m": Marble() },
      materials: { "plain": Lambert(albedo: (0.5, 0.5, 0.5)), "tex": Lambert(albedo: Texture("t")),
                   "blend": Blend(a: "plain", b: "rough", weight: Texture("m")), "rough": RoughConductor(alpha: 0.2) },
      entities: [
        (shape: Sphere(center: (-3, 0, 0), radius: 0.5), material: "plain"),
        (shape: Sphere(center: (-1, 0, 0), radius: 0.5), material: "tex"),
        (shape: Sphere(center: (1, 0, 0), radius: 0.5), material: "blend"),
        (shape: Sphere(center: (3, 0, 0), radius: 0.5), material: "rough"),
        (shape: Sphere(center: (0, 3, 0), radius: 0.5), material: "plain", light: Area(radiance: (1, 1, 1))),
      ])"#;
    let mut app = app_from_ron(text, Overrides::default());
    app.setup().expect("the scene loads");
    let scene = app.resources.scene.as_ref().expect("a scene");
    let flags: Vec<bool> = scene.prims.spheres.iter().map(|s| s.coordinates).collect();
    assert_eq!(
        flags,
        [false, true, true, false, true],
        "plain, image-textured, blended by a solid texture, rough metal, emitter"
    );
    for (x, computed) in [(-3.0f32, false), (-1.0, true)] {
        let centre = Vec3A::new(x, 0.0, 0.0);
        let s = scene.trace(&Ray::new(Vec3A::new(x + 0.1, 0.2, 5.0), Vec3A::NEG_Z)).unwrap();
        if computed {
            let (uv, dpdu, dpdv) = prism::primitives::sphere_uv((s.p - centre).normalize(), 0.5);
            assert!((s.uv - uv).abs().max_element() < 1e-5, "{:?} vs {uv:?}", s.uv);
            assert!((s.dpdu - dpdu).abs().max_element() < 1e-4 && (s.dpdv - dpdv).abs().max_element() < 1e-4);
            assert!(s.uv != Vec2::ZERO && s.dpdu.length() > 0.1);
        } else {
            assert_eq!((s.uv, s.dpdu, s.dpdv), (Vec2::ZERO, Vec3A::ZERO, Vec3A::ZERO));
        }
    }
}

#[test]
fn a_colour_is_zero_exactly_when_every_component_equals_zero() {
    // `ColorParam::is_zero` decides which lobes a material has (a zero lobe is left out, and a Phong material with
    // only a constant diffuse colour takes the one-Lambert-lobe path); it compares bits, and must agree with
    // `== 0.0` per component: both zeros count, NaN, denormals and anything else do not.
    let specials = [
        0.0,
        -0.0,
        f32::MIN_POSITIVE,
        -f32::from_bits(1),
        f32::from_bits(1),
        1.0,
        -2.5,
        f32::NAN,
        -f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::MAX,
    ];
    for &x in &specials {
        for &y in &specials {
            for &z in &specials {
                let c = Vec3::new(x, y, z);
                let expected = x == 0.0 && y == 0.0 && z == 0.0;
                assert_eq!(ColorParam::Const(c).is_zero(), expected, "{c:?}");
            }
        }
    }
    assert!(!ColorParam::Map { tex: 0, scale: Vec3::ZERO }.is_zero(), "a texture is never the constant 0");
}

#[test]
fn the_one_lambert_lobe_shortcut_gives_the_general_bsdf_and_only_plain_lambert_materials_take_it() {
    // `MaterialSet` classifies materials when the scene is built; a Phong-family material whose only term is a
    // constant diffuse colour is resolved at a hit without the general lobe assembly. The shortcut must change no
    // number: the BSDF it builds reflects exactly what the one Lambertian lobe of the general assembly reflects
    // (albedo / pi times the cosine, cosine-distributed samples), front and back, and every other material —
    // textured, with ambient, specular, mirror or glass terms, another kind — must not take it.
    use prism::bsdf::{Bsdf, Lobe};
    use prism::material::{Material, MaterialKind, MaterialSet, PhongParams};
    use prism::primitives::{Primitives, SurfaceHit};
    use prism::texture::{ScalarParam, TextureSet};
    let albedo = Vec3::new(0.7, 0.5, 0.3);
    let with = |p: PhongParams| Material::phong("m", p);
    let base = PhongParams { diffuse: ColorParam::Const(albedo), ..PhongParams::default() };
    let mut one_sided = Material::lambert("one-sided", albedo);
    one_sided.two_sided = false;
    let list = vec![
        Material::lambert("plain", albedo),
        one_sided,
        Material::lambert("black", Vec3::ZERO),
        with(PhongParams { diffuse: ColorParam::Map { tex: 0, scale: Vec3::ONE }, ..PhongParams::default() }),
        with(PhongParams { ambient: ColorParam::Const(Vec3::splat(0.1)), ..base.clone() }),
        with(PhongParams {
            specular: ColorParam::Const(Vec3::splat(0.2)),
            exponent: ScalarParam::Const(20.0),
            ..base.clone()
        }),
        with(PhongParams { reflective: ColorParam::Const(Vec3::splat(0.2)), ..base.clone() }),
        with(PhongParams { transparent: ColorParam::Const(Vec3::splat(0.2)), ..base.clone() }),
        Material {
            name: "blend".into(),
            kind: MaterialKind::Blend { a: 0, b: 0, weight: ScalarParam::Const(0.5) },
            two_sided: true,
        },
    ];
    let set = MaterialSet::new(list);
    let shortcut: Vec<bool> = (0..10).map(|id| set.lambert(id).is_some()).collect();
    assert_eq!(shortcut, [true, true, true, false, false, false, false, false, false, false]);
    assert_eq!(set.lambert(0), Some(albedo));

    let n = Vec3A::new(0.3, 0.4, 0.866).normalize();
    let hit = |material: u32| SurfaceHit {
        p: Vec3A::ZERO,
        p_err: Vec3A::ZERO,
        ng: n,
        ns: n,
        uv: Vec2::ZERO,
        dpdu: Vec3A::X,
        dpdv: Vec3A::Y,
        t: 1.0,
        prim: 0,
        material,
        light: u32::MAX,
    };
    let (textures, prims) = (TextureSet::default(), Primitives::default());
    let resolve = |material: u32, wo: Vec3A| {
        let mut b = Bsdf::from_lobes(Vec3A::Z, Vec3A::Z, &[Lobe::Diffuse { albedo: Vec3::ONE }]).unwrap();
        prism::material::bsdf_into(&set, &textures, &prims, &hit(material), wo, None, &mut b).then_some(b)
    };
    for wo in [Vec3A::new(0.1, -0.2, 1.0).normalize(), Vec3A::new(-0.5, 0.3, -0.8).normalize()] {
        let general = Bsdf::from_lobes(n, wo, &[Lobe::Diffuse { albedo }]).expect("a lit lobe");
        let fast = resolve(0, wo).expect("two-sided plain Lambert reflects on both sides");
        for k in 0..16 {
            let u = Vec2::new((k as f32 + 0.5) / 16.0, ((k * 7) % 16) as f32 / 16.0 + 0.03);
            let (a, b) = (fast.sample(0.5, u).unwrap(), general.sample(0.5, u).unwrap());
            assert_eq!((a.wi, a.weight, a.pdf, a.delta), (b.wi, b.weight, b.pdf, b.delta), "wo {wo}, u {u}");
            assert_eq!(fast.eval(a.wi), general.eval(a.wi));
        }
        // The one-sided copy reflects only on the normal's side; black reflects nothing.
        assert_eq!(resolve(1, wo).is_some(), wo.dot(n) >= 0.0, "wo {wo}");
        assert!(resolve(2, wo).is_none());
    }
}

/// A colour mixed by a 2D checkerboard: every pixel of a Lambertian sphere under a uniform white sky is one of
/// the two colours (its albedo), and both cover a good share of the sphere.
#[test]
fn a_checkerboard_mix_paints_each_cell_one_of_its_two_colours() {
    let scene = "(
    camera: (eye: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0), fov: 30, size: (48, 48)),
    render: (filter: Box()),
    textures: { \"c\": Checker2d(uv_scale: (8, 4)) },
    materials: { \"m\": Lambert(albedo: Mix(texture: \"c\", a: (0.8, 0.1, 0.1), b: (0.1, 0.1, 0.8))) },
    entities: [(shape: Sphere(), material: \"m\"), (light: Environment(radiance: (1, 1, 1)))],
)";
    let mut o = crate::common::spp(16);
    o.integrator = Some("envlight".into());
    let img = crate::common::render_ron(scene, o);
    let (mut red, mut blue) = (0, 0);
    for p in &img.pixels {
        if (*p - glam::Vec3::new(0.8, 0.1, 0.1)).abs().max_element() < 0.02 {
            red += 1;
        } else if (*p - glam::Vec3::new(0.1, 0.1, 0.8)).abs().max_element() < 0.02 {
            blue += 1;
        }
    }
    assert!(red > 150 && blue > 150, "{red} red and {blue} blue pixels of {}", img.pixels.len());
}
