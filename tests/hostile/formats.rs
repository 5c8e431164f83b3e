//! Hostile glTF, PLY and pbrt files: a small valid file of each, then every field, count and structure mutated —
//! extreme and malformed numbers, out-of-range indices, shared and cyclic node graphs, sparse accessors claiming
//! billions of elements, GLB headers that lie, PLY headers whose counts, types and encodings disagree with the data,
//! pbrt directives misspelt, malformed, included in fans and cycles, objects instancing objects.

use super::scenes::Rng;
use super::{Case, Expect, dir};
use crate::common::data;
use std::path::Path;

fn render(class: &'static str, name: String, scene: &Path, expect: Expect) -> Case {
    let out = scene.with_extension("out.png");
    let args: [&dyn AsRef<std::ffi::OsStr>; 11] =
        [&"render", &scene, &"-o", &out, &"-q", &"--threads", &"1", &"--size", &"8x8", &"--spp", &"1"];
    Case::new(class, name, &args, expect)
}

/// The base glTF: one triangle of a data-URI buffer under one node, with a camera and a light node.
fn gltf_base() -> serde_json::Value {
    use base64::Engine;
    let positions: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 0., 1., 0.].iter().flat_map(|v| v.to_le_bytes()).collect();
    let b64 = base64::engine::general_purpose::STANDARD.encode(&positions);
    serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0, "translation": [0, 0, 0]},
            {"camera": 0, "translation": [0.3, 0.3, 3]}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "aspectRatio": 1.0}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.2, 1.0], "metallicFactor": 0.0}}],
        "buffers": [{"byteLength": 36, "uri": format!("data:application/octet-stream;base64,{b64}")}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}]
    })
}

/// Set `value` at the JSON pointer `path` (creating nothing: a missing path leaves the document as it is).
fn set(doc: &mut serde_json::Value, path: &str, value: serde_json::Value) {
    if let Some(v) = doc.pointer_mut(path) {
        *v = value;
    }
}

fn gltf_cases(v: &mut Vec<Case>) {
    use serde_json::json;
    let d = dir("gltf");
    let mut n = 0;
    let mut add = |v: &mut Vec<Case>, name: &str, doc: &serde_json::Value, expect: Expect| {
        n += 1;
        let p = d.join(format!("g{n}.gltf"));
        std::fs::write(&p, serde_json::to_vec(doc).unwrap()).unwrap();
        v.push(render("gltf", format!("{name} ({})", p.display()), &p, expect));
    };
    let base = gltf_base();
    add(v, "the base file", &base, Expect::Ok);
    // Every top-level member removed.
    for key in
        ["asset", "scene", "scenes", "nodes", "cameras", "meshes", "materials", "buffers", "bufferViews", "accessors"]
    {
        let mut doc = base.clone();
        doc.as_object_mut().unwrap().remove(key);
        add(v, &format!("no {key}"), &doc, Expect::Either);
    }
    // Numbers and indices replaced by extreme values.
    let numbers =
        [json!(0), json!(1), json!(-1), json!(4294967296u64), json!(9007199254740993u64), json!(1e300), json!(0.5)];
    for path in [
        "/accessors/0/count",
        "/accessors/0/componentType",
        "/accessors/0/bufferView",
        "/bufferViews/0/byteLength",
        "/bufferViews/0/buffer",
        "/buffers/0/byteLength",
        "/meshes/0/primitives/0/attributes/POSITION",
        "/meshes/0/primitives/0/material",
        "/nodes/0/mesh",
        "/nodes/1/camera",
        "/scene",
        "/scenes/0/nodes/0",
        "/cameras/0/perspective/yfov",
        "/cameras/0/perspective/znear",
        "/cameras/0/perspective/aspectRatio",
        "/materials/0/pbrMetallicRoughness/metallicFactor",
    ] {
        for x in &numbers {
            let mut doc = base.clone();
            set(&mut doc, path, x.clone());
            add(v, &format!("{path} = {x}"), &doc, Expect::Either);
        }
    }
    for ty in ["SCALAR", "VEC2", "VEC4", "MAT4", "X"] {
        let mut doc = base.clone();
        set(&mut doc, "/accessors/0/type", json!(ty));
        add(v, &format!("accessor type {ty}"), &doc, Expect::Either);
    }
    // Node graphs: cycles, deep chains, shared nodes (2^k instances).
    let mut cyclic = base.clone();
    set(&mut cyclic, "/nodes/0", json!({"mesh": 0, "children": [0]}));
    add(v, "a node its own child", &cyclic, Expect::Error);
    let mut deep = base.clone();
    let chain: Vec<serde_json::Value> =
        (0..400).map(|i| json!({"children": [i + 1]})).chain([json!({"mesh": 0})]).collect();
    set(&mut deep, "/nodes", json!(chain));
    set(&mut deep, "/scenes/0/nodes", json!([0]));
    add(v, "400 nested nodes", &deep, Expect::Error);
    for (levels, fan) in [(10, 2), (25, 2), (40, 2), (10, 3), (3, 2000)] {
        let mut dag = base.clone();
        let nodes: Vec<serde_json::Value> = (0..levels)
            .map(|i| json!({"children": vec![i + 1; fan]}))
            .chain([json!({"mesh": 0}), json!({"camera": 0, "translation": [0.3, 0.3, 3]})])
            .collect();
        set(&mut dag, "/nodes", json!(nodes));
        set(&mut dag, "/scenes/0/nodes", json!([0, levels + 1]));
        let instances = (fan as f64).powi(levels);
        let expect = if instances > (1u64 << 20) as f64 { Expect::Error } else { Expect::Either };
        add(v, &format!("{levels} levels of {fan} shared children"), &dag, expect);
    }
    // Transforms.
    for (what, m) in [
        ("a non-affine matrix", json!([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 1])),
        ("a NaN-free huge matrix", json!([1e38, 0, 0, 0, 0, 1e38, 0, 0, 0, 0, 1e38, 0, 0, 0, 0, 1])),
        ("a zero matrix", json!([0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1])),
        ("a projective matrix", json!([1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1])),
    ] {
        let mut doc = base.clone();
        set(&mut doc, "/nodes/0", json!({"mesh": 0, "matrix": m}));
        let expect =
            if what.contains("affine") || what.contains("projective") { Expect::Error } else { Expect::Either };
        add(v, what, &doc, expect);
    }
    for scale in [json!([0, 0, 0]), json!([1e30, 1e30, 1e30]), json!([-1, 1, 1])] {
        let mut doc = base.clone();
        set(&mut doc, "/nodes/0", json!({"mesh": 0, "scale": scale}));
        add(v, &format!("scale {scale}"), &doc, Expect::Either);
    }
    // Sparse accessors claiming far more than the file holds.
    for count in [3u64, 1_000_000, 100_000_000, 1_000_000_000, 4_000_000_000] {
        let mut doc = base.clone();
        set(
            &mut doc,
            "/accessors/0",
            json!({"componentType": 5126, "count": count, "type": "VEC3",
                   "sparse": {"count": 1, "indices": {"bufferView": 0, "componentType": 5125}, "values": {"bufferView": 0}}}),
        );
        let expect = if count * 12 > 256 << 20 { Expect::Error } else { Expect::Either };
        add(v, &format!("sparse accessor of {count}"), &doc, expect);
    }
    // Buffers and images from hostile URIs.
    for uri in [
        "../../../../../../etc/passwd",
        "%2e%2e/%2e%2e/%2e%2e/etc/hostname",
        "/dev/zero",
        "missing.bin",
        "data:;base64,!!!",
        "http://example.com/x.bin",
    ] {
        let mut doc = base.clone();
        set(&mut doc, "/buffers/0/uri", json!(uri));
        let expect = if uri == "/dev/zero" || uri.starts_with("missing") || uri.starts_with("http") {
            Expect::Error
        } else {
            Expect::Either
        };
        add(v, &format!("buffer uri {uri}"), &doc, expect);
        let mut doc = base.clone();
        set(&mut doc, "/materials/0/pbrMetallicRoughness/baseColorTexture", json!({"index": 0}));
        doc["textures"] = json!([{"source": 0}]);
        doc["images"] = json!([{"uri": uri}]);
        add(v, &format!("image uri {uri}"), &doc, Expect::Either);
    }
    // Lights and cameras with absurd values.
    for x in [json!(-1), json!(1e39), json!(0)] {
        let mut doc = base.clone();
        doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
        doc["extensions"] = json!({"KHR_lights_punctual": {"lights": [{"type": "spot", "intensity": x, "spot": {"innerConeAngle": x, "outerConeAngle": 0.5}}]}});
        set(&mut doc, "/nodes/0", json!({"mesh": 0, "extensions": {"KHR_lights_punctual": {"light": 0}}}));
        add(v, &format!("spot light values {x}"), &doc, Expect::Either);
    }
    // GLB containers that lie about their lengths.
    let glb = std::fs::read(data("gltf/BoxTextured-glb/BoxTextured.glb")).unwrap();
    let mut m = 0;
    let mut glb_case = |v: &mut Vec<Case>, name: &str, bytes: Vec<u8>, expect: Expect| {
        m += 1;
        let p = d.join(format!("b{m}.glb"));
        std::fs::write(&p, bytes).unwrap();
        v.push(render("gltf", format!("GLB: {name}"), &p, expect));
    };
    glb_case(v, "as it is", glb.clone(), Expect::Ok);
    for (name, len) in [
        ("length 0", 0u32),
        ("length 12", 12),
        ("length - 1", glb.len() as u32 - 1),
        ("length + 100", glb.len() as u32 + 100),
        ("length 2^32-1", u32::MAX),
    ] {
        let mut b = glb.clone();
        b[8..12].copy_from_slice(&len.to_le_bytes());
        glb_case(v, name, b, Expect::Error);
    }
    let mut longer = glb.clone();
    longer.extend_from_slice(&[0; 100]);
    glb_case(v, "trailing bytes", longer, Expect::Error);
    for cut in [12, 20, 28, glb.len() / 2, glb.len() - 1] {
        glb_case(v, &format!("truncated at {cut}"), glb[..cut].to_vec(), Expect::Error);
    }
    let mut chunk = glb.clone();
    chunk[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
    glb_case(v, "JSON chunk length 2^32-1", chunk, Expect::Error);
}

/// A small PLY: a triangle, in the given encoding, with the header lines given.
fn ply(format: &str, header: &str, body: &[u8]) -> Vec<u8> {
    let mut out = format!("ply\nformat {format} 1.0\n{header}end_header\n").into_bytes();
    out.extend_from_slice(body);
    out
}

fn ply_cases(v: &mut Vec<Case>) {
    let d = dir("ply");
    let mut n = 0;
    let mut add = |v: &mut Vec<Case>, name: String, bytes: Vec<u8>, expect: Expect| {
        n += 1;
        let p = d.join(format!("p{n}.ply"));
        std::fs::write(&p, bytes).unwrap();
        v.push(render("ply", name, &p, expect));
    };
    let vertex = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    let face = "element face 1\nproperty list uchar int vertex_indices\n";
    let mut bin = Vec::new();
    for x in [0f32, 0., -2., 1., 0., -2., 0., 1., -2.] {
        bin.extend_from_slice(&x.to_le_bytes());
    }
    bin.push(3);
    for i in [0i32, 1, 2] {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    let ascii = b"0 0 -2\n1 0 -2\n0 1 -2\n3 0 1 2\n".to_vec();
    add(v, "binary triangle".into(), ply("binary_little_endian", &format!("{vertex}{face}"), &bin), Expect::Ok);
    add(v, "ascii triangle".into(), ply("ascii", &format!("{vertex}{face}"), &ascii), Expect::Ok);
    // Counts the data does not hold.
    for count in ["0", "2", "4", "2147483648", "9223372036854775807", "18446744073709551615", "-1", "1e9", "x"] {
        for (fmt, body) in [("binary_little_endian", &bin), ("ascii", &ascii)] {
            let h = format!("{}{face}", vertex.replace("vertex 3", &format!("vertex {count}")));
            add(v, format!("{fmt}: vertex count {count}"), ply(fmt, &h, body), Expect::Either);
            let h = format!("{vertex}{}", face.replace("face 1", &format!("face {count}")));
            add(v, format!("{fmt}: face count {count}"), ply(fmt, &h, body), Expect::Either);
        }
    }
    // Elements without properties.
    for count in ["0", "1", "1000000", "9223372036854775807"] {
        let h = format!("{vertex}element junk {count}\n{face}");
        let expect = if count == "0" { Expect::Ok } else { Expect::Error };
        add(v, format!("element without properties, count {count}"), ply("binary_little_endian", &h, &bin), expect);
    }
    // Encodings, types and lists.
    for fmt in ["binary_big_endian", "binary", "ascii2", ""] {
        add(v, format!("format `{fmt}`"), ply(fmt, &format!("{vertex}{face}"), &bin), Expect::Either);
    }
    for ty in ["double", "uchar", "int64", "flot", "list uchar float"] {
        let h = format!("{}{face}", vertex.replace("property float x", &format!("property {ty} x")));
        add(v, format!("x of type `{ty}`"), ply("binary_little_endian", &h, &bin), Expect::Either);
    }
    for list in ["list uint int", "list uchar uchar", "list float int", "list uchar int64"] {
        let h = format!("{vertex}element face 1\nproperty {list} vertex_indices\n");
        add(v, format!("face list `{list}`"), ply("binary_little_endian", &h, &bin), Expect::Either);
    }
    for (i, bad) in [[0i32, 1, 7], [0, 1, -1], [0, 0, 0], [i32::MAX, 0, 1]].iter().enumerate() {
        let mut b = bin[..36].to_vec();
        b.push(3);
        for k in bad {
            b.extend_from_slice(&k.to_le_bytes());
        }
        add(
            v,
            format!("face indices {i} {bad:?}"),
            ply("binary_little_endian", &format!("{vertex}{face}"), &b),
            Expect::Either,
        );
    }
    for len in [0u8, 1, 2, 255] {
        let mut b = bin[..36].to_vec();
        b.push(len);
        b.extend(std::iter::repeat_n(0u8, 4 * len.min(3) as usize));
        add(
            v,
            format!("face list of {len}"),
            ply("binary_little_endian", &format!("{vertex}{face}"), &b),
            Expect::Either,
        );
    }
    for x in [f32::NAN, f32::INFINITY, 1e38] {
        let mut b = bin.clone();
        b[0..4].copy_from_slice(&x.to_le_bytes());
        add(v, format!("x = {x}"), ply("binary_little_endian", &format!("{vertex}{face}"), &b), Expect::Either);
    }
    // Truncated at every tenth byte, and headers without their end.
    let whole = ply("binary_little_endian", &format!("{vertex}{face}"), &bin);
    for cut in (0..whole.len()).step_by(11) {
        add(v, format!("truncated at {cut}"), whole[..cut].to_vec(), Expect::Either);
    }
    add(v, "no end_header".into(), format!("ply\nformat ascii 1.0\n{vertex}{face}").into_bytes(), Expect::Error);
}

fn pbrt_cases(v: &mut Vec<Case>) {
    let d = dir("pbrt");
    let mut n = 0;
    let mut add = |v: &mut Vec<Case>, name: String, text: String, expect: Expect| {
        n += 1;
        let p = d.join(format!("s{n}.pbrt"));
        std::fs::write(&p, text).unwrap();
        v.push(render("pbrt", name, &p, expect));
    };
    let head = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\nFilm \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nWorldBegin\n";
    let world = "LightSource \"point\" \"rgb I\" [10 10 10] \"point3 from\" [0 2 2]\nMaterial \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\nShape \"sphere\" \"float radius\" 1\n";
    add(v, "the base scene".into(), format!("{head}{world}"), Expect::Ok);
    // Misspelt, unknown and malformed directives and tokens.
    for junk in [
        "Shpe \"sphere\"",
        "Frobnicate 1 2",
        "root:x:0:0:root:/root:/bin/bash",
        "\u{0}\u{1}\u{2}",
        "[[[[",
        "]",
        "\"unterminated",
        "Shape 1 2 3",
        "Translate 1 2",
        "Rotate NaN 0 0 1",
        "Scale 1e999 1 1",
        "LookAt 0 0 0 0 0 0 0 0 0",
        "Transform [1 2 3]",
        "ConcatTransform [0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0]",
    ] {
        add(v, format!("world line `{}`", junk.escape_debug()), format!("{head}{world}{junk}\n"), Expect::Either);
    }
    // Shapes and lights with hostile parameters.
    for x in ["NaN", "-1", "0", "1e39", "3e38"] {
        for line in [
            format!("Shape \"sphere\" \"float radius\" {x}"),
            format!("Shape \"disk\" \"float radius\" {x}"),
            format!("Shape \"cylinder\" \"float radius\" 1 \"float zmin\" 0 \"float zmax\" {x}"),
            format!("LightSource \"point\" \"rgb I\" [{x} 1 1]"),
            format!("LightSource \"point\" \"blackbody I\" [{x}]"),
            format!("LightSource \"distant\" \"rgb L\" [1 1 1] \"float scale\" {x}"),
            format!("Material \"conductor\" \"float roughness\" {x}"),
            format!("Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 {x} 0] \"integer indices\" [0 1 2]"),
        ] {
            add(v, format!("`{line}`"), format!("{head}{world}{line}\n"), Expect::Either);
        }
    }
    for idx in ["[0 1 3]", "[0 1 -1]", "[0 1]", "[0 1 2 0]", "[4294967296 0 1]"] {
        add(
            v,
            format!("triangle mesh indices {idx}"),
            format!("{head}Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" {idx}\n"),
            Expect::Error,
        );
    }
    for res in ["0", "-8", "100000", "1e10"] {
        add(
            v,
            format!("film resolution {res}"),
            format!("{}{world}", head.replace("xresolution\" 8", &format!("xresolution\" {res}"))),
            Expect::Either,
        );
    }
    // Includes: missing, a folder, a pipe, a cycle, a fan; objects instancing objects.
    std::fs::create_dir_all(d.join("folder.pbrt")).unwrap();
    let fifo = d.join("pipe.pbrt");
    let _ = std::fs::remove_file(&fifo);
    let _ = std::process::Command::new("mkfifo").arg(&fifo).status();
    std::fs::write(d.join("cycle.pbrt"), "Include \"cycle.pbrt\"\n").unwrap();
    for k in 0..9 {
        let body = if k == 8 { world.to_string() } else { format!("Include \"fan{}.pbrt\"\n", k + 1).repeat(8) };
        std::fs::write(d.join(format!("fan{k}.pbrt")), body).unwrap();
    }
    for (what, target) in [
        ("a missing file", "nowhere.pbrt"),
        ("a folder", "folder.pbrt"),
        ("a pipe", "pipe.pbrt"),
        ("itself, forever", "cycle.pbrt"),
        ("8^8 spheres", "fan0.pbrt"),
        ("/dev/zero", "/dev/zero"),
    ] {
        add(v, format!("Include of {what}"), format!("{head}Include \"{target}\"\n"), Expect::Error);
    }
    for (levels, copies) in [(5, 2), (20, 2), (40, 2), (8, 10)] {
        let mut text = format!("{head}ObjectBegin \"o0\"\n{world}ObjectEnd\n");
        for k in 1..levels {
            text += &format!(
                "ObjectBegin \"o{k}\"\n{}ObjectEnd\n",
                format!("ObjectInstance \"o{}\"\n", k - 1).repeat(copies)
            );
        }
        text += &format!("ObjectInstance \"o{}\"\n", levels - 1);
        let bytes = world.len() as f64 * (copies as f64).powi(levels - 1);
        let expect = if bytes > (256u64 << 20) as f64 { Expect::Error } else { Expect::Either };
        add(v, format!("{levels} levels of objects instancing {copies} copies"), text, expect);
    }
    // Mutations of the base scene's numbers.
    let base = format!("{head}{world}");
    let mut rng = Rng(55);
    let spots: Vec<usize> = base.char_indices().filter(|(_, c)| c.is_ascii_digit()).map(|(i, _)| i).collect();
    for _ in 0..20 {
        let at = spots[rng.below(spots.len())];
        let repl = ["NaN", "-1e39", "1e39", "-0", "0x10", "1e-999", "--1"][rng.below(7)];
        let text = format!("{}{repl}{}", &base[..at], &base[at + 1..]);
        add(v, format!("a digit at {at} replaced by {repl}"), text, Expect::Either);
    }
}

pub fn cases() -> Vec<Case> {
    let mut v = Vec::new();
    gltf_cases(&mut v);
    ply_cases(&mut v);
    pbrt_cases(&mut v);
    v
}
