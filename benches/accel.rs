//! Accelerator benchmarks on the Stanford bunny (69k triangles, `../shared/data/meshes/stanford-bunny.obj`):
//! - build: Prism's BVH (obvhs CWBVH over primitive bounds, plus leaf-order copies) vs raw obvhs
//!   `build_cwbvh_from_tris`;
//! - closest hit, one thread, the same rays: Prism's accelerator path (`Accel::intersect`: watertight triangles,
//!   barycentrics, spheres allowed) vs raw obvhs traversal with its own Möller–Trumbore triangles in leaf order.
//!   Camera rays (coherent) and random rays (incoherent). Throughput is in rays.
//!
//! `cargo bench --bench accel`; the ratio prism/raw is the quantity to watch (target >= 0.9).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::{Vec2, Vec3A};
use obvhs::{BvhBuildParams, ray::RayHit, triangle::Triangle};
use prism::app::{App, SceneSource};
use prism::camera::CameraRig;
use prism::components::{Camera, Projection};
use prism::geometry::Ray;
use prism::sampling::{Rng, warp};
use prism::scene::Scene;
use prism::settings::{AccelKind, Overrides};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

fn bunny_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes/stanford-bunny.obj")
}

fn load_bunny(kind: AccelKind) -> App {
    let mut app = App::with_default_plugins();
    app.resources.source = SceneSource::RonText {
        text: format!("(camera: (), entities: [(shape: Mesh(path: \"{}\"))])", bunny_path().display()),
        name: "bench.ron".into(),
        base_dir: ".".into(),
    };
    app.resources.overrides = Overrides { accel: Some(kind), ..Default::default() };
    app.setup().expect("load the Stanford bunny");
    app
}

/// 256x256 camera rays framing the bunny, and as many random rays through its bounds.
fn ray_sets(scene: &Scene) -> (Vec<Ray>, Vec<Ray>) {
    let b = scene.prims.bounds;
    let c = b.center();
    let r = b.diagonal().length() * 0.5;
    let cam = Camera {
        eye: (c + Vec3A::new(0.0, 0.0, 2.8 * r)).into(),
        target: c.into(),
        up: glam::Vec3::Y,
        projection: Projection::Perspective { fov_y: 40.0 },
        width: 256,
        height: 256,
    };
    let rig = CameraRig::new(&cam, &glam::Affine3A::IDENTITY).unwrap();
    let mut camera = Vec::with_capacity(256 * 256);
    for y in 0..256 {
        for x in 0..256 {
            camera.push(rig.generate_ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5)));
        }
    }
    let mut rng = Rng::new(1, 2);
    let random = (0..256 * 256)
        .map(|_| {
            let o = c + warp::uniform_sphere(rng.next_2d()) * (2.0 * r);
            let target = b.min + b.diagonal() * Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            Ray::new(o, (target - o).normalize())
        })
        .collect();
    (camera, random)
}

fn bench_bunny(c: &mut Criterion) {
    if !bunny_path().is_file() {
        eprintln!("skipping: {} not found", bunny_path().display());
        return;
    }
    let app = load_bunny(AccelKind::Bvh);
    let scene = app.resources.scene.as_ref().unwrap();
    let prims = &scene.prims;
    let tris: Vec<Triangle> = prims.tris.iter().map(|t| Triangle { v0: t[0], v1: t[1], v2: t[2] }).collect();

    let mut g = c.benchmark_group("bunny_build");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    g.bench_function("prism_bvh", |b| {
        b.iter(|| black_box(prism::accel::Accel::build(AccelKind::Bvh, black_box(prims)).unwrap()))
    });
    g.bench_function("raw_obvhs", |b| {
        b.iter(|| {
            black_box(obvhs::cwbvh::builder::build_cwbvh_from_tris(
                black_box(&tris),
                BvhBuildParams::medium_build(),
                &mut Duration::default(),
            ))
        })
    });
    g.finish();

    // Raw obvhs: its own build from triangles, triangles reordered into leaf order (obvhs's recommended layout).
    let raw =
        obvhs::cwbvh::builder::build_cwbvh_from_tris(&tris, BvhBuildParams::medium_build(), &mut Duration::default());
    let raw_tris: Vec<Triangle> = raw.primitive_indices.iter().map(|&i| tris[i as usize]).collect();

    let (camera, random) = ray_sets(scene);
    for (name, rays) in [("camera", &camera), ("random", &random)] {
        let mut g = c.benchmark_group(format!("bunny_closest_hit_{name}"));
        g.throughput(Throughput::Elements(rays.len() as u64)).sample_size(20).measurement_time(Duration::from_secs(8));
        g.bench_with_input(BenchmarkId::new("prism_bvh", rays.len()), rays, |b, rays| {
            b.iter(|| {
                let mut hits = 0u32;
                for r in rays {
                    hits += scene.accel.intersect(prims, r).is_some() as u32;
                }
                black_box(hits)
            })
        });
        g.bench_with_input(BenchmarkId::new("raw_obvhs", rays.len()), rays, |b, rays| {
            b.iter(|| {
                let mut hits = 0u32;
                for r in rays {
                    let ray = obvhs::ray::Ray::new(r.origin, r.dir, 0.0, r.tmax);
                    let mut hit = RayHit::none();
                    hits += raw.ray_traverse(ray, &mut hit, |ray, id| raw_tris[id].intersect(ray)) as u32;
                }
                black_box(hits)
            })
        });
        g.finish();
    }
}

criterion_group!(benches, bench_bunny);
criterion_main!(benches);
