//! The BuildAccel stage: the entities flattened into primitives, the chosen accelerator built over them, and the
//! camera; the render scene assembled (its lights follow in Prepare).

use super::{flatten_shapes, in_scene_file};
use crate::Resources;
use crate::components::{Camera, WorldFromLocal};
use hecs::World;
use prism_core::accel::Accel;
use prism_core::camera::CameraRig;
use prism_core::error::{PrismError, Result};
use prism_core::lights::LightSet;
use prism_core::primitives::EntityPrims;
use prism_core::scene::Scene;
use std::time::Instant;

/// Entities with area lights and their primitive ranges, from BuildAccel to Prepare.
pub(super) struct Emitters(pub(super) Vec<(hecs::Entity, EntityPrims)>);

/// Flatten the entities into primitives, build the chosen accelerator and the camera, and store the render scene
/// (without lights) in `scene`. Errors when there is no camera or its view is degenerate, and on bad geometry or
/// accelerator settings.
pub fn build_scene_system(world: &mut World, res: &mut Resources) -> Result<()> {
    let t0 = Instant::now();
    let camera = {
        let mut q = world.query::<(&Camera, Option<&WorldFromLocal>)>();
        let (cam, wfl) = q.iter().next().ok_or_else(|| PrismError::invalid("the scene has no camera"))?;
        CameraRig::new(cam, &wfl.map(|w| w.0).unwrap_or_default())
            .ok_or_else(|| PrismError::invalid("camera: eye, target and up do not define a view"))?
    };
    let (prims, emitters) = flatten_shapes(world, &res.meshes, &res.materials).map_err(|e| in_scene_file(res, e))?;
    if prims.skipped_degenerate > 0 {
        eprintln!("warning: skipped {} degenerate (zero-area or non-finite) mesh triangles", prims.skipped_degenerate);
    }
    let st = &res.settings;
    let samples = st.spp.map(|spp| st.width as u64 * st.height as u64 * spp as u64);
    let splits = prism_core::accel::SpatialSplits::for_samples(samples, prims.num_bounded() as u64);
    let kind = st.accel;
    // A process that loads the scene again (`prism watch`) reuses the last accelerator over the same geometry.
    let cached = res.get_mut::<crate::reload_cache::ReloadCache>().map(|c| {
        let key = crate::reload_cache::geometry_key(&prims, &format!("{kind:?} {splits:?}"));
        c.take_accel(key)
    });
    let accel = match cached {
        Some(Some(accel)) => accel,
        _ => Accel::build_with(kind, &prims, splits)?,
    };
    res.insert(Emitters(emitters));
    res.scene = Some(Scene {
        camera,
        prims,
        accel,
        lights: LightSet::default(),
        materials: prism_core::material::MaterialSet::new(res.materials.clone()),
        textures: res.textures.clone(),
        globals: res.globals,
        cancel: res.cancel.clone(),
    });
    res.progress.setup += t0.elapsed();
    Ok(())
}
