//! The meshes MIT 6.837 assignment 8's scenes name (`obj_file torus_high.obj` ...) are not in the course data: the
//! students made them with the course's curve editor from the spline files. This table says which spline file and
//! which resolutions made each one (the course's command lines, e.g. `curve_editor -input spline8_06_torus.txt
//! -curve_tessellation 30 -revolution_tessellation 60 -output torus_high.obj`), so a scene naming a missing course
//! mesh is rendered with that very tessellation, made on the fly, or with the exact surfaces (`--exact-curves`).
//! The vase meshes were made from each student's own edit of `spline8_07_vase.txt` (`output8_07_edit.txt`); the
//! unedited vase stands in for it.

use super::spline::Tessellation;

/// `(mesh file name, spline file, curve, revolution, patch tessellation)`.
const COURSE_MESHES: &[(&str, &str, usize, usize, usize)] = &[
    ("torus_low.obj", "spline8_06_torus.txt", 4, 10, 10),
    ("torus_high.obj", "spline8_06_torus.txt", 30, 60, 10),
    ("vase_low.obj", "spline8_07_vase.txt", 4, 10, 10),
    ("vase_high.obj", "spline8_07_vase.txt", 10, 60, 10),
    ("vase_very_high.obj", "spline8_07_vase.txt", 20, 100, 10),
    ("patch_low.obj", "spline8_08_bezier_patch.txt", 10, 10, 4),
    ("patch_med.obj", "spline8_08_bezier_patch.txt", 10, 10, 10),
    ("patch_high.obj", "spline8_08_bezier_patch.txt", 10, 10, 40),
    ("teapot_low.obj", "spline8_09_teapot.txt", 4, 10, 4),
    ("teapot_high.obj", "spline8_09_teapot.txt", 30, 100, 30),
];

/// The spline file and resolutions a course mesh was made with.
pub fn course_mesh(file_name: &str) -> Option<(&'static str, Tessellation)> {
    COURSE_MESHES
        .iter()
        .find(|m| m.0 == file_name)
        .map(|&(_, spline, curve, revolution, patch)| (spline, Tessellation { curve, revolution, patch }))
}

/// Every course mesh name (for documentation and tests).
pub fn course_mesh_names() -> impl Iterator<Item = &'static str> {
    COURSE_MESHES.iter().map(|m| m.0)
}
