//! Environment maps: one direction convention, checked texel by texel on synthetic maps in every layout and by
//! continuity across the cube edges of the real maps; solid angles; bad files.

use crate::common::{data, scratch};
use glam::{Vec2, Vec3, Vec3A};
use prism::envmap::{
    CUBE_FACES, EnvImage, EnvLayout, EnvMap, SourceLayout, cube_coords, cube_direction, equal_area_coords,
    equal_area_direction, equirect_coords, equirect_direction, octahedral_texel,
};
use std::path::PathBuf;

/// A map whose texel (x, y) holds (x, y, image index): lookups at texel centres must return them exactly.
fn coded(layout: EnvLayout, w: u32, h: u32) -> EnvMap {
    let img = |k: u32| EnvImage {
        width: w,
        height: h,
        texels: (0..h).flat_map(|y| (0..w).map(move |x| Vec3::new(x as f32, y as f32, k as f32))).collect(),
    };
    match layout {
        EnvLayout::Equirect => EnvMap::equirect(img(0)),
        EnvLayout::Cube => EnvMap::cube((0..6).map(img).collect()),
        EnvLayout::EqualArea => EnvMap::from_image(
            prism::io::Image::new(w, h, img(0).texels),
            std::path::Path::new("coded.exr"),
            Some(SourceLayout::EqualArea),
        )
        .unwrap(),
    }
}

#[test]
fn equirect_convention_centre_is_minus_z_right_is_plus_x_top_is_plus_y() {
    let map = coded(EnvLayout::Equirect, 64, 32);
    // Texel centres read back exactly through direction -> (u, v) -> bilinear.
    for (x, y) in [(0, 0), (31, 16), (32, 15), (48, 10), (63, 31), (5, 27)] {
        let uv = Vec2::new((x as f32 + 0.5) / 64.0, (y as f32 + 0.5) / 32.0);
        let v = map.lookup(equirect_direction(uv));
        assert!((v - Vec3::new(x as f32, y as f32, 0.0)).abs().max_element() < 1e-3, "texel ({x},{y}) read {v}");
    }
    let c = |d: Vec3A| equirect_coords(d.normalize());
    assert!((c(-Vec3A::Z) - Vec2::new(0.5, 0.5)).length() < 1e-6, "-z is the image centre");
    assert!((c(Vec3A::X) - Vec2::new(0.75, 0.5)).length() < 1e-6, "+x is right of centre");
    assert!((c(-Vec3A::X) - Vec2::new(0.25, 0.5)).length() < 1e-6);
    assert!(c(Vec3A::Y).y < 1e-6 && (c(-Vec3A::Y).y - 1.0).abs() < 1e-6, "+y is the top row");
    for d in [Vec3A::new(0.3, 0.5, -0.8), Vec3A::new(-0.9, -0.1, 0.2), Vec3A::new(0.1, 0.0, 0.99)] {
        let d = d.normalize();
        assert!((equirect_direction(equirect_coords(d)) - d).length() < 1e-5);
    }
}

#[test]
fn cube_faces_follow_the_documented_frames() {
    let map = coded(EnvLayout::Cube, 8, 8);
    for (face, fr) in CUBE_FACES.iter().enumerate() {
        assert!(
            (fr.right.cross(fr.down) - fr.center).length() < 1e-6
                || (fr.down.cross(fr.right) - fr.center).length() < 1e-6
        );
        // The face centre, its right and its bottom neighbours.
        assert_eq!(cube_coords(fr.center).0, face);
        let v = map.lookup((fr.center + 0.625 * fr.right).normalize());
        assert_eq!((v.x, v.z), (6.0, face as f32), "face {face}: image-right");
        let v = map.lookup((fr.center + 0.625 * fr.down).normalize());
        assert_eq!((v.y, v.z), (6.0, face as f32), "face {face}: image-down");
        for (x, y) in [(0, 0), (7, 0), (3, 5), (7, 7)] {
            let d = cube_direction(face, Vec2::new((x as f32 + 0.5) / 8.0, (y as f32 + 0.5) / 8.0));
            assert_eq!(map.lookup(d), Vec3::new(x as f32, y as f32, face as f32));
        }
    }
}

/// Write a synthetic image with a distinct value per cell of a grid of `cells`, return its path.
fn write_cells(name: &str, w: u32, h: u32, value: impl Fn(u32, u32) -> Vec3) -> PathBuf {
    let path = scratch("envmap").join(name);
    let img = prism::io::Image::new(
        w,
        h,
        (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).map(|(x, y)| value(x, y)).collect(),
    );
    prism::io::write_exr(&path, &img).unwrap();
    path
}

#[test]
fn vertical_cross_places_each_face_in_its_documented_cell() {
    // Cell (column, row) of a 3x4 cross gets value 10 row + column; the +z face (row 3) also carries a gradient
    // so the 180-degree rotation is visible.
    let s = 4;
    let path = write_cells("cross.exr", 3 * s, 4 * s, |x, y| {
        let base = (10 * (y / s) + x / s) as f32;
        Vec3::new(base, (x % s) as f32, (y % s) as f32)
    });
    let map = EnvMap::load(&[path], None).unwrap();
    assert_eq!(map.layout, EnvLayout::Cube, "a 3:4 image is read as a cross");
    let cell = |d: Vec3A| map.lookup(d).x;
    assert_eq!(cell(Vec3A::Y), 1.0, "+y: row 0, middle");
    assert_eq!(cell(-Vec3A::X), 10.0, "-x: row 1, left");
    assert_eq!(cell(-Vec3A::Z), 11.0, "-z: row 1, middle");
    assert_eq!(cell(Vec3A::X), 12.0, "+x: row 1, right");
    assert_eq!(cell(-Vec3A::Y), 21.0, "-y: row 2, middle");
    assert_eq!(cell(Vec3A::Z), 31.0, "+z: row 3, middle");
    // +z is stored rotated by 180 degrees: the texel at its image top-left (seen from inside) is the cell's
    // bottom-right stored texel.
    let d = cube_direction(4, Vec2::new(0.5 / s as f32, 0.5 / s as f32));
    let v = map.lookup(d);
    assert_eq!((v.y, v.z), ((s - 1) as f32, (s - 1) as f32));
}

#[test]
fn six_gl_faces_map_px_to_the_documented_world_direction() {
    let s = 4;
    let paths: Vec<PathBuf> =
        (0..6).map(|k| write_cells(&format!("face{k}.exr"), s, s, move |_, _| Vec3::splat(k as f32))).collect();
    let map = EnvMap::load(&paths, Some(SourceLayout::Faces)).unwrap();
    // three.js convention: world w is looked up as (-w.x, w.y, w.z): world +x reads file nx (index 1).
    assert_eq!(map.lookup(Vec3A::X).x, 1.0);
    assert_eq!(map.lookup(-Vec3A::X).x, 0.0);
    assert_eq!(map.lookup(Vec3A::Y).x, 2.0);
    assert_eq!(map.lookup(-Vec3A::Y).x, 3.0);
    assert_eq!(map.lookup(Vec3A::Z).x, 4.0);
    assert_eq!(map.lookup(-Vec3A::Z).x, 5.0);
}

/// Mean luminance difference of texel pairs straddling every cube edge, relative to that of neighbouring texels
/// inside the faces. Right face orientations make seams look like any other pair of neighbours.
fn seam_ratio(map: &EnvMap) -> f64 {
    let n = map.images[0].width;
    let lum = |v: Vec3| (v.x + v.y + v.z) as f64;
    let nearest = |face: usize, uv: Vec2| {
        let img = &map.images[face];
        lum(img.texel(((uv.x * n as f32) as u32).min(n - 1), ((uv.y * n as f32) as u32).min(n - 1)))
    };
    let (mut seam, mut seams) = (0.0, 0);
    let (mut inner, mut inners) = (0.0, 0);
    let h = 0.5 / n as f32;
    for (face, fr) in CUBE_FACES.iter().enumerate() {
        for i in 0..n {
            let t = (i as f32 + 0.5) / n as f32;
            for (inside, outside) in [
                (Vec2::new(h, t), Vec2::new(-h, t)),
                (Vec2::new(1.0 - h, t), Vec2::new(1.0 + h, t)),
                (Vec2::new(t, h), Vec2::new(t, -h)),
                (Vec2::new(t, 1.0 - h), Vec2::new(t, 1.0 + h)),
            ] {
                let out_dir = fr.center + fr.right * (2.0 * outside.x - 1.0) + fr.down * (2.0 * outside.y - 1.0);
                let (g, uv) = cube_coords(out_dir);
                seam += (nearest(face, inside) - nearest(g, uv)).abs();
                seams += 1;
                let step = inside + (inside - outside) * 1.0;
                inner += (nearest(face, inside) - nearest(face, step)).abs();
                inners += 1;
            }
        }
    }
    (seam / seams as f64) / (inner / inners as f64)
}

#[test]
fn real_cube_maps_are_continuous_across_all_twelve_edges() {
    let cross = EnvMap::load(&[data("envmaps/cross/grace_cross.hdr")], None).unwrap();
    let faces: Vec<PathBuf> = ["px", "nx", "py", "ny", "pz", "nz"]
        .iter()
        .map(|f| data(&format!("envmaps/cube_faces/pisaHDR/{f}.hdr")))
        .collect();
    let pisa = EnvMap::load(&faces, None).unwrap();
    for (name, map) in [("grace_cross", &cross), ("pisa faces", &pisa)] {
        let r = seam_ratio(map);
        eprintln!("{name}: seam / interior neighbour difference = {r:.2}");
        assert!(r < 1.6, "{name}: seams differ {r:.2}x more than neighbouring texels: a face is misoriented");
    }
}

#[test]
fn texel_solid_angles_sum_to_four_pi() {
    for (layout, w, h) in [(EnvLayout::Equirect, 64, 32), (EnvLayout::Cube, 16, 16), (EnvLayout::EqualArea, 16, 16)] {
        let map = coded(layout, w, h);
        let mut sum = 0.0f64;
        for (k, img) in map.images.iter().enumerate() {
            for y in 0..img.height {
                for x in 0..img.width {
                    sum += map.texel_solid_angle(k, x, y) as f64;
                }
            }
        }
        assert!((sum - 4.0 * std::f64::consts::PI).abs() < 1e-4, "{layout:?}: {sum}");
    }
}

#[test]
fn bad_environment_files_give_clear_errors() {
    let dir = scratch("envbad");
    let truncated = dir.join("truncated.hdr");
    let full = std::fs::read(data("envmaps/equirect/probulator_grace_256x128.hdr")).unwrap();
    std::fs::write(&truncated, &full[..full.len() / 3]).unwrap();
    let e = EnvMap::load(&[truncated], None).unwrap_err().to_string();
    assert!(e.contains("truncated.hdr"), "{e}");
    let not_hdr = dir.join("text.hdr");
    std::fs::write(&not_hdr, "hello, not an image").unwrap();
    let e = EnvMap::load(&[not_hdr], None).unwrap_err().to_string();
    assert!(e.contains("text.hdr") && e.contains("Radiance"), "{e}");
    let wrong = write_cells("wrong_aspect.exr", 30, 20, |_, _| Vec3::ONE);
    let e = EnvMap::load(std::slice::from_ref(&wrong), None).unwrap_err().to_string();
    assert!(e.contains("2:1") && e.contains("3:4") && e.contains("square"), "{e}");
    let e = EnvMap::load(&[wrong], Some(SourceLayout::Cross)).unwrap_err().to_string();
    assert!(e.contains("3:4"), "{e}");
    let missing = EnvMap::load(&[dir.join("nope.hdr")], None).unwrap_err().to_string();
    assert!(missing.contains("nope.hdr"), "{missing}");
}

#[test]
fn nan_and_negative_texels_are_clamped_and_infinite_ones_rejected() {
    let bad = write_cells("nan.exr", 8, 4, |x, _| match x {
        0 => Vec3::new(f32::NAN, 1.0, 1.0),
        1 => Vec3::new(-2.0, 1.0, 1.0),
        _ => Vec3::ONE,
    });
    let map = EnvMap::load(&[bad], None).unwrap();
    assert_eq!(map.clamped_texels, 8, "4 rows x 2 bad channels");
    assert!(map.images[0].texels.iter().all(|t| t.is_finite() && t.min_element() >= 0.0));
    let inf =
        write_cells("inf.exr", 8, 4, |x, y| if (x, y) == (3, 2) { Vec3::splat(f32::INFINITY) } else { Vec3::ONE });
    let e = EnvMap::load(&[inf], None).unwrap_err().to_string();
    assert!(e.contains("(3, 2)") && e.contains("infinite"), "{e}");
}

// pbrt-v4's equal-area octahedral maps (`envmap/equal_area.rs`).

#[test]
fn the_mapping_round_trips_and_its_inverse_is_a_unit_vector() {
    for i in 0..64 {
        for j in 0..64 {
            let uv = Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0);
            let d = equal_area_direction(uv);
            assert!((d.length() - 1.0).abs() < 1e-5, "{uv} -> {d}");
            let back = equal_area_coords(d);
            assert!((back - uv).abs().max_element() < 1e-4, "{uv} -> {d} -> {back}");
        }
    }
}

#[test]
fn up_is_the_centre_and_down_the_corners() {
    assert!((equal_area_direction(Vec2::splat(0.5)) - Vec3A::Y).length() < 1e-6);
    for c in [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE] {
        assert!((equal_area_direction(c) - Vec3A::NEG_Y).length() < 1e-6, "{c}");
    }
}

/// Equal area: the directions of a uniform grid over the square are uniform on the sphere, so the mean of any
/// function over them is its mean over the sphere (here z^2, whose mean is 1/3, and the first moments, 0).
#[test]
fn equal_areas_of_the_square_are_equal_solid_angles() {
    let n = 512;
    let (mut z2, mut m) = (0.0f64, Vec3A::ZERO);
    for i in 0..n {
        for j in 0..n {
            let d = equal_area_direction(Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32));
            z2 += (d.z * d.z) as f64;
            m += d;
        }
    }
    let count = (n * n) as f64;
    assert!((z2 / count - 1.0 / 3.0).abs() < 1e-3, "{}", z2 / count);
    assert!((m / count as f32).abs().max_element() < 1e-3, "{m}");
}

#[test]
fn texels_past_an_edge_are_their_mirror_images() {
    // Across an edge, the texel at the same distance from the edge's midpoint on the other side.
    assert_eq!(octahedral_texel(-1, 0, 8, 8), (0, 7));
    assert_eq!(octahedral_texel(8, 2, 8, 8), (7, 5));
    assert_eq!(octahedral_texel(3, -1, 8, 8), (4, 0));
    assert_eq!(octahedral_texel(3, 8, 8, 8), (4, 7));
    // The mapping agrees: points just either side of an edge map to nearby directions.
    let a = equal_area_direction(Vec2::new(0.001, 0.3));
    let b = equal_area_direction(Vec2::new(0.001, 0.7));
    assert!((a - b).length() < 0.02, "{a} {b}");
}

#[test]
fn equal_area_lookups_at_texel_centres_return_the_texels() {
    let map = coded(EnvLayout::EqualArea, 8, 8);
    for y in 0..8 {
        for x in 0..8 {
            let uv = Vec2::new((x as f32 + 0.5) / 8.0, (y as f32 + 0.5) / 8.0);
            let d = map.direction(0, uv);
            let v = map.lookup(d);
            assert!((v - Vec3::new(x as f32, y as f32, 0.0)).abs().max_element() < 1e-3, "({x}, {y}) -> {d} -> {v}");
        }
    }
}

/// The same sky in both layouts has the same integral: an equirect map resampled into an equal-area square (each
/// texel the mean of 16 lookups) integrates, with the constant 4 pi / texels, to the panorama's integral.
#[test]
fn an_equirect_sky_resampled_to_equal_area_keeps_its_integral() {
    let pano = EnvMap::load(&[data("envmaps/equirect/probulator_grace_256x128.hdr")], None).unwrap();
    let n = 128u32;
    let mut texels = Vec::with_capacity((n * n) as usize);
    for y in 0..n {
        for x in 0..n {
            let mut sum = Vec3::ZERO;
            for j in 0..4 {
                for i in 0..4 {
                    let uv = Vec2::new(
                        (x as f32 + (i as f32 + 0.5) / 4.0) / n as f32,
                        (y as f32 + (j as f32 + 0.5) / 4.0) / n as f32,
                    );
                    sum += pano.lookup(equal_area_direction(uv));
                }
            }
            texels.push(sum / 16.0);
        }
    }
    let square = EnvMap::from_image(prism::io::Image::new(n, n, texels), std::path::Path::new("sq.exr"), None).unwrap();
    assert_eq!(square.layout, EnvLayout::EqualArea, "a square map is read as equal-area");
    let (a, b) = (pano.integral(), square.integral());
    for c in 0..3 {
        assert!((a[c] - b[c]).abs() < 0.01 * a[c], "channel {c}: equirect {a} vs equal-area {b}");
    }
}
