//! Render settings: what the scene file's `render: (...)` block and the command line decide together (the
//! command line wins), resolved once in the Load stage and read by every later stage.

use crate::error::{PrismError, Result, SourcePos};
use crate::sampling::PixelPattern;
use serde::de::DeserializeOwned;

/// Largest accepted image side, and largest pixel count (a 16k x 16k film already needs 6 GiB of sums).
pub const MAX_IMAGE_SIDE: u32 = 16384;
pub const MAX_IMAGE_PIXELS: u64 = 1 << 28;

/// A plugin chosen by name, with its parameter text as written in the scene (`phong(max_depth: 3)`), parsed by
/// the plugin itself so that it owns its parameter struct.
#[derive(Clone, Debug, PartialEq)]
pub struct PluginConfig {
    pub name: String,
    /// The parenthesised parameter list, e.g. `(max_depth: 3)`, if one was given.
    pub params: Option<String>,
    /// Where `params` starts in the scene file (for error positions).
    pub origin: Option<SourcePos>,
}

impl PluginConfig {
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
        opts.from_str::<T>(text).map_err(|e| {
            let message = format!("integrator '{}': {}", self.name, e.code);
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

/// Which accelerator to build over the scene's bounded primitives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum AccelKind {
    /// Compressed 8-wide BVH via obvhs (the default).
    #[default]
    Bvh,
    /// SAH kd-tree (`src/accel/kdtree.rs`).
    KdTree,
    /// Uniform grid with the given resolution (`src/accel/grid.rs`).
    Grid(GridResolution),
    /// Test every primitive: the ground truth.
    Brute,
}

/// Cells of a uniform grid along x, y and z, or chosen from the primitive count and the scene bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum GridResolution {
    #[default]
    Auto,
    Fixed([u32; 3]),
}

impl AccelKind {
    /// `bvh`, `kdtree`, `grid` (automatic resolution) or `brute`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "bvh" => Some(Self::Bvh),
            "kdtree" => Some(Self::KdTree),
            "grid" => Some(Self::Grid(GridResolution::Auto)),
            "brute" => Some(Self::Brute),
            _ => None,
        }
    }

    pub fn name(&self) -> &'static str {
        match self {
            Self::Bvh => "bvh",
            Self::KdTree => "kdtree",
            Self::Grid(_) => "grid",
            Self::Brute => "brute",
        }
    }

    /// Every accelerator (the grid with automatic resolution).
    pub const ALL: [AccelKind; 4] =
        [AccelKind::Bvh, AccelKind::KdTree, AccelKind::Grid(GridResolution::Auto), AccelKind::Brute];

    /// The names `parse` accepts, for messages.
    pub const NAMES: &'static str = "bvh, kdtree, grid or brute";
}

/// The resolved settings of one render.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Total samples per pixel (`None` = unlimited, only with a time budget).
    pub spp: Option<u32>,
    /// Number of progressive passes `spp` is split into (the pass limit when `spp` is `None`).
    pub passes: u32,
    /// Samples per pixel of each pass when `spp` is `None` (time-budget renders).
    pub pass_spp: u32,
    pub pattern: PixelPattern,
    pub seed: u64,
    /// Stop after the pass that crosses this many seconds.
    pub time_budget: Option<f64>,
    pub integrator: PluginConfig,
    pub accel: AccelKind,
    /// PNG exposure in stops.
    pub exposure: f32,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 256,
            height: 256,
            spp: Some(16),
            passes: 16,
            pass_spp: 1,
            pattern: PixelPattern::Stratified,
            seed: 0,
            time_budget: None,
            integrator: PluginConfig::named("phong"),
            accel: AccelKind::Bvh,
            exposure: 0.0,
        }
    }
}

impl RenderSettings {
    /// Samples per pixel of pass `pass` (0-based): the total split as evenly as possible; without a sample limit
    /// every pass takes `pass_spp`.
    pub fn samples_in_pass(&self, pass: u32) -> u32 {
        match self.spp {
            Some(spp) => {
                let passes = self.passes as u64;
                let a = (pass as u64 * spp as u64) / passes;
                let b = ((pass as u64 + 1) * spp as u64) / passes;
                (b - a) as u32
            }
            None => self.pass_spp,
        }
    }

    /// Samples per pixel rendered before pass `pass` (the index of its first sample).
    pub fn samples_before_pass(&self, pass: u32) -> u64 {
        match self.spp {
            Some(spp) => (pass as u64 * spp as u64) / self.passes as u64,
            None => pass as u64 * self.pass_spp as u64,
        }
    }

    pub fn validate(&self) -> Result<()> {
        if self.width == 0 || self.height == 0 {
            return Err(PrismError::invalid(format!("image size {}x{} is empty", self.width, self.height)));
        }
        if self.width > MAX_IMAGE_SIDE
            || self.height > MAX_IMAGE_SIDE
            || self.width as u64 * self.height as u64 > MAX_IMAGE_PIXELS
        {
            return Err(PrismError::invalid(format!(
                "image size {}x{} is too large (at most {MAX_IMAGE_SIDE} per side and {MAX_IMAGE_PIXELS} pixels)",
                self.width, self.height
            )));
        }
        if self.spp == Some(0) {
            return Err(PrismError::invalid("spp must be at least 1"));
        }
        if self.passes == 0 {
            return Err(PrismError::invalid("passes must be at least 1"));
        }
        if let Some(spp) = self.spp
            && self.passes > spp
        {
            return Err(PrismError::invalid(format!("{} passes cannot split {spp} samples per pixel", self.passes)));
        }
        if let Some(t) = self.time_budget
            && !(t.is_finite() && t > 0.0)
        {
            return Err(PrismError::invalid(format!("time budget must be a positive number of seconds, got {t}")));
        }
        if !self.exposure.is_finite() {
            return Err(PrismError::invalid("exposure must be finite"));
        }
        Ok(())
    }
}

/// Command-line overrides of the scene's settings (`None` = keep the scene's).
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    pub size: Option<(u32, u32)>,
    pub spp: Option<u32>,
    pub passes: Option<u32>,
    pub pattern: Option<PixelPattern>,
    pub seed: Option<u64>,
    pub time_budget: Option<f64>,
    /// No sample limit unless `spp` is given (set with a time budget on the command line).
    pub spp_unlimited: bool,
    pub integrator: Option<String>,
    pub accel: Option<AccelKind>,
    pub exposure: Option<f32>,
    /// Render curved surfaces exactly where the scene asks for a tessellation (RON `tessellation`, the meshes
    /// 6.837 assignment 8 scenes name).
    pub exact_curves: bool,
}
