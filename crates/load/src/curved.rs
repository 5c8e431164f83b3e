//! Curved shapes of a RON scene (`Revolution`, `BezierPatch`, `Splines`) into `Shape` components: validated
//! control points, exact surfaces or, with a `tessellation`, triangle meshes made at load time.

use super::mit6837::spline::{SplineTxt, Tessellation, parse_spline_file, tessellate_splines};
use super::schema::{CurveDesc, TessellationDesc, V3};
use glam::{DVec3, Vec3};
use prism_core::error::{PrismError, Result};
use prism_core::shapes::tessellate::{patch_tessellation, revolution_tessellation};
use prism_core::shapes::{Curve, CurveKind};
use prism_engine::Resources;
use prism_engine::components::Shape;
use std::path::Path;

fn tess(t: TessellationDesc) -> Tessellation {
    Tessellation { curve: t.curve, revolution: t.revolution, patch: t.patch }
}

/// A profile curve: finite control points in the xy-plane (z = 0), a count its basis can use.
pub fn profile_curve(c: &CurveDesc, ctx: &str) -> Result<Curve> {
    let (kind, pts) = match c {
        CurveDesc::Bezier(p) => (CurveKind::Bezier, p),
        CurveDesc::BSpline(p) => (CurveKind::BSpline, p),
    };
    for (i, p) in pts.iter().enumerate() {
        if p.iter().any(|x| !x.is_finite()) {
            return Err(PrismError::scene(ctx, format!("profile control point {i} is not finite: {p:?}")));
        }
        if p[2] != 0.0 {
            return Err(PrismError::scene(
                ctx,
                format!("the profile leaves the xy-plane: control point {i} has z = {} (must be 0)", p[2]),
            ));
        }
    }
    let points = pts.iter().map(|p| DVec3::new(p[0] as f64, p[1] as f64, 0.0)).collect();
    Curve::new(kind, points).map_err(|e| PrismError::scene(ctx, format!("profile: {e}")))
}

/// The 16 finite control points of a Bézier patch.
pub fn patch_points(points: &[V3], ctx: &str) -> Result<[Vec3; 16]> {
    if points.len() != 16 {
        return Err(PrismError::scene(
            ctx,
            format!("a Bézier patch needs 16 control points (4 rows of 4), got {}", points.len()),
        ));
    }
    let mut out = [Vec3::ZERO; 16];
    for (i, (o, p)) in out.iter_mut().zip(points).enumerate() {
        if p.iter().any(|x| !x.is_finite()) {
            return Err(PrismError::scene(ctx, format!("patch control point {i} is not finite: {p:?}")));
        }
        *o = Vec3::from(*p);
    }
    Ok(out)
}

/// An exact surface of revolution, or its mesh.
pub fn revolution_shape(res: &mut Resources, profile: Curve, t: Option<TessellationDesc>, ctx: &str) -> Result<Shape> {
    Ok(match t {
        None => Shape::Revolution { profile },
        Some(t) => {
            let mesh =
                revolution_tessellation(&profile, t.curve, t.revolution).map_err(|e| PrismError::scene(ctx, e))?;
            Shape::Mesh(res.meshes.add(mesh))
        }
    })
}

/// An exact Bézier patch, or its mesh.
pub fn patch_shape(res: &mut Resources, points: [Vec3; 16], t: Option<TessellationDesc>, ctx: &str) -> Result<Shape> {
    Ok(match t {
        None => Shape::BezierPatch { points },
        Some(t) => {
            let ctrl = points.map(|p| p.as_dvec3());
            let mesh = patch_tessellation(&ctrl, t.patch).map_err(|e| PrismError::scene(ctx, e))?;
            Shape::Mesh(res.meshes.add(mesh))
        }
    })
}

/// The surfaces of a 6.837 spline file: one exact shape per surface, or one mesh of them all.
pub fn spline_file_shapes(
    res: &mut Resources,
    path: &Path,
    t: Option<TessellationDesc>,
    ctx: &str,
) -> Result<Vec<(String, Shape)>> {
    if !path.is_file() {
        return Err(PrismError::scene(ctx, format!("spline file not found: {}", path.display())));
    }
    let items = parse_spline_file(path)?;
    let name = path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into());
    let no_surface =
        || PrismError::scene(ctx, format!("{}: the spline file has no surface (only curves)", path.display()));
    if let Some(t) = t {
        let mesh =
            tessellate_splines(&items, tess(t)).map_err(|e| PrismError::scene(ctx, e))?.ok_or_else(no_surface)?;
        return Ok(vec![(name, Shape::Mesh(res.meshes.add(mesh)))]);
    }
    let mut out = Vec::new();
    for item in items {
        match item {
            SplineTxt::Curve { .. } => {}
            SplineTxt::Revolution { line, profile } => {
                out.push((format!("{name}:{line} surface_of_revolution"), Shape::Revolution { profile }))
            }
            SplineTxt::Patch { line, points } => out.push((
                format!("{name}:{line} bezier_patch"),
                Shape::BezierPatch { points: points.map(|p| p.as_vec3()) },
            )),
        }
    }
    if out.is_empty() {
        return Err(no_surface());
    }
    Ok(out)
}
