//! # prism-lab
//!
//! Prism's measuring instruments, kept out of the renderer: the speed-against-accuracy report ([`report`]), error
//! against a reference as the budget grows ([`converge`]), charts ([`chart`]), image comparison ([`compare`]), the
//! accelerator benchmark ([`accel_bench`]), the ray sets and ray files it traces ([`ray_sets`], [`ray_file`]), and
//! the fuzz targets' entry points ([`fuzz`]). Each renders through the plugins it is handed, so the lab names no
//! plugin set of its own.

pub mod accel_bench;
pub mod chart;
pub mod compare;
pub mod converge;
pub mod fuzz;
pub mod ray_file;
pub mod ray_sets;
pub mod report;
