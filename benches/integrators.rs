//! Integrator benchmarks: `scenes/cornell_box.ron` with `phong` at 256x256, 64 spp (16 passes), on 2 threads —
//! the whole render loop (passes, film accumulation) after set-up.
//!
//! `cargo bench --bench integrators`.

use criterion::{Criterion, criterion_group, criterion_main};
use prism::app::{App, SceneSource};
use prism::settings::Overrides;
use std::path::PathBuf;
use std::time::Duration;

fn cornell(integrator: &str, spp: u32) -> App {
    let mut app = App::with_default_plugins();
    app.resources.source = SceneSource::File(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell_box.ron"));
    app.resources.overrides = Overrides { spp: Some(spp), integrator: Some(integrator.into()), ..Default::default() };
    app.setup().expect("set up the Cornell box");
    app
}

fn bench_cornell(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let mut g = c.benchmark_group("cornell_256");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    g.bench_function("phong_64spp_2threads", |b| {
        b.iter_batched(
            || cornell("phong", 64),
            |mut app| pool.install(|| app.render().unwrap()),
            criterion::BatchSize::PerIteration,
        )
    });
    g.finish();
}

criterion_group!(benches, bench_cornell);
criterion_main!(benches);
