//! The image is a function of the scene, the seed, the sample count and the settings alone — not of how the work is
//! split: for every scene in `scenes/` and every integrator, the merge of `--shard K/N` renders (N = 2, 3, 5, each
//! with the pass plan its shard count gives) and a render interrupted at a random moment and resumed from its film
//! equal the one-process render bit for bit. Small images, few samples; the random moments come from a seeded
//! generator, and the equality must hold wherever they fall.

use crate::common::root;
use prism::app::{App, SceneSource};
use prism::film::Film;
use prism::sampling::Rng;
use prism::settings::Overrides;
use prism::{DefaultPlugins, Result};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

const INTEGRATORS: [&str; 4] = ["phong", "envlight", "ppm", "debug"];

fn scenes() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("scenes"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    v.sort();
    v
}

/// One render of `scene` at 24x18 with 6 samples (or iterations) per pixel.
fn app(scene: &Path, integrator: &str, adaptive: bool, shard: Option<(u32, u32)>) -> App {
    let mut app = App::with(DefaultPlugins);
    app.resources.source = SceneSource::File(scene.to_path_buf());
    app.resources.overrides = Overrides {
        size: Some((24, 18)),
        spp: Some(6),
        integrator: Some(integrator.into()),
        adaptive: Some(adaptive),
        shard,
        ..Default::default()
    };
    app
}

fn bits(film: &Film) -> Vec<[u32; 3]> {
    film.image().iter().map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]).collect()
}

fn run(mut app: App) -> Result<Film> {
    app.run()?;
    app.resources.film.take().ok_or_else(|| prism::PrismError::invalid("no film"))
}

/// The merge of the `n` shards of the render, as `prism merge` adds them.
fn merged(scene: &Path, integrator: &str, adaptive: bool, n: u32) -> Film {
    let mut films = (0..n).map(|k| run(app(scene, integrator, adaptive, Some((k, n)))).unwrap());
    let mut first = films.next().unwrap();
    for f in films {
        first.accumulate(&f);
    }
    first
}

/// The render interrupted `after` into it (its film saved as Ctrl-C saves it), then resumed to the end.
fn interrupted_and_resumed(scene: &Path, integrator: &str, adaptive: bool, after: Duration, dir: &Path) -> Film {
    let film_path = dir.join("interrupted.prism-film");
    let _ = std::fs::remove_file(&film_path);
    let mut first = app(scene, integrator, adaptive, None);
    let cancel = Arc::new(AtomicBool::new(false));
    first.resources.cancel = cancel.clone();
    first.resources.film_path = Some(film_path.clone());
    let film = std::thread::scope(|s| {
        s.spawn(|| {
            std::thread::sleep(after);
            cancel.store(true, Ordering::Relaxed);
        });
        run(first).unwrap()
    });
    if !film_path.is_file() {
        // The render finished before the interruption: it is the whole render.
        return film;
    }
    let mut second = app(scene, integrator, adaptive, None);
    second.resources.resume = Some(film_path);
    run(second).unwrap()
}

#[test]
fn every_scene_and_integrator_renders_the_same_bits_in_shards_and_after_an_interruption() {
    let dir = crate::common::scratch("exactness");
    let mut rng = Rng::new(2026, 12);
    let mut cases = 0;
    for scene in scenes() {
        let name = scene.file_name().unwrap().to_string_lossy().to_string();
        let mut configs: Vec<(&str, bool)> = INTEGRATORS.iter().map(|&i| (i, false)).collect();
        configs.push(("envlight", true));
        for (integrator, adaptive) in configs {
            let what = format!("{name} with {integrator}{}", if adaptive { ", adaptive" } else { "" });
            let t0 = Instant::now();
            let whole = match run(app(&scene, integrator, adaptive, None)) {
                Ok(f) => f,
                // A scene an integrator does not render (the debug grid view needs a grid) is not a case.
                Err(e) => {
                    assert!(integrator == "debug", "{what}: {e}");
                    continue;
                }
            };
            let took = t0.elapsed();
            let want = bits(&whole);
            for n in [2, 3, 5] {
                assert!(bits(&merged(&scene, integrator, adaptive, n)) == want, "{what}: {n} shards differ");
            }
            let after = took.mul_f64(rng.next_f32() as f64);
            let resumed = interrupted_and_resumed(&scene, integrator, adaptive, after, &dir);
            assert!(bits(&resumed) == want, "{what}: interrupted after {after:?} and resumed, it differs");
            cases += 1;
        }
    }
    assert!(cases >= 50, "only {cases} cases ran");
}
