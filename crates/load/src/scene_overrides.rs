//! The Load stage's `apply_scene_overrides` system: the command line's changes to a loaded scene, whatever its
//! format, before anything is built from it.
//!
//! - **Environment** (`--env FILE [--env-scale S] [--env-rotate DEG] [--env-layout L]`, `--sky R,G,B`): every environment light of
//!   the scene is removed and the given one added (a map turned by `DEG` about +y, or a uniform sky). The map is an
//!   input of the render (outputs may not overwrite it). Loaders add no default light when an environment is given.
//! - **View** (`--look-from X,Y,Z`, `--look-at X,Y,Z`, `--up X,Y,Z`, `--fov DEG`): the scene camera's eye, target,
//!   up hint and vertical field of view, in world space; what is not given keeps the camera's (composed with the
//!   camera's parents into world space first). `--fov` on an orthographic camera is an error.
//! - The overrides that change the image (these, `--camera`, `--no-default-light`) are part of the film's
//!   fingerprint, so `--resume` refuses a film rendered with other ones.

use crate::spawn::environment_light;
use glam::{Affine3A, Vec3};
use hecs::{Entity, World};
use prism_core::error::{PrismError, Result};
use prism_core::settings::{EnvOverride, Overrides, ViewOverride};
use prism_engine::Resources;
use prism_engine::components::{Camera, Light, Name, Parent, Projection, Transform};

/// Whether a loader may add its default light (a bare mesh's headlight, a light-less glTF's sky): not when the
/// command line gives an environment or asks for none.
pub fn default_light_allowed(o: &Overrides) -> bool {
    !o.no_default_light && o.environment.is_none()
}

/// Load-stage system: apply `--env`/`--sky` and the view overrides to the loaded scene; fold every
/// image-changing override into the scene's fingerprint.
pub fn apply_scene_overrides(world: &mut World, res: &mut Resources) -> Result<()> {
    let o = res.overrides.clone();
    if let Some(env) = &o.environment {
        replace_environment(world, res, env)?;
    }
    if o.view.is_set() {
        apply_view(world, &o.view)?;
    }
    if o.view.is_set() || o.environment.is_some() || o.no_default_light || o.camera.is_some() {
        let key = format!("{:?} {:?} {} {:?}", o.view, o.environment, o.no_default_light, o.camera);
        res.scene_hash = key
            .bytes()
            .fold(res.scene_hash ^ 0x5851_F42D_4C95_7F2D, |h, b| (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3));
    }
    Ok(())
}

fn replace_environment(world: &mut World, res: &mut Resources, env: &EnvOverride) -> Result<()> {
    let old: Vec<Entity> = world
        .query::<(Entity, &Light)>()
        .iter()
        .filter(|(_, l)| matches!(l, Light::Environment { .. }))
        .map(|(e, _)| e)
        .collect();
    for e in old {
        world.remove_one::<Light>(e).map_err(|_| PrismError::invalid("environment light entity vanished"))?;
    }
    match env {
        EnvOverride::Sky(radiance) => {
            if !(radiance.is_finite() && radiance.min_element() >= 0.0) {
                return Err(PrismError::invalid(format!("--sky: radiance must be finite and >= 0, got {radiance}")));
            }
            world.spawn((Name("--sky".into()), Light::Environment { radiance: *radiance, map: None }));
        }
        EnvOverride::Map { path, scale, rotate_deg, layout } => {
            if !(scale.is_finite() && *scale >= 0.0) {
                return Err(PrismError::invalid(format!("--env-scale must be finite and >= 0, got {scale}")));
            }
            if !rotate_deg.is_finite() {
                return Err(PrismError::invalid(format!("--env-rotate must be finite, got {rotate_deg}")));
            }
            res.inputs.push(path.clone());
            let layout = match layout {
                Some(name) => Some(ron::from_str::<prism_core::envmap::SourceLayout>(name).map_err(|_| {
                    PrismError::invalid(format!("--env-layout: unknown layout '{name}' (Equirect, Cross, EqualArea)"))
                })?),
                None => None,
            };
            let light = environment_light(std::slice::from_ref(path), layout, Vec3::splat(*scale)).map_err(|e| {
                PrismError::invalid(
                    format!("--env: {e}").replace("give `layout: Equirect`", "give `--env-layout equirect`"),
                )
            })?;
            // As a RON `Rotate(axis: (0, 1, 0), degrees: DEG)` makes it.
            let turn = Affine3A::from_quat(glam::Quat::from_axis_angle(Vec3::Y, rotate_deg.to_radians()));
            world.spawn((Name("--env".into()), Transform(turn), light));
        }
    }
    Ok(())
}

/// The scene's camera with its eye, target and up in world space (its parents' frames composed in).
pub fn camera_in_world(world: &World) -> Result<Camera> {
    scene_camera(world).map(|(_, cam)| cam)
}

/// The scene's camera entity, and its camera with eye, target and up in world space.
fn scene_camera(world: &World) -> Result<(Entity, Camera)> {
    let (e, mut cam) = world
        .query::<(Entity, &Camera)>()
        .iter()
        .map(|(e, c)| (e, *c))
        .next()
        .ok_or_else(|| PrismError::invalid("the scene has no camera"))?;
    let m = world_from_camera(world, e)?;
    cam.eye = m.transform_point3(cam.eye);
    cam.target = m.transform_point3(cam.target);
    cam.up = m.transform_vector3(cam.up);
    Ok((e, cam))
}

/// The camera's frame composed with its parents' (the Propagate stage has not run yet).
fn world_from_camera(world: &World, cam: Entity) -> Result<Affine3A> {
    let mut m = Affine3A::IDENTITY;
    let mut cur = Some(cam);
    let mut steps = 0usize;
    let limit = world.len() as usize + 1;
    while let Some(e) = cur {
        steps += 1;
        if steps > limit {
            return Err(PrismError::invalid("the camera's parent chain has a cycle"));
        }
        if let Ok(t) = world.get::<&Transform>(e) {
            m = t.0 * m;
        }
        cur = world.get::<&Parent>(e).ok().map(|p| p.0);
    }
    Ok(m)
}

fn apply_view(world: &mut World, view: &ViewOverride) -> Result<()> {
    let (cam_entity, mut cam) = scene_camera(world)?;
    let check = |v: Option<Vec3>, flag: &str| -> Result<Option<Vec3>> {
        match v {
            Some(p) if !p.is_finite() || p.abs().max_element() > prism_core::limits::MAX_COORDINATE => {
                Err(PrismError::invalid(format!("{flag}: {p} is not finite or beyond Prism's coordinate limit")))
            }
            other => Ok(other),
        }
    };
    let eye = check(view.from, "--look-from")?.unwrap_or(cam.eye);
    let target = check(view.at, "--look-at")?.unwrap_or(cam.target);
    let up = check(view.up, "--up")?.unwrap_or(cam.up);
    let forward = prism_core::math::unit_vector(target - eye)
        .ok_or_else(|| PrismError::invalid(format!("--look-from and --look-at are the same point ({eye})")))?;
    if prism_core::math::unit_vector(forward.cross(up)).is_none() {
        return Err(PrismError::invalid(format!(
            "--up {up} is parallel to the view direction {forward} (give another --up)"
        )));
    }
    if let Some(fov) = view.fov {
        match &mut cam.projection {
            Projection::Perspective { fov_y } => {
                if !(fov > 0.0 && fov < 180.0) {
                    return Err(PrismError::invalid(format!("--fov must be in (0, 180) degrees, got {fov}")));
                }
                *fov_y = fov;
            }
            _ => return Err(PrismError::invalid("--fov applies to perspective cameras; this camera is orthographic")),
        }
    }
    // A moved thin-lens camera keeps its focus on the point it now looks at.
    if view.from.is_some() || view.at.is_some() {
        cam.focus_distance = (target - eye).length();
    }
    cam.eye = eye;
    cam.target = target;
    cam.up = up;
    world.insert_one(cam_entity, cam).map_err(|_| PrismError::invalid("camera entity vanished"))?;
    // The view is now in world space: the camera leaves its parents' frames (absent components are fine).
    let _ = world.remove_one::<Transform>(cam_entity);
    let _ = world.remove_one::<Parent>(cam_entity);
    Ok(())
}
