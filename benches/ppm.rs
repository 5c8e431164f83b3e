//! Photon mapping benchmarks (2 threads, 256x256, `photons` = 65536 = the pixel count, as `ppm`'s default):
//! - `photon_pass/{cornell,caustic}`: tracing one iteration's photons (throughput: photons emitted);
//! - `eye_pass/{cornell,caustic}`: one eye pass (camera paths to visible points, direct light);
//! - `lookup_build/{hash_grid,kdtree}` and `gather/{hash_grid,kdtree}`: building each photon lookup over the same
//!   stored photons and gathering at every visible point with the pixels' initial radii (3 pixel footprints, the default).
//!   Both lookups find the same photons; the ratio of their times is the comparison the design card asks for.
//!
//! `cargo bench --bench ppm` (the first run prints photons stored and the interleaved best-of ratios on stderr).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use prism::app::{App, SceneSource};
use prism::lights::{EnvStrategy, LightSampler};
use prism::plugins::ppm::gather::gather;
use prism::plugins::ppm::photons::{Photon, PhotonPass};
use prism::plugins::ppm::{EyePass, EyeResult, PhotonHashGrid, PhotonKdTree};
use prism::scene::Scene;
use prism::settings::{Overrides, RenderSettings};
use rayon::prelude::*;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

struct Setup {
    scene: Scene,
    settings: RenderSettings,
    lights: LightSampler,
}

fn setup(file: &str) -> Setup {
    let mut app = App::with(prism::DefaultPlugins);
    app.resources.source = SceneSource::File(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes").join(file));
    app.resources.overrides = Overrides { integrator: Some("ppm".into()), ..Default::default() };
    app.setup().expect("set up the scene");
    let scene = app.resources.scene.take().unwrap();
    let lights = LightSampler::new(&scene.lights, &scene.prims, EnvStrategy::Quadtree);
    Setup { scene, settings: app.resources.settings.clone(), lights }
}

fn photon_pass<'a>(s: &'a Setup, iteration: u64) -> PhotonPass<'a> {
    PhotonPass {
        scene: &s.scene,
        lights: &s.lights,
        sampler: s.settings.sampler,
        seed: 0,
        iteration,
        photons: 65536,
        max_vertices: 255,
        first_deposit: 1,
        store_on_glossy: false,
    }
}

fn eye_pass(s: &Setup) -> EyePass<'_> {
    EyePass {
        scene: &s.scene,
        lights: &s.lights,
        settings: &s.settings,
        sampler: s.settings.sampler,
        max_segments: 256,
        eye_segments: 256,
        direct_lighting: true,
        pixel_centre: false,
        trace_glossy: true,
        split_near_specular: true,
    }
}

fn eye_results(s: &Setup) -> Vec<EyeResult> {
    let eye = eye_pass(s);
    let w = s.settings.width;
    (0..w * s.settings.height).into_par_iter().map(|i| eye.trace_pixel(i % w, i / w, 0)).collect()
}

fn radii(s: &Setup, eye: &[EyeResult]) -> Vec<f32> {
    eye.iter().map(|e| e.vp.map_or(0.0, |vp| 2.0 * s.scene.camera.pixel_footprint(vp.path_length))).collect()
}

/// A photon lookup: call the closure for every photon within a radius of a point.
type Lookup<'a> = dyn Fn(glam::Vec3A, f32, &mut dyn FnMut(&Photon)) + Sync + 'a;

fn gather_all(s: &Setup, eye: &[EyeResult], r: &[f32], q: &Lookup) -> u64 {
    eye.par_iter()
        .zip(r.par_iter())
        .map(|(e, &r)| match &e.vp {
            Some(vp) => gather(&s.scene, vp, r, 256, true, |p, r, f| q(p, r, f)).1 as u64,
            None => 0,
        })
        .sum()
}

fn bench_ppm(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    for (name, file) in [("cornell", "cornell_box.ron"), ("caustic", "cornell_caustic.ron")] {
        let s = setup(file);
        let cancel = AtomicBool::new(false);
        let mut chunks: Vec<Vec<Photon>> = vec![];
        let mut g = c.benchmark_group(format!("ppm_{name}"));
        g.sample_size(10).measurement_time(Duration::from_secs(10));
        g.throughput(Throughput::Elements(65536));
        g.bench_function("photon_pass", |b| b.iter(|| pool.install(|| photon_pass(&s, 0).trace(&mut chunks, &cancel))));
        g.throughput(Throughput::Elements(256 * 256));
        g.bench_function("eye_pass", |b| b.iter(|| pool.install(|| eye_results(&s))));
        // The same photons and visible points for both lookups.
        pool.install(|| photon_pass(&s, 0).trace(&mut chunks, &cancel));
        let eye = pool.install(|| eye_results(&s));
        let r = radii(&s, &eye);
        let r_max = r.iter().copied().fold(0.0, f32::max);
        let (mut grid, mut kd) = (PhotonHashGrid::default(), PhotonKdTree::default());
        g.bench_function("lookup_build/hash_grid", |b| b.iter(|| pool.install(|| grid.build(&chunks, 2.0 * r_max))));
        g.bench_function("lookup_build/kdtree", |b| b.iter(|| pool.install(|| kd.build(&chunks))));
        pool.install(|| {
            grid.build(&chunks, 2.0 * r_max);
            kd.build(&chunks);
        });
        let found_grid = pool.install(|| gather_all(&s, &eye, &r, &|p, r, f| grid.query(p, r, f)));
        let found_kd = pool.install(|| gather_all(&s, &eye, &r, &|p, r, f| kd.query(p, r, f)));
        assert_eq!(found_grid, found_kd, "the two lookups must find the same photons");
        let stored: usize = chunks.iter().map(Vec::len).sum();
        eprintln!("{name}: {stored} photons stored from 65536 emitted, {found_grid} photon-visible point pairs");
        g.bench_function("gather/hash_grid", |b| {
            b.iter(|| pool.install(|| gather_all(&s, &eye, &r, &|p, r, f| grid.query(p, r, f))))
        });
        g.bench_function("gather/kdtree", |b| {
            b.iter(|| pool.install(|| gather_all(&s, &eye, &r, &|p, r, f| kd.query(p, r, f))))
        });
        g.finish();
        // Interleaved best-of-15 build + gather, the ratio docs/decisions/0022-photon-hash-grid.md reports.
        let (mut tg, mut tk) = (f64::INFINITY, f64::INFINITY);
        for _ in 0..15 {
            let t = Instant::now();
            pool.install(|| {
                grid.build(&chunks, 2.0 * r_max);
                gather_all(&s, &eye, &r, &|p, r, f| grid.query(p, r, f))
            });
            tg = tg.min(t.elapsed().as_secs_f64());
            let t = Instant::now();
            pool.install(|| {
                kd.build(&chunks);
                gather_all(&s, &eye, &r, &|p, r, f| kd.query(p, r, f))
            });
            tk = tk.min(t.elapsed().as_secs_f64());
        }
        eprintln!(
            "{name}: build + gather, interleaved best of 15: hash grid {:.2} ms, kd-tree {:.2} ms (kd / grid {:.2}x)",
            tg * 1e3,
            tk * 1e3,
            tk / tg
        );
    }
}

criterion_group!(benches, bench_ppm);
criterion_main!(benches);
