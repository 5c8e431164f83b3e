//! pbrt's `curve` shapes (hair, fur, grass) tessellated into triangle meshes: each curve becomes cubic Bézier
//! segments exactly as pbrt-v4's `CreateCurve` makes them (`src/pbrt/shapes.cpp`: B-splines converted, quadratics
//! elevated, the width interpolated from `width0` to `width1` over the segments), and each segment a tube of
//! [`SIDES`] sides over [`STEPS`] steps (`cylinder` and `flat`: pbrt's flat curves face the ray, a tube has the
//! same silhouette) or a strip of [`STEPS`] steps turned by the segment's end normals (`ribbon`).
//!
//! pbrt intersects curves by recursive subdivision instead; a tessellation reuses Prism's triangle path (every
//! accelerator, every integrator) at [`TRIANGLES_PER_SEGMENT`] triangles a segment. Work is bounded before it is
//! spent: a file whose curves would make more than [`MAX_CURVE_TRIANGLES`] triangles is refused at the curve that
//! crosses the bound.

use glam::DVec3;

/// Steps along each Bézier segment.
pub const STEPS: usize = 4;
/// Sides of a tube.
pub const SIDES: usize = 6;
/// Triangles a segment of a tube makes.
pub const TRIANGLES_PER_SEGMENT: usize = 2 * STEPS * SIDES;
/// Most triangles all of a file's curves may make.
pub const MAX_CURVE_TRIANGLES: usize = 16_000_000;

/// How a curve is drawn (pbrt's `type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveKind {
    /// A flat strip facing the viewer in pbrt: a tube here.
    Flat,
    /// A tube.
    Cylinder,
    /// A strip oriented by normals at the segments' ends.
    Ribbon,
}

/// One cubic Bézier segment with its widths at both ends (and, for ribbons, its end normals).
#[derive(Clone, Copy, Debug)]
pub struct Segment {
    pub cp: [DVec3; 4],
    pub width: [f64; 2],
    pub normal: Option<[DVec3; 2]>,
}

fn lerp(t: f64, a: DVec3, b: DVec3) -> DVec3 {
    a + (b - a) * t
}

/// The cubic Bézier segments of pbrt's control points `p` for `basis` ("bezier" or "bspline") and `degree` (2 or
/// 3), or the reason they do not make a curve.
pub fn bezier_segments(p: &[DVec3], basis: &str, degree: usize) -> Result<Vec<[DVec3; 4]>, String> {
    if degree != 2 && degree != 3 {
        return Err(format!("\"degree\" must be 2 or 3, got {degree}"));
    }
    match basis {
        "bezier" => {
            if p.len() <= degree || !(p.len() - 1).is_multiple_of(degree) {
                return Err(format!(
                    "a degree-{degree} Bézier curve needs 1 + {degree} n control points, got {}",
                    p.len()
                ));
            }
            Ok(p.windows(degree + 1)
                .step_by(degree)
                .map(|w| {
                    if degree == 3 {
                        [w[0], w[1], w[2], w[3]]
                    } else {
                        [w[0], lerp(2.0 / 3.0, w[0], w[1]), lerp(1.0 / 3.0, w[1], w[2]), w[2]]
                    }
                })
                .collect())
        }
        "bspline" => {
            if p.len() <= degree {
                return Err(format!(
                    "a degree-{degree} B-spline needs more than {degree} control points, got {}",
                    p.len()
                ));
            }
            Ok(p.windows(degree + 1)
                .map(|w| {
                    if degree == 3 {
                        let p122 = lerp(2.0 / 3.0, w[0], w[1]);
                        let p223 = lerp(1.0 / 3.0, w[1], w[2]);
                        let p233 = lerp(2.0 / 3.0, w[1], w[2]);
                        let p334 = lerp(1.0 / 3.0, w[2], w[3]);
                        [lerp(0.5, p122, p223), p223, p233, lerp(0.5, p233, p334)]
                    } else {
                        let p11 = lerp(0.5, w[0], w[1]);
                        let p22 = lerp(0.5, w[1], w[2]);
                        [p11, lerp(2.0 / 3.0, p11, w[1]), lerp(1.0 / 3.0, w[1], p22), p22]
                    }
                })
                .collect())
        }
        other => Err(format!("unknown curve basis \"{other}\" (bezier or bspline)")),
    }
}

fn bezier(cp: &[DVec3; 4], t: f64) -> (DVec3, DVec3) {
    let s = 1.0 - t;
    let p = cp[0] * (s * s * s) + cp[1] * (3.0 * s * s * t) + cp[2] * (3.0 * s * t * t) + cp[3] * (t * t * t);
    let d = (cp[1] - cp[0]) * (3.0 * s * s) + (cp[2] - cp[1]) * (6.0 * s * t) + (cp[3] - cp[2]) * (3.0 * t * t);
    (p, d)
}

/// A unit vector perpendicular to `t` (any, for the first ring; the next rings transport it along the curve).
fn perpendicular(t: DVec3) -> DVec3 {
    let a = if t.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    t.cross(a).normalize_or_zero()
}

/// Append the triangles of `segments` (one curve) of `kind` to the mesh `(positions, normals, triangles)`.
pub fn tessellate(
    segments: &[Segment],
    kind: CurveKind,
    pts: &mut Vec<[f64; 3]>,
    nrm: &mut Vec<[f64; 3]>,
    tris: &mut Vec<[u32; 3]>,
) {
    let mut frame: Option<DVec3> = None;
    let mut prev_ring: Option<u32> = None;
    for s in segments {
        for k in 0..=STEPS {
            if k == 0 && prev_ring.is_some() && kind != CurveKind::Ribbon {
                // A tube's segments share rings: this segment starts where the previous one ended.
                continue;
            }
            let t = k as f64 / STEPS as f64;
            let (p, d) = bezier(&s.cp, t);
            let tangent = d.normalize_or_zero();
            let tangent = if tangent == DVec3::ZERO { DVec3::Z } else { tangent };
            let r = 0.5 * (s.width[0] + (s.width[1] - s.width[0]) * t);
            let base = pts.len() as u32;
            match (kind, s.normal) {
                (CurveKind::Ribbon, Some([n0, n1])) => {
                    let n = lerp(t, n0, n1).normalize_or_zero();
                    let side = tangent.cross(n).normalize_or_zero();
                    let side = if side == DVec3::ZERO { perpendicular(tangent) } else { side };
                    let n = side.cross(tangent);
                    for sign in [-1.0, 1.0] {
                        pts.push((p + side * (sign * r)).to_array());
                        nrm.push(n.to_array());
                    }
                    if k > 0 {
                        let (a0, a1, b0, b1) = (base - 2, base - 1, base, base + 1);
                        tris.push([a0, b0, b1]);
                        tris.push([a0, b1, a1]);
                    }
                }
                _ => {
                    // Parallel transport: project the previous ring's reference direction off the new tangent.
                    let u = match frame {
                        Some(prev) => {
                            let v = (prev - tangent * prev.dot(tangent)).normalize_or_zero();
                            if v == DVec3::ZERO { perpendicular(tangent) } else { v }
                        }
                        None => perpendicular(tangent),
                    };
                    frame = Some(u);
                    let w = tangent.cross(u);
                    for j in 0..SIDES {
                        let a = std::f64::consts::TAU * j as f64 / SIDES as f64;
                        let n = u * a.cos() + w * a.sin();
                        pts.push((p + n * r).to_array());
                        nrm.push(n.to_array());
                    }
                    if let Some(prev) = prev_ring {
                        for j in 0..SIDES as u32 {
                            let j1 = (j + 1) % SIDES as u32;
                            tris.push([prev + j, prev + j1, base + j1]);
                            tris.push([prev + j, base + j1, base + j]);
                        }
                    }
                    prev_ring = Some(base);
                }
            }
        }
    }
}
