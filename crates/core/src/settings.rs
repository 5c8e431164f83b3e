//! Render settings: what the scene file's `render: (...)` block and the command line decide together (the
//! command line wins), resolved once in the Load stage and read by every later stage.

use crate::error::{PrismError, Result, SourcePos};
use crate::sampling::{PixelFilter, PixelPattern, SamplerKind};
use serde::de::DeserializeOwned;

/// Largest accepted image side and pixel count (see [`crate::limits`]).
pub use crate::limits::{MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE};

/// Largest exposure in stops either way (2^100 still scales an f32 radiance without overflowing to infinity).
pub const MAX_EXPOSURE: f32 = 100.0;

/// A plugin chosen by name, with its parameter text as written in the scene (`phong(max_depth: 3)`), parsed by
/// the plugin itself so that it owns its parameter struct.
#[derive(Clone, Debug, PartialEq)]
pub struct PluginConfig {
    /// The plugin's registered name (`phong`, `envlight`, `ppm`, ...).
    pub name: String,
    /// The parenthesised parameter list, e.g. `(max_depth: 3)`, if one was given.
    pub params: Option<String>,
    /// Where `params` starts in the scene file (for error positions).
    pub origin: Option<SourcePos>,
}

impl PluginConfig {
    /// The plugin `name` with no parameters (its defaults) and no position in a file.
    pub fn named(name: impl Into<String>) -> Self {
        PluginConfig { name: name.into(), params: None, origin: None }
    }

    /// Parse a command-line spec: `name` or `name(param: value, ...)` (parameters are checked by the plugin).
    pub fn from_spec(spec: &str) -> Result<Self> {
        let s = spec.trim();
        let ident = s.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(s.len());
        let rest = s[ident..].trim();
        if ident == 0 || !(rest.is_empty() || (rest.starts_with('(') && rest.ends_with(')'))) {
            return Err(PrismError::invalid(format!(
                "integrator spec '{spec}': expected `name` or `name(param: value, ...)`"
            )));
        }
        let params = (!rest.is_empty()).then(|| rest.to_string());
        Ok(PluginConfig { name: s[..ident].to_string(), params, origin: None })
    }

    /// Deserialize the plugin's parameter struct (defaults when none were given). Errors point into the scene file.
    pub fn parse_params<T: DeserializeOwned + Default>(&self) -> Result<T> {
        let Some(text) = &self.params else {
            return Ok(T::default());
        };
        let opts = ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
        let mut de = ron::Deserializer::from_str_with_options(text, &opts)
            .map_err(|e| PrismError::invalid(format!("integrator '{}': {}", self.name, e.code)))?;
        let parsed = match serde_path_to_error::deserialize::<_, T>(&mut de) {
            Ok(v) => de.end().map(|_| v).map_err(|e| (String::new(), e)),
            Err(e) => Err((e.path().to_string(), e.into_inner())),
        };
        parsed.map_err(|(path, e)| {
            let e = de.span_error(e);
            let what = crate::ron_error::describe(&e.code);
            let message = if path.is_empty() || path == "." || path == "?" {
                format!("integrator '{}': {what}", self.name)
            } else {
                format!("integrator '{}': `{path}`: {what}", self.name)
            };
            match &self.origin {
                Some(o) => {
                    let (line, col) = (e.span.start.line, e.span.start.col);
                    let pos = SourcePos {
                        file: o.file.clone(),
                        line: o.line + line - 1,
                        col: if line == 1 { o.col + col - 1 } else { col },
                    };
                    PrismError::Parse { pos, message }
                }
                None => PrismError::invalid(message),
            }
        })
    }
}

/// A plugin config as one line, `name` or `name(params)` (film headers, summaries).
pub fn describe_plugin(c: &PluginConfig) -> String {
    match &c.params {
        Some(p) => format!("{}{}", c.name, p.split_whitespace().collect::<Vec<_>>().join(" ")),
        None => c.name.clone(),
    }
}

/// Which accelerator to build over the scene's bounded primitives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum AccelKind {
    /// Wide BVH with SoA boxes and packet leaves (`accel/wide_bvh/`), built by obvhs (the default).
    #[default]
    Bvh,
    /// obvhs's compressed 8-wide BVH (CWBVH) and its own traversal (`accel/cwbvh.rs`), kept for comparison.
    CwBvh,
    /// SAH kd-tree (`accel/kdtree/`).
    KdTree,
    /// Uniform grid with the given resolution (`accel/grid/`).
    Grid(GridResolution),
    /// Test every primitive: the ground truth.
    Brute,
}

/// Cells of a uniform grid along x, y and z, or chosen from the primitive count and the scene bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum GridResolution {
    /// From the primitive count and the bounds (`lambda * cbrt(N)` cells along the longest axis), with nested grids
    /// in crowded cells.
    #[default]
    Auto,
    /// Exactly these cells along x, y and z, no nested grids.
    Fixed([u32; 3]),
}

impl AccelKind {
    /// `bvh`, `cwbvh`, `kdtree`, `grid` (automatic resolution) or `brute`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "bvh" => Some(Self::Bvh),
            "cwbvh" => Some(Self::CwBvh),
            "kdtree" => Some(Self::KdTree),
            "grid" => Some(Self::Grid(GridResolution::Auto)),
            "brute" => Some(Self::Brute),
            _ => None,
        }
    }

    /// The accelerator's `--accel` name (what [`AccelKind::parse`] reads back, the grid's resolution aside).
    pub fn name(&self) -> &'static str {
        match self {
            Self::Bvh => "bvh",
            Self::CwBvh => "cwbvh",
            Self::KdTree => "kdtree",
            Self::Grid(_) => "grid",
            Self::Brute => "brute",
        }
    }

    /// Every accelerator (the grid with automatic resolution).
    pub const ALL: [AccelKind; 5] =
        [AccelKind::Bvh, AccelKind::CwBvh, AccelKind::KdTree, AccelKind::Grid(GridResolution::Auto), AccelKind::Brute];

    /// The names `parse` accepts, for messages.
    pub const NAMES: &'static str = "bvh, cwbvh, kdtree, grid or brute";
}

/// The resolved settings of one render.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Total samples per pixel (`None` = unlimited, only with a time budget).
    pub spp: Option<u32>,
    /// Number of progressive passes `spp` is split into (the pass limit when `spp` is `None`).
    pub passes: u32,
    /// Samples per pixel of the first pass when it is set apart from the rest (the adaptive pilot of a render
    /// whose passes were not given: see [`default_pass_layout`]); the other passes split the remaining samples
    /// evenly. `None`: all passes split `spp` evenly.
    pub pilot_spp: Option<u32>,
    /// Samples per pixel of each pass when `spp` is `None` (time-budget renders).
    pub pass_spp: u32,
    /// Which sampler fills every dimension of a sample.
    pub sampler: SamplerKind,
    /// Pixel positions from an explicit pattern instead of the sampler (`None`: the sampler's own: Sobol points
    /// for `sobol`, jittered strata for `stratified`, uniform random for `independent`).
    pub pattern: Option<PixelPattern>,
    /// Pixel reconstruction filter (by filter importance sampling).
    pub filter: PixelFilter,
    /// After a uniform first pass, give each pixel samples by its estimated noise (in proportion to its square
    /// root; per-pixel integrators; see `integrator::adaptive`).
    pub adaptive: bool,
    /// Seed of every random number of the render (the same seed and settings give the same image).
    pub seed: u64,
    /// Stop when this many seconds of rendering are spent (the pass then running is cut short).
    pub time_budget: Option<f64>,
    /// Stop after the first pass at which the image's estimated relative error (relMSE, estimated from the film:
    /// `film::noise`) is at most this (`--noise`, RON `render: (noise: Some(..))`).
    pub noise: Option<f32>,
    /// The rendering method and its parameters.
    pub integrator: PluginConfig,
    /// The accelerator built over the bounded primitives.
    pub accel: AccelKind,
    /// PNG exposure in stops.
    pub exposure: f32,
    /// This process renders shard `k` of `n` (`(0, 1)`: the whole render).
    pub shard: (u32, u32),
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 256,
            height: 256,
            spp: Some(16),
            passes: 16,
            pilot_spp: None,
            pass_spp: 1,
            sampler: SamplerKind::default(),
            pattern: None,
            filter: PixelFilter::default(),
            adaptive: false,
            seed: 0,
            time_budget: None,
            noise: None,
            integrator: PluginConfig::named("phong"),
            accel: AccelKind::Bvh,
            exposure: 0.0,
            shard: (0, 1),
        }
    }
}

impl RenderSettings {
    /// A fingerprint of every setting that changes the image (not the time budget or the PNG exposure), mixed
    /// with `scene`, a hash of the scene file: films of different scenes or settings do not resume or merge.
    pub fn fingerprint(&self, scene: u64) -> u64 {
        let key = format!(
            "{}x{} spp {:?} passes {} pass_spp {} sampler {:?} pattern {:?} filter {:?}{} seed {} integrator {} {:?} accel {:?}",
            self.width,
            self.height,
            self.spp,
            self.passes,
            self.pass_spp,
            self.sampler,
            self.pattern,
            self.filter,
            match (self.adaptive, self.pilot_spp) {
                (false, _) => String::new(),
                (true, None) => " adaptive".into(),
                (true, Some(p)) => format!(" adaptive pilot {p}"),
            },
            self.seed,
            self.integrator.name,
            self.integrator.params,
            self.accel
        );
        let mut h = scene ^ 0x9E37_79B9_7F4A_7C15;
        for b in key.bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        h
    }

    /// The pattern pixel positions follow: the explicit one, else the sampler's (`None` for Sobol points).
    pub fn pixel_pattern(&self) -> Option<PixelPattern> {
        match (self.pattern, self.sampler) {
            (Some(p), _) => Some(p),
            (None, SamplerKind::Stratified) => Some(PixelPattern::Stratified),
            (None, SamplerKind::Independent) => Some(PixelPattern::Random),
            (None, SamplerKind::Sobol) => None,
        }
    }

    /// A one-word description of how pixel positions are chosen (for summaries).
    pub fn pattern_name(&self) -> &'static str {
        self.pixel_pattern().map_or("sobol", |p| p.name())
    }

    /// Samples per pixel of pass `pass` (0-based): the total split as evenly as possible (after the first pass's
    /// [`pilot_spp`](Self::pilot_spp) when it is set apart); without a sample limit every pass takes `pass_spp`.
    pub fn samples_in_pass(&self, pass: u32) -> u32 {
        match self.spp {
            Some(_) => (self.samples_before_pass(pass + 1) - self.samples_before_pass(pass)) as u32,
            None => self.pass_spp,
        }
    }

    /// Samples per pixel rendered before pass `pass` (the index of its first sample).
    pub fn samples_before_pass(&self, pass: u32) -> u64 {
        let pass = pass as u64;
        match (self.spp, self.pilot_spp) {
            (Some(spp), Some(pilot)) if self.passes > 1 => match pass {
                0 => 0,
                k => pilot as u64 + ((k - 1) * (spp - pilot) as u64) / (self.passes - 1) as u64,
            },
            (Some(spp), _) => (pass * spp as u64) / self.passes as u64,
            (None, _) => pass * self.pass_spp as u64,
        }
    }

    /// Check the settings against each other and against Prism's limits: image size, sample and pass counts, the
    /// pilot, the time budget, the filter, the exposure and the shard. Errors say which value is wrong.
    pub fn validate(&self) -> Result<()> {
        self.check().map_err(|(_, message)| PrismError::invalid(message))
    }

    /// [`RenderSettings::validate`], naming the setting at fault beside the message: `size`, `spp`, `passes`,
    /// `time`, `filter`, `exposure` or `shard` (so a loader can point at the line of its scene that gave it).
    pub fn check(&self) -> std::result::Result<(), (&'static str, String)> {
        if self.width == 0 || self.height == 0 {
            return Err(("size", format!("image size {}x{} is empty", self.width, self.height)));
        }
        if self.width > MAX_IMAGE_SIDE
            || self.height > MAX_IMAGE_SIDE
            || self.width as u64 * self.height as u64 > MAX_IMAGE_PIXELS
        {
            return Err((
                "size",
                format!(
                    "image size {}x{} is too large (at most {MAX_IMAGE_SIDE} per side and {MAX_IMAGE_PIXELS} pixels)",
                    self.width, self.height
                ),
            ));
        }
        if self.spp == Some(0) {
            return Err(("spp", "spp must be at least 1".into()));
        }
        if self.passes == 0 {
            return Err(("passes", "passes must be at least 1".into()));
        }
        if let Some(spp) = self.spp
            && self.passes > spp
        {
            return Err(("passes", format!("{} passes cannot split {spp} samples per pixel", self.passes)));
        }
        if let Some(pilot) = self.pilot_spp {
            let fits = self.spp.is_some_and(|spp| {
                self.passes > 1 && pilot >= 1 && pilot as u64 + (self.passes - 1) as u64 <= spp as u64
            });
            if !fits {
                return Err((
                    "passes",
                    format!(
                        "a first pass of {pilot} samples per pixel and {} more passes cannot split {:?} samples per \
                         pixel",
                        self.passes.saturating_sub(1),
                        self.spp
                    ),
                ));
            }
        }
        if let Some(t) = self.time_budget
            && !(t.is_finite() && t > 0.0 && t <= crate::limits::MAX_SECONDS)
        {
            return Err((
                "time",
                format!(
                    "time budget must be a positive number of seconds (at most {}), got {t}",
                    crate::limits::MAX_SECONDS
                ),
            ));
        }
        if let Some(n) = self.noise
            && !(n.is_finite() && n > 0.0)
        {
            return Err(("noise", format!("noise target must be a positive relative error (relMSE), got {n}")));
        }
        self.filter.validate().map_err(|m| ("filter", m))?;
        if !(self.exposure.is_finite() && self.exposure.abs() <= MAX_EXPOSURE) {
            return Err((
                "exposure",
                format!("exposure must be between -{MAX_EXPOSURE} and {MAX_EXPOSURE} stops, got {}", self.exposure),
            ));
        }
        let (k, n) = self.shard;
        if n == 0 || k >= n {
            return Err(("shard", format!("--shard {k}/{n}: K must be below N")));
        }
        if n > 1 && self.spp.is_none() {
            return Err((
                "shard",
                "--shard needs a sample count (--spp), not only a time budget or a noise target".into(),
            ));
        }
        if let Some(spp) = self.spp
            && n > self.passes.min(spp)
            && n > self.height
        {
            return Err((
                "shard",
                format!("--shard {k}/{n}: more shards than passes ({}) and pixel rows ({})", self.passes, self.height),
            ));
        }
        Ok(())
    }
}

/// Fewest samples per pixel a default pass holds: two camera-ray packets per pixel (`accel::PACKET` is 16), and
/// few enough passes that their fixed cost per pixel (the sampler's scramble keys, the film) stays small.
pub const MIN_PASS_SPP: u32 = 32;
/// Most passes a render is split into by default (progress, checkpoints and time budgets work in passes).
pub const MAX_DEFAULT_PASSES: u32 = 16;

/// The pass layout of `spp` samples per pixel when neither the command line nor the scene gives `passes`:
/// `(passes, pilot_spp)`.
///
/// Passes of at least [`MIN_PASS_SPP`] samples, at most [`MAX_DEFAULT_PASSES`] of them. An adaptive render's first
/// pass is its pilot, which keeps `spp / 16` samples (at least 1: how much of the budget the pilot spends was chosen
/// by measuring the error; see `integrator::adaptive`); the samples after it are split into passes as above. A
/// render in `shards` shards by passes gets at least as many passes as shards (where the samples allow), so
/// every shard has work. Each pass costs every pixel a fixed set-up: 16 passes of 1 sample made a 16-spp Cornell
/// box render 15% slower than one pass, 16 passes of 4 samples a 64-spp one 4-5% slower than 4 passes; at 48 spp
/// each pass beyond the first costs about 0.85%, so passes hold at least 32 samples (an adaptive 64-spp render in 2
/// passes instead of 4: 2% faster; see `docs/decisions/0015-passes-of-32-samples.md`). Time budgets without a
/// sample count keep their small passes (`RenderSettings::pass_spp`).
pub fn default_pass_layout(spp: u32, adaptive: bool, shards: u32) -> (u32, Option<u32>) {
    let spp = spp.max(1);
    // `n` samples in passes of at least MIN_PASS_SPP, at most `most` of them, but `want` passes where `n` allows.
    let split = |n: u32, most: u32, want: u32| (n / MIN_PASS_SPP).clamp(1, most).max(want.min(n));
    let pilot = (spp / 16).max(1);
    if !adaptive || pilot >= spp {
        return (split(spp, MAX_DEFAULT_PASSES, shards), None);
    }
    (1 + split(spp - pilot, MAX_DEFAULT_PASSES - 1, shards.saturating_sub(1)), Some(pilot))
}

/// The parts of the scene camera's view the command line replaces (`None` = keep the camera's), in world space.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ViewOverride {
    /// The eye (`--look-from X,Y,Z`).
    pub from: Option<glam::Vec3>,
    /// The point looked at (`--look-at X,Y,Z`).
    pub at: Option<glam::Vec3>,
    /// The up hint (`--up X,Y,Z`).
    pub up: Option<glam::Vec3>,
    /// The vertical field of view in degrees of a perspective camera (`--fov DEG`).
    pub fov: Option<f32>,
}

impl ViewOverride {
    /// Whether any part of the view is replaced.
    pub fn is_set(&self) -> bool {
        self.from.is_some() || self.at.is_some() || self.up.is_some() || self.fov.is_some()
    }
}

/// The environment the command line lights a scene with, replacing every environment light of the scene.
#[derive(Clone, Debug, PartialEq)]
pub enum EnvOverride {
    /// An environment map (`--env FILE`, any layout the RON `Environment` light reads), times `scale`
    /// (`--env-scale`), turned by `rotate_deg` degrees about +y (`--env-rotate`).
    Map {
        /// The image file.
        path: std::path::PathBuf,
        /// Radiance scale.
        scale: f32,
        /// Rotation about the world's +y axis, degrees.
        rotate_deg: f32,
        /// The map's layout (`--env-layout`) by its RON name (`Equirect`, `Cross`, `EqualArea`); `None` guesses
        /// it from the image's shape.
        layout: Option<String>,
    },
    /// A uniform environment of this radiance (`--sky R,G,B`).
    Sky(glam::Vec3),
}

/// Command-line overrides of the scene's settings (`None` = keep the scene's).
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    /// Image `(width, height)` in pixels (`--size`).
    pub size: Option<(u32, u32)>,
    /// Total samples per pixel (`--spp`).
    pub spp: Option<u32>,
    /// Number of progressive passes (`--passes`).
    pub passes: Option<u32>,
    /// The sampler (`--sampler`).
    pub sampler: Option<SamplerKind>,
    /// An explicit pixel sample pattern (`--pattern`).
    pub pattern: Option<PixelPattern>,
    /// The pixel filter (`--filter`).
    pub filter: Option<PixelFilter>,
    /// Adaptive sampling on or off (`--adaptive`).
    pub adaptive: Option<bool>,
    /// The render's seed (`--seed`).
    pub seed: Option<u64>,
    /// Stop when this many seconds of rendering are spent (the pass then running is cut short).(`--time`).
    pub time_budget: Option<f64>,
    /// No sample limit unless `spp` is given (set with a time budget or a noise target on the command line).
    pub spp_unlimited: bool,
    /// The noise target (`--noise`): stop when the estimated relMSE is at most this.
    pub noise: Option<f32>,
    /// The integrator spec, `name` or `name(params)` (`--integrator`), parsed by [`PluginConfig::from_spec`].
    pub integrator: Option<String>,
    /// The accelerator (`--accel`, with `--grid` for a fixed grid resolution).
    pub accel: Option<AccelKind>,
    /// PNG exposure in stops (`--exposure`).
    pub exposure: Option<f32>,
    /// Render shard `(k, n)` only (`--shard K/N`).
    pub shard: Option<(u32, u32)>,
    /// The camera to render from, by name or by index in node order, in files that hold several (glTF).
    pub camera: Option<String>,
    /// The view replacing the scene camera's (`--look-from`, `--look-at`, `--up`, `--fov`); world space.
    pub view: ViewOverride,
    /// The environment replacing the scene's (`--env`, `--sky`).
    pub environment: Option<EnvOverride>,
    /// Add no default light to a scene without one (`--no-default-light`): a bare mesh's headlight, a glTF's sky.
    pub no_default_light: bool,
    /// Render curved surfaces exactly where the scene asks for a tessellation (RON `tessellation`, the meshes
    /// 6.837 assignment 8 scenes name).
    pub exact_curves: bool,
}
