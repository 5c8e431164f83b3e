//! `prism raytracer -input scene.txt -size 200 200 -output out.tga ...`: a 6.837 course command line (assignments
//! 1-7), translated option by option into `prism render` runs. The mapping (also in `docs/guide/mit6837.md`):
//!
//! | course option | Prism |
//! |---|---|
//! | `-input F` | `SCENE` (`F`, a 6.837 `.txt`) |
//! | `-size W H` | `--size WxH` |
//! | `-output F` | `-o F`: a `.tga` is written at exactly that path, linear values quantised as the course does (`int(255 c)` clamped, no sRGB) |
//! | `-depth NEAR FAR F` | a second render `--integrator 'debug(mode: depth, near: NEAR, far: FAR)' -o F` (`raw: true` for `.tga`) |
//! | `-normals F` | a render `--integrator 'debug(mode: normals)' -o F` (`raw: true` for `.tga`) |
//! | `-shadows` | `phong(shadows: true)` (off without it) |
//! | `-bounces N` | `phong(max_depth: N)` (0 without it) |
//! | `-weight W` | `phong(min_weight: W)` |
//! | `-shade_back` | `phong(shade_back: true)` (`false` without it: back faces black) |
//! | `-grid NX NY NZ` | `--accel grid --grid NX NY NZ` |
//! | `-visualize_grid` | `--integrator 'debug(mode: grid_cells)'` for the `-output` image |
//! | `-stats` | the accelerator's statistics on stderr |
//! | `-random_samples N`, `-uniform_samples N`, `-jittered_samples N` | `--spp N --pattern random\|uniform\|stratified` (default: 1 sample at the pixel centre, as the course) |
//! | `-box_filter R`, `-tent_filter R`, `-gaussian_filter S` | `--filter box:R\|tent:R\|gaussian:S` (sampled by importance, the course's radii) |
//! | `-render_samples F Z` | an image of every pixel's sample positions, `Z` texels per pixel |
//! | `-render_filter F Z` | an image of the filter's weights around the centre pixel, `Z` texels per pixel |
//! | `-exact_curves` (Prism's own) | `--exact-curves`: assignment 8's meshes as the exact surfaces of their spline files |
//! | `-gui`, `-tessellation A B`, `-gouraud` | ignored (OpenGL preview) |
//!
//! Course depths are measured from the camera centre; for orthographic cameras, whose eye Prism moves back
//! behind the scene, NEAR and FAR are shifted by that distance. Without a sampling option each image is rendered
//! with 1 sample at each pixel centre, as the course's ray tracer does.

use super::render_cmd::{RenderArgs, run as render};
use prism_core::error::PrismError;
use prism_core::sampling::{PixelFilter, PixelPattern};
use prism_load::mit6837;
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
    /// Samples per pixel and their pattern (`-random_samples N` ...).
    pub samples: Option<(PixelPattern, u32)>,
    pub filter: Option<PixelFilter>,
    /// `-render_samples FILE ZOOM`.
    pub render_samples: Option<(PathBuf, u32)>,
    /// `-render_filter FILE ZOOM`.
    pub render_filter: Option<(PathBuf, u32)>,
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
            "-random_samples" | "-uniform_samples" | "-jittered_samples" => {
                let n: u32 = num(take(&mut i, opt)?, opt)?;
                if n == 0 || n > 1 << 16 {
                    return Err(PrismError::invalid(format!("{opt}: the sample count must be 1 to 65536, got {n}")));
                }
                let pattern = match opt {
                    "-random_samples" => PixelPattern::Random,
                    "-uniform_samples" => PixelPattern::Uniform,
                    _ => PixelPattern::Stratified,
                };
                o.samples = Some((pattern, n));
            }
            "-box_filter" | "-tent_filter" | "-gaussian_filter" => {
                let r: f32 = num(take(&mut i, opt)?, opt)?;
                let f = match opt {
                    "-box_filter" => PixelFilter::Box { radius: r },
                    "-tent_filter" => PixelFilter::Tent { radius: r },
                    _ => PixelFilter::Gaussian { sigma: r },
                };
                f.validate().map_err(|e| PrismError::invalid(format!("{opt}: {e}")))?;
                o.filter = Some(f);
            }
            "-render_samples" | "-render_filter" => {
                let file: PathBuf = take(&mut i, opt)?.into();
                let zoom: u32 = num(take(&mut i, opt)?, opt)?;
                if opt == "-render_samples" {
                    o.render_samples = Some((file, zoom));
                } else {
                    o.render_filter = Some((file, zoom));
                }
            }
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
                     -bounces -weight -shade_back -grid -visualize_grid -stats -random_samples -uniform_samples \
                     -jittered_samples -box_filter -tent_filter -gaussian_filter -render_samples -render_filter, and Prism's \
                     -exact_curves;                      -gui -tessellation -gouraud are ignored)"
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

/// True for the course's TGA outputs, written with linear values (`int(255 c)`), so the debug views write their
/// values raw.
fn is_tga(p: &Path) -> bool {
    p.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("tga"))
}

pub fn run(args: RaytracerArgs) -> anyhow::Result<()> {
    let o = parse_course_options(&args.args)?;
    let input = o.input.clone().ok_or_else(|| PrismError::invalid("-input SCENE.txt is required"))?;
    let base = |output: PathBuf, integrator: String| RenderArgs {
        scene: input.clone(),
        output: vec![output],
        integrator: Some(integrator),
        accel: None,
        grid: o.grid.map(|g| g.to_vec()),
        spp: Some(o.samples.map_or(1, |s| s.1)),
        passes: None,
        time: None,
        noise: None,
        size: o.size,
        seed: None,
        threads: None,
        sampler: None,
        pattern: Some(o.samples.map_or(PixelPattern::Uniform, |s| s.0)),
        filter: o.filter,
        adaptive: None,
        exposure: None,
        checkpoint: 0.0,
        quiet: true,
        shard: None,
        resume: None,
        camera: None,
        view: super::render_cmd::ViewArgs::default(),
        exact_curves: o.exact_curves,
        allow_read: vec![],
    };
    if o.stats {
        let mut app = prism_engine::App::with(crate::DefaultPlugins);
        app.resources.source = prism_engine::SceneSource::File(input.clone());
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
            format!("debug(mode: grid_cells, raw: {})", is_tga(out))
        } else {
            format!(
                "phong(max_depth: {}, shadows: {}, min_weight: {:?}, shade_back: {})",
                o.bounces, o.shadows, o.weight, o.shade_back
            )
        };
        render(base(out.clone(), integrator))?;
    }
    if let Some((near, far, out)) = &o.depth {
        let back =
            prism_load::with_loader_stack(|| mit6837::convert_file(&input, Path::new("."), o.exact_curves))?.eye_back;
        let (near, far, raw) = (near + back, far + back, is_tga(out));
        render(base(out.clone(), format!("debug(mode: depth, near: {near:?}, far: {far:?}, raw: {raw})")))?;
    }
    if let Some(out) = &o.normals {
        render(base(out.clone(), format!("debug(mode: normals, raw: {})", is_tga(out))))?;
    }
    if o.render_samples.is_some() || o.render_filter.is_some() {
        let size = o.size.unwrap_or((200, 200));
        let (pattern, n) = o.samples.unwrap_or((PixelPattern::Uniform, 1));
        let filter = o.filter.unwrap_or_default();
        if let Some((out, zoom)) = &o.render_samples {
            super::course_views::render_samples(out, size, *zoom, pattern, filter, n)?;
        }
        if let Some((out, zoom)) = &o.render_filter {
            super::course_views::render_filter(out, size, *zoom, filter)?;
        }
    }
    Ok(())
}
