//! # prism-core
//!
//! Prism's renderer core, with no ECS and no scene format: everything a render needs once its scene is flattened —
//! geometry, sampling, images, BSDFs, shapes, the primitive store, the accelerators, materials, lights, the camera,
//! the render-time [`scene::Scene`], the exact [`film::Film`] and the [`integrator`] interface plugins implement.
//!
//! Its modules form layers: a module uses only the modules of the layers before its own (a test,
//! `tests/layers.rs`, fails on any folder-level import cycle and on any import that runs against this order):
//!
//! | layer | modules |
//! |---|---|
//! | 1 | [`error`], [`limits`], [`cpu_time`], [`ron_error`] |
//! | 2 | [`math`] |
//! | 3 | [`geometry`] (rays, bounds, [`geometry::Hit`] and [`geometry::SurfaceHit`]) |
//! | 4 | [`sampling`] |
//! | 5 | [`settings`] |
//! | 6 | [`io`], [`texture`], [`envmap`], [`alpha`] (images) |
//! | 7 | [`bsdf`] |
//! | 8 | [`mesh`], [`mesh_tangents`] |
//! | 9 | [`shapes`] |
//! | 10 | [`primitives`] (the flat store) |
//! | 11 | [`accel`] |
//! | 12 | [`material`] |
//! | 13 | [`lights`] |
//! | 14 | [`camera`] |
//! | 15 | [`scene`] |
//! | 16 | [`film`] |
//! | 17 | [`integrator`] |

pub mod accel;
pub mod alpha;
pub mod bsdf;
pub mod camera;
pub mod cpu_time;
pub mod envmap;
pub mod error;
pub mod film;
pub mod geometry;
pub mod integrator;
pub mod io;
pub mod lights;
pub mod limits;
pub mod material;
pub mod math;
pub mod mesh;
pub mod mesh_tangents;
pub mod primitives;
pub mod ron_error;
pub mod sampling;
pub mod scene;
pub mod settings;
pub mod shapes;
pub mod texture;

pub use error::{PrismError, Result};
