//! Ray–primitive geometry: rays, bounds, watertight ray–triangle (Woop, Benthin & Wald 2013), numerically robust
//! ray–sphere (Haines et al., Ray Tracing Gems ch. 7), ray–plane, the hit and surface records ([`Hit`], [`SurfaceHit`]), and the ray-origin offset that prevents
//! self-intersection without a scene-dependent epsilon (floating-point error bounds, pbrt-v4 section 6.8).

mod bounds;
mod interaction;
mod offset;
mod ray;
mod ray_plane;
mod ray_sphere;
mod separation;
mod triangle;
mod triangle_packet;

pub use bounds::Bounds;
pub use interaction::{Hit, SurfaceHit};
pub use offset::{gamma, offset_ray_origin, spawn_ray, spawn_ray_to};
pub use ray::{NO_PRIM, Ray};
pub use ray_plane::intersect_plane;
pub use ray_sphere::intersect_sphere;
pub use separation::hulls_apart;
pub use triangle::{TriSoa, TriangleHit, WatertightRay};
pub use triangle_packet::TriPacket;
