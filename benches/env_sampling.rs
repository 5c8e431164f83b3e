//! Environment sampling comparison (issue: quad-tree importance sampling). For three maps — Grace Cathedral
//! (cross), quarry_01 (equirect, a tiny very bright sun) and a uniform map (a 256x128 equirect image of ones) — a
//! diffuse sphere on a plane is lit by
//! the environment alone with direct lighting (`max_depth: 2`). Each strategy is used on its own (`mis: false`):
//! uniform sphere directions, cosine-weighted directions, the piecewise-constant 2D baseline and the quad-tree.
//! Error = RMSE at equal samples per pixel against a reference (quad-tree + MIS, 4096 spp, another seed), averaged
//! over 3 seeds so that the ranking is not one noise realisation.
//!
//! `cargo bench --bench env_sampling` writes `target/env_sampling/env_sampling.csv` and one SVG chart per map,
//! and prints the table.

use prism::app::{App, SceneSource};
use prism::chart::{Chart, Series};
use prism::compare::compare;
use prism::io::Image;
use prism::settings::Overrides;
use std::fmt::Write as _;
use std::path::PathBuf;

const STRATEGIES: [&str; 4] = ["uniform", "cosine", "piecewise", "quadtree"];
const SPP: [u32; 4] = [4, 16, 64, 256];
fn spp_list() -> Vec<u32> {
    std::env::var("ENV_SPP").map(|s| s.split(',').map(|v| v.parse().unwrap()).collect()).unwrap_or(SPP.to_vec())
}

fn scene(env: &str) -> String {
    format!(
        "(camera: (eye: (0, 1.0, 4.0), target: (0, 0.5, 0), fov: 35, size: (128, 96)),
          materials: {{\"clay\": Lambert(albedo: (0.8, 0.8, 0.8)), \"ground\": Lambert(albedo: (0.5, 0.5, 0.5))}},
          entities: [(shape: Sphere(center: (0, 0.6, 0), radius: 0.6), material: \"clay\"),
                     (shape: Quad(), material: \"ground\", transform: [Rotate(axis: (1, 0, 0), degrees: -90), UniformScale(3)]),
                     (light: {env})])"
    )
}

fn render(text: &str, integrator: &str, spp: u32, seed: u64) -> Image {
    let mut app = App::with(prism::DefaultPlugins);
    app.resources.source =
        SceneSource::RonText { text: text.into(), name: "env_sampling.ron".into(), base_dir: ".".into() };
    app.resources.overrides =
        Overrides { integrator: Some(integrator.into()), spp: Some(spp), seed: Some(seed), ..Default::default() };
    app.run().expect("render");
    prism::stages::film_image(&app.resources).unwrap()
}

fn main() {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/envmaps");
    let out = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/env_sampling");
    std::fs::create_dir_all(&out).unwrap();
    let only = std::env::var("ENV_ONLY").ok();
    let uniform = out.join("uniform_256x128.exr");
    prism::io::write_exr(&uniform, &Image::new(256, 128, vec![glam::Vec3::ONE; 256 * 128])).unwrap();
    let maps = [
        ("grace_cross", format!("Environment(map: \"{}\")", data.join("cross/grace_cross.hdr").display())),
        ("quarry_01_1k", format!("Environment(map: \"{}\")", data.join("equirect/quarry_01_1k.hdr").display())),
        ("uniform_map", format!("Environment(map: \"{}\")", uniform.display())),
    ];
    let mut csv = String::from("map,strategy,spp,rmse\n");
    println!("{:<14} {:>5} {}", "map", "spp", STRATEGIES.map(|s| format!("{s:>12}")).join(""));
    for (name, env) in maps.iter().filter(|(n, _)| only.as_deref().is_none_or(|o| o == *n)) {
        let text = scene(env);
        let reference = render(&text, "envlight(max_depth: 2)", 4096, 99);
        let mut series: Vec<Series> =
            STRATEGIES.iter().map(|s| Series { name: s.to_string(), points: vec![] }).collect();
        for spp in spp_list() {
            let mut row = format!("{name:<14} {spp:>5}");
            for (k, strategy) in STRATEGIES.iter().enumerate() {
                let seeds = [1, 2, 3];
                let rmse = seeds
                    .iter()
                    .map(|&seed| {
                        let spec = format!("envlight(max_depth: 2, env_sampling: {strategy}, mis: false)");
                        compare(&render(&text, &spec, spp, seed), &reference).unwrap().rmse
                    })
                    .sum::<f64>()
                    / seeds.len() as f64;
                let _ = writeln!(csv, "{name},{strategy},{spp},{rmse:.6e}");
                let _ = write!(row, " {rmse:>12.5}");
                series[k].points.push((spp as f64, rmse));
            }
            println!("{row}");
        }
        let chart = Chart {
            title: format!("{name}: direct environment lighting, error at equal samples"),
            x_label: "samples per pixel".into(),
            y_label: "RMSE".into(),
            log_x: true,
            log_y: true,
            series,
        };
        chart.write_svg(&out.join(format!("env_sampling_{name}.svg"))).unwrap();
    }
    std::fs::write(out.join("env_sampling.csv"), csv).unwrap();
    println!("wrote {}", out.display());
}
