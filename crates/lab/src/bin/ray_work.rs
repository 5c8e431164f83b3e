//! Traversal work per ray of the default BVH on a scene's bench rays (`prism bench`'s camera, bounce and shadow
//! sets): nodes tested and primitive lanes tested per ray, for comparing trees.
//!
//! `cargo run --release -p prism-lab --bin ray_work SCENE` prints the averages. With `PASSES=N` it instead traces the
//! bounce rays N times and prints the hit count: run it under `valgrind --tool=cachegrind` with N = 0 and N = 10
//! and the difference of the two counts (`cg_diff`), divided by 10 x the bounce rays, is the cost of one bounce
//! ray — instructions, branch mispredictions (`--branch-sim=yes`), cache misses (`--cache-sim=yes`) — without the
//! scene's set-up.

use prism_core::accel::{Accel, TraversalWork};
use prism_core::settings::{AccelKind, Overrides};
use prism_engine::{App, CorePlugin, SceneSource};
use prism_lab::ray_sets::{camera_rays, secondary_rays};

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: ray_work SCENE (PASSES=N: trace the bounce rays N times)");
        std::process::exit(2);
    };
    // The scene's geometry is all it needs: the loaders, the engine's stages, and `debug` as the integrator to
    // prepare (whatever the scene names).
    let mut app = App::with(CorePlugin);
    app.add_plugin(prism_load::LoadPlugin).add_plugin(prism_debug::DebugPlugin);
    app.resources.source = SceneSource::File(path.into());
    app.resources.overrides = Overrides { integrator: Some("debug".into()), ..Default::default() };
    if let Err(e) = app.setup() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
    let s = app.resources.scene.as_ref().expect("a scene after set-up");
    let accel = Accel::build(AccelKind::Bvh, &s.prims).expect("a BVH");
    let camera = camera_rays(s, 256, 256);
    let (bounce, shadow) = secondary_rays(s, &camera, 1);
    if let Ok(passes) = std::env::var("PASSES") {
        let passes: u32 = passes.parse().expect("PASSES: a number");
        let mut hits = 0u64;
        for _ in 0..passes {
            hits += bounce.iter().filter(|r| accel.intersect(&s.prims, r).is_some()).count() as u64;
        }
        println!("{hits} hits");
        return;
    }
    for (name, rays) in [("camera", &camera), ("bounce", &bounce), ("shadow", &shadow)] {
        let mut work = TraversalWork::default();
        let hits = rays.iter().filter(|r| accel.intersect_counted(&s.prims, r, &mut work).is_some()).count();
        let n = rays.len().max(1) as f64;
        println!(
            "{name}: {} rays, {:.3} hit, {:.2} nodes and {:.2} primitive lanes tested per ray",
            rays.len(),
            hits as f64 / n,
            work.nodes as f64 / n,
            work.prims as f64 / n
        );
    }
}
