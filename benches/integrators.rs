//! Integrator benchmarks on `scenes/cornell_box.ron` at 256x256, 2 threads, after set-up:
//! - `envlight_one_pass`: one progressive pass of the path tracer (4 spp, the scene's pass size, max_depth 8);
//!   throughput in camera samples;
//! - `furnace_one_pass`: one pass (4 spp) of the furnace scene (128x128);
//! - `phong_64spp_2threads`: the whole 64 spp render with `phong` (16 passes).
//!
//! `cargo bench --bench integrators`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use prism::app::{App, SceneSource};
use prism::settings::Overrides;
use std::path::PathBuf;
use std::time::Duration;

fn scene(file: &str, integrator: &str, spp: u32, passes: u32) -> App {
    let mut app = App::with(prism::DefaultPlugins);
    app.resources.source = SceneSource::File(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes").join(file));
    app.resources.overrides =
        Overrides { spp: Some(spp), passes: Some(passes), integrator: Some(integrator.into()), ..Default::default() };
    app.setup().expect("set up the scene");
    app
}

fn bench_cornell(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let mut g = c.benchmark_group("cornell_256");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    g.throughput(Throughput::Elements(4 * 256 * 256));
    g.bench_function("envlight_one_pass", |b| {
        b.iter_batched(
            || scene("cornell_box.ron", "envlight(max_depth: 8)", 4, 1),
            |mut app| pool.install(|| app.render().unwrap()),
            criterion::BatchSize::PerIteration,
        )
    });
    g.throughput(Throughput::Elements(64 * 256 * 256));
    g.bench_function("phong_64spp_2threads", |b| {
        b.iter_batched(
            || scene("cornell_box.ron", "phong", 64, 16),
            |mut app| pool.install(|| app.render().unwrap()),
            criterion::BatchSize::PerIteration,
        )
    });
    g.finish();
    let mut g = c.benchmark_group("furnace_128");
    g.sample_size(20).throughput(Throughput::Elements(4 * 128 * 128));
    g.bench_function("envlight_one_pass", |b| {
        b.iter_batched(
            || scene("furnace.ron", "envlight", 4, 1),
            |mut app| pool.install(|| app.render().unwrap()),
            criterion::BatchSize::PerIteration,
        )
    });
    g.finish();
}

criterion_group!(benches, bench_cornell);
criterion_main!(benches);
