//! Reproducible ray sets for measuring accelerators (`prism bench`, `benches/accel.rs`): camera rays through
//! every pixel centre, and the secondary rays a path tracer would trace from their hits: a diffuse bounce
//! (uniform direction in the hemisphere on the camera's side of the surface) and a shadow ray towards a random
//! point of the scene's bounds (finite `tmax`, for occlusion queries). The secondary rays do not carry
//! [`Ray::leaves`] (the triangle they start on), so every accelerator and peer answers the same information.

use glam::{Vec2, Vec3A};
use prism_core::geometry::{NO_PRIM, Ray};
use prism_core::sampling::{Rng, warp};
use prism_core::scene::Scene;

/// One ray through the centre of each pixel of a `width x height` image of the scene's camera.
pub fn camera_rays(scene: &Scene, width: u32, height: u32) -> Vec<Ray> {
    let cam = &scene.camera;
    let (sx, sy) = (cam.width as f32 / width as f32, cam.height as f32 / height as f32);
    let mut out = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            out.push(cam.generate_ray(Vec2::new((x as f32 + 0.5) * sx, (y as f32 + 0.5) * sy)));
        }
    }
    out
}

/// From the closest hit of each ray that hits something: a bounce ray and a shadow ray (see the module doc).
pub fn secondary_rays(scene: &Scene, primary: &[Ray], seed: u64) -> (Vec<Ray>, Vec<Ray>) {
    let mut rng = Rng::new(seed, 17);
    let b = scene.prims.bounds;
    let (mut bounce, mut shadow) = (Vec::new(), Vec::new());
    for r in primary {
        let Some(s) = scene.trace(r) else {
            continue;
        };
        let n = if s.ng.dot(r.dir) < 0.0 { s.ng } else { -s.ng };
        let mut d = warp::uniform_sphere(rng.next_2d());
        if d.dot(n) < 0.0 {
            d = -d;
        }
        // Without the `leaves` hint: the rays carry exactly what an exported ray file gives a peer (Embree).
        bounce.push(s.spawn(d).leaving(NO_PRIM));
        if !b.is_empty() {
            let target = b.min + b.diagonal() * Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            let to = target - s.p;
            if to.dot(n) > 0.0 && to.length_squared() > 0.0 {
                let dist = to.length();
                let mut ray = s.spawn(to / dist).leaving(NO_PRIM);
                ray.tmax = dist;
                shadow.push(ray);
            }
        }
    }
    (bounce, shadow)
}
