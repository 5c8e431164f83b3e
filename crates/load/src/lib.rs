//! The Load stage: read the scene (RON, a bare OBJ mesh, or a 6.837 `.txt` scene), spawn its entities, and resolve
//! the render settings from the file and the command-line overrides.

mod curved;
mod deep_stack;
pub mod gltf;
mod inline_mesh;
mod material_schema;
mod material_tables;
pub mod mit6837;
mod obj;
mod obj_check;
pub mod pbrt;
mod plugin;
pub mod ply;
mod ron_scene;
pub mod scene_overrides;
pub mod schema;
mod spawn;
mod transform;

pub use deep_stack::{LOADER_STACK_BYTES, RON_RECURSION_LIMIT, with_loader_stack};
pub use obj::{ObjPart, load_obj, parse_obj};
pub use plugin::LoadPlugin;
pub use prism_core::math::check_affine;
pub use prism_core::ron_error::describe as describe_ron_error;
pub use prism_engine::components::entity_label;
pub use ron_scene::{line_col, parse_scene, plugin_config};
pub use spawn::{FileSettings, camera_component, spawn_scene};
pub use transform::compose;

use glam::Vec3;
use hecs::World;
use prism_core::error::{PrismError, Result};
use prism_core::material::Material;
use prism_core::settings::{MAX_DEFAULT_PASSES, PluginConfig, RenderSettings, default_pass_layout};
use prism_engine::components::{Camera, Light, MaterialId, Name, Projection, Shape};
use prism_engine::{Resources, SceneSource};
use std::path::Path;

/// Load-stage system: spawn the scene's entities and resolve the settings.
pub fn load_scene_system(world: &mut World, res: &mut Resources) -> Result<()> {
    res.scene_hash = match &res.source {
        SceneSource::Prebuilt => 0,
        SceneSource::File(path) => hash_bytes(&prism_core::io::read_regular(path, "scene file")?),
        SceneSource::RonText { text, .. } => hash_bytes(text.as_bytes()),
    };
    // Parsing and spawning recurse once per nesting level: on a stack sized for the deepest nesting accepted.
    let file_settings = with_loader_stack(|| match res.source.clone() {
        SceneSource::Prebuilt => Ok(FileSettings::default()),
        SceneSource::File(path) => load_file(&path, world, res),
        SceneSource::RonText { text, name, base_dir } => {
            let desc = parse_scene(&text, &name)?;
            spawn_scene(&desc, &text, &name, &base_dir, world, res)
        }
    })?;
    if res.materials.is_empty() {
        res.materials.push(Material::default());
    }
    resolve_settings(world, res, file_settings)
}

/// Load-stage system, after the scene is loaded: every output (images, the film checkpoints write) can be written
/// and overwrites none of the scene's inputs, before any rendering starts.
pub fn check_outputs_system(_world: &mut World, res: &mut Resources) -> Result<()> {
    let mut outputs = res.outputs.clone();
    outputs.extend(res.film_path.iter().cloned());
    prism_core::io::check_outputs(&outputs, &res.inputs)
}

/// FNV-1a 64 of a scene file (part of a film's fingerprint).
fn hash_bytes(b: &[u8]) -> u64 {
    b.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &x| (h ^ x as u64).wrapping_mul(0x0000_0100_0000_01b3))
}

fn load_file(path: &Path, world: &mut World, res: &mut Resources) -> Result<FileSettings> {
    res.inputs.push(path.to_path_buf());
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    match ext.as_str() {
        "ron" => {
            let text = prism_core::io::read_regular_text(path, "scene file")?;
            let base = path.parent().unwrap_or(Path::new("."));
            let desc = parse_scene(&text, path)?;
            spawn_scene(&desc, &text, path, base, world, res)
        }
        "obj" => load_obj_scene(path, world, res),
        "ply" => load_ply_scene(path, world, res),
        "gltf" | "glb" => {
            res.materials.push(Material::default());
            gltf::load_gltf(path, world, res)
        }
        "pbrt" => {
            // A pbrt scene: spawned through its RON equivalent (what `prism convert` writes).
            let base = path.parent().unwrap_or(Path::new("."));
            let converted = pbrt::convert_file(path, base)?;
            res.inputs.extend(converted.files.iter().cloned());
            for w in &converted.warnings {
                eprintln!("warning: {w}");
            }
            let desc = parse_scene(&converted.ron, path)?;
            spawn_scene(&desc, &converted.ron, path, base, world, res)
        }
        "txt" => {
            // A 6.837 scene: spawned through its RON equivalent (what `prism convert` writes).
            let base = path.parent().unwrap_or(Path::new("."));
            let text = mit6837::convert_file(path, base, res.overrides.exact_curves)?.ron;
            let desc = parse_scene(&text, path)?;
            spawn_scene(&desc, &text, path, base, world, res)
        }
        "" => Err(PrismError::invalid(format!(
            "{}: scene file has no extension (expected .ron, .obj, .ply, .gltf, .glb, .pbrt or a 6.837 .txt)",
            path.display()
        ))),
        other => Err(PrismError::invalid(format!(
            "{}: unsupported scene format '.{other}' (expected .ron, .obj, .ply, .gltf, .glb, .pbrt or a 6.837 .txt)",
            path.display()
        ))),
    }
}

/// A bare PLY mesh as a scene: grey Lambert, framed and lit like a bare OBJ.
fn load_ply_scene(path: &Path, world: &mut World, res: &mut Resources) -> Result<FileSettings> {
    res.materials.push(Material::default());
    let mesh = ply::load_ply(path)?;
    let (lo, hi) =
        mesh.positions.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let name = Name(mesh.name.clone());
    let h = res.meshes.add(mesh);
    world.spawn((name, Shape::Mesh(h)));
    spawn_framing_camera_and_headlight(world, lo, hi, path, scene_overrides::default_light_allowed(&res.overrides))?;
    Ok(FileSettings::default())
}

/// A bare OBJ file as a scene: the mesh with its MTL materials, a camera framing it from +z, and a headlight
/// (a directional light along the view, irradiance pi, so an albedo-a surface facing the camera shows radiance a).
fn load_obj_scene(path: &Path, world: &mut World, res: &mut Resources) -> Result<FileSettings> {
    prism_core::io::open_regular(path, "scene file")?;
    res.materials.push(Material::default());
    let parts = load_obj(path)?;
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for part in parts {
        part.mesh.positions.iter().for_each(|p| {
            lo = lo.min(*p);
            hi = hi.max(*p);
        });
        let material = part.material.map(|m| {
            res.materials.push(m);
            res.materials.len() as u32 - 1
        });
        let name = Name(part.mesh.name.clone());
        let h = res.meshes.add(part.mesh);
        let e = world.spawn((name, Shape::Mesh(h)));
        if let Some(id) = material {
            world.insert_one(e, MaterialId(id)).ok();
        }
        if let Some(radiance) = part.emission {
            world.insert_one(e, Light::Area { radiance, two_sided: false, texture: None }).ok();
        }
    }
    spawn_framing_camera_and_headlight(world, lo, hi, path, scene_overrides::default_light_allowed(&res.overrides))?;
    Ok(FileSettings::default())
}

/// A 256 x 256 camera framing the box `[lo, hi]` from +z (fov 40) and, with `headlight`, a headlight along the
/// view (irradiance pi). A box beyond Prism's coordinate limit is an error naming the mesh file (`path`).
fn spawn_framing_camera_and_headlight(
    world: &mut World,
    lo: Vec3,
    hi: Vec3,
    path: &Path,
    headlight: bool,
) -> Result<()> {
    let reach = lo.abs().max(hi.abs()).max_element();
    if lo.cmple(hi).all() && (reach.is_nan() || reach > prism_core::limits::MAX_COORDINATE) {
        return Err(PrismError::format(
            path,
            format!(
                "coordinates reach {reach:e}, beyond Prism's coordinate limit of {:e}",
                prism_core::limits::MAX_COORDINATE
            ),
        ));
    }
    let (lo, hi) = if lo.cmple(hi).all() { (lo, hi) } else { (Vec3::ZERO, Vec3::ZERO) };
    let center = 0.5 * (lo + hi);
    let radius = (0.5 * (hi - lo).length()).max(1e-6);
    let fov: f32 = 40.0;
    let dist = 1.1 * radius / (0.5 * fov.to_radians()).sin();
    let eye = center + Vec3::new(0.0, 0.0, dist);
    world.spawn((
        Name("camera".into()),
        Camera {
            eye,
            target: center,
            up: Vec3::Y,
            projection: Projection::Perspective { fov_y: fov },
            width: 256,
            height: 256,
            aperture_radius: 0.0,
            focus_distance: dist,
            ..Camera::default()
        },
    ));
    if headlight {
        world.spawn((
            Name("headlight".into()),
            Light::Directional { irradiance: Vec3::splat(std::f32::consts::PI), direction: -Vec3::Z },
        ));
    }
    Ok(())
}

/// Merge file settings and overrides into `res.settings`; apply `--size` to the camera.
fn resolve_settings(world: &mut World, res: &mut Resources, f: FileSettings) -> Result<()> {
    let o = res.overrides.clone();
    let mut cams = world.query_mut::<&mut Camera>().into_iter();
    let cam = cams.next().ok_or_else(|| match &res.source {
        SceneSource::File(p) => PrismError::format(p, "the scene has no camera (add `camera: (...)`)"),
        SceneSource::RonText { name, .. } => PrismError::format(name, "the scene has no camera (add `camera: (...)`)"),
        SceneSource::Prebuilt => PrismError::invalid("the scene has no camera (spawn an entity with a `Camera`)"),
    })?;
    if cams.next().is_some() {
        return Err(PrismError::invalid("the scene has more than one camera"));
    }
    if let Some((w, h)) = o.size {
        cam.width = w;
        cam.height = h;
    }
    let (width, height) = (cam.width, cam.height);
    let d = RenderSettings::default();
    let f_integrator_pos = f.position("integrator").cloned();
    // A bare `--integrator NAME` naming the scene's integrator keeps the scene's parameters.
    let integrator = match (o.integrator.as_deref().map(PluginConfig::from_spec).transpose()?, f.integrator.clone()) {
        (Some(spec), Some(cfg)) if spec.name == cfg.name && spec.params.is_none() => cfg,
        (Some(spec), _) => spec,
        (None, Some(cfg)) => cfg,
        (None, None) => d.integrator.clone(),
    };
    let time_budget = o.time_budget.or(f.time);
    let noise = o.noise.or(f.noise);
    // A time budget given without a sample count renders until the budget is spent.
    // So does a scene's noise target without a sample count (up to `MAX_NOISE_SPP`).
    let unlimited = o.spp_unlimited || (f.noise.is_some() && f.spp.is_none());
    let spp = if unlimited && o.spp.is_none() { None } else { Some(o.spp.or(f.spp).unwrap_or(d.spp.unwrap_or(16))) };
    let adaptive = o.adaptive.or(f.adaptive).unwrap_or(d.adaptive);
    let shards = o.shard.unwrap_or(d.shard).1;
    // Passes given (on the command line, or in the scene unless the command line sets the sample count) split the
    // samples evenly; otherwise the default layout, whose adaptive pilot is a first pass of its own.
    // An adaptive render's pilot is always its own first pass of `spp / 16` samples, before the passes asked for:
    // the pilot decides every pixel's samples, so the image must not depend on how the rest is split.
    let with_pilot = |n: u32, p: u32| match default_pass_layout(n, adaptive, 1) {
        (_, Some(pilot)) => (1 + p.min(n - pilot).max(1), Some(pilot)),
        (_, None) => (p.min(n).max(1), None),
    };
    let (passes, pilot_spp) = match (o.passes, spp) {
        (Some(p), Some(n)) if adaptive => with_pilot(n, p),
        (Some(p), Some(_)) => (p, None),
        // Without a sample limit `passes` sets the passes' size (below), not their number.
        (Some(_), None) => (u32::MAX, None),
        (None, None) => (u32::MAX, None),
        // A noise target checks the error after every pass: passes of `NOISE_PASS_SPP` samples.
        (None, Some(n)) if noise.is_some() && (f.passes.is_none() || o.spp.is_some()) => {
            let p = (n / prism_core::film::NOISE_PASS_SPP).max(1);
            if adaptive { with_pilot(n, p.max(2)) } else { (p, None) }
        }
        (None, Some(n)) => match f.passes {
            Some(p) if o.spp.is_none() && adaptive => with_pilot(n, p),
            Some(p) if o.spp.is_none() => (p.min(n), None),
            _ => default_pass_layout(n, adaptive, shards),
        },
    };
    // Without a sample limit (a time budget) a pass holds the scene's samples split into `passes` (the command
    // line's, else the scene's) or up to 16 passes; the budget stops the pass it runs out in (that pass is cut short
    // and does not count), and convergence curves sample time through these budgets.
    let scene_spp = f.spp.unwrap_or(16);
    let pass_spp = match (noise, o.passes) {
        // A noise target without a sample limit checks the error after every pass of `NOISE_PASS_SPP` samples.
        (Some(_), None) => prism_core::film::NOISE_PASS_SPP,
        _ => (scene_spp / o.passes.or(f.passes).unwrap_or(scene_spp.clamp(1, MAX_DEFAULT_PASSES)).max(1)).max(1),
    };
    res.settings = RenderSettings {
        width,
        height,
        spp,
        passes,
        pilot_spp,
        pass_spp,
        sampler: o.sampler.or(f.sampler).unwrap_or(d.sampler),
        pattern: o.pattern.or(f.pattern),
        filter: o.filter.or(f.filter).unwrap_or(d.filter),
        adaptive,
        seed: o.seed.or(f.seed).unwrap_or(d.seed),
        time_budget,
        noise,
        integrator,
        accel: o.accel.or(f.accel).unwrap_or(d.accel),
        exposure: o.exposure.or(f.exposure).unwrap_or(d.exposure),
        shard: o.shard.unwrap_or(d.shard),
    };
    if let Err((field, message)) = res.settings.check() {
        // A value the scene gave (the command line did not override it) is reported where the scene gives it.
        let from_file = match field {
            "size" => o.size.is_none(),
            "spp" => o.spp.is_none(),
            "passes" => o.passes.is_none() && (f.passes.is_some() || o.spp.is_none()),
            "time" => o.time_budget.is_none(),
            "noise" => o.noise.is_none(),
            "filter" => o.filter.is_none(),
            "exposure" => o.exposure.is_none(),
            _ => false,
        };
        let at = if field == "passes" && f.position("passes").is_none() { "spp" } else { field };
        let block = if field == "size" { "camera" } else { "render" };
        return Err(match f.position(at).filter(|_| from_file) {
            Some(pos) => PrismError::Parse { pos: pos.clone(), message: format!("{block}: {message}") },
            None => PrismError::invalid(message),
        });
    }
    if !res.integrators.contains(&res.settings.integrator.name) {
        let message = format!(
            "unknown integrator '{}' (available: {})",
            res.settings.integrator.name,
            res.integrators.names().join(", ")
        );
        return Err(match f_integrator_pos {
            Some(pos) if o.integrator.is_none() => PrismError::Parse { pos, message: format!("render: {message}") },
            _ => PrismError::invalid(message),
        });
    }
    Ok(())
}
