//! # prism-engine
//!
//! The application: one `hecs::World` of scene entities, plain [`Resources`], and a [`Schedule`] of systems in
//! named stages that run in order:
//!
//! ```text
//! Load ─► Propagate ─► BuildAccel ─► Prepare ─► (Render ─► Accumulate)* ─► Output
//! ```
//!
//! A system is a plain function over `(&mut World, &mut Resources)`. Plugins add systems and integrators through
//! the public [`Plugin`] trait; [`CorePlugin`] registers the engine's stage systems, the loaders' plugin the Load
//! stage's, and integrator plugins their integrators. The app names no plugin: the set the binary ships is
//! `DefaultPlugins`, at the top of the crate graph. `Render` and `Accumulate` repeat once per progressive pass until
//! the pass count or time budget is reached or the render is cancelled.
//!
//! The entities' [`components`] and the stage systems ([`stages`]) live here too.

pub mod components;
mod core_plugin;
mod plugin;
pub mod reload_cache;
mod resources;
mod schedule;
pub mod stages;

pub use core_plugin::CorePlugin;
pub use plugin::Plugin;
pub use prism_core::scene::SceneGlobals;
pub use resources::{Progress, Resources, SceneSource};
pub use schedule::{Schedule, Stage, System};

use hecs::World;
use prism_core::error::Result;
use prism_core::integrator::IntegratorFactory;

/// The application: the scene's entities, the shared resources, the schedule of systems and the plugins added.
pub struct App {
    /// The scene's entities and their components.
    pub world: World,
    /// Settings, tables, the render scene, the integrator, the film and progress.
    pub resources: Resources,
    schedule: Schedule,
    plugins: Vec<String>,
}

impl Default for App {
    fn default() -> Self {
        Self::empty()
    }
}

impl App {
    /// An app with no systems and no plugins.
    pub fn empty() -> Self {
        App { world: World::new(), resources: Resources::default(), schedule: Schedule::default(), plugins: vec![] }
    }

    /// An app with `plugin` added (for the `prism` binary's set, `App::with(prism::DefaultPlugins)`).
    pub fn with(plugin: impl Plugin) -> Self {
        let mut app = Self::empty();
        app.add_plugin(plugin);
        app
    }

    /// Register a plugin (once per name).
    pub fn add_plugin(&mut self, plugin: impl Plugin) -> &mut Self {
        let name = plugin.name().to_string();
        if !self.plugins.contains(&name) {
            plugin.build(self);
            self.plugins.push(name);
        }
        self
    }

    /// The names of the plugins added, in the order they were added.
    pub fn plugin_names(&self) -> &[String] {
        &self.plugins
    }

    /// Append a system to a stage; systems of a stage run in the order they were added.
    pub fn add_system(
        &mut self,
        stage: Stage,
        name: &'static str,
        run: impl FnMut(&mut World, &mut Resources) -> Result<()> + Send + 'static,
    ) -> &mut Self {
        self.schedule.add(stage, System::new(name, run));
        self
    }

    /// Make an integrator available under `name` (selected by the scene's `integrator:` or `--integrator`).
    pub fn register_integrator(&mut self, name: &str, factory: IntegratorFactory) -> &mut Self {
        self.resources.integrators.register(name, factory);
        self
    }

    /// The systems registered so far, stage by stage.
    pub fn schedule(&self) -> &Schedule {
        &self.schedule
    }

    /// Run one stage's systems once.
    pub fn run_stage(&mut self, stage: Stage) -> Result<()> {
        self.schedule.run_stage(stage, &mut self.world, &mut self.resources)
    }

    /// Run the set-up stages (Load, Propagate, BuildAccel, Prepare) once: afterwards `resources.scene` holds the
    /// render scene and `resources.integrator` the chosen integrator.
    pub fn setup(&mut self) -> Result<()> {
        for stage in [Stage::Load, Stage::Propagate, Stage::BuildAccel, Stage::Prepare] {
            self.run_stage(stage)?;
        }
        Ok(())
    }

    /// Run the passes and the Output stage (after [`App::setup`]).
    pub fn render(&mut self) -> Result<()> {
        while !self.resources.progress.finished {
            self.run_stage(Stage::Render)?;
            self.run_stage(Stage::Accumulate)?;
        }
        self.run_stage(Stage::Output)
    }

    /// Run the whole schedule: the set-up stages once, Render + Accumulate per pass until done, then Output.
    pub fn run(&mut self) -> Result<()> {
        self.setup()?;
        self.render()
    }
}
