//! Hostile texture images (PNG and JPEG headers claiming sizes beyond the decoded-pixel cap, truncated and
//! mislabelled files) as textures, environment maps and `compare` inputs; hostile report suites and output folders;
//! scenes of an untrusted source under `--allow-read` reaching outside their folder by `..`, absolute paths,
//! symbolic links and percent-encoded glTF URIs.

use super::{Case, Expect, dir};
use crate::common::png_header_only;
use std::path::PathBuf;

/// A baseline JPEG header (SOI, a start-of-frame of `w x h`, 3 components) and nothing else.
fn jpeg(w: u16, h: u16) -> Vec<u8> {
    let mut out = vec![0xFF, 0xD8, 0xFF, 0xC0, 0, 17, 8];
    out.extend_from_slice(&h.to_be_bytes());
    out.extend_from_slice(&w.to_be_bytes());
    out.extend_from_slice(&[3, 1, 0x22, 0, 2, 0x11, 0, 3, 0x11, 0]);
    out
}

fn texture_cases(v: &mut Vec<Case>) {
    let d = dir("textures");
    let mut files: Vec<(String, PathBuf, Expect)> = vec![];
    let mut put = |name: &str, file: &str, bytes: Vec<u8>, expect: Expect| {
        let p = d.join(file);
        std::fs::write(&p, bytes).unwrap();
        files.push((name.to_string(), p, expect));
    };
    for (w, h, expect) in [
        (16384u32, 16384u32, Expect::Error),
        (65536, 1025, Expect::Error),
        (65537, 1, Expect::Error),
        (8193, 8193, Expect::Error),
        (0, 0, Expect::Error),
        (16, 16, Expect::Error),
    ] {
        for (depth, ty) in [(8u8, 0u8), (16, 2), (8, 6)] {
            put(
                &format!("PNG {w}x{h}, depth {depth}, type {ty}"),
                &format!("p{w}x{h}_{depth}_{ty}.png"),
                png_header_only(w, h, depth, ty),
                expect,
            );
        }
    }
    for (w, h) in [(65535u16, 65535u16), (16384, 16384), (0, 0), (8, 8)] {
        put(&format!("JPEG header {w}x{h}"), &format!("j{w}x{h}.jpg"), jpeg(w, h), Expect::Error);
    }
    put("a PNG named .jpg", "mislabelled.jpg", png_header_only(16384, 16384, 8, 0), Expect::Error);
    put("text named .png", "text.png", b"not an image".to_vec(), Expect::Error);
    put("an empty .png", "empty.png", vec![], Expect::Error);
    for (name, path, expect) in files {
        let tex = d.join(format!("{}.tex.ron", path.file_name().unwrap().to_string_lossy()));
        std::fs::write(
            &tex,
            format!(
                "(camera: (size: (8, 8)), textures: {{\"t\": Image(path: {:?})}}, materials: {{\"m\": \
                 Lambert(albedo: Texture(\"t\"))}}, entities: [(shape: Sphere(), material: \"m\")])",
                path.to_string_lossy()
            ),
        )
        .unwrap();
        let out = tex.with_extension("png");
        v.push(Case::new("textures", format!("{name} as a texture"), &[&"render", &tex, &"-o", &out, &"-q"], expect));
        v.push(Case::new("textures", format!("{name} in compare"), &[&"compare", &path, &path], expect));
    }
}

fn report_cases(v: &mut Vec<Case>) {
    let d = dir("reports");
    let suite = crate::common::root().join("scenes/report/small.ron");
    let fifo = d.join("fifo.ron");
    let _ = std::fs::remove_file(&fifo);
    let _ = std::process::Command::new("mkfifo").arg(&fifo).status();
    let empty = d.join("empty.ron");
    std::fs::write(&empty, "").unwrap();
    let folder = d.join("a-folder.ron");
    std::fs::create_dir_all(&folder).unwrap();
    let foreign = d.join("foreign");
    std::fs::create_dir_all(&foreign).unwrap();
    std::fs::write(foreign.join("notes.txt"), "the user's").unwrap();
    let file_out = d.join("a-file");
    std::fs::write(&file_out, "x").unwrap();
    let forged = d.join("forged");
    std::fs::create_dir_all(&forged).unwrap();
    std::fs::write(forged.join(".prism-report"), "../a-file\n/etc/hostname\n../../x\n").unwrap();
    for (name, s, out, expect) in [
        ("a suite that is a pipe", &fifo, d.join("o1"), Expect::Error),
        ("an empty suite", &empty, d.join("o2"), Expect::Error),
        ("a suite that is a folder", &folder, d.join("o3"), Expect::Error),
        ("a missing suite", &d.join("missing.ron"), d.join("o4"), Expect::Error),
        ("an output folder of someone else's files", &suite, foreign.clone(), Expect::Error),
        ("an output that is a file", &suite, file_out.clone(), Expect::Error),
    ] {
        v.push(Case::new("reports", name, &[&"report", s, &"-o", &out, &"--threads", &"1"], expect));
    }
    // A manifest naming files outside its folder: nothing outside is removed (`a-file` must survive the run).
    v.push(Case::new(
        "reports",
        "a forged manifest",
        &[&"report", &suite, &"-o", &forged, &"--threads", &"2"],
        Expect::Ok,
    ));
}

fn untrusted_cases(v: &mut Vec<Case>) {
    let d = dir("untrusted");
    let jail = d.join("jail");
    std::fs::create_dir_all(jail.join("sub")).unwrap();
    let obj = "v 0 0 -2\nv 1 0 -2\nv 0 1 -2\nf 1 2 3\n";
    let outside = d.join("outside.obj");
    std::fs::write(&outside, obj).unwrap();
    std::fs::write(jail.join("inside.obj"), obj).unwrap();
    std::fs::write(jail.join("sub/deeper.obj"), obj).unwrap();
    let link = jail.join("link.obj");
    let _ = std::fs::remove_file(&link);
    let _ = std::os::unix::fs::symlink(&outside, &link);
    let dirlink = jail.join("up");
    let _ = std::fs::remove_file(&dirlink);
    let _ = std::os::unix::fs::symlink(&d, &dirlink);
    let mut n = 0;
    let mut scene = |v: &mut Vec<Case>, name: &str, text: String, ext: &str, expect: Expect| {
        n += 1;
        let p = jail.join(format!("s{n}.{ext}"));
        std::fs::write(&p, text).unwrap();
        let out = d.join(format!("s{n}.png"));
        v.push(Case::new("untrusted", name, &[&"render", &p, &"-o", &out, &"-q", &"--allow-read", &jail], expect));
    };
    let ron = |mesh: &str| format!("(camera: (size: (8, 8)), entities: [(shape: Mesh(path: {mesh:?}))])");
    scene(v, "a mesh inside", ron("inside.obj"), "ron", Expect::Ok);
    scene(v, "a mesh in a subfolder", ron("sub/deeper.obj"), "ron", Expect::Ok);
    scene(v, "a mesh by ..", ron("../outside.obj"), "ron", Expect::Error);
    scene(v, "a mesh by .. inside and out", ron("sub/../../outside.obj"), "ron", Expect::Error);
    scene(v, "a mesh by an absolute path", ron(&outside.to_string_lossy()), "ron", Expect::Error);
    scene(v, "a mesh by a symbolic link", ron("link.obj"), "ron", Expect::Error);
    scene(v, "a mesh through a linked folder", ron("up/outside.obj"), "ron", Expect::Error);
    scene(v, "/etc/passwd as a mesh", ron("/etc/passwd"), "ron", Expect::Error);
    let pbrt = |inc: &str| format!("LookAt 0 0 5 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\nInclude \"{inc}\"\n");
    scene(v, "a pbrt Include of /etc/passwd", pbrt("/etc/passwd"), "pbrt", Expect::Error);
    scene(v, "a pbrt Include by ..", pbrt("../outside.obj"), "pbrt", Expect::Error);
    for uri in ["../outside.obj", "%2e%2e/outside.obj", "..%2Foutside.obj", "/etc/passwd", "link.obj"] {
        let doc = format!(
            r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
            "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
            "buffers": [{{"byteLength": 36, "uri": "{uri}"}}], "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
            "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]}}]}}"#
        );
        scene(v, &format!("a glTF buffer {uri}"), doc, "gltf", Expect::Error);
    }
}

pub fn cases() -> Vec<Case> {
    let mut v = Vec::new();
    texture_cases(&mut v);
    report_cases(&mut v);
    untrusted_cases(&mut v);
    v
}
