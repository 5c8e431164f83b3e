//! ECS components carried by scene entities. An entity carries only what it uses: a group node has a `Name` and a
//! `Transform`; a sphere adds `Shape` and `MaterialId`; an area light adds `Light::Area` to a shape; the camera
//! is an entity with a `Camera`. `WorldFromLocal` is derived by the Propagate stage from `Transform` and `Parent`.

use glam::Affine3A;

pub use prism_core::alpha::AlphaMask;
pub use prism_core::camera::{Camera, Projection};
pub use prism_core::lights::Light;
pub use prism_core::material::MaterialId;
pub use prism_core::mesh::MeshHandle;
pub use prism_core::shapes::Shape;

/// Human-readable entity name, used in error messages and statistics.
#[derive(Clone, Debug)]
pub struct Name(pub String);

/// The entity's local transform: `parent_from_local`. Absent means identity.
#[derive(Clone, Copy, Debug)]
pub struct Transform(pub Affine3A);

/// The entity this one is nested in; it inherits that entity's transform.
#[derive(Clone, Copy, Debug)]
pub struct Parent(pub hecs::Entity);

/// Composed transform from the entity's local frame to world space (written by the Propagate stage).
#[derive(Clone, Copy, Debug)]
pub struct WorldFromLocal(pub Affine3A);

/// How errors name an entity: `entity 'NAME'`, or `entity #ID` when it has no name.
pub fn entity_label(world: &hecs::World, e: hecs::Entity) -> String {
    match world.get::<&Name>(e) {
        Ok(n) => format!("entity '{}'", n.0),
        Err(_) => format!("entity #{}", e.id()),
    }
}
