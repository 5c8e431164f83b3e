//! In-memory entry points of the fuzz targets (`fuzz/fuzz_targets/`, libFuzzer through `cargo fuzz`) and of the
//! stable-toolchain test that replays their corpus of past crashes (`tests/fuzz_replay.rs`). Each takes arbitrary
//! bytes, runs one parser (and what consumes its output) and must return: errors are expected, panics, aborts and
//! hangs are bugs. None of them reads a file of the system (scenes that name files are only parsed); `film_resume`
//! writes the film it resumes to one temporary file of its own, as `--resume` reads from a path.

use prism_core::settings::{Overrides, PluginConfig};
use prism_engine::{App, Plugin, SceneSource};
use std::path::Path;

/// A fuzz entry point: arbitrary bytes in, nothing out; scenes are loaded and rendered with the plugins given (the
/// binary's `DefaultPlugins`), which the parsers of plain files do not need.
pub type Entry = fn(&[u8], &dyn Plugin);

/// Every target, by the name of its `fuzz/fuzz_targets/NAME.rs` and `tests/fuzz_corpus/NAME/`.
pub const TARGETS: [(&str, Entry); 13] = [
    ("ron_scene", ron_scene),
    ("mit6837_scene", mit6837_scene),
    ("obj_mtl", obj_mtl),
    ("hdr_image", hdr_image),
    ("exr_image", exr_image),
    ("integrator_spec", integrator_spec),
    ("film_file", film_file),
    ("film_resume", film_resume),
    ("ray_file", ray_file),
    ("mit6837_spline", mit6837_spline),
    ("ply_mesh", ply_mesh),
    ("gltf_scene", gltf_scene),
    ("pbrt_scene", pbrt_scene),
];

/// A base directory that does not exist: relative file names in fuzzed scenes resolve to nothing.
const NO_DIR: &str = "/nonexistent/prism-fuzz";

/// True when scene text may name a file (meshes, textures, environment maps, 6.837 meshes): such scenes are
/// only parsed, never loaded, so fuzzing touches no disk.
fn names_files(text: &str) -> bool {
    ["path", "map", "faces", "obj_file", "TriangleMesh"].iter().any(|w| text.contains(w))
}

/// Load, set up and render one 4x4 pass of RON scene text (no files).
fn load_and_render(text: &str, name: &str, plugins: &dyn Plugin) {
    let mut app = App::with(plugins);
    app.resources.source = SceneSource::RonText { text: text.into(), name: name.into(), base_dir: NO_DIR.into() };
    app.resources.overrides =
        Overrides { size: Some((4, 4)), spp: Some(1), passes: Some(1), time_budget: None, ..Default::default() };
    let _ = app.run();
}

/// A RON scene: parsed; when it names no file, loaded, set up and rendered (4x4 pixels, 1 sample).
pub fn ron_scene(data: &[u8], plugins: &dyn Plugin) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if prism_load::parse_scene(text, Path::new("fuzz.ron")).is_err() || names_files(text) {
        return;
    }
    load_and_render(text, "fuzz.ron", plugins);
}

/// A 6.837 scene: parsed; when it names no mesh, converted to RON, which must parse, then loaded and rendered.
pub fn mit6837_scene(data: &[u8], plugins: &dyn Plugin) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let file = Path::new("fuzz.txt");
    let Ok(scene) = prism_load::with_loader_stack(|| prism_load::mit6837::parse_txt(text, file, Path::new(NO_DIR)))
    else {
        return;
    };
    if names_files(text) {
        return;
    }
    let converted = prism_load::with_loader_stack(|| {
        let ron = prism_load::mit6837::to_ron(&scene, file, Path::new(NO_DIR), false)?.ron;
        if let Err(e) = prism_load::parse_scene(&ron, file) {
            panic!("the RON written for a 6.837 scene does not parse: {e}\n{ron}");
        }
        Ok(ron)
    });
    if let Ok(ron) = converted {
        load_and_render(&ron, "fuzz.txt", plugins);
    }
}

/// OBJ text and its MTL library, separated by the first 0xFF byte (every `mtllib` names that library); the
/// parts' tangent frames are computed too (as for normal-mapped meshes).
pub fn obj_mtl(data: &[u8], _plugins: &dyn Plugin) {
    let (obj, mtl) = match data.iter().position(|&b| b == 0xff) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (data, &[][..]),
    };
    let Ok(parts) = prism_load::parse_obj(obj, Path::new("fuzz.obj"), |_| Some(("fuzz.mtl".into(), mtl.to_vec())))
    else {
        return;
    };
    for p in parts {
        let _ = prism_core::mesh_tangents::mikktspace_tangents(&p.mesh);
    }
}

/// An image as an environment map: decoded, checked, laid out (guessed, then forced equirect) and importance
/// sampled.
fn environment(img: prism_core::io::Image, name: &str) {
    for layout in [None, Some(prism_core::envmap::SourceLayout::Equirect)] {
        if let Ok(map) = prism_core::envmap::EnvMap::from_image(img.clone(), Path::new(name), layout) {
            let _ = map.integral();
            if let Some(tree) = prism_core::lights::QuadTree::build(&map) {
                let _ = tree.sample(&map, glam::Vec2::new(0.3, 0.7));
            }
        }
    }
}

/// A Radiance HDR file, then the image as an environment map.
pub fn hdr_image(data: &[u8], _plugins: &dyn Plugin) {
    if let Ok(img) = prism_core::io::read_hdr_bytes(data, Path::new("fuzz.hdr")) {
        environment(img, "fuzz.hdr");
    }
}

/// An OpenEXR file, then the image as an environment map.
pub fn exr_image(data: &[u8], _plugins: &dyn Plugin) {
    if let Ok(img) = prism_core::io::read_exr_bytes(data, Path::new("fuzz.exr")) {
        environment(img, "fuzz.exr");
    }
}

/// An integrator spec (`--integrator`), parsed by every built-in integrator's factory.
pub fn integrator_spec(data: &[u8], plugins: &dyn Plugin) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(cfg) = PluginConfig::from_spec(text) else { return };
    let app = App::with(plugins);
    for name in ["phong", "envlight", "ppm", "debug"] {
        let c = PluginConfig { name: name.into(), ..cfg.clone() };
        let _ = app.resources.integrators.create(&c);
    }
}

/// The bytes with their last 8 replaced by the film checksum of the rest, so mutations reach past the checksum.
fn sealed(data: &[u8]) -> Vec<u8> {
    let mut v = data.to_vec();
    if v.len() >= 8 {
        let n = v.len() - 8;
        let sum = prism_core::film::checksum(&v[..n]);
        v[n..].copy_from_slice(&sum.to_le_bytes());
    }
    v
}

/// A `.prism-film` file, as given and with its checksum made right: decoded, its image computed and merged with
/// itself (as `prism merge` does).
pub fn film_file(data: &[u8], _plugins: &dyn Plugin) {
    for bytes in [data.to_vec(), sealed(data)] {
        if let Ok(mut f) = prism_core::film::parse_film(&bytes, Path::new("fuzz.prism-film")) {
            let _ = f.film.image();
            let copy = f.film.clone();
            f.film.accumulate(&copy);
            let _ = f.film.sample_range();
        }
    }
}

/// The scene `film_resume` resumes: 4x4 pixels, 4 passes of 1 sample.
const RESUME_SCENE: &str = r#"(
    camera: (eye: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0), fov: 40, size: (4, 4)),
    render: (spp: 4, passes: 4),
    materials: { "grey": Lambert(albedo: (0.8, 0.8, 0.8)) },
    entities: [
        (shape: Sphere(), material: "grey"),
        (shape: Quad(), light: Area(radiance: (4, 4, 4)), transform: [Translate((0, 2, 0)), Euler((90, 0, 0))]),
        (light: Environment(radiance: (0.2, 0.2, 0.2))),
    ],
)"#;

/// The integrators `film_resume` resumes (the first byte of its input picks one), with `--adaptive` or not.
const RESUME_INTEGRATORS: [(&str, bool); 5] =
    [("phong", false), ("envlight", false), ("envlight", true), ("ppm(photons: 16)", false), ("debug", false)];

/// An app rendering [`RESUME_SCENE`] with integrator `k`, writing or resuming the film at `film`.
fn resume_app(k: usize, plugins: &dyn Plugin, film: &Path, resume: bool) -> App {
    let (spec, adaptive) = RESUME_INTEGRATORS[k];
    let mut app = App::with(plugins);
    app.resources.source =
        SceneSource::RonText { text: RESUME_SCENE.into(), name: "resume.ron".into(), base_dir: NO_DIR.into() };
    app.resources.overrides =
        Overrides { integrator: Some(spec.into()), adaptive: Some(adaptive), time_budget: None, ..Default::default() };
    if resume {
        app.resources.resume = Some(film.to_path_buf());
    } else {
        app.resources.outputs = vec![film.to_path_buf()];
    }
    app
}

/// A saved render resumed (`prism render --resume`) and merged (`prism merge`). The first byte picks an
/// integrator; the rest, with its checksum made right, is a film file whose size, integrator, shard and fingerprint
/// are set to those of a real render of a tiny scene, so its sums, counts, progress and the integrator's own state
/// reach `--resume` and the passes rendered after it, then the merge with that real render.
pub fn film_resume(data: &[u8], plugins: &dyn Plugin) {
    use prism_core::film::{parse_film, read_film, write_film};
    let Some((&pick, rest)) = data.split_first() else { return };
    let k = pick as usize % RESUME_INTEGRATORS.len();
    let dir = std::env::temp_dir().join(format!("prism-fuzz-resume-{}", std::process::id()));
    if std::fs::create_dir_all(&dir).is_err() {
        return;
    }
    let real_path = dir.join(format!("real{k}.prism-film"));
    if !real_path.is_file() {
        let mut app = resume_app(k, plugins, &real_path, false);
        if let Err(e) = app.run() {
            panic!("the tiny scene does not render with `{}`: {e}", RESUME_INTEGRATORS[k].0);
        }
    }
    let Ok(real) = read_film(&real_path) else { return };
    let Ok(mut f) = parse_film(&sealed(rest), Path::new("fuzz.prism-film")) else { return };
    if f.film.width * f.film.height != real.film.width * real.film.height {
        return;
    }
    let h = &real.header;
    f.header = prism_core::film::FilmHeader {
        passes_done: f.header.passes_done,
        passes: f.header.passes,
        spp_done: f.header.spp_done,
        ..h.clone()
    };
    let film = prism_core::film::Film::from_parts(
        h.width,
        h.height,
        f.film.parts().0.to_vec(),
        f.film.parts().1.to_vec(),
        f.film.nonfinite,
    );
    let forged = dir.join("forged.prism-film");
    if write_film(&forged, &f.header, &film, &f.state).is_err() {
        return;
    }
    let mut app = resume_app(k, plugins, &forged, true);
    if app.run().is_ok()
        && let Some(mut resumed) = app.resources.film.take()
    {
        resumed.accumulate(&real.film);
        let _ = resumed.image();
    }
    let _ = std::fs::remove_file(&forged);
}

/// A `.prism-rays` file (`prism bench --export-rays`).
pub fn ray_file(data: &[u8], _plugins: &dyn Plugin) {
    let _ = crate::ray_file::RaySetFile::from_bytes(data, Path::new("fuzz.prism-rays"));
}

/// A 6.837 spline file: parsed, its surfaces tessellated (the curve editor's default resolutions) with their
/// tangent frames, and written back in both bases, which must parse again.
pub fn mit6837_spline(data: &[u8], _plugins: &dyn Plugin) {
    use prism_load::mit6837::spline::{Tessellation, parse_splines, tessellate_splines, write_splines};
    let Ok(text) = std::str::from_utf8(data) else { return };
    let file = Path::new("fuzz.txt");
    let Ok(items) = parse_splines(text, file) else { return };
    if let Ok(Some(mesh)) = tessellate_splines(&items, Tessellation::default()) {
        let _ = prism_core::mesh_tangents::mikktspace_tangents(&mesh);
    }
    for kind in [prism_core::shapes::CurveKind::Bezier, prism_core::shapes::CurveKind::BSpline] {
        if let Ok(written) = write_splines(&items, kind)
            && let Err(e) = parse_splines(&written, file)
        {
            panic!("the spline file written in the {} basis does not parse: {e}\n{written}", kind.name());
        }
    }
}

/// A PLY file (ASCII or binary), then its mesh's tangent frames (as for normal-mapped meshes).
pub fn ply_mesh(data: &[u8], _plugins: &dyn Plugin) {
    if let Ok(mesh) = prism_load::ply::parse_ply(data, Path::new("fuzz.ply")) {
        let _ = prism_core::mesh_tangents::mikktspace_tangents(&mesh);
    }
}

/// glTF JSON or GLB bytes, external buffers and images resolving to nothing: loaded, set up and rendered (4x4
/// pixels, 1 sample).
pub fn gltf_scene(data: &[u8], plugins: &dyn Plugin) {
    let mut app = App::with(plugins);
    app.resources.materials.push(prism_core::material::Material::default());
    let (world, res) = (&mut app.world, &mut app.resources);
    let loaded = prism_load::with_loader_stack(|| {
        prism_load::gltf::load_gltf_bytes(data, Path::new("fuzz.glb"), None, world, res)
    });
    if loaded.is_err() {
        return;
    }
    app.resources.overrides =
        Overrides { size: Some((4, 4)), spp: Some(1), passes: Some(1), time_budget: None, ..Default::default() };
    let _ = app.run();
}

/// A pbrt-v3/v4 scene: converted to RON (no file it names is read), which must parse; when the RON names no
/// file, loaded, set up and rendered (4x4 pixels, 1 sample).
pub fn pbrt_scene(data: &[u8], plugins: &dyn Plugin) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let file = Path::new("fuzz.pbrt");
    let converted = prism_load::with_loader_stack(|| {
        let ron = prism_load::pbrt::convert_text(text, file, None, Path::new(NO_DIR))?.ron;
        if let Err(e) = prism_load::parse_scene(&ron, file) {
            panic!("the RON written for a pbrt scene does not parse: {e}\n{ron}");
        }
        Ok(ron)
    });
    let Ok(ron) = converted else { return };
    // PLY meshes, image textures and environment maps are files (`path`, `map`); inline meshes are not.
    if ron.contains("path") || ron.contains("map") {
        return;
    }
    load_and_render(&ron, "fuzz.pbrt", plugins);
}
