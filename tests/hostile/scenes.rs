//! Hostile scenes: every number of a RON scene replaced by NaN, infinities, huge, negative, zero and denormal
//! values; RON text truncated, with characters deleted, brackets unbalanced, bytes that are not UTF-8; 6.837
//! scenes with numbers, braces and counts mutated; OBJ/MTL files with bad indices, values and structure.

use super::{Case, Expect, dir};
use crate::common::{data, root};
use std::path::Path;

/// A small deterministic generator (SplitMix64).
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// The hostile replacements for a number.
const VALUES: [&str; 9] = ["NaN", "inf", "-inf", "1e39", "3e38", "-1", "0", "1e-45", "-0"];

/// Byte ranges of the numbers in `text` (outside strings and comments).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let (mut in_str, mut in_comment) = (false, false);
    while i < b.len() {
        let c = b[i];
        if in_comment {
            in_comment = c != b'\n';
        } else if in_str {
            in_str = c != b'"' || b[i - 1] == b'\\';
        } else if c == b'"' {
            in_str = true;
        } else if c == b'/' && b.get(i + 1) == Some(&b'/') {
            in_comment = true;
        } else if (c.is_ascii_digit() || c == b'-')
            && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'))
        {
            let start = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_digit() || b".eE-+".contains(&b[i])) {
                i += 1;
            }
            if b[start..i].iter().any(u8::is_ascii_digit) {
                out.push((start, i));
            }
            continue;
        }
        i += 1;
    }
    out
}

fn render_case(class: &'static str, name: String, scene: &Path, extra: &[&str], expect: Expect) -> Case {
    let out = scene.with_extension("out.png");
    let mut args: Vec<&dyn AsRef<std::ffi::OsStr>> = vec![&"render", &scene, &"-o", &out, &"-q", &"--threads", &"1"];
    for e in extra {
        args.push(e);
    }
    Case::new(class, name, &args, expect)
}

fn ron_cases(v: &mut Vec<Case>) {
    let d = dir("ron");
    let base = "(
    camera: (eye: (0, 0.5, 4), target: (0, 0, 0), up: (0, 1, 0), fov: 40, size: (8, 8), aperture_radius: 0.01),
    render: (spp: 2, passes: 2, seed: 3, exposure: 0.5, filter: Tent(radius: 1)),
    materials: {
        \"a\": Lambert(albedo: (0.5, 0.4, 0.3)),
        \"b\": Phong(diffuse: 0.2, specular: 0.5, exponent: 20, reflective: 0.3, transparent: 0.2, ior: 1.4),
        \"c\": RoughConductor(alpha: 0.2, reflectance: (0.9, 0.8, 0.7)),
        \"d\": RoughDielectric(alpha: 0.1, ior: 1.5),
    },
    entities: [
        (name: \"ball\", shape: Sphere(center: (0, 0, 0), radius: 1), material: \"b\"),
        (name: \"floor\", shape: Plane(normal: (0, 1, 0), offset: -1), material: \"a\"),
        (name: \"tri\", shape: Triangle(vertices: ((0, 0, 0), (1, 0, 0), (0, 1, 0))), material: \"c\"),
        (name: \"box\", shape: Cube, material: \"d\", transform: [Translate((1, 0, 0)), Rotate(axis: (0, 1, 0), degrees: 30), Scale((0.2, 0.3, 0.4))]),
        (name: \"lamp\", shape: Quad(), light: Area(radiance: (5, 5, 5)), transform: [Translate((0, 2, 0)), Euler((90, 0, 0)), UniformScale(0.5)]),
        (name: \"bulb\", light: Point(intensity: (3, 3, 3), position: (1, 2, 1), attenuation: (0, 0, 1))),
        (name: \"spot\", light: Spot(intensity: (3, 3, 3), position: (0, 3, 0), direction: (0, -1, 0), cone_angle: 30, falloff: 5)),
        (name: \"sun\", light: Directional(irradiance: (1, 1, 1), direction: (0, -1, -1))),
        (name: \"sky\", light: Environment(radiance: (0.1, 0.1, 0.2), scale: 2)),
    ],
)";
    let good = d.join("base.ron");
    std::fs::write(&good, base).unwrap();
    v.push(render_case("ron values", "the base scene".into(), &good, &[], Expect::Ok));
    for integrator in ["phong", "envlight", "ppm(photons: 64)", "debug(mode: normals)", "debug(mode: depth)"] {
        v.push(render_case(
            "ron values",
            format!("base with {integrator}"),
            &good,
            &["--integrator", integrator],
            Expect::Ok,
        ));
    }
    // Every number replaced by every hostile value would be ~1000 renders: every number gets three values,
    // cycling through the list.
    let nums = numbers(base);
    for (k, (a, b)) in nums.iter().enumerate() {
        for j in 0..3 {
            let value = VALUES[(3 * k + j) % VALUES.len()];
            let text = format!("{}{value}{}", &base[..*a], &base[*b..]);
            let p = d.join(format!("n{k}_{j}.ron"));
            std::fs::write(&p, &text).unwrap();
            let ctx = &base[a.saturating_sub(24)..*a];
            let name = format!("`{}` -> {value} after `{}`", &base[*a..*b], ctx.replace('\n', " "));
            // The envlight integrator samples every light by power: overflow is caught there too.
            v.push(render_case("ron values", name, &p, &["--integrator", "envlight"], Expect::Either));
        }
    }
    // Syntax: truncations, deleted characters, unbalanced brackets, invalid UTF-8, empty, huge strings.
    let mut rng = Rng(11);
    let cornell = std::fs::read_to_string(root().join("scenes/cornell_box.ron")).unwrap();
    for k in 0..20 {
        let cut = rng.below(cornell.len());
        let cut = (0..=cut).rev().find(|i| cornell.is_char_boundary(*i)).unwrap();
        let p = d.join(format!("trunc{k}.ron"));
        std::fs::write(&p, &cornell[..cut]).unwrap();
        v.push(render_case(
            "ron syntax",
            format!("cornell truncated at {cut}"),
            &p,
            &["--size", "8x8", "--spp", "1"],
            Expect::Error,
        ));
    }
    for k in 0..25 {
        let mut t = cornell.clone().into_bytes();
        let at = rng.below(t.len());
        let what = match k % 5 {
            0 => {
                t.remove(at);
                "deleted"
            }
            1 => {
                t.insert(at, b'(');
                "( inserted"
            }
            2 => {
                t.insert(at, b']');
                "] inserted"
            }
            3 => {
                t[at] = 0xff;
                "0xff byte"
            }
            _ => {
                t.insert(at, b',');
                ", inserted"
            }
        };
        let p = d.join(format!("mut{k}.ron"));
        std::fs::write(&p, &t).unwrap();
        v.push(render_case(
            "ron syntax",
            format!("cornell, {what} at {at}"),
            &p,
            &["--size", "8x8", "--spp", "1"],
            Expect::Either,
        ));
    }
    let specials: Vec<(&str, String, Expect)> = vec![
        ("empty file", String::new(), Expect::Error),
        ("only a comment", "// nothing".into(), Expect::Error),
        ("byte order mark", format!("\u{feff}{}", "(camera: (size: (8, 8)))"), Expect::Either),
        ("no camera", "(entities: [(shape: Sphere())])".into(), Expect::Error),
        ("two cameras", "(camera: (size: (8, 8)), camera: (size: (8, 8)))".into(), Expect::Error),
        ("unknown field", "(camera: (size: (8, 8)), cameras: ())".into(), Expect::Error),
        ("unknown shape", "(camera: (size: (8, 8)), entities: [(shape: Torus())])".into(), Expect::Error),
        ("unknown material", "(camera: (size: (8, 8)), entities: [(shape: Sphere(), material: \"x\")])".into(), Expect::Error),
        ("size 0x0", "(camera: (size: (0, 0)))".into(), Expect::Error),
        ("size 99999x8", "(camera: (size: (99999, 8)))".into(), Expect::Error),
        ("size -1", "(camera: (size: (-1, 8)))".into(), Expect::Error),
        ("size 2^32", "(camera: (size: (4294967296, 8)))".into(), Expect::Error),
        ("spp 0", "(camera: (size: (8, 8)), render: (spp: 0))".into(), Expect::Error),
        ("passes above spp (clamped to spp)", "(camera: (size: (8, 8)), render: (spp: 2, passes: 3))".into(), Expect::Ok),
        ("grid 0", "(camera: (size: (8, 8)), render: (grid: (0, 1, 1)))".into(), Expect::Error),
        ("grid 10^4 cubed", "(camera: (size: (8, 8)), render: (grid: (10000, 10000, 10000)))".into(), Expect::Error),
        ("integrator number", "(camera: (size: (8, 8)), render: (integrator: 5))".into(), Expect::Error),
        ("integrator unclosed", "(camera: (size: (8, 8)), render: (integrator: phong(max_depth: 2)".into(), Expect::Error),
        ("huge name", format!("(camera: (size: (8, 8)), entities: [(name: \"{}\", shape: Sphere())])", "x".repeat(1 << 20)), Expect::Ok),
        ("control characters in a name", "(camera: (size: (8, 8)), entities: [(name: \"\\u{1b}[2J\\u{7}\", shape: Sphere(radius: 0))])".into(), Expect::Error),
        ("deep brackets", format!("(camera: (size: (8, 8)), background: {}1{})", "(".repeat(50_000), ")".repeat(50_000)), Expect::Error),
        ("deep children", format!("(camera: (size: (8, 8)), entities: [{}(shape: Sphere()){}])", "(children: [".repeat(20_000), "])".repeat(20_000)), Expect::Error),
        ("matrix not affine", "(camera: (size: (8, 8)), entities: [(shape: Sphere(), transform: [Matrix(((1,0,0,0),(0,1,0,0),(0,0,1,0),(1,0,0,1)))])])".into(), Expect::Error),
        ("transform underflows", "(camera: (size: (8, 8)), entities: [(transform: [UniformScale(1e-20)], children: [(transform: [UniformScale(1e-20)], shape: Sphere())])])".into(), Expect::Error),
        ("transform overflows", "(camera: (size: (8, 8)), entities: [(transform: [UniformScale(1e20)], children: [(transform: [UniformScale(1e20)], shape: Sphere())])])".into(), Expect::Error),
        ("two environments", "(camera: (size: (8, 8)), entities: [(light: Environment()), (light: Environment())])".into(), Expect::Error),
        ("missing mesh", "(camera: (size: (8, 8)), entities: [(shape: Mesh(path: \"nope.obj\"))])".into(), Expect::Error),
        ("mesh not obj", "(camera: (size: (8, 8)), entities: [(shape: Mesh(path: \"x.stl\"))])".into(), Expect::Error),
        ("texture cycle name", "(camera: (size: (8, 8)), materials: {\"m\": Blend(a: \"m\", b: \"m\", weight: 0.5)}, entities: [(shape: Sphere(), material: \"m\")])".into(), Expect::Error),
        ("emissive and light", "(camera: (size: (8, 8)), materials: {\"e\": Emissive(radiance: 1)}, entities: [(shape: Quad(), material: \"e\", light: Area(radiance: (1,1,1)))])".into(), Expect::Error),
    ];
    for (k, (name, text, expect)) in specials.into_iter().enumerate() {
        let p = d.join(format!("special{k}.ron"));
        std::fs::write(&p, text).unwrap();
        v.push(render_case("ron syntax", name.into(), &p, &[], expect));
    }
}

fn mit6837_cases(v: &mut Vec<Case>) {
    let d = dir("6837");
    let mut rng = Rng(6837);
    let scenes = [
        "assignment4/scene4_04_reflective_sphere.txt",
        "assignment2/scene2_05_inside_sphere.txt",
        "assignment3/scene3_05_axes_cube.txt",
        "assignment5/scene5_12_nested_transformations.txt",
        "assignment7/scene7_02_checkerboard.txt",
    ];
    for s in scenes {
        let src = data(&format!("mit6837/{s}"));
        let Ok(text) = std::fs::read_to_string(&src) else { continue };
        let stem = src.file_stem().unwrap().to_string_lossy().into_owned();
        // Keep the scene's meshes resolvable: write the mutants beside the original's copies.
        for mesh in std::fs::read_dir(src.parent().unwrap()).unwrap().flatten() {
            if mesh.path().extension().is_some_and(|e| e == "obj") {
                let _ = std::fs::copy(mesh.path(), d.join(mesh.file_name()));
            }
        }
        let nums = numbers(&text);
        for k in 0..8 {
            let (a, b) = nums[rng.below(nums.len())];
            let value = ["nan", "inf", "1e39", "-5", "0", "3e38", "abc", "1e-45"][k];
            let p = d.join(format!("{stem}_n{k}.txt"));
            std::fs::write(&p, format!("{}{value}{}", &text[..a], &text[b..])).unwrap();
            v.push(render_case(
                "6.837",
                format!("{stem}: `{}` -> {value}", &text[a..b]),
                &p,
                &["--size", "8x8"],
                Expect::Either,
            ));
        }
        let braces: Vec<usize> = text.match_indices(['{', '}']).map(|(i, _)| i).collect();
        for k in 0..3 {
            let at = braces[rng.below(braces.len())];
            let p = d.join(format!("{stem}_b{k}.txt"));
            std::fs::write(&p, format!("{}{}", &text[..at], &text[at + 1..])).unwrap();
            v.push(render_case(
                "6.837",
                format!("{stem}: brace at {at} deleted"),
                &p,
                &["--size", "8x8"],
                Expect::Error,
            ));
        }
        for k in 0..3 {
            let cut = rng.below(text.len());
            let p = d.join(format!("{stem}_t{k}.txt"));
            std::fs::write(&p, &text[..cut]).unwrap();
            v.push(render_case("6.837", format!("{stem}: truncated at {cut}"), &p, &["--size", "8x8"], Expect::Error));
        }
        for (k, from, to) in [
            (0, "numObjects", "numObjects 99999999999999999999 x"),
            (1, "Sphere", "Cylinder"),
            (2, "MaterialIndex", "MaterialIndex 4000000000\nMaterialIndex"),
        ] {
            if text.contains(from) {
                let p = d.join(format!("{stem}_k{k}.txt"));
                std::fs::write(&p, text.replacen(from, to, 1)).unwrap();
                v.push(render_case("6.837", format!("{stem}: {from} -> {to}"), &p, &["--size", "8x8"], Expect::Error));
            }
        }
    }
}

fn obj_cases(v: &mut Vec<Case>) {
    let d = dir("obj");
    let good_mtl = "newmtl a\nKd 0.5 0.5 0.5\nKs 0.1 0.1 0.1\nNs 10\nnewmtl glass\nillum 7\nNi 1.5\nTf 1 1 1\n";
    let good = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nusemtl a\nf 1/1/1 2/2/1 3/3/1\nusemtl glass\nf 2 4 3\n";
    std::fs::write(d.join("m.mtl"), good_mtl).unwrap();
    let objs: Vec<(&str, String, Expect)> = vec![
        ("good", good.into(), Expect::Ok),
        ("empty", String::new(), Expect::Error),
        ("no faces", "v 0 0 0\nv 1 0 0\nv 0 1 0\n".into(), Expect::Error),
        ("index 0", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n".into(), Expect::Error),
        ("index beyond", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n".into(), Expect::Error),
        ("index 2^40", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 1099511627776\n".into(), Expect::Error),
        ("negative beyond", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -9\n".into(), Expect::Error),
        ("texcoord beyond", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n".into(), Expect::Error),
        ("two corners", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n".into(), Expect::Error),
        ("nan vertex", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".into(), Expect::Error),
        ("inf vertex", "v 0 0 inf\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".into(), Expect::Error),
        ("huge vertex", "v 0 0 1e30\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".into(), Expect::Error),
        ("nan normal", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn nan 0 1\nf 1//1 2//1 3//1\n".into(), Expect::Error),
        ("word vertex", "v 0 zero 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".into(), Expect::Error),
        ("short vertex", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".into(), Expect::Error),
        ("all degenerate", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n".into(), Expect::Either),
        (
            "50000-gon",
            format!(
                "{}f {}\n",
                (0..50_000)
                    .map(|i| format!("v {} {} 0\n", (i as f32 * 1e-4).cos(), (i as f32 * 1e-4).sin()))
                    .collect::<String>(),
                (1..=50_000).map(|i| i.to_string()).collect::<Vec<_>>().join(" ")
            ),
            Expect::Ok,
        ),
        ("missing mtl", "mtllib nope.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n".into(), Expect::Ok),
        ("mtl is a directory", "mtllib sub\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n".into(), Expect::Ok),
        ("binary garbage", "\u{0}\u{1}\u{2}v 1 2\u{0}".into(), Expect::Error),
    ];
    std::fs::create_dir_all(d.join("sub")).unwrap();
    for (k, (name, text, expect)) in objs.into_iter().enumerate() {
        let p = d.join(format!("o{k}.obj"));
        std::fs::write(&p, text).unwrap();
        v.push(render_case("obj/mtl", format!("obj: {name}"), &p, &["--size", "8x8", "--spp", "1"], expect));
    }
    let mtls: Vec<(&str, &str, Expect)> = vec![
        ("Kd -1", "newmtl a\nKd -1 0 0\n", Expect::Error),
        ("Kd nan", "newmtl a\nKd nan 0 0\n", Expect::Error),
        ("Kd one number", "newmtl a\nKd 0.5\n", Expect::Either),
        ("Ks inf", "newmtl a\nKs inf 0 0\n", Expect::Error),
        ("Ke 1e39", "newmtl a\nKe 1e39 0 0\n", Expect::Error),
        ("Ke 3e38", "newmtl a\nKe 3e38 3e38 3e38\n", Expect::Error),
        ("Ns -5", "newmtl a\nNs -5\n", Expect::Error),
        ("Ns nan", "newmtl a\nNs nan\n", Expect::Error),
        ("Ni 0 glass", "newmtl a\nillum 7\nNi 0\n", Expect::Error),
        ("Tf words", "newmtl a\nillum 7\nTf red\n", Expect::Error),
        ("Tf -1", "newmtl a\nillum 4\nTf -1 1 1\n", Expect::Error),
        ("illum 99", "newmtl a\nillum 99\n", Expect::Ok),
        ("no newmtl", "Kd 1 1 1\n", Expect::Either),
        ("garbage", "\u{0}\u{ff}newmtl\n", Expect::Either),
    ];
    for (k, (name, mtl, expect)) in mtls.into_iter().enumerate() {
        let sub = d.join(format!("mtl{k}"));
        std::fs::create_dir_all(&sub).unwrap();
        std::fs::write(sub.join("m.mtl"), mtl).unwrap();
        let p = sub.join("t.obj");
        std::fs::write(&p, "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n").unwrap();
        v.push(render_case("obj/mtl", format!("mtl: {name}"), &p, &["--size", "8x8", "--spp", "1"], expect));
    }
}

pub fn cases() -> Vec<Case> {
    let mut v = Vec::new();
    ron_cases(&mut v);
    mit6837_cases(&mut v);
    obj_cases(&mut v);
    v
}
