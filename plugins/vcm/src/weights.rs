//! The MIS weight of each strategy where a path is completed, as pure functions of the two subpaths' running
//! quantities ([`Partial`]) and the densities at the joint. The camera pass, the light pass and the path checker
//! ([`crate::path_weights`]) all evaluate these, so what the checker proves about them holds for the renders.
//!
//! Every function returns `1 / (1 + sum of the other strategies' density ratios)`, the balance heuristic or the
//! power heuristic according to [`Mis::m`].

use super::mis::{LightPdfs, Mis, Partial};

/// Emission found by the camera path (`s = 0`), `cam` after arriving at the light, `pdfs` the light's densities
/// towards the previous camera vertex [tech. rep. (42)-(43)].
#[inline(always)]
pub fn emission(mis: &Mis, cam: &Partial, pdfs: &LightPdfs) -> f32 {
    1.0 / (1.0 + mis.m(pdfs.nee) * cam.dvcm + mis.m(pdfs.emission) * cam.dvc)
}

/// Next-event estimation (`s = 1`) at camera vertex `cam`: `bsdf` the camera vertex BSDF's forward and reverse
/// densities of the direction to the light, `nee_w` next-event estimation's solid-angle density of it (see
/// [`LightPdfs`]), `cos_geo` and `cos_light` the geometric cosines at the two ends [tech. rep. (44)-(45)].
#[inline(always)]
pub fn next_event(
    mis: &Mis,
    cam: &Partial,
    pdfs: &LightPdfs,
    bsdf: (f32, f32),
    nee_w: f32,
    cos_geo: f32,
    cos_light: f32,
) -> f32 {
    let (bsdf_pdf, bsdf_rev) = bsdf;
    let w_light = if pdfs.delta { 0.0 } else { mis.m(bsdf_pdf / nee_w) };
    let w_camera =
        mis.m(pdfs.emission * cos_geo / (nee_w * cos_light)) * (mis.vm + cam.dvcm + cam.dvc * mis.m(bsdf_rev));
    1.0 / (w_light + 1.0 + w_camera)
}

/// A connection of camera vertex `cam` and light vertex `light` (`s, t >= 2`): `camera_pdf_a` is the camera
/// vertex BSDF's density of the light vertex (area measure there), `light_pdf_a` the light vertex BSDF's density
/// of the camera vertex, `camera_rev` and `light_rev` each BSDF's reverse density (solid angle)
/// [tech. rep. (40)-(41)].
#[inline(always)]
pub fn connection(
    mis: &Mis,
    cam: &Partial,
    light: &Partial,
    camera_pdf_a: f32,
    light_pdf_a: f32,
    camera_rev: f32,
    light_rev: f32,
) -> f32 {
    let w_light = mis.m(camera_pdf_a) * (mis.vm + light.dvcm + light.dvc * mis.m(light_rev));
    let w_camera = mis.m(light_pdf_a) * (mis.vm + cam.dvcm + cam.dvc * mis.m(camera_rev));
    1.0 / (w_light + 1.0 + w_camera)
}

/// Light tracing (`t = 1`) from light vertex `light`: `cam_pdf_a` the camera's density of the vertex (area measure,
/// the pixel's filter included), `light_paths` the paths per iteration, `rev` the vertex BSDF's reverse density of
/// the direction to the eye [tech. rep. (46)].
#[inline(always)]
pub fn light_tracing(mis: &Mis, light: &Partial, cam_pdf_a: f32, light_paths: f32, rev: f32) -> f32 {
    let w_light = mis.m(cam_pdf_a / light_paths) * (mis.vm + light.dvcm + light.dvc * mis.m(rev));
    1.0 / (1.0 + w_light)
}

/// Merging camera vertex `cam` with a light vertex of quantities `light_dvcm`, `light_dvm`: `pdf` and `rev` the
/// camera vertex BSDF's forward and reverse densities of the direction the light arrived from
/// [tech. rep. (38)-(39)].
#[inline(always)]
pub fn merge(mis: &Mis, cam: &Partial, light_dvcm: f32, light_dvm: f32, pdf: f32, rev: f32) -> f32 {
    let w_light = light_dvcm * mis.vc + light_dvm * mis.m(pdf);
    let w_camera = cam.dvcm * mis.vc + cam.dvm * mis.m(rev);
    1.0 / (w_light + 1.0 + w_camera)
}
