//! The suite file of `prism report` (RON, every struct rejects unknown fields, paths relative to the suite file):
//! which scenes to measure against which references with which methods and budgets, which accelerators to
//! benchmark, and which failure modes to picture. `docs/guide/report.md` documents every field; the
//! default suite is `scenes/report/default.ron`.
//!
//! ```ron
//! (
//!     title: "...", intro: "...", threads: Some(2),
//!     scenes: [(name: "cornell", scene: "../cornell_box.ron", reference: File("../../../shared/refs/cornell.exr"),
//!               methods: [(integrator: "envlight(max_depth: 8)", sampler: independent)],
//!               budgets: Times([0.5, 1, 2]), compare_at: Some(1), peers: [], crop: None)],
//!     accelerators: Some((scenes: ["..."], accels: ["bvh", "kdtree"], heat: Some((scene: "..."))),
//!     stability: [Renders((...)), Traversal((...)), ShadowAcne((...))],
//! )
//! ```

use prism_core::error::{PrismError, Result, SourcePos};
use prism_core::sampling::SamplerKind;
use prism_debug::HeatCount;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// A whole suite.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct Suite {
    #[serde(default = "default_title")]
    pub title: String,
    /// A paragraph under the title.
    #[serde(default)]
    pub intro: String,
    /// Render threads (default: every core); `--threads` overrides it.
    #[serde(default)]
    pub threads: Option<usize>,
    #[serde(default)]
    pub scenes: Vec<SceneCase>,
    #[serde(default)]
    pub accelerators: Option<AccelCase>,
    #[serde(default)]
    pub stability: Vec<StabilityCase>,
}

fn default_title() -> String {
    "Prism report".into()
}

/// How a reference image is obtained.
#[derive(Deserialize, Debug, Clone)]
pub enum Reference {
    /// An image file (`.exr`, or `.png`): its size must be the render's or an integer multiple of it (then it is
    /// box-filtered down, which is what a box-filtered render of the smaller size converges to). A `NAME.json`
    /// beside it with `noise_rmse_estimate` gives the reference's own noise, drawn on the charts.
    File(PathBuf),
    /// Rendered by the report before the measurements: `integrator` with `spp` samples per pixel.
    Render(ReferenceRender),
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct ReferenceRender {
    pub integrator: String,
    pub spp: u32,
    #[serde(default)]
    pub sampler: Option<SamplerKind>,
    /// Seed of the reference (default: 1000003, far from the measured renders' seed 0).
    #[serde(default)]
    pub seed: Option<u64>,
    /// The scene rendered as the reference (default: the case's), e.g. an analytic shape that a variant's
    /// surface approximates.
    #[serde(default)]
    pub scene: Option<PathBuf>,
}

/// One curve of a convergence chart: an integrator spec and optionally a sampler, an accelerator and adaptive
/// sampling.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct Method {
    /// The name in the charts and tables (default: the integrator spec and the sampler).
    #[serde(default)]
    pub label: Option<String>,
    pub integrator: String,
    #[serde(default)]
    pub sampler: Option<SamplerKind>,
    #[serde(default)]
    pub accel: Option<String>,
    /// Adaptive sampling on or off (default: the scene's setting).
    #[serde(default)]
    pub adaptive: Option<bool>,
}

impl Method {
    pub fn label(&self) -> String {
        self.label.clone().unwrap_or_else(|| {
            let mut l = match self.sampler {
                Some(s) => format!("{} {}", self.integrator, s.name()),
                None => self.integrator.clone(),
            };
            if self.adaptive == Some(true) {
                l += " adaptive";
            }
            l
        })
    }
}

/// The budgets of one curve's renders: seconds of render passes, or samples per pixel.
#[derive(Deserialize, Debug, Clone)]
pub enum Budgets {
    Times(Vec<f64>),
    Spp(Vec<u32>),
}

/// A peer renderer's curve from a CSV with `scene,spp,seconds,rmse,variant` columns (`converge::read_peer`).
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct Peer {
    pub file: PathBuf,
    pub scene: String,
    #[serde(default = "default_variant")]
    pub variant: String,
    #[serde(default)]
    pub sampler: Option<String>,
    #[serde(default)]
    pub label: Option<String>,
}

fn default_variant() -> String {
    "llvm_ad_rgb".into()
}

/// A scene measured against a reference: error against time per method, images at one budget side by side with
/// their error maps, the hardest region enlarged, the equal-error time ratios.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct SceneCase {
    /// Identifier (file names, anchors): letters, digits, `_` and `-`.
    pub name: String,
    #[serde(default)]
    pub title: Option<String>,
    #[serde(default)]
    pub caption: String,
    pub scene: PathBuf,
    pub reference: Reference,
    /// Render size (default: the scene's).
    #[serde(default)]
    pub size: Option<(u32, u32)>,
    pub methods: Vec<Method>,
    pub budgets: Budgets,
    /// The budget whose images are shown side by side (default: the largest); added to the budgets if missing.
    #[serde(default)]
    pub compare_at: Option<f64>,
    #[serde(default)]
    pub peers: Vec<Peer>,
    /// The enlarged region `(x, y, w, h)` (default: the quarter-size window where the shown images' squared
    /// error is largest).
    #[serde(default)]
    pub crop: Option<(u32, u32, u32, u32)>,
}

/// The accelerator benchmark: `prism bench` over several scenes, and heat maps of one view.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct AccelCase {
    #[serde(default)]
    pub caption: String,
    pub scenes: Vec<PathBuf>,
    /// `bvh`, `cwbvh`, `kdtree`, `grid`, `grid:NXxNYxNZ`, `brute`.
    #[serde(default = "default_accels")]
    pub accels: Vec<String>,
    /// Camera rays: one per pixel of a `rays x rays` image.
    #[serde(default = "default_rays")]
    pub rays: u32,
    /// Minimum measuring time per number (`prism bench --seconds`).
    #[serde(default = "default_seconds")]
    pub seconds: f64,
    #[serde(default = "default_brute_limit")]
    pub brute_limit: u32,
    /// Traversal threads (default 1, as `prism bench`).
    #[serde(default = "one")]
    pub threads: usize,
    #[serde(default)]
    pub heat: Option<HeatView>,
}

fn default_accels() -> Vec<String> {
    ["bvh", "kdtree", "grid", "brute"].map(String::from).to_vec()
}
fn default_rays() -> u32 {
    256
}
fn default_seconds() -> f64 {
    0.5
}
fn default_brute_limit() -> u32 {
    20_000
}
fn one() -> usize {
    1
}

/// The heat maps (`debug(mode: heat)`) of several accelerators on one view, on one colour scale.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct HeatView {
    pub scene: PathBuf,
    /// Default: the section's accelerators without brute force (flat: it tests everything everywhere).
    #[serde(default)]
    pub accels: Option<Vec<String>>,
    #[serde(default = "default_heat_size")]
    pub size: u32,
    #[serde(default = "default_heat_count")]
    pub count: HeatCount,
    /// The count shown white (default: the largest of the maps' 99th percentiles).
    #[serde(default)]
    pub max: Option<f32>,
}

fn default_heat_size() -> u32 {
    192
}
fn default_heat_count() -> HeatCount {
    HeatCount::Total
}

/// One failure mode of the stability atlas.
#[derive(Deserialize, Debug, Clone)]
pub enum StabilityCase {
    /// Renders of a scene under several variants (parameters, scenes, expected errors), measured.
    Renders(RendersCase),
    /// Accelerators on one view: heat maps, work per ray, build time, camera Mrays/s.
    Traversal(TraversalCase),
    /// Shadow rays from lit surfaces with several ray-origin offsets, at several scene scales.
    ShadowAcne(AcneCase),
}

impl StabilityCase {
    pub fn name(&self) -> &str {
        match self {
            StabilityCase::Renders(c) => &c.name,
            StabilityCase::Traversal(c) => &c.name,
            StabilityCase::ShadowAcne(c) => &c.name,
        }
    }
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct RendersCase {
    pub name: String,
    pub title: String,
    #[serde(default)]
    pub caption: String,
    /// The scene of every variant that names none.
    #[serde(default)]
    pub scene: Option<PathBuf>,
    #[serde(default)]
    pub reference: Option<Reference>,
    #[serde(default)]
    pub size: Option<(u32, u32)>,
    /// Mean radiance over this pixel rectangle `(x, y, w, h)`, measured for every variant.
    #[serde(default)]
    pub region: Option<(u32, u32, u32, u32)>,
    /// What the region is (for the table), e.g. "dark side of the wall".
    #[serde(default)]
    pub region_label: Option<String>,
    pub variants: Vec<Variant>,
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct Variant {
    pub label: String,
    #[serde(default)]
    pub scene: Option<PathBuf>,
    #[serde(default)]
    pub integrator: Option<String>,
    #[serde(default)]
    pub spp: Option<u32>,
    /// Seconds of render passes instead of `spp`.
    #[serde(default)]
    pub time: Option<f64>,
    #[serde(default)]
    pub sampler: Option<SamplerKind>,
    #[serde(default)]
    pub accel: Option<String>,
    /// The variant is expected to be rejected (its one-line error is the measured effect).
    #[serde(default)]
    pub expect_error: bool,
    /// A line under the picture.
    #[serde(default)]
    pub note: String,
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct TraversalCase {
    pub name: String,
    pub title: String,
    #[serde(default)]
    pub caption: String,
    pub scene: PathBuf,
    /// As the accelerator section's, plus `grid:flat` (the automatic resolution without nested grids).
    pub accels: Vec<String>,
    #[serde(default = "default_traversal_size")]
    pub size: u32,
    #[serde(default = "default_traversal_count")]
    pub count: HeatCount,
    /// Minimum measuring time of the camera-ray throughput.
    #[serde(default = "default_traversal_seconds")]
    pub seconds: f64,
}

fn default_traversal_size() -> u32 {
    128
}
fn default_traversal_count() -> HeatCount {
    HeatCount::Prims
}
fn default_traversal_seconds() -> f64 {
    0.2
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct AcneCase {
    pub name: String,
    pub title: String,
    #[serde(default)]
    pub caption: String,
    /// `(label, scene)`: scenes with a point light as their first light.
    pub scenes: Vec<(String, PathBuf)>,
    pub offsets: Vec<Offset>,
    #[serde(default = "default_traversal_size")]
    pub size: u32,
}

/// How a shadow ray leaves its surface.
#[derive(Deserialize, Debug, Clone, Copy, PartialEq)]
pub enum Offset {
    /// From the hit point itself.
    None,
    /// Pushed this far along the normal (world units), the usual fixed epsilon.
    Fixed(f32),
    /// Prism's: just past the hit point's conservative floating-point error bound (`geometry::spawn_ray_to`).
    ErrorBounded,
}

impl Offset {
    pub fn label(&self) -> String {
        match self {
            Offset::None => "no offset".into(),
            Offset::Fixed(e) => format!("fixed epsilon {e:e}"),
            Offset::ErrorBounded => "error-bounded offset".into(),
        }
    }
}

/// Read and check a suite; every path is made relative to the suite file's directory.
pub fn load(path: &Path) -> Result<Suite> {
    let text = prism_core::io::read_regular_text(path, "report suite")?;
    let opts = ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let mut suite: Suite = opts.from_str(&text).map_err(|e| PrismError::Parse {
        pos: SourcePos { file: path.to_path_buf(), line: e.span.start.line, col: e.span.start.col },
        message: prism_load::describe_ron_error(&e.code),
    })?;
    let base = path.parent().unwrap_or(Path::new("."));
    resolve_paths(&mut suite, base);
    check(&suite).map_err(|m| PrismError::invalid(format!("{}: {m}", path.display())))?;
    Ok(suite)
}

/// `a/b/../c` as `a/c`, lexically (as people write paths; nothing is resolved on disk).
fn lexical(p: &Path) -> PathBuf {
    use std::path::Component;
    let mut out: Vec<Component> = vec![];
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir if matches!(out.last(), Some(Component::Normal(_))) => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    if out.is_empty() { PathBuf::from(".") } else { out.iter().collect() }
}

fn resolve_paths(s: &mut Suite, base: &Path) {
    let fix = |p: &mut PathBuf| {
        if p.is_relative() {
            *p = lexical(&base.join(&*p));
        }
    };
    let fix_ref = |r: &mut Reference| {
        let p = match r {
            Reference::File(p) => p,
            Reference::Render(ReferenceRender { scene: Some(p), .. }) => p,
            Reference::Render(_) => return,
        };
        if p.is_relative() {
            *p = lexical(&base.join(&*p));
        }
    };
    for c in &mut s.scenes {
        fix(&mut c.scene);
        fix_ref(&mut c.reference);
        c.peers.iter_mut().for_each(|p| fix(&mut p.file));
    }
    if let Some(a) = &mut s.accelerators {
        a.scenes.iter_mut().for_each(fix);
        if let Some(h) = &mut a.heat {
            fix(&mut h.scene);
        }
    }
    for c in &mut s.stability {
        match c {
            StabilityCase::Renders(r) => {
                r.scene.iter_mut().for_each(fix);
                r.reference.iter_mut().for_each(fix_ref);
                r.variants.iter_mut().for_each(|v| v.scene.iter_mut().for_each(fix));
            }
            StabilityCase::Traversal(t) => fix(&mut t.scene),
            StabilityCase::ShadowAcne(a) => a.scenes.iter_mut().for_each(|(_, p)| fix(p)),
        }
    }
}

/// The checks that make a suite meaningful before anything runs (one message naming the item).
fn check(s: &Suite) -> std::result::Result<(), String> {
    let ident = |kind: &str, n: &str| {
        if n.is_empty() || !n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
            Err(format!("{kind} name `{n}` must be letters, digits, `_` or `-`"))
        } else {
            Ok(())
        }
    };
    let mut names: Vec<String> = vec![];
    let mut unique = |name: &str| -> std::result::Result<(), String> {
        if names.iter().any(|m| m == name) {
            return Err(format!("the name `{name}` is used twice"));
        }
        names.push(name.to_string());
        Ok(())
    };
    if s.threads == Some(0) {
        return Err("threads must be at least 1".into());
    }
    for c in &s.scenes {
        ident("scene", &c.name)?;
        unique(&c.name)?;
        if c.methods.is_empty() {
            return Err(format!("scene `{}`: no methods", c.name));
        }
        let ok = match &c.budgets {
            Budgets::Times(t) => !t.is_empty() && t.iter().all(|t| t.is_finite() && *t > 0.0 && *t <= 3600.0),
            Budgets::Spp(n) => !n.is_empty() && n.iter().all(|n| (1..=1 << 20).contains(n)),
        };
        if !ok {
            return Err(format!(
                "scene `{}`: budgets must be a non-empty list of positive seconds (at most 3600) or sample counts",
                c.name
            ));
        }
        if let Some((_, _, w, h)) = c.crop
            && (w == 0 || h == 0)
        {
            return Err(format!("scene `{}`: the crop is empty", c.name));
        }
    }
    if let Some(a) = &s.accelerators {
        if a.threads == 0 || a.rays == 0 || a.rays > 4096 {
            return Err("accelerators: threads must be at least 1 and rays between 1 and 4096".into());
        }
        if !(a.seconds.is_finite() && a.seconds > 0.0 && a.seconds <= 60.0) {
            return Err("accelerators: seconds must be in (0, 60]".into());
        }
        if let Some(h) = &a.heat
            && (h.size == 0 || h.size > 4096)
        {
            return Err("accelerators: heat size must be between 1 and 4096".into());
        }
    }
    for c in &s.stability {
        ident("stability case", c.name())?;
        unique(c.name())?;
        match c {
            StabilityCase::Renders(r) => {
                if r.variants.is_empty() {
                    return Err(format!("stability case `{}`: no variants", r.name));
                }
                for v in &r.variants {
                    if v.scene.is_none() && r.scene.is_none() {
                        return Err(format!("stability case `{}`: variant `{}` has no scene", r.name, v.label));
                    }
                    if v.time.is_some_and(|t| !(t.is_finite() && t > 0.0 && t <= 3600.0)) || v.spp == Some(0) {
                        return Err(format!("stability case `{}`: variant `{}`: bad budget", r.name, v.label));
                    }
                }
            }
            StabilityCase::Traversal(t) => {
                if t.accels.is_empty() || t.size == 0 || t.size > 4096 {
                    return Err(format!("stability case `{}`: accels must be given, size 1 to 4096", t.name));
                }
            }
            StabilityCase::ShadowAcne(a) => {
                if a.scenes.is_empty() || a.offsets.is_empty() || a.size == 0 || a.size > 4096 {
                    return Err(format!(
                        "stability case `{}`: scenes and offsets must be given, size 1 to 4096",
                        a.name
                    ));
                }
            }
        }
    }
    Ok(())
}
