//! The Propagate stage: compose each entity's `Transform` with its ancestors' into `WorldFromLocal`
//! (world_from_local = parent.world_from_local * local), for every entity, in any nesting depth.

use crate::components::{Parent, Transform, WorldFromLocal};
use glam::Affine3A;
use hecs::{Entity, World};
use prism_core::error::{PrismError, Result};
use std::collections::HashMap;

/// Insert every entity's `WorldFromLocal`: its `Transform` composed with its ancestors'. Errors on a parent cycle
/// and on a composed transform that is not finite and invertible.
pub fn propagate_transforms(world: &mut World, res: &mut crate::Resources) -> Result<()> {
    let nodes: HashMap<Entity, (Affine3A, Option<Entity>)> = world
        .query::<(Entity, Option<&Transform>, Option<&Parent>)>()
        .iter()
        .map(|(e, t, p)| (e, (t.map_or(Affine3A::IDENTITY, |t| t.0), p.map(|p| p.0))))
        .collect();
    let mut resolved: HashMap<Entity, Affine3A> = HashMap::with_capacity(nodes.len());
    for &start in nodes.keys() {
        // Walk up to the first resolved ancestor (or the root), then compose back down.
        let mut chain = vec![];
        let mut cur = Some(start);
        while let Some(e) = cur {
            if resolved.contains_key(&e) {
                break;
            }
            if chain.len() > nodes.len() {
                return Err(PrismError::invalid(format!(
                    "{}: parent chain has a cycle",
                    crate::components::entity_label(world, start)
                )));
            }
            chain.push(e);
            cur = nodes.get(&e).and_then(|(_, p)| *p);
        }
        let mut m = cur.and_then(|e| resolved.get(&e).copied()).unwrap_or(Affine3A::IDENTITY);
        for e in chain.into_iter().rev() {
            m *= nodes.get(&e).map_or(Affine3A::IDENTITY, |n| n.0);
            resolved.insert(e, m);
        }
    }
    for (e, m) in resolved {
        prism_core::math::check_affine(&m, &crate::components::entity_label(world, e))
            .map_err(|err| crate::stages::in_scene_file(res, err))?;
        world.insert_one(e, WorldFromLocal(m)).map_err(|_| PrismError::invalid("entity vanished during Propagate"))?;
    }
    Ok(())
}
