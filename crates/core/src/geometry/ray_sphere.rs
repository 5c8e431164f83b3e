//! Ray–sphere intersection in the sphere's own frame, numerically robust for rays far from the sphere and for
//! large spheres (Haines, Günther & Akenine-Möller, "Precision Improvements for Ray/Sphere Intersection", Ray Tracing
//! Gems 2019, ch. 7). The direction need not be unit length, so a ray transformed into object space by an affine
//! map keeps its world-space `t` (that is how nested transforms turn a sphere into an ellipsoid).

use glam::Vec3A;

/// Smallest `t` in `(0, tmax)` where `origin + t dir` meets the sphere.
#[inline]
pub fn intersect_sphere(center: Vec3A, radius: f32, origin: Vec3A, dir: Vec3A, tmax: f32) -> Option<f32> {
    let f = origin - center;
    let a = dir.dot(dir);
    let b = -f.dot(dir);
    // Perpendicular distance from the centre to the ray, computed without cancellation.
    let l = f + (b / a) * dir;
    let r2 = radius * radius;
    let disc = a * (r2 - l.dot(l));
    if disc < 0.0 {
        return None;
    }
    let c = f.dot(f) - r2;
    let q = b + disc.sqrt().copysign(b);
    let (t0, t1) = if q == 0.0 {
        (0.0, 0.0)
    } else {
        let ta = c / q;
        let tb = q / a;
        if ta < tb { (ta, tb) } else { (tb, ta) }
    };
    if t0 > 0.0 && t0 < tmax {
        Some(t0)
    } else if t1 > 0.0 && t1 < tmax {
        Some(t1)
    } else {
        None
    }
}
