//! Curved surfaces: speed against accuracy (`cargo bench --bench curves`).
//!
//! 1. **Sweep** (printed, and written to `target/curves/`: `speed_accuracy.csv`, `speed_accuracy.svg`): the
//!    6.837 vase and Utah teapot (their assignment 8 views, Phong shading with a shadowed directional light,
//!    256 x 256, 4 stratified samples per pixel, one thread) rendered with the exact surfaces and with
//!    tessellations of increasing resolution (level k: `2^k` segments per profile piece, `4 * 2^k` steps around,
//!    `2^k` quads per patch side). Every render uses the same seed and pixel samples, so the difference between a
//!    mesh image and the exact image is the geometric error alone: its RMSE is the image error. Times are the
//!    best of 3 interleaved rounds: render (the passes) and set-up (tessellation and accelerator build).
//! 2. **Criterion** (`curves/...`): closest-hit rays/s for camera and bounce rays of the exact vase and teapot
//!    and of their meshes at equal image error (the coarsest level whose RMSE against the exact image is at most
//!    `EQUAL_ERROR`), and the build time of the exact surfaces' seeding structures against the tessellation and
//!    BVH build of those meshes.

use criterion::{Criterion, Throughput};
use prism::app::{App, SceneSource};
use prism::chart::{Chart, Series};
use prism::geometry::Ray;
use prism::ray_sets::{camera_rays, secondary_rays};
use prism::settings::{AccelKind, Overrides};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Image RMSE below which a mesh counts as equal to the exact surface (about half an 8-bit step at radiance 1).
const EQUAL_ERROR: f64 = 0.002;
const LEVELS: u32 = 8;
const ROUNDS: usize = 3;

fn data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data").join(rel)
}

#[derive(Clone, Copy, PartialEq)]
enum Object {
    Vase,
    Teapot,
}

impl Object {
    fn name(self) -> &'static str {
        match self {
            Object::Vase => "vase",
            Object::Teapot => "teapot",
        }
    }
}

/// Tessellation of level `k` as RON (`None`: exact).
fn tessellation(level: Option<u32>) -> String {
    match level {
        None => "None".into(),
        Some(k) => format!("Some((curve: {}, revolution: {}, patch: {}))", 1 << k, 4 << k, 1 << k),
    }
}

fn scene_text(o: Object, level: Option<u32>) -> String {
    let t = tessellation(level);
    let (camera, shape) = match o {
        Object::Vase => (
            "eye: (-0.090388, 6.412207, 9.038475), target: (-0.082164, 5.843304, 8.216111), fov: 50",
            format!(
                "Revolution(profile: BSpline([(0, -3, 0), (0, -3, 0), (0, -3, 0), (1.5, -3, 0), (2.5, 4, 0), (3, 4, 0), \
                 (2, -4, 0), (0, -4, 0), (0, -4, 0), (0, -4, 0)]), tessellation: {t})"
            ),
        ),
        Object::Teapot => (
            "eye: (0.227053, 6.538768, 11.642794), target: (0.227053, 6.13263, 10.728982), fov: 30",
            format!(
                "Splines(path: \"{}\", tessellation: {t})",
                data("mit6837/assignment8/spline8_09_teapot.txt").display()
            ),
        ),
    };
    format!(
        "(camera: ({camera}, size: (256, 256)), render: (integrator: phong, spp: 4, passes: 1), background: (0.2, 0, 0.6),
          ambient: (0.1, 0.1, 0.1),
          materials: {{\"m\": Phong(diffuse: (0.8, 0.1, 0.1), specular: (0.4, 0.4, 0.4), exponent: 40)}},
          entities: [(light: Directional(irradiance: (2.8, 2.8, 2.8), direction: (-0.2, -1, -0.5))),
                     (material: \"m\", shape: {shape})])"
    )
}

fn app(text: &str) -> App {
    let mut app = App::with(prism::DefaultPlugins);
    app.resources.source = SceneSource::RonText { text: text.into(), name: "curves.ron".into(), base_dir: ".".into() };
    app.resources.overrides = Overrides { accel: Some(AccelKind::Bvh), ..Default::default() };
    app
}

/// One measured render: (image, render seconds, set-up seconds, bounded primitives).
fn render(text: &str) -> (prism::io::Image, f64, f64, u32) {
    let mut a = app(text);
    a.run().expect("render");
    let img = prism::stages::film_image(&a.resources).unwrap();
    let p = &a.resources.progress;
    let n = a.resources.scene.as_ref().map_or(0, |s| s.prims.num_bounded());
    (img, p.elapsed.as_secs_f64(), p.setup.as_secs_f64(), n)
}

struct Row {
    object: Object,
    level: Option<u32>,
    prims: u32,
    rmse: f64,
    render_s: f64,
    setup_s: f64,
}

fn sweep() -> Vec<Row> {
    let mut rows: Vec<Row> = Vec::new();
    for object in [Object::Vase, Object::Teapot] {
        let configs: Vec<Option<u32>> = std::iter::once(None).chain((0..LEVELS).map(Some)).collect();
        let (reference, ..) = render(&scene_text(object, None));
        let mut best = vec![(f64::INFINITY, f64::INFINITY, 0.0, 0); configs.len()];
        for _ in 0..ROUNDS {
            for (i, &level) in configs.iter().enumerate() {
                let (img, r, s, n) = render(&scene_text(object, level));
                let rmse = prism::compare::compare(&img, &reference).unwrap().rmse as f64;
                best[i] = (best[i].0.min(r), best[i].1.min(s), rmse, n);
            }
        }
        for (i, &level) in configs.iter().enumerate() {
            let (render_s, setup_s, rmse, prims) = best[i];
            rows.push(Row { object, level, prims, rmse, render_s, setup_s });
        }
    }
    rows
}

fn write_results(rows: &[Row]) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/curves");
    std::fs::create_dir_all(&dir).unwrap();
    let mut csv = String::from("object,level,primitives,rmse,render_s,setup_s\n");
    println!("| object | surface | primitives | image RMSE | render s | set-up s |\n|---|---|---:|---:|---:|---:|");
    for r in rows {
        let level = r.level.map_or("exact".to_string(), |k| k.to_string());
        csv += &format!("{},{level},{},{:.6e},{:.4},{:.4}\n", r.object.name(), r.prims, r.rmse, r.render_s, r.setup_s);
        let surface = r.level.map_or("exact".to_string(), |k| format!("mesh {}/{}/{}", 1 << k, 4 << k, 1 << k));
        println!(
            "| {} | {surface} | {} | {:.2e} | {:.3} | {:.3} |",
            r.object.name(),
            r.prims,
            r.rmse,
            r.render_s,
            r.setup_s
        );
    }
    std::fs::write(dir.join("speed_accuracy.csv"), csv).unwrap();
    let mut series = Vec::new();
    for o in [Object::Vase, Object::Teapot] {
        let mesh: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.object == o && r.level.is_some())
            .map(|r| (r.render_s + r.setup_s, r.rmse.max(1e-5)))
            .collect();
        let exact = rows.iter().find(|r| r.object == o && r.level.is_none()).unwrap();
        let t = exact.render_s + exact.setup_s;
        series.push(Series { name: format!("{} meshes", o.name()), points: mesh });
        // The exact surface has no error against itself: a vertical line at its time.
        series.push(Series { name: format!("{} exact", o.name()), points: vec![(t, 2e-4), (t, 0.5)] });
        if let Some(r) = rows.iter().find(|r| r.object == o && r.level.is_some() && r.rmse <= EQUAL_ERROR) {
            println!(
                "{}: the coarsest mesh within RMSE {EQUAL_ERROR} is level {} ({} triangles): {:.3} s vs exact {:.3} s \
                 (render + set-up)",
                o.name(),
                r.level.unwrap(),
                r.prims,
                r.render_s + r.setup_s,
                t
            );
        }
    }
    let chart = Chart {
        title: "Curved surfaces: image error against time (256x256, 4 spp, 1 thread)".into(),
        x_label: "render + set-up seconds".into(),
        y_label: "RMSE against the exact surface".into(),
        log_x: true,
        log_y: true,
        series,
    };
    chart.write_svg(&dir.join("speed_accuracy.svg")).unwrap();
}

/// The coarsest level within `EQUAL_ERROR` of the exact image, per object.
fn equal_error_level(rows: &[Row], o: Object) -> u32 {
    rows.iter()
        .filter(|r| r.object == o && r.level.is_some())
        .find(|r| r.rmse <= EQUAL_ERROR)
        .and_then(|r| r.level)
        .unwrap_or(LEVELS - 1)
}

fn bench(c: &mut Criterion, rows: &[Row]) {
    for o in [Object::Vase, Object::Teapot] {
        let level = equal_error_level(rows, o);
        let mut exact = app(&scene_text(o, None));
        exact.setup().unwrap();
        let mut mesh = app(&scene_text(o, Some(level)));
        mesh.setup().unwrap();
        let (se, sm) = (exact.resources.scene.as_ref().unwrap(), mesh.resources.scene.as_ref().unwrap());
        let camera = camera_rays(se, 128, 128);
        let (bounce, _) = secondary_rays(se, &camera, 5);
        for (kind, rays) in [("camera", &camera), ("bounce", &bounce)] {
            let mut g = c.benchmark_group(format!("curves/{}_{kind}_rays", o.name()));
            g.throughput(Throughput::Elements(rays.len() as u64))
                .sample_size(10)
                .measurement_time(Duration::from_secs(6));
            let trace =
                |s: &prism::scene::Scene, rays: &[Ray]| rays.iter().filter(|r| s.intersect(r).is_some()).count();
            g.bench_function("exact", |b| b.iter(|| black_box(trace(se, rays))));
            g.bench_function(format!("mesh_level_{level}"), |b| b.iter(|| black_box(trace(sm, rays))));
            g.finish();
        }
        let mut g = c.benchmark_group(format!("curves/{}_build", o.name()));
        g.sample_size(10).measurement_time(Duration::from_secs(6));
        g.bench_function("exact_seeding_structures", |b| {
            b.iter(|| {
                let mut a = app(&scene_text(o, None));
                a.setup().unwrap();
                black_box(a.resources.scene.as_ref().unwrap().prims.num_bounded())
            })
        });
        g.bench_function(format!("mesh_level_{level}_tessellate_and_bvh"), |b| {
            b.iter(|| {
                let mut a = app(&scene_text(o, Some(level)));
                a.setup().unwrap();
                black_box(a.resources.scene.as_ref().unwrap().prims.num_bounded())
            })
        });
        g.finish();
    }
}

fn main() {
    if !data("mit6837/assignment8/spline8_09_teapot.txt").is_file() {
        eprintln!("skipping: ../shared/data is missing");
        return;
    }
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let t0 = Instant::now();
    let rows = pool.install(sweep);
    write_results(&rows);
    eprintln!("sweep: {:.1} s", t0.elapsed().as_secs_f64());
    let mut c = Criterion::default().configure_from_args();
    bench(&mut c, &rows);
    c.final_summary();
}
