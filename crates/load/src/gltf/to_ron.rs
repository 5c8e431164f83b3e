//! `prism convert model.glb -o scene.ron`: a RON scene that places the glTF file as one `Gltf` entity, with the
//! camera Prism would render it from (the file's first, or `--camera`'s, or the automatic framing) written out in
//! world space, the `envlight` integrator, and the default white sky when the file has no light of its own, so
//! the RON scene renders as `prism render model.glb` does and is ready to be edited.

use super::Placement;
use hecs::World;
use prism_core::camera::Projection;
use prism_core::error::Result;
use prism_engine::Resources;
use prism_engine::components::Light;
use std::path::Path;

/// The RON text for `file`, its paths relative to `out_dir`; `camera` picks a camera of the file by name or index.
pub fn gltf_to_ron(file: &Path, out_dir: &Path, camera: Option<&str>) -> Result<String> {
    let mut world = World::new();
    let mut res = Resources::default();
    res.overrides.camera = camera.map(str::to_string);
    res.overrides.no_default_light = true;
    res.materials.push(prism_core::material::Material::default());
    super::place_gltf(file, &mut world, &mut res, &Placement::standalone(), &mut Default::default())?;
    let cam = crate::scene_overrides::camera_in_world(&world)?;
    let lit = world.query::<&Light>().iter().any(|l| !matches!(l, Light::Area { .. }));
    let v = |p: glam::Vec3| format!("({:?}, {:?}, {:?})", p.x, p.y, p.z);
    let projection = match cam.projection {
        Projection::Perspective { fov_y } => format!("fov: {fov_y:?}"),
        Projection::Orthographic { height } => format!("orthographic: Some({height:?})"),
    };
    let rel = crate::mit6837::relative_path(file, out_dir);
    let mut out = format!(
        "// {name} placed as one entity (written by `prism convert`). Replace its materials by name with\n\
         // `Gltf(path: ..., materials: {{\"glTF material\": \"RON material\"}})`.\n\
         (\n    camera: (eye: {}, target: {}, up: {}, {projection}, size: ({}, {})),\n    \
         render: (integrator: envlight),\n    entities: [\n        (name: {name:?}, shape: Gltf(path: {:?})),\n",
        v(cam.eye),
        v(cam.target),
        v(cam.up),
        cam.width,
        cam.height,
        rel.to_string_lossy(),
        name = file.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_else(|| "model".into()),
    );
    if !lit {
        out.push_str(
            "        // The file has no light (or only emissive surfaces): the white sky `prism render` adds.\n",
        );
        out.push_str("        (name: \"sky\", light: Environment(radiance: (1, 1, 1))),\n");
    }
    out.push_str("    ],\n)\n");
    Ok(out)
}
