//! The scene's materials as the renderer reads them: the list (indexed by a primitive's material id; it derefs to
//! `[Material]`) and, classified once when the scene is built, each material's shortcut at a hit. Today one
//! shortcut: a material that is one constant Lambertian lobe (every wall of a Cornell box) is resolved without
//! looking at its terms, where classifying it at every path vertex had cost four parameter tests and a match
//! (1.8% of the Cornell box's instructions).

use super::{Material, MaterialKind, PhongParams};
use glam::Vec3;

/// The materials, with their per-hit shortcuts (see the module notes). Built by [`MaterialSet::new`]; read-only.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MaterialSet {
    list: Vec<Material>,
    /// Per material: its albedo if it is a Phong-family material whose only term is a constant diffuse one.
    lambert: Vec<Option<Vec3>>,
}

impl MaterialSet {
    /// The set of `list`, classified.
    pub fn new(list: Vec<Material>) -> Self {
        let lambert = list
            .iter()
            .map(|m| match &m.kind {
                MaterialKind::Phong(p) => plain_lambert(p),
                _ => None,
            })
            .collect();
        MaterialSet { list, lambert }
    }

    /// Material `id`'s albedo if it is a Phong-family material that is only a constant Lambertian lobe (no
    /// ambient, specular, mirror or transmission term, no texture); `None` otherwise (also for an unknown id).
    #[inline(always)]
    pub fn lambert(&self, id: u32) -> Option<Vec3> {
        self.lambert.get(id as usize).copied().flatten()
    }
}

impl std::ops::Deref for MaterialSet {
    type Target = [Material];

    fn deref(&self) -> &[Material] {
        &self.list
    }
}

/// The albedo of a Phong-family material that is only a constant Lambertian lobe.
fn plain_lambert(p: &PhongParams) -> Option<Vec3> {
    if p.ambient.is_zero() && p.specular.is_zero() && p.reflective.is_zero() && p.transparent.is_zero() {
        p.diffuse.constant()
    } else {
        None
    }
}
