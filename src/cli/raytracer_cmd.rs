//! `prism raytracer -input scene.txt -size 200 200 -output out.tga ...`: a 6.837 course command line (assignments
//! 1-5), translated option by option into `prism render` runs. The mapping (also in the README):
//!
//! | course option | Prism |
//! |---|---|
//! | `-input F` | `SCENE` (`F`, a 6.837 `.txt`) |
//! | `-size W H` | `--size WxH` |
//! | `-output F` | `-o F` (`.tga` written as `.png`) |
//! | `-depth NEAR FAR F` | a second render `--integrator 'debug(mode: depth, near: NEAR, far: FAR)' -o F` |
//! | `-normals F` | a render `--integrator 'debug(mode: normals)' -o F` |
//! | `-shadows` | `phong(shadows: true)` (off without it) |
//! | `-bounces N` | `phong(max_depth: N)` (0 without it) |
//! | `-weight W` | `phong(min_weight: W)` |
//! | `-shade_back` | `phong(shade_back: true)` (`false` without it: back faces black) |
//! | `-grid NX NY NZ` | `--accel grid --grid NX NY NZ` |
//! | `-visualize_grid` | `--integrator 'debug(mode: grid_cells)'` for the `-output` image |
//! | `-stats` | the accelerator's statistics on stderr |
//! | `-exact_curves` (Prism's own) | `--exact-curves`: assignment 8's meshes as the exact surfaces of their spline files |
//! | `-gui`, `-tessellation A B`, `-gouraud` | ignored (OpenGL preview) |
//!
//! Course depths are measured from the camera centre; for orthographic cameras, whose eye Prism moves back
//! behind the scene, NEAR and FAR are shifted by that distance. Each image is rendered with 1 sample per pixel,
//! as the course's ray tracer does (jittered within the pixel).

use super::render_cmd::{RenderArgs, run as render};
use crate::error::PrismError;
use crate::load::mit6837;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug, Clone)]
pub struct RaytracerArgs {
    /// The course's options, e.g. `-input scene5_01_sphere.txt -size 200 200 -grid 5 5 5 -visualize_grid`.
    #[arg(trailing_var_arg = true, allow_hyphen_values = true, num_args = 1..)]
    pub args: Vec<String>,
}

/// The course options, parsed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CourseOptions {
    pub input: Option<PathBuf>,
    pub size: Option<(u32, u32)>,
    pub output: Option<PathBuf>,
    pub depth: Option<(f32, f32, PathBuf)>,
    pub normals: Option<PathBuf>,
    pub shadows: bool,
    pub bounces: u32,
    pub weight: f32,
    pub shade_back: bool,
    pub grid: Option<[u32; 3]>,
    pub visualize_grid: bool,
    pub stats: bool,
    /// Prism's own `-exact_curves`: assignment 8's meshes as exact curved surfaces.
    pub exact_curves: bool,
}

/// Parse course options; unknown ones are errors naming the option.
pub fn parse_course_options(args: &[String]) -> Result<CourseOptions, PrismError> {
    let mut o = CourseOptions::default();
    let mut i = 0;
    let take = |i: &mut usize, what: &str| -> Result<String, PrismError> {
        *i += 1;
        args.get(*i).cloned().ok_or_else(|| PrismError::invalid(format!("{what}: missing value")))
    };
    fn num<T: std::str::FromStr>(s: String, what: &str) -> Result<T, PrismError> {
        s.parse().map_err(|_| PrismError::invalid(format!("{what}: `{s}` is not a valid number")))
    }
    while i < args.len() {
        let opt = args[i].as_str();
        match opt {
            "-input" => o.input = Some(take(&mut i, opt)?.into()),
            "-size" => o.size = Some((num(take(&mut i, opt)?, opt)?, num(take(&mut i, opt)?, opt)?)),
            "-output" => o.output = Some(take(&mut i, opt)?.into()),
            "-depth" => {
                o.depth =
                    Some((num(take(&mut i, opt)?, opt)?, num(take(&mut i, opt)?, opt)?, take(&mut i, opt)?.into()))
            }
            "-normals" => o.normals = Some(take(&mut i, opt)?.into()),
            "-shadows" => o.shadows = true,
            "-bounces" => o.bounces = num(take(&mut i, opt)?, opt)?,
            "-weight" => o.weight = num(take(&mut i, opt)?, opt)?,
            "-shade_back" => o.shade_back = true,
            "-grid" => {
                o.grid =
                    Some([num(take(&mut i, opt)?, opt)?, num(take(&mut i, opt)?, opt)?, num(take(&mut i, opt)?, opt)?])
            }
            "-visualize_grid" => o.visualize_grid = true,
            "-stats" => o.stats = true,
            "-exact_curves" => o.exact_curves = true,
            "-gui" | "-gouraud" => {}
            "-tessellation" => {
                take(&mut i, opt)?;
                take(&mut i, opt)?;
            }
            other => {
                return Err(PrismError::invalid(format!(
                    "unsupported 6.837 option `{other}` (supported: -input -size -output -depth -normals -shadows \
                     -bounces -weight -shade_back -grid -visualize_grid -stats, and Prism's -exact_curves; -gui \
                     -tessellation -gouraud are ignored)"
                )));
            }
        }
        i += 1;
    }
    if o.visualize_grid && o.grid.is_none() {
        return Err(PrismError::invalid("-visualize_grid needs -grid NX NY NZ"));
    }
    Ok(o)
}

/// `.tga` outputs are written as `.png`.
fn image_path(p: &Path) -> PathBuf {
    match p.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("png" | "exr") => p.to_path_buf(),
        _ => p.with_extension("png"),
    }
}

pub fn run(args: RaytracerArgs) -> anyhow::Result<()> {
    let o = parse_course_options(&args.args)?;
    let input = o.input.clone().ok_or_else(|| PrismError::invalid("-input SCENE.txt is required"))?;
    let base = |output: PathBuf, integrator: String| RenderArgs {
        scene: input.clone(),
        output: vec![image_path(&output)],
        integrator: Some(integrator),
        accel: None,
        grid: o.grid.map(|g| g.to_vec()),
        spp: Some(1),
        passes: None,
        time: None,
        size: o.size,
        seed: None,
        threads: None,
        pattern: None,
        exposure: None,
        checkpoint: 0.0,
        quiet: true,
        exact_curves: o.exact_curves,
    };
    if o.stats {
        let mut app = crate::App::with_default_plugins();
        app.resources.source = crate::app::SceneSource::File(input.clone());
        app.resources.overrides.accel = super::render_cmd::accel_override(None, o.grid.as_ref().map(|g| &g[..]))?;
        app.resources.overrides.exact_curves = o.exact_curves;
        app.setup()?;
        let s = app.resources.scene()?.accel.stats();
        eprintln!(
            "{}: {} in {:.1} ms, {} bytes, {} nodes/cells, {}",
            input.display(),
            s.kind,
            s.build_time.as_secs_f64() * 1e3,
            s.memory_bytes,
            s.nodes,
            s.detail
        );
    }
    if let Some(out) = &o.output {
        let integrator = if o.visualize_grid {
            "debug(mode: grid_cells)".to_string()
        } else {
            format!(
                "phong(max_depth: {}, shadows: {}, min_weight: {:?}, shade_back: {})",
                o.bounces, o.shadows, o.weight, o.shade_back
            )
        };
        render(base(out.clone(), integrator))?;
    }
    if let Some((near, far, out)) = &o.depth {
        let back = mit6837::convert_file(&input, Path::new("."), o.exact_curves)?.eye_back;
        render(base(out.clone(), format!("debug(mode: depth, near: {:?}, far: {:?})", near + back, far + back)))?;
    }
    if let Some(out) = &o.normals {
        render(base(out.clone(), "debug(mode: normals)".into()))?;
    }
    Ok(())
}
