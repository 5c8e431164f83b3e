//! `prism report SUITE.ron -o DIR`: the speed-against-accuracy and stability atlas as one static page.
//!
//! A suite (`suite.rs`) names scenes with references, methods and budgets; accelerators to benchmark; and the
//! failure modes to picture. The report renders and measures all of it with the library functions of `converge`
//! (one render per budget, errors against the reference, equal-error times), `accel::bench` (build time, memory,
//! interleaved Mrays/s) and the `debug` plugin's traversal counts, and writes `DIR/index.html` (inline SVG
//! charts, PNG thumbnails and false-colour maps in `DIR/img/`, no script, no network) and one CSV per kind of
//! measurement. Every item that fails (a missing scene or reference, a reference of the wrong size, an integrator
//! that fails on a scene) is named in the page and in the returned problems, and everything else is still written.
//!
//! | file | what |
//! |---|---|
//! | `suite.rs` | the suite format |
//! | `convergence.rs` | per scene: curves, equal-time images, error maps, hardest region, equal-error table |
//! | `accelerators.rs`, `traversal.rs` | per accelerator: bench charts and table; heat maps and work per ray |
//! | `stability.rs`, `acne.rs` | the stability atlas |
//! | `images.rs`, `html.rs`, `machine.rs` | pictures, markup, machine load during the run |

mod accelerators;
mod acne;
mod convergence;
pub mod html;
pub mod images;
mod machine;
mod manifest;
mod stability;
pub mod suite;
mod traversal;

use crate::converge::{Budget, BudgetRender, render_budget};
use prism_core::error::{PrismError, Result};
use prism_core::primitives::Primitives;
use prism_core::sampling::SamplerKind;
use prism_core::settings::{AccelKind, GridResolution, Overrides};
use prism_engine::{App, Plugin, SceneSource, Stage};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Something the suite asked for that could not be measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// `scenes`, `accelerators` or `stability`.
    pub section: String,
    /// The scene, method, case or variant.
    pub item: String,
    pub message: String,
}

/// How the report runs.
#[derive(Clone, Debug, Default)]
pub struct ReportOptions {
    /// Render threads (overrides the suite's).
    pub threads: Option<usize>,
    /// A line added to the page's footnote (e.g. how the machine was shared).
    pub note: Option<String>,
    /// The command line that made the page, shown in the footer.
    pub command: String,
}

/// What was written.
#[derive(Clone, Debug)]
pub struct ReportOutcome {
    pub index: PathBuf,
    pub problems: Vec<Problem>,
    pub seconds: f64,
}

/// One CSV file of measurements.
struct Csv {
    file: &'static str,
    header: &'static str,
    rows: Vec<String>,
}

/// What every section shares: where pictures go, the problems and measurements so far, the thread pool.
pub(crate) struct Ctx<'p> {
    /// The plugins every render of the report is built with.
    pub(crate) plugins: &'p dyn Plugin,
    out: PathBuf,
    /// Every file the run names (relative to `out`): the manifest the next run removes them by.
    written: std::cell::RefCell<Vec<String>>,
    problems: Vec<Problem>,
    csvs: Vec<Csv>,
    pool: rayon::ThreadPool,
}

impl Ctx<'_> {
    /// Record a problem; returns the box that shows it where the item would have been.
    fn problem(&mut self, section: &str, item: &str, message: impl std::fmt::Display) -> String {
        let message = message.to_string();
        eprintln!("report: problem: {section} / {item}: {message}");
        let b = html::problem_box(item, &message);
        self.problems.push(Problem { section: section.into(), item: item.into(), message });
        b
    }

    /// The file for picture `name` (`img/NAME.png`) and its path relative to the page.
    fn picture(&self, name: &str) -> (PathBuf, String) {
        let rel = format!("img/{name}.png");
        self.written.borrow_mut().push(rel.clone());
        (self.out.join(&rel), rel)
    }

    /// Add a row (already CSV-formatted) to `file`, creating it with `header` on first use.
    fn csv(&mut self, file: &'static str, header: &'static str, row: String) {
        match self.csvs.iter_mut().find(|c| c.file == file) {
            Some(c) => c.rows.push(row),
            None => self.csvs.push(Csv { file, header, rows: vec![row] }),
        }
    }

    fn log(&self, msg: impl std::fmt::Display) {
        eprintln!("report: {msg}");
    }
}

/// A CSV field: quoted when it holds a comma, quote or newline.
fn field(s: &str) -> String {
    if s.contains([',', '"', '\n']) { format!("\"{}\"", s.replace('"', "\"\"")) } else { s.to_string() }
}

/// What one render of the report is.
#[derive(Clone, Debug)]
pub(crate) struct RenderJob<'a> {
    pub scene: &'a Path,
    pub integrator: Option<&'a str>,
    pub sampler: Option<SamplerKind>,
    pub accel: Option<AccelKind>,
    pub size: Option<(u32, u32)>,
    pub seed: Option<u64>,
    pub adaptive: Option<bool>,
}

impl Default for RenderJob<'_> {
    fn default() -> Self {
        RenderJob {
            scene: Path::new(""),
            integrator: None,
            sampler: None,
            accel: None,
            size: None,
            seed: None,
            adaptive: None,
        }
    }
}

impl RenderJob<'_> {
    fn app(&self, ctx: &Ctx) -> App {
        let mut app = App::with(ctx.plugins);
        app.resources.source = SceneSource::File(self.scene.to_path_buf());
        app.resources.overrides = Overrides {
            integrator: self.integrator.map(String::from),
            sampler: self.sampler,
            accel: self.accel,
            size: self.size,
            seed: self.seed,
            adaptive: self.adaptive,
            ..Default::default()
        };
        app
    }

    /// Render with `budget` on the report's threads.
    fn render(&self, ctx: &Ctx, budget: Budget) -> Result<BudgetRender> {
        if !self.scene.is_file() {
            return Err(PrismError::io(
                self.scene,
                std::io::Error::new(std::io::ErrorKind::NotFound, "scene file not found"),
            ));
        }
        let mut app = self.app(ctx);
        ctx.pool.install(|| render_budget(&mut app, budget))
    }

    /// The image size the scene resolves to (its Load stage only).
    fn size_of(&self, ctx: &Ctx) -> Result<(u32, u32)> {
        if !self.scene.is_file() {
            return Err(PrismError::io(
                self.scene,
                std::io::Error::new(std::io::ErrorKind::NotFound, "scene file not found"),
            ));
        }
        let mut app = self.app(ctx);
        app.run_stage(Stage::Load)?;
        Ok((app.resources.settings.width, app.resources.settings.height))
    }
}

/// An accelerator named in a suite: `bvh`, `cwbvh`, `kdtree`, `grid`, `grid:NXxNYxNZ`, `grid:flat` (the automatic
/// resolution without nested grids: needs the primitives), `brute`.
pub(crate) fn parse_accel(spec: &str, prims: Option<&Primitives>) -> Result<AccelKind> {
    let bad = || {
        PrismError::invalid(format!(
            "unknown accelerator `{spec}` (expected bvh, cwbvh, kdtree, grid, grid:NXxNYxNZ, grid:flat or brute)"
        ))
    };
    match spec.split_once(':') {
        None => AccelKind::parse(spec).ok_or_else(bad),
        Some(("grid", "flat")) => {
            let prims =
                prims.ok_or_else(|| PrismError::invalid("`grid:flat` is only known once the scene is loaded"))?;
            let res =
                prism_core::accel::grid::auto_resolution(prims.num_bounded() as usize, prims.bounds.diagonal(), 2.0);
            Ok(AccelKind::Grid(GridResolution::Fixed(res)))
        }
        Some(("grid", res)) => {
            let n: Vec<u32> = res.split('x').map(|v| v.parse().map_err(|_| bad())).collect::<Result<_>>()?;
            match n[..] {
                [x, y, z] if x > 0 && y > 0 && z > 0 => Ok(AccelKind::Grid(GridResolution::Fixed([x, y, z]))),
                _ => Err(bad()),
            }
        }
        _ => Err(bad()),
    }
}

/// Run the suite at `suite_path`, writing the page and its files into `out`. Errors only when nothing can be
/// written (unreadable or malformed suite, unwritable directory); every other failure is a [`Problem`].
/// Every render is built with `plugins` (the binary passes its `DefaultPlugins`).
pub fn run(suite_path: &Path, out: &Path, opts: &ReportOptions, plugins: &dyn Plugin) -> Result<ReportOutcome> {
    let suite = suite::load(suite_path)?;
    // Files of an earlier run would be stale (the page names every file it uses): remove what that run wrote, and
    // nothing else; a folder it did not write is refused.
    manifest::clear(out)?;
    let img_dir = out.join("img");
    std::fs::create_dir_all(&img_dir).map_err(|e| PrismError::io(&img_dir, e))?;
    let threads =
        opts.threads.or(suite.threads).unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    if !(1..=1024).contains(&threads) {
        return Err(PrismError::invalid(format!("threads must be between 1 and 1024, got {threads}")));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| PrismError::invalid(format!("cannot start {threads} threads: {e}")))?;
    let mut ctx =
        Ctx { plugins, out: out.to_path_buf(), written: Default::default(), problems: vec![], csvs: vec![], pool };
    let result = write_report(&mut ctx, &suite, opts, threads);
    // Whatever happened, the next run can remove every file this one wrote.
    manifest::write(out, &ctx.written.borrow())?;
    result
}

/// The sections, the CSVs and the page of `suite`.
fn write_report(ctx: &mut Ctx, suite: &suite::Suite, opts: &ReportOptions, threads: usize) -> Result<ReportOutcome> {
    let out = ctx.out.clone();
    let started = Instant::now();
    let load = machine::Usage::start();
    let mut body = String::new();
    let mut toc: Vec<(String, String)> = vec![];
    for case in &suite.scenes {
        let (anchor, title, section) = convergence::section(ctx, case);
        toc.push((anchor, title));
        body += &section;
    }
    if let Some(a) = &suite.accelerators {
        toc.push(("accelerators".into(), "Accelerators".into()));
        body += &accelerators::section(ctx, a);
    }
    if !suite.stability.is_empty() {
        toc.push(("stability".into(), "Stability atlas".into()));
        body += &stability::section(ctx, &suite.stability);
    }
    let seconds = started.elapsed().as_secs_f64();
    let usage = load.finish();
    for p in ctx.problems.clone() {
        ctx.csv(
            "problems.csv",
            "section,item,message",
            format!("{},{},{}", field(&p.section), field(&p.item), field(&p.message)),
        );
    }
    let mut csv_links = vec![];
    for c in &ctx.csvs {
        let path = out.join(c.file);
        ctx.written.borrow_mut().push(c.file.to_string());
        let mut text = format!("{}\n", c.header);
        for r in &c.rows {
            text += r;
            text.push('\n');
        }
        prism_core::io::write_atomic(&path, text.as_bytes())?;
        csv_links.push(format!(r#"<a href="{0}">{0}</a>"#, c.file));
    }
    let mut footer = String::new();
    let _ = write!(
        footer,
        "<p>Generated by <code>{}</code> in {:.0} s with {} render thread{}. Measurements: {}.</p>",
        html::esc(&opts.command),
        seconds,
        threads,
        if threads == 1 { "" } else { "s" },
        csv_links.join(", ")
    );
    let _ = write!(footer, "<p>{}</p>", html::esc(&usage.describe(threads)));
    if let Some(n) = &opts.note {
        let _ = write!(footer, "<p>{}</p>", html::esc(n));
    }
    let _ = write!(
        footer,
        "<p>Times are wall-clock seconds of the render passes (scene loading and accelerator builds excluded, as in \
         the peer's timings); errors are RMSE and relMSE <code>mean((a-r)^2/(r^2+0.01))</code> of linear radiance \
         against the reference. Prism {}.</p>",
        env!("CARGO_PKG_VERSION")
    );
    let page = html::Page {
        title: &suite.title,
        intro: &suite.intro,
        toc: &toc,
        problems: &ctx.problems,
        body: &body,
        footer: &footer,
    };
    let index = out.join("index.html");
    ctx.written.borrow_mut().push("index.html".into());
    prism_core::io::write_atomic(&index, page.render().as_bytes())?;
    Ok(ReportOutcome { index, problems: ctx.problems.clone(), seconds })
}
