//! The render-time scene integrators see: camera, primitives, accelerator, lights, materials and scene globals,
//! flattened out of the ECS world by the BuildAccel and Prepare stages. Read-only while rendering, shared by all
//! threads.

use crate::accel::Accel;
use crate::bsdf::Bsdf;
use crate::camera::CameraRig;
use crate::geometry::Ray;
use crate::lights::LightSet;
use crate::material::{Material, MaterialSet};
use crate::primitives::{Hit, NO_LIGHT, Primitives, SurfaceHit};
use crate::texture::TextureSet;
use glam::{Vec3, Vec3A};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Scene-wide values that are not entities.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SceneGlobals {
    /// Radiance of rays that leave the scene.
    pub background: Vec3,
    /// Ambient radiance (reflected by materials' `ambient` coefficient).
    pub ambient: Vec3,
}

/// Everything a render reads: built once before the first pass, then shared read-only by every thread.
pub struct Scene {
    /// The camera the render looks through, in world space.
    pub camera: CameraRig,
    /// Every primitive in world space.
    pub prims: Primitives,
    /// The accelerator over the bounded primitives.
    pub accel: Accel,
    /// The lights in world space.
    pub lights: LightSet,
    /// The material table primitives' `material` indices refer to.
    pub materials: MaterialSet,
    /// The texture table materials refer to.
    pub textures: TextureSet,
    /// Background and ambient radiance.
    pub globals: SceneGlobals,
    /// Set when the render is cancelled (Ctrl-C): estimators whose work per sample can be huge (Whitted-style
    /// branching) check it and return early; the sample is then discarded.
    pub cancel: Arc<AtomicBool>,
}

impl Scene {
    /// True once the render has been cancelled.
    #[inline]
    pub fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// Closest hit along the ray (accelerator for bounded primitives, then the unbounded planes); hits on the
    /// holes of alpha-masked triangles are skipped (see [`crate::alpha`]).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        if self.prims.has_alpha() {
            return self.intersect_through_alpha(ray);
        }
        self.intersect_opaque(ray)
    }

    /// The closest hit of each of `rays` into `out` (as long as `rays`): rays traced together, such as one pixel's
    /// camera rays, go down the accelerator as a packet ([`crate::accel::Accelerator::intersect_packet`]). The same
    /// hits as [`Scene::intersect`] ray by ray, except that of two surfaces at exactly the same distance either may
    /// be reported.
    pub fn intersect_packet(&self, rays: &[Ray], out: &mut [Option<Hit>]) {
        if self.prims.has_alpha() || !self.prims.planes.is_empty() {
            for (o, r) in out.iter_mut().zip(rays) {
                *o = self.intersect(r);
            }
            return;
        }
        self.accel.intersect_packet(&self.prims, rays, out);
    }

    #[inline]
    fn intersect_opaque(&self, ray: &Ray) -> Option<Hit> {
        let hit = self.accel.intersect(&self.prims, ray);
        if self.prims.planes.is_empty() {
            return hit;
        }
        let r = Ray { tmax: hit.map_or(ray.tmax, |h| h.t), ..*ray };
        self.prims.intersect_planes(&r).or(hit)
    }

    /// Closest hit that an alpha mask does not let through: each skipped hit restarts the ray just behind the
    /// surface (offset by its error bound) with `t` kept relative to the original ray. After 1024 crossed surfaces
    /// the ray counts as escaped (nothing loops forever).
    fn intersect_through_alpha(&self, ray: &Ray) -> Option<Hit> {
        let mut r = *ray;
        let mut t0 = 0.0f32;
        for _ in 0..1024 {
            let h = self.intersect_opaque(&r)?;
            if !self.prims.alpha_passes(&h, &r) {
                return Some(Hit { t: t0 + h.t, ..h });
            }
            let s = self.prims.surface(&r, &h);
            let next = s.spawn(r.dir);
            let dt = (next.origin - ray.origin).dot(ray.dir) / ray.dir.length_squared();
            if dt.is_nan() || dt <= t0 || dt >= ray.tmax {
                return None;
            }
            t0 = dt;
            r = Ray {
                origin: next.origin,
                dir: ray.dir,
                tmax: ray.tmax - t0,
                leaves: next.leaves,
                coherent: ray.coherent,
            };
        }
        None
    }

    /// True when anything blocks the ray before `ray.tmax` (alpha holes let it through).
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        if self.prims.has_alpha() {
            return self.intersect_through_alpha(ray).is_some();
        }
        self.prims.planes_occlude(ray) || self.accel.occluded(&self.prims, ray)
    }

    /// Closest hit with its surface data.
    #[inline(always)]
    pub fn trace(&self, ray: &Ray) -> Option<SurfaceHit> {
        self.intersect(ray).map(|h| self.prims.surface(ray, &h))
    }

    /// Material `id` of the table (an index some primitive holds; panics beyond the table).
    #[inline]
    pub fn material(&self, id: u32) -> &Material {
        &self.materials[id as usize]
    }

    /// The BSDF of the surface at `s` seen from `wo` (unit, pointing away from the surface): the material
    /// resolved at the hit (textures, blends, normal and bump maps). `None` when the surface reflects nothing
    /// towards `wo` and has no ambient term (a black material, the back of a one-sided one).
    #[inline(always)]
    pub fn bsdf(&self, s: &SurfaceHit, wo: Vec3A) -> Option<Bsdf> {
        crate::material::bsdf(&self.materials, &self.textures, &self.prims, s, wo, None)
    }

    /// [`Scene::bsdf`] written into `out` (reusing its storage); false when the surface reflects nothing towards
    /// `wo`. For path loops: one `Bsdf` per path instead of one moved out of every hit.
    #[inline(always)]
    pub fn bsdf_into(&self, s: &SurfaceHit, wo: Vec3A, out: &mut Bsdf) -> bool {
        crate::material::bsdf_into(&self.materials, &self.textures, &self.prims, s, wo, None, out)
    }

    /// [`Scene::bsdf`] with every material's sidedness overridden when `two_sided` is given (6.837 `-shade_back`).
    #[inline]
    pub fn bsdf_sided(&self, s: &SurfaceHit, wo: Vec3A, two_sided: Option<bool>) -> Option<Bsdf> {
        crate::material::bsdf(&self.materials, &self.textures, &self.prims, s, wo, two_sided)
    }

    /// Radiance arriving along a ray that leaves the scene in unit direction `dir`: the environment light's, or the
    /// background's when there is none.
    #[inline]
    pub fn escaped(&self, dir: Vec3A) -> Vec3 {
        match &self.lights.environment {
            Some(env) => env.eval(dir),
            None => self.globals.background,
        }
    }

    /// Radiance emitted by the surface at `s` towards `wo` (unit, pointing away from the surface).
    #[inline]
    pub fn emitted(&self, s: &SurfaceHit, wo: Vec3A) -> Vec3 {
        if s.light == NO_LIGHT {
            return Vec3::ZERO;
        }
        self.lights.area_radiance(s.light, s, wo)
    }
}
