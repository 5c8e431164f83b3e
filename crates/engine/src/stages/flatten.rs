//! The BuildAccel and Prepare stages' view of the world: the entities with a `Shape` gathered into the primitive
//! store's [`ShapeInstance`]s (in entity-id order, so the primitive order does not depend on archetypes), and the
//! entities with a `Light` into [`PlacedLight`]s, with errors naming the entity.

use crate::components::{AlphaMask, Light, MaterialId, Shape, WorldFromLocal, entity_label};
use glam::Affine3A;
use hecs::{Entity, World};
use prism_core::error::Result;
use prism_core::lights::{LightSet, PlacedLight};
use prism_core::material::Material;
use prism_core::mesh::MeshStore;
use prism_core::primitives::{EntityPrims, Primitives, ShapeInstance};

/// Flatten every entity with a shape. Returns the primitives and, per entity with an area light (in light-slot
/// order), its primitives.
pub fn flatten_shapes(
    world: &World,
    meshes: &MeshStore,
    materials: &[Material],
) -> Result<(Primitives, Vec<(Entity, EntityPrims)>)> {
    let num_materials = materials.len() as u32;
    let mut q = world
        .query::<(Entity, &Shape, Option<&WorldFromLocal>, Option<&MaterialId>, Option<&Light>, Option<&AlphaMask>)>();
    let mut items: Vec<_> = q.iter().collect();
    // Entity order is deterministic already; sort by id so the primitive order does not depend on archetypes.
    items.sort_by_key(|(e, ..)| e.id());
    let shapes: Vec<ShapeInstance> = items
        .iter()
        .map(|&(_, shape, wfl, mat, light, alpha)| {
            let material = mat.map(|m| m.0).unwrap_or(0).min(num_materials.saturating_sub(1));
            let m = materials.get(material as usize);
            ShapeInstance {
                shape,
                world_from_local: wfl.map(|w| w.0).unwrap_or(Affine3A::IDENTITY),
                material,
                area_light: matches!(light, Some(Light::Area { .. })),
                alpha,
                // Asked only where the store reads the answer (spheres' texture coordinates, meshes' tangents).
                surface_coordinates: matches!(shape, Shape::Sphere { .. })
                    && m.is_none_or(|x| x.uses_surface_coordinates(materials)),
                tangents: matches!(shape, Shape::Mesh(_)) && m.is_some_and(|x| x.needs_tangents()),
            }
        })
        .collect();
    let (prims, emitters) = Primitives::build(&shapes, meshes, |i| entity_label(world, items[i].0))?;
    Ok((prims, emitters.into_iter().map(|(i, ep)| (items[i].0, ep)).collect()))
}

/// Resolve the world's lights: the area lights of `emitters` (entities and their primitives, in light-slot order),
/// then every other light in entity-id order.
pub fn place_lights(world: &World, prims: &Primitives, emitters: &[(Entity, EntityPrims)]) -> Result<LightSet> {
    let area: Vec<(Entity, hecs::Ref<'_, Light>, EntityPrims)> =
        emitters.iter().filter_map(|&(e, ep)| world.get::<&Light>(e).ok().map(|l| (e, l, ep))).collect();
    let mut q = world.query::<(Entity, &Light, Option<&WorldFromLocal>)>();
    let mut others: Vec<_> = q.iter().filter(|(_, l, _)| !matches!(l, Light::Area { .. })).collect();
    others.sort_by_key(|(e, ..)| e.id());
    let mut owners = Vec::with_capacity(area.len() + others.len());
    let mut placed = Vec::with_capacity(area.len() + others.len());
    for (e, light, ep) in &area {
        owners.push(*e);
        placed.push(PlacedLight { light, world_from_local: Affine3A::IDENTITY, emitter: Some(*ep) });
    }
    for &(e, light, wfl) in &others {
        owners.push(e);
        placed.push(PlacedLight { light, world_from_local: wfl.map(|w| w.0).unwrap_or_default(), emitter: None });
    }
    LightSet::build(&placed, prims, |i| entity_label(world, owners[i]))
}
