//! How directions towards the environment light are sampled, for next-event estimation and for emitted rays: the
//! quad-tree (default), the piecewise-constant 2D baseline, uniform directions on the sphere, or cosine-weighted
//! directions around the shading normal (no knowledge of the map; emission, which has no normal, then samples
//! uniformly). A constant environment is sampled uniformly whatever the choice, which is exact importance sampling
//! for it. Built in Prepare by the integrators that sample the environment, only when the scene has one.

use super::piecewise::Piecewise2D;
use super::quadtree::QuadTree;
use crate::envmap::EnvMap;
use crate::lights::EnvironmentLight;
use crate::math::Frame;
use crate::sampling::warp;
use glam::{Vec2, Vec3A};
use serde::Deserialize;

/// The direction sampler an integrator asks for (`envlight`'s `env_sampling`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum EnvStrategy {
    /// The map's quad-tree: directions by the map's radiance times solid angle (the default).
    #[default]
    Quadtree,
    /// The piecewise-constant 2D distribution over the map's texels (pbrt-v3's `Distribution2D`).
    Piecewise,
    /// Uniform directions on the sphere.
    Uniform,
    /// Cosine-weighted directions about the shading normal, whatever the map.
    Cosine,
}

#[derive(Clone, Debug)]
enum Sampler {
    Uniform,
    Cosine,
    QuadTree(QuadTree),
    Piecewise(Piecewise2D),
    /// The map is black: nothing to sample.
    Black,
}

/// The environment light's direction sampler, built for one [`EnvStrategy`].
#[derive(Clone, Debug)]
pub struct EnvSampling {
    sampler: Sampler,
}

impl EnvSampling {
    /// The sampler of `strategy` for `env`: uniform for a constant environment (unless `Cosine`, which never
    /// reads the map), none at all for a map with no radiance (every sample `None`, every pdf 0).
    pub fn new(env: &EnvironmentLight, strategy: EnvStrategy) -> Self {
        let sampler = match (&env.map, strategy) {
            (_, EnvStrategy::Cosine) => Sampler::Cosine,
            (None, _) | (_, EnvStrategy::Uniform) => Sampler::Uniform,
            (Some(map), EnvStrategy::Quadtree) => QuadTree::build(map).map_or(Sampler::Black, Sampler::QuadTree),
            (Some(map), EnvStrategy::Piecewise) => Piecewise2D::build(map).map_or(Sampler::Black, Sampler::Piecewise),
        };
        EnvSampling { sampler }
    }

    /// Quad-tree statistics (nodes, non-empty leaves), if that is the sampler.
    pub fn quadtree_size(&self) -> Option<(usize, usize)> {
        match &self.sampler {
            Sampler::QuadTree(q) => Some((q.node_count(), q.leaf_count())),
            _ => None,
        }
    }

    /// A world direction towards the environment and its solid-angle pdf; `n` is the shading normal (used by the
    /// cosine strategy).
    #[inline]
    pub fn sample(&self, env: &EnvironmentLight, n: Vec3A, u: Vec2) -> Option<(Vec3A, f32)> {
        match &self.sampler {
            Sampler::Uniform => Some((warp::uniform_sphere(u), warp::uniform_sphere_pdf())),
            Sampler::Cosine => {
                let local = warp::cosine_hemisphere(u);
                let pdf = warp::cosine_hemisphere_pdf(local);
                (pdf > 0.0).then(|| (Frame::from_normal(n).to_world(local), pdf))
            }
            Sampler::QuadTree(q) => {
                let map: &EnvMap = env.map.as_deref()?;
                q.sample(map, u).map(|s| (env.to_world(s.dir), s.pdf))
            }
            Sampler::Piecewise(p) => {
                let map: &EnvMap = env.map.as_deref()?;
                p.sample(map, u).map(|(d, pdf)| (env.to_world(d), pdf))
            }
            Sampler::Black => None,
        }
    }

    /// A world direction towards the environment for an emitted ray, with its solid-angle pdf (the cosine
    /// strategy, which needs a surface normal, samples uniformly here).
    #[inline]
    pub fn sample_emission(&self, env: &EnvironmentLight, u: Vec2) -> Option<(Vec3A, f32)> {
        match &self.sampler {
            Sampler::Cosine => Some((warp::uniform_sphere(u), warp::uniform_sphere_pdf())),
            _ => self.sample(env, Vec3A::Z, u),
        }
    }

    /// Solid-angle pdf of `sample_emission` producing the world direction `dir` (towards the environment).
    #[inline]
    pub fn pdf_emission(&self, env: &EnvironmentLight, dir: Vec3A) -> f32 {
        match &self.sampler {
            Sampler::Cosine => warp::uniform_sphere_pdf(),
            _ => self.pdf(env, Vec3A::Z, dir),
        }
    }

    /// Solid-angle pdf of `sample` producing world direction `dir` at a point with shading normal `n`.
    #[inline]
    pub fn pdf(&self, env: &EnvironmentLight, n: Vec3A, dir: Vec3A) -> f32 {
        match &self.sampler {
            Sampler::Uniform => warp::uniform_sphere_pdf(),
            Sampler::Cosine => warp::cosine_hemisphere_pdf(Vec3A::new(0.0, 0.0, dir.dot(n))),
            Sampler::QuadTree(q) => env.map.as_deref().map_or(0.0, |m| q.pdf(m, env.to_env(dir))),
            Sampler::Piecewise(p) => env.map.as_deref().map_or(0.0, |m| p.pdf(m, env.to_env(dir))),
            Sampler::Black => 0.0,
        }
    }
}
