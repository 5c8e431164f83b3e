//! `prism render SCENE [options]`: overrides on top of the scene's settings, a thread pool of the requested size,
//! Ctrl-C keeps what was rendered (the film is written, then the process exits non-zero), a progress bar on a
//! terminal, a one-paragraph summary on stderr.

use clap::Args;
use prism_core::error::PrismError;
use prism_core::sampling::{PixelFilter, PixelPattern, SamplerKind};
use prism_core::settings::{AccelKind, EnvOverride, GridResolution, Overrides, ViewOverride};
use prism_engine::{App, SceneSource};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::Instant;

#[derive(Args, Debug, Clone)]
pub struct RenderArgs {
    /// Scene file: .ron (Prism scene), .obj or .ply (mesh with an automatic camera and headlight), .gltf/.glb, .pbrt, or a 6.837 .txt.
    pub scene: PathBuf,
    /// Output image(s); .png (sRGB), .exr (linear) or .tga (the 6.837 course's linear 8-bit). Repeat for several. Default: SCENE-NAME.png.
    #[arg(short, long = "output")]
    pub output: Vec<PathBuf>,
    /// Integrator plugin, `name` or `name(param: value, ...)`, e.g. `envlight(max_depth: 2)` or
    /// `'debug(mode: grid_cells)'`.
    #[arg(long)]
    pub integrator: Option<String>,
    /// Accelerator: bvh (the default), cwbvh, kdtree, grid or brute.
    #[arg(long, value_parser = parse_accel)]
    pub accel: Option<AccelKind>,
    /// Uniform grid resolution NX NY NZ (implies --accel grid).
    #[arg(long, num_args = 3, value_names = ["NX", "NY", "NZ"])]
    pub grid: Option<Vec<u32>>,
    /// Total samples per pixel.
    #[arg(long)]
    pub spp: Option<u32>,
    /// Progressive passes the samples are split into evenly (default: passes of at least 32 samples, at most 16, after
    /// the adaptive pilot's own pass).
    #[arg(long)]
    pub passes: Option<u32>,
    /// Time budget in seconds: stop when it is spent, cutting the pass then running short (unlimited samples unless --spp is given)
    #[arg(long, allow_negative_numbers = true)]
    pub time: Option<f64>,
    /// Noise target: stop after the first pass at which the image's estimated relative error (relMSE, from the
    /// film itself) is at most REL, or at --spp or --time if that comes first; with neither, at most 65536 spp
    #[arg(long, value_name = "REL", allow_negative_numbers = true)]
    pub noise: Option<f32>,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    #[arg(long)]
    pub seed: Option<u64>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Sampler for every dimension of a sample: independent, stratified or sobol (default).
    #[arg(long, value_parser = parse_sampler)]
    pub sampler: Option<SamplerKind>,
    /// Pixel positions from an explicit pattern instead of the sampler: random, stratified, uniform or rgss.
    #[arg(long, value_parser = parse_pattern)]
    pub pattern: Option<PixelPattern>,
    /// Pixel filter: box, tent or gaussian, with its radius (sigma for gaussian) after a colon: `tent:1.5`.
    #[arg(long, value_parser = parse_filter)]
    pub filter: Option<PixelFilter>,
    /// Adaptive sampling: after a uniform first pass, samples go where the image is noisy (same total);
    /// `--adaptive false` turns off a scene's `adaptive: true`.
    #[arg(long, num_args = 0..=1, default_missing_value = "true", value_name = "BOOL")]
    pub adaptive: Option<bool>,
    /// PNG exposure in stops.
    #[arg(long, allow_negative_numbers = true)]
    pub exposure: Option<f32>,
    /// Write the outputs every this many seconds while rendering (0: only at the end).
    #[arg(long, default_value_t = 10.0)]
    pub checkpoint: f64,
    /// No progress bar and no summary.
    #[arg(long, short)]
    pub quiet: bool,
    /// Render shard K of N (`--shard 2/8`): the passes `p % N == K`, or for `ppm` the pixel rows `y % N == K`;
    /// write it with `-o part.prism-film` and combine the parts with `prism merge`.
    #[arg(long, value_parser = parse_shard)]
    pub shard: Option<(u32, u32)>,
    /// The camera to render from, by camera or node name or by index in node order, for scene files with several
    /// (glTF); default the first.
    #[arg(long, value_name = "NAME|INDEX")]
    pub camera: Option<String>,
    #[command(flatten)]
    pub view: ViewArgs,
    /// Continue the render saved in a `.prism-film` file (same scene and settings); the result equals an
    /// uninterrupted render bit for bit.
    #[arg(long)]
    pub resume: Option<PathBuf>,
    /// Render curved surfaces (revolutions, Bézier patches) exactly where the scene asks for a tessellation: RON
    /// `tessellation`, and the meshes 6.837 assignment 8 scenes name.
    #[arg(long)]
    pub exact_curves: bool,
    /// Read only files inside this folder (repeatable; symbolic links followed): the scene, everything it references
    /// and a --resume film. For scenes from untrusted sources; by default every path is read.
    #[arg(long = "allow-read", value_name = "DIR")]
    pub allow_read: Vec<PathBuf>,
}

/// The light and the view of any scene, replacing the scene's.
#[derive(Args, Debug, Clone)]
pub struct ViewArgs {
    /// Light the scene with this environment map (.hdr, .exr, .pfm, .png; any layout a RON `Environment` reads),
    /// replacing the scene's environment lights.
    #[arg(long, value_name = "FILE")]
    pub env: Option<PathBuf>,
    /// Scale the --env map's radiance.
    #[arg(long, requires = "env", default_value_t = 1.0, value_name = "S")]
    pub env_scale: f32,
    /// Turn the --env map about +y by this many degrees.
    #[arg(long, requires = "env", default_value_t = 0.0, allow_negative_numbers = true, value_name = "DEG")]
    pub env_rotate: f32,
    /// The --env map's layout: equirect, cross or equal-area (default: guessed from its shape).
    #[arg(long, requires = "env", value_parser = parse_env_layout, value_name = "LAYOUT")]
    pub env_layout: Option<String>,
    /// Light the scene with a uniform environment of this linear RGB radiance (`--sky 1,1,1`), replacing the
    /// scene's environment lights.
    #[arg(long, conflicts_with = "env", value_parser = parse_vec3, value_name = "R,G,B")]
    pub sky: Option<glam::Vec3>,
    /// Add no default light to a scene without lights (a bare OBJ/PLY's headlight, a glTF's white sky).
    #[arg(long)]
    pub no_default_light: bool,
    /// Move the camera's eye to this world-space point (keeps what it looks at unless --look-at is given).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub look_from: Option<glam::Vec3>,
    /// Aim the camera at this world-space point.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub look_at: Option<glam::Vec3>,
    /// The camera's up direction (world space).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub up: Option<glam::Vec3>,
    /// The perspective camera's vertical field of view, degrees.
    #[arg(long, value_name = "DEG")]
    pub fov: Option<f32>,
}

impl Default for ViewArgs {
    /// No override: the scene's light and view.
    fn default() -> Self {
        ViewArgs {
            env: None,
            env_scale: 1.0,
            env_rotate: 0.0,
            env_layout: None,
            sky: None,
            no_default_light: false,
            look_from: None,
            look_at: None,
            up: None,
            fov: None,
        }
    }
}

impl ViewArgs {
    /// The overrides these flags set.
    pub fn apply(&self, o: &mut Overrides) {
        o.view = ViewOverride { from: self.look_from, at: self.look_at, up: self.up, fov: self.fov };
        o.environment = match (&self.env, self.sky) {
            (Some(path), _) => Some(EnvOverride::Map {
                path: path.clone(),
                scale: self.env_scale,
                rotate_deg: self.env_rotate,
                layout: self.env_layout.clone(),
            }),
            (None, Some(rgb)) => Some(EnvOverride::Sky(rgb)),
            (None, None) => None,
        };
        o.no_default_light = self.no_default_light;
    }
}

/// `equirect`, `cross` or `equal-area`, as the RON name of the layout.
pub(super) fn parse_env_layout(s: &str) -> Result<String, String> {
    match s.trim().to_ascii_lowercase().as_str() {
        "equirect" => Ok("Equirect".into()),
        "cross" => Ok("Cross".into()),
        "equal-area" | "equalarea" => Ok("EqualArea".into()),
        _ => Err(format!("unknown layout '{s}' (expected equirect, cross or equal-area)")),
    }
}

/// `X,Y,Z` (three finite numbers, commas or spaces between them).
pub(super) fn parse_vec3(s: &str) -> Result<glam::Vec3, String> {
    let parts: Vec<&str> = s.split([',', ' ']).filter(|p| !p.is_empty()).collect();
    let nums: Vec<f32> = parts
        .iter()
        .map(|p| p.trim().parse::<f32>().map_err(|_| format!("'{p}' in '{s}' is not a number")))
        .collect::<Result<_, _>>()?;
    match nums[..] {
        [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => Ok(glam::Vec3::new(x, y, z)),
        [_, _, _] => Err(format!("'{s}' has a number that is not finite")),
        _ => Err(format!("expected three numbers X,Y,Z, got '{s}'")),
    }
}

/// `K/N` with `K < N`.
pub(super) fn parse_shard(s: &str) -> Result<(u32, u32), String> {
    let (k, n) = s.split_once('/').ok_or_else(|| format!("expected K/N, got '{s}'"))?;
    let k = k.trim().parse::<u32>().map_err(|_| format!("bad shard index in '{s}'"))?;
    let n = n.trim().parse::<u32>().map_err(|_| format!("bad shard count in '{s}'"))?;
    if n == 0 || k >= n {
        return Err(format!("shard '{s}': need 0 <= K < N"));
    }
    Ok((k, n))
}

pub(super) fn parse_accel(s: &str) -> Result<AccelKind, String> {
    AccelKind::parse(s).ok_or_else(|| format!("unknown accelerator '{s}' (expected {})", AccelKind::NAMES))
}

/// `--accel` and `--grid` together: `--grid` alone means the grid; with another accelerator it is an error.
pub(super) fn accel_override(accel: Option<AccelKind>, grid: Option<&[u32]>) -> Result<Option<AccelKind>, PrismError> {
    let Some(g) = grid else {
        return Ok(accel);
    };
    prism_core::accel::grid::check_resolution([g[0], g[1], g[2]])?;
    let res = GridResolution::Fixed([g[0], g[1], g[2]]);
    match accel {
        None | Some(AccelKind::Grid(_)) => Ok(Some(AccelKind::Grid(res))),
        Some(other) => {
            Err(PrismError::invalid(format!("--grid sets a grid resolution but --accel is {}", other.name())))
        }
    }
}

pub(super) fn parse_pattern(s: &str) -> Result<PixelPattern, String> {
    PixelPattern::parse(s)
        .ok_or_else(|| format!("unknown pattern '{s}' (expected random, stratified, uniform or rgss)"))
}

pub(super) fn parse_sampler(s: &str) -> Result<SamplerKind, String> {
    SamplerKind::parse(s).ok_or_else(|| format!("unknown sampler '{s}' (expected {})", SamplerKind::NAMES))
}

/// `box`, `tent`, `gaussian`, optionally with `:RADIUS` (`:SIGMA` for gaussian); defaults 0.5, 1, 0.5.
pub(super) fn parse_filter(s: &str) -> Result<PixelFilter, String> {
    let (name, value) = match s.split_once(':') {
        Some((n, v)) => (n, Some(v.trim().parse::<f32>().map_err(|_| format!("filter '{s}': '{v}' is not a number"))?)),
        None => (s, None),
    };
    let f = match name.trim() {
        "box" => PixelFilter::Box { radius: value.unwrap_or(0.5) },
        "tent" => PixelFilter::Tent { radius: value.unwrap_or(1.0) },
        "gaussian" => PixelFilter::Gaussian { sigma: value.unwrap_or(0.5) },
        other => return Err(format!("unknown filter '{other}' (expected box, tent or gaussian)")),
    };
    f.validate()?;
    Ok(f)
}

pub(super) fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("expected WIDTHxHEIGHT, got '{s}'"))?;
    let w = w.trim().parse::<u32>().map_err(|_| format!("bad width in '{s}'"))?;
    let h = h.trim().parse::<u32>().map_err(|_| format!("bad height in '{s}'"))?;
    Ok((w, h))
}

/// Set while a render loads its scene and builds what it renders with (decoding, meshes, the accelerator): nothing
/// has been rendered yet, so Ctrl-C then exits at once instead of waiting for the set-up to finish.
static SETTING_UP: AtomicBool = AtomicBool::new(false);

/// The process-wide cancel flag, set by Ctrl-C.
pub(super) fn cancel_flag() -> Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let f = flag.clone();
        // A second Ctrl-C exits at once.
        let _ = ctrlc::set_handler(move || {
            if SETTING_UP.load(Ordering::SeqCst) {
                eprintln!("interrupted while setting up: nothing was rendered, no file was written");
                std::process::exit(130);
            }
            if f.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
        });
        flag
    })
    .clone()
}

pub fn run(args: RenderArgs) -> anyhow::Result<()> {
    if !args.allow_read.is_empty() {
        prism_core::io::restrict_reads(&args.allow_read)?;
    }
    if let Some(t) = args.threads {
        prism_core::limits::threads(t)?;
    }
    let checkpoint = prism_core::limits::seconds(args.checkpoint, "--checkpoint")?;
    let outputs = if args.output.is_empty() {
        let stem = args.scene.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_else(|| "out".into());
        vec![PathBuf::from(format!("{stem}.png"))]
    } else {
        args.output.clone()
    };
    for o in &outputs {
        let ext = o.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        if ext != "png" && ext != "exr" && ext != "tga" && !prism_core::io::is_film_path(o) {
            return Err(PrismError::invalid(format!(
                "{}: unsupported output format (use .png, .exr, .tga or .prism-film)",
                o.display()
            ))
            .into());
        }
    }
    let mut app = App::with(crate::DefaultPlugins);
    let r = &mut app.resources;
    r.source = SceneSource::File(args.scene.clone());
    r.overrides = overrides(&args)?;
    r.outputs = outputs.clone();
    r.resume = args.resume.clone();
    // Checkpoints and interruptions save the film beside the first output (or in the .prism-film output).
    r.film_path = outputs
        .iter()
        .find(|o| prism_core::io::is_film_path(o))
        .cloned()
        .or_else(|| outputs.first().map(|o| o.with_extension("prism-film")));
    r.checkpoint_every = (!checkpoint.is_zero()).then_some(checkpoint);
    r.cancel = cancel_flag();
    r.show_progress = !args.quiet && std::io::stderr().is_terminal();
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        builder = builder.num_threads(n);
    }
    let pool = builder
        .build()
        .map_err(|e| PrismError::invalid(format!("cannot start {} threads: {e}", args.threads.unwrap_or(0))))?;
    let t0 = Instant::now();
    pool.install(|| {
        SETTING_UP.store(true, Ordering::SeqCst);
        let setup = app.setup();
        SETTING_UP.store(false, Ordering::SeqCst);
        setup?;
        app.render()
    })?;
    let wall = t0.elapsed().as_secs_f64();
    let res = &app.resources;
    let p = &res.progress;
    let s = &res.settings;
    if !args.quiet {
        let render_s = p.elapsed.as_secs_f64();
        let samples = (p.spp_done - p.spp_resumed) as f64 * s.width as f64 * s.height as f64;
        eprintln!(
            "{}x{} {} spp ({} passes, {}, {}, {} sampler{}) in {:.3} s render + {:.2} s setup ({:.2} Msamples/s); wrote {}",
            s.width,
            s.height,
            p.spp_done,
            p.passes_done,
            s.integrator.name,
            s.accel.name(),
            s.sampler.name(),
            if s.adaptive { ", adaptive" } else { "" },
            render_s,
            (wall - render_s).max(0.0),
            samples / render_s.max(1e-9) / 1e6,
            outputs.iter().map(|o| o.display().to_string()).collect::<Vec<_>>().join(", ")
        );
        if let Some(note) = res.integrator.as_ref().and_then(|i| i.status()) {
            eprintln!("{}: {note}", s.integrator.name);
        }
        if let Some(target) = s.noise {
            eprintln!("{}", noise_line(target, p.noise, p.spp_done, p.finished && !p.interrupted));
        }
        if let Some(f) = &res.film
            && f.nonfinite > 0
        {
            eprintln!("warning: {} samples were NaN or infinite and counted as 0", f.nonfinite);
        }
    }
    // Even with -q: a clipped image is a wrong image.
    if let Some(f) = &res.film {
        let clipped = f.saturated_pixels();
        if clipped > 0 {
            eprintln!(
                "warning: {clipped} pixels reached the film's range (radiance sums above {:.2e}) and are clipped there",
                prism_core::film::fixed::MAX_SUM
            );
        }
    }
    if p.interrupted {
        let (lo, hi) = res.film.as_ref().map_or((0, 0), |f| f.sample_range());
        return Err(anyhow::anyhow!(
            "interrupted: wrote what was rendered ({} complete passes; {lo} to {hi} samples per pixel){}",
            p.passes_done,
            res.film_path.as_ref().map_or(String::new(), |f| format!("; continue with --resume {}", f.display()))
        ));
    }
    Ok(())
}

/// The summary's noise line: the estimate against the target, and whether the target stopped the render.
fn noise_line(target: f32, estimate: Option<f64>, spp: u64, finished: bool) -> String {
    match estimate {
        Some(e) if e <= target as f64 => format!("noise: estimated relMSE {e:.3e} at {spp} spp, target {target:e} met"),
        Some(e) if finished => format!(
            "noise: estimated relMSE {e:.3e} at {spp} spp, above the target {target:e} (the sample or time limit came first)"
        ),
        Some(e) => format!("noise: estimated relMSE {e:.3e} at {spp} spp, target {target:e}"),
        None => format!("noise: no estimate yet at {spp} spp (it needs two complete passes), target {target:e}"),
    }
}

/// The command line's overrides of the scene's settings (`prism render` and `prism watch`).
pub(super) fn overrides(args: &RenderArgs) -> anyhow::Result<Overrides> {
    let mut o = Overrides {
        size: args.size,
        spp: args.spp,
        passes: args.passes,
        sampler: args.sampler,
        pattern: args.pattern,
        filter: args.filter,
        adaptive: args.adaptive,
        seed: args.seed,
        time_budget: args.time,
        spp_unlimited: args.time.is_some() || args.noise.is_some(),
        noise: args.noise,
        integrator: args.integrator.clone(),
        accel: accel_override(args.accel, args.grid.as_deref())?,
        exposure: args.exposure,
        shard: args.shard,
        camera: args.camera.clone(),
        exact_curves: args.exact_curves,
        ..Overrides::default()
    };
    args.view.apply(&mut o);
    Ok(o)
}
