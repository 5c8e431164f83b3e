//! PLY import: the three encodings read the same mesh, the real files load, and every malformed file is a
//! one-line error (no panic, no allocation from a header before its data is known to be there).

use crate::common::{data, render_ron, scratch, spp};
use prism::load::ply::{load_ply, parse_ply};
use std::path::Path;

/// A square (one quad) and a triangle, with normals and uvs, as PLY in the given encoding.
fn square_ply(encoding: &str) -> Vec<u8> {
    let verts: [[f32; 8]; 5] = [
        [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0],
        [1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        [0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0],
        [2.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.5, 0.25],
    ];
    let faces: [&[i32]; 2] = [&[0, 1, 2, 3], &[1, 4, 2]];
    let mut out = format!(
        "ply\nformat {encoding} 1.0\ncomment test\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\n\
         element face 2\nproperty list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes();
    let be = encoding == "binary_big_endian";
    for v in &verts {
        if encoding == "ascii" {
            out.extend(format!("{}\n", v.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(" ")).bytes());
        } else {
            for x in v {
                out.extend(if be { x.to_be_bytes() } else { x.to_le_bytes() });
            }
        }
    }
    for f in faces {
        if encoding == "ascii" {
            out.extend(
                format!("{} {}\n", f.len(), f.iter().map(|i| i.to_string()).collect::<Vec<_>>().join(" ")).bytes(),
            );
        } else {
            out.push(f.len() as u8);
            for i in f {
                out.extend(if be { i.to_be_bytes() } else { i.to_le_bytes() });
            }
        }
    }
    out
}

#[test]
fn ascii_and_both_binary_encodings_read_the_same_mesh_with_quads_split_and_v_flipped() {
    let meshes: Vec<_> = ["ascii", "binary_little_endian", "binary_big_endian"]
        .iter()
        .map(|e| parse_ply(&square_ply(e), Path::new("square.ply")).unwrap_or_else(|err| panic!("{e}: {err}")))
        .collect();
    for m in &meshes {
        assert_eq!(m.positions.len(), 5);
        assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3], [1, 4, 2]], "quad split along 0-2, then the triangle");
        assert_eq!(m.normals.len(), 5);
        // PLY's v points up the image, Prism's down.
        assert_eq!(m.uvs[2], glam::Vec2::new(1.0, 0.0));
        assert_eq!(m.uvs[4], glam::Vec2::new(0.5, 0.75));
        assert_eq!(m.positions, meshes[0].positions);
    }
}

#[test]
fn the_real_ply_files_load_with_their_declared_counts() {
    let bunny = load_ply(&data("meshes/bunny_binary.ply")).unwrap();
    assert_eq!((bunny.positions.len(), bunny.indices.len()), (35947, 69451));
    assert!(bunny.normals.is_empty() && bunny.uvs.is_empty());
    let glass = load_ply(&data("caustic_glass/geometry/mesh_00001.ply")).unwrap();
    assert_eq!((glass.positions.len(), glass.indices.len(), glass.normals.len()), (44034, 88064, 44034));
    let floor = load_ply(&data("caustic_glass/geometry/mesh_00002.ply")).unwrap();
    assert_eq!((floor.positions.len(), floor.indices.len()), (4, 2));
}

#[test]
fn a_ply_mesh_in_a_ron_scene_renders_and_reverse_flips_its_emitting_side() {
    let dir = scratch("ply-ron");
    std::fs::write(dir.join("square.ply"), square_ply("binary_little_endian")).unwrap();
    // The square faces +z; seen from +z it emits, reversed it does not.
    let scene = |reverse: bool| {
        format!(
            "(camera: (eye: (0.5, 0.5, 3), target: (0.5, 0.5, 0), fov: 30, size: (8, 8)), render: (integrator: envlight(max_depth: 1)), \
             entities: [(shape: Mesh(path: \"{}\", reverse: {reverse}), light: Area(radiance: (1, 1, 1)))])",
            dir.join("square.ply").display()
        )
    };
    let front = render_ron(&scene(false), spp(1));
    let back = render_ron(&scene(true), spp(1));
    let mean = |img: &prism::io::Image| img.pixels.iter().map(|p| p.x).sum::<f32>() / img.pixels.len() as f32;
    assert!(mean(&front) > 0.3, "the square's front should emit towards the camera: {}", mean(&front));
    assert_eq!(mean(&back), 0.0, "reversed, the camera sees the back of a one-sided emitter");
}

fn ply_err(bytes: &[u8]) -> String {
    let e = parse_ply(bytes, Path::new("bad.ply")).expect_err("malformed PLY must fail").to_string();
    assert!(!e.contains('\n'), "errors are one line: {e}");
    assert!(e.starts_with("bad.ply"), "errors name the file: {e}");
    e
}

#[test]
fn a_header_that_lies_about_its_counts_is_an_error_before_any_allocation() {
    let good = square_ply("binary_little_endian");
    let text = String::from_utf8_lossy(&good).to_string();
    // More vertices than the data holds.
    let lie = text.replacen("element vertex 5", "element vertex 6", 1);
    let mut bytes = lie.as_bytes().to_vec();
    bytes.truncate(good.len());
    let e = ply_err(&bytes);
    assert!(e.contains("declares") || e.contains("vertex"), "{e}");
    // Four billion faces: refused from the file size, not allocated.
    let huge = String::from_utf8_lossy(&good).replacen("element face 2", "element face 4000000000", 1);
    let e = ply_err(huge.as_bytes());
    assert!(e.contains("4000000000") && e.contains("bytes"), "{e}");
    // A truncated binary file.
    let e = ply_err(&good[..good.len() - 5]);
    assert!(e.contains("face"), "{e}");
}

#[test]
fn out_of_range_and_negative_indices_nan_vertices_and_bad_headers_are_named() {
    let ascii = String::from_utf8(square_ply("ascii")).unwrap();
    let e = ply_err(ascii.replacen("3 1 4 2", "3 1 9 2", 1).as_bytes());
    assert!(e.contains("face 1") && e.contains("vertex 9"), "{e}");
    let e = ply_err(ascii.replacen("3 1 4 2", "3 1 -4 2", 1).as_bytes());
    assert!(e.contains("face 1") && e.contains("-4"), "{e}");
    // A NaN coordinate (binary: the bytes of a NaN float as vertex 4's x).
    let mut bin = square_ply("binary_little_endian");
    let header = bin.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    bin[header + 4 * 32..header + 4 * 33].copy_from_slice(&f32::NAN.to_le_bytes());
    let e = ply_err(&bin);
    assert!(e.contains("vertex 4") && e.contains("NaN"), "{e}");
    let e = ply_err(ascii.replacen("3 1 4 2", "2 1 4", 1).as_bytes());
    assert!(e.contains("face 1") && e.contains("2 vertices"), "{e}");
    let e = ply_err(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n");
    assert!(e.contains("x, y, z"), "{e}");
    let e = ply_err(b"not a ply file at all");
    assert!(e.contains("header"), "{e}");
    let e = ply_err(ascii.replacen("1 1 0 0 0 1 1 1", "1 one 0 0 0 1 1 1", 1).as_bytes());
    assert!(e.contains("vertex"), "{e}");
}

/// A vertex normal of NaN (written by some exporters at degenerate vertices) takes the geometric normal of the
/// vertex's faces: the square's faces lie in z = 0 with counter-clockwise winding, so +z; the mesh still loads.
#[test]
fn nan_vertex_normals_become_the_geometric_normal_of_their_faces() {
    // Binary (ASCII PLY has no spelling for NaN): vertex 2's nx becomes NaN, vertex 4's ny infinite.
    let mut bytes = square_ply("binary_little_endian");
    let start = bytes.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let at = |vertex: usize, field: usize| start + (vertex * 8 + field) * 4;
    bytes[at(2, 3)..at(2, 4)].copy_from_slice(&f32::NAN.to_le_bytes());
    bytes[at(4, 4)..at(4, 5)].copy_from_slice(&f32::INFINITY.to_le_bytes());
    let m = parse_ply(&bytes, Path::new("nan_normals.ply")).unwrap();
    assert_eq!(m.normals.len(), 5);
    for (i, n) in m.normals.iter().enumerate() {
        assert!((*n - glam::Vec3::Z).length() < 1e-6, "vertex {i}: {n}");
    }
}
