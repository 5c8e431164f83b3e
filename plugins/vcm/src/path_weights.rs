//! The MIS weight that each strategy of a mode gives one explicit path, computed as the renderer computes it: the
//! light subpath's and the camera subpath's running quantities (`Partial` in `mis.rs`) built vertex by vertex
//! along the path with the same functions as the light and camera passes, then every strategy's weight from the
//! functions those passes call where they complete a path. The weights of one path sum to 1 when the recursive
//! bookkeeping is right; `tests/vcm_mis.rs` checks that, and each weight against the heuristic written out as
//! products of densities, on random paths in random scenes.
//!
//! A path is `z_0` on an area light, surface points `z_1 .. z_(k-1)` whose BSDFs have smooth lobes, and the eye
//! `z_k` (a pinhole camera), seen through pixel `pixel`.

use glam::{UVec2, Vec2};
use prism_core::bsdf::Bsdf;
use prism_core::geometry::SurfaceHit;
use prism_core::lights::{EnvStrategy, LightSampler};
use prism_core::primitives::NO_LIGHT;
use prism_core::sampling::PixelFilter;
use prism_core::scene::Scene;

use super::mis::{Mis, Partial, light_pdfs};
use super::params::{VcmMode, VcmParams};
use super::weights;

/// A way of building a path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// The camera path hits the light (`s = 0`).
    Emission,
    /// Next-event estimation from the camera vertex next to the light (`s = 1`).
    NextEvent,
    /// The light subpath's first `s` vertices connected to the camera subpath's (`s, t >= 2`).
    Connection {
        /// Vertices of the light subpath.
        s: usize,
    },
    /// Light tracing: every vertex but the eye from the light (`t = 1`).
    LightTracing,
    /// Merging at surface vertex `z_vertex`.
    Merge {
        /// The index of the vertex along the path from the light.
        vertex: usize,
    },
}

/// The iteration a path is weighed in.
#[derive(Clone, Copy, Debug)]
pub struct Iteration {
    /// Light paths per iteration.
    pub light_paths: u64,
    /// Merging radius.
    pub radius: f32,
    /// The pixel filter (the camera's density of a point depends on the pixel).
    pub filter: PixelFilter,
}

/// Every strategy of `params.mode` that can build `path` (light point first; the eye is implied) through `pixel`,
/// with the weight the renderer gives it. `None` if the path is not one the renderer weighs this way: fewer than
/// two segments, a first vertex that is not on an area light, a surface without a smooth lobe, or a last vertex the
/// camera does not see through `pixel`.
pub fn path_weights(
    scene: &Scene,
    params: &VcmParams,
    it: &Iteration,
    path: &[SurfaceHit],
    pixel: UVec2,
) -> Option<Vec<(Strategy, f32)>> {
    let k = path.len();
    if k < 2 || path[0].light == NO_LIGHT {
        return None;
    }
    let lights = LightSampler::new(&scene.lights, &scene.prims, EnvStrategy::Quadtree);
    let n_light = it.light_paths as f32;
    let mis = Mis::new(params.heuristic, it.radius, n_light, params.connects(), params.merges());
    let cam = &scene.camera;
    let pos = |i: usize| if i == k { cam.eye() } else { path[i].p };
    let dir = |a: usize, b: usize| (pos(b) - pos(a)).normalize();
    let dist = |a: usize, b: usize| (pos(b) - pos(a)).length();
    let slot = path[0].light as usize;

    // The light subpath as the light pass builds it: at z_i, its quantities after arriving and its BSDF (seen
    // from z_(i-1)).
    let pdfs0 = light_pdfs(scene, &lights, slot, path[0].p, path[0].ng, dir(0, 1));
    let mut wl = Partial::light(&mis, &pdfs0, path[0].ng.dot(dir(0, 1)).abs());
    let mut light_at = vec![(Partial::default(), None::<Bsdf>); k];
    for i in 1..k {
        let wo = dir(i, i - 1);
        wl.arrive(&mis, Some(dist(i - 1, i)), path[i].ng.dot(wo).abs());
        let bsdf = scene.bsdf(&path[i], wo).filter(Bsdf::has_smooth)?;
        light_at[i] = (wl, Some(bsdf));
        if i + 1 < k {
            let wi = dir(i, i + 1);
            wl.scatter(&mis, path[i].ng.dot(wi).abs(), Some((bsdf.pdf(wi), bsdf.pdf_rev(wi))));
        }
    }

    // The camera subpath as the camera pass builds it, from the eye through the pixel.
    let (film, to_eye, _, ray_pdf) = cam.project(path[k - 1].p)?;
    if film.floor().as_uvec2() != pixel {
        return None;
    }
    let density = it.filter.density(film - (pixel.as_vec2() + Vec2::splat(0.5)));
    let mut wc = Partial::camera(&mis, n_light, ray_pdf * density);
    let mut cam_at = vec![(Partial::default(), None::<Bsdf>); k];
    for i in (0..k).rev() {
        let wo = dir(i, i + 1);
        wc.arrive(&mis, Some(dist(i, i + 1)), path[i].ng.dot(wo).abs());
        if i == 0 {
            cam_at[0].0 = wc;
            break;
        }
        let bsdf = scene.bsdf(&path[i], wo).filter(Bsdf::has_smooth)?;
        cam_at[i] = (wc, Some(bsdf));
        let wi = dir(i, i - 1);
        wc.scatter(&mis, path[i].ng.dot(wi).abs(), Some((bsdf.pdf(wi), bsdf.pdf_rev(wi))));
    }

    let mut out = Vec::new();
    let connects = params.connects();
    if params.mode == VcmMode::Light {
        out.push((Strategy::LightTracing, 1.0));
        return Some(out);
    }
    if connects {
        // s = 0: the camera path arrives at the light.
        let pdfs = light_pdfs(scene, &lights, slot, path[0].p, path[0].ng, dir(0, 1));
        out.push((Strategy::Emission, weights::emission(&mis, &cam_at[0].0, &pdfs)));
        // s = 1: next-event estimation from z_1.
        let (wc1, bsdf1) = &cam_at[1];
        let bsdf1 = bsdf1.as_ref()?;
        let wi = dir(1, 0);
        let cos_light = path[0].ng.dot(wi).abs();
        let nee_w = pdfs.nee * dist(0, 1).powi(2) / cos_light;
        let cos_geo = path[1].ng.dot(wi).abs();
        let w = weights::next_event(&mis, wc1, &pdfs, (bsdf1.pdf(wi), bsdf1.pdf_rev(wi)), nee_w, cos_geo, cos_light);
        out.push((Strategy::NextEvent, w));
        // 2 <= s <= k - 1: camera vertex z_s to light vertex z_(s-1).
        for s in 2..k {
            let ((wc, cb), (wl, lb)) = (&cam_at[s], &light_at[s - 1]);
            let (cb, lb) = (cb.as_ref()?, lb.as_ref()?);
            let d = dir(s, s - 1);
            let d2 = dist(s, s - 1).powi(2);
            let camera_pdf_a = cb.pdf(d) * path[s - 1].ng.dot(d).abs() / d2;
            let light_pdf_a = lb.pdf(-d) * path[s].ng.dot(d).abs() / d2;
            let w = weights::connection(&mis, wc, wl, camera_pdf_a, light_pdf_a, cb.pdf_rev(d), lb.pdf_rev(-d));
            out.push((Strategy::Connection { s }, w));
        }
        // t = 1: light vertex z_(k-1) to the eye.
        let (wl, lb) = &light_at[k - 1];
        let cam_pdf_a = ray_pdf * density * path[k - 1].ng.dot(to_eye).abs() / dist(k - 1, k).powi(2);
        let rev = lb.as_ref()?.pdf_rev(to_eye);
        out.push((Strategy::LightTracing, weights::light_tracing(&mis, wl, cam_pdf_a, n_light, rev)));
    }
    if params.merges() {
        for i in 1..k {
            let ((wc, cb), (wl, _)) = (&cam_at[i], &light_at[i]);
            let wo = dir(i, i - 1);
            let cb = cb.as_ref()?;
            out.push((
                Strategy::Merge { vertex: i },
                weights::merge(&mis, wc, wl.dvcm, wl.dvm, cb.pdf(wo), cb.pdf_rev(wo)),
            ));
        }
    }
    Some(out)
}
