//! Resources: the plain, typed data shared by systems (settings, material and mesh tables, the render scene, the
//! chosen integrator, the film, progress), plus a type-keyed slot per plugin for its own state.

use prism_core::error::Result;
use prism_core::film::Film;
use prism_core::integrator::{Integrator, IntegratorRegistry, PassOutput};
use prism_core::material::Material;
use prism_core::mesh::MeshStore;
use prism_core::scene::{Scene, SceneGlobals};
use prism_core::settings::{Overrides, RenderSettings};
use std::any::{Any, TypeId};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

/// Where the Load stage gets the scene from.
#[derive(Clone, Debug, Default)]
pub enum SceneSource {
    /// Entities were spawned by code; Load only resolves settings.
    #[default]
    Prebuilt,
    /// A scene file (`.ron`, `.obj`), loaded by extension.
    File(PathBuf),
    /// RON text; `name` is used in error messages and relative paths resolve against `base_dir`.
    RonText {
        /// The scene, in RON.
        text: String,
        /// What to call it in error messages.
        name: PathBuf,
        /// Directory relative paths in the text resolve against.
        base_dir: PathBuf,
    },
}

/// Progress of the progressive render.
#[derive(Clone, Debug)]
pub struct Progress {
    /// Passes merged into the film so far.
    pub passes_done: u32,
    /// Samples per pixel merged so far (for complete passes).
    pub spp_done: u64,
    /// Of those, the samples a resumed film brought (not rendered by this process).
    pub spp_resumed: u64,
    /// When the first pass of this process started (`None` before it).
    pub started: Option<Instant>,
    /// Wall time spent in the Render stage.
    pub elapsed: Duration,
    /// CPU time (all threads) spent in the Render stage, where the platform reports it.
    pub cpu: Option<Duration>,
    /// Set when no further pass should run.
    pub finished: bool,
    /// Set when the render was interrupted (the film holds what was done).
    pub interrupted: bool,
    /// Time spent in the set-up stages before the first pass.
    pub setup: Duration,
    /// The image's estimated relMSE after the last pass, in a render with a noise target.
    pub noise: Option<f64>,
    /// The render ended because the estimate met the noise target (its film is then complete with the passes
    /// done).
    pub noise_met: bool,
}

impl Default for Progress {
    fn default() -> Self {
        Progress {
            passes_done: 0,
            spp_done: 0,
            spp_resumed: 0,
            started: None,
            elapsed: Duration::ZERO,
            cpu: Some(Duration::ZERO),
            finished: false,
            interrupted: false,
            setup: Duration::ZERO,
            noise: None,
            noise_met: false,
        }
    }
}

/// The typed data systems share, plus one slot per type for plugins' own state.
#[derive(Default)]
pub struct Resources {
    /// Where the Load stage reads the scene from.
    pub source: SceneSource,
    /// Command-line values that replace the scene's settings.
    pub overrides: Overrides,
    /// The render's settings, resolved in Load.
    pub settings: RenderSettings,
    /// Background and ambient radiance of the scene.
    pub globals: SceneGlobals,
    /// The scene's material table (entities' `MaterialId`s index it).
    pub materials: Vec<Material>,
    /// Textures the materials refer to (images shared through `Arc`).
    pub textures: prism_core::texture::TextureSet,
    /// The meshes entities' `Shape::Mesh` handles refer to.
    pub meshes: MeshStore,
    /// The flattened scene integrators see (built in BuildAccel, lights added in Prepare).
    pub scene: Option<Scene>,
    /// The integrators plugins registered, by name.
    pub integrators: IntegratorRegistry,
    /// The integrator chosen for this render (instantiated in Prepare).
    pub integrator: Option<Box<dyn Integrator>>,
    /// The image being rendered (made in Prepare, or resumed from a film file).
    pub film: Option<Film>,
    /// The last pass, between Render and Accumulate.
    pub pass_output: Option<PassOutput>,
    /// Passes and samples done, timings, and whether the render is finished.
    pub progress: Progress,
    /// Image files written by Output (and by checkpoints); format by extension (`.png`, `.exr`).
    pub outputs: Vec<PathBuf>,
    /// Write the outputs after a pass when this long has passed since the last write (None: only at the end).
    pub checkpoint_every: Option<Duration>,
    /// Set from another thread (Ctrl-C) to stop after the current tiles; the film keeps what was done.
    pub cancel: Arc<AtomicBool>,
    /// Show a progress bar (the CLI enables it on a terminal).
    pub show_progress: bool,
    /// A hash of the scene file (with the settings, the fingerprint of saved films).
    pub scene_hash: u64,
    /// Continue the render saved in this `.prism-film` file.
    pub resume: Option<PathBuf>,
    /// Where checkpoints and interruptions save the film (`.prism-film` beside the first image output).
    pub film_path: Option<PathBuf>,
    /// Files the scene was read from (scene, meshes, textures, environment maps): outputs must not overwrite them.
    pub inputs: Vec<PathBuf>,
    plugin_state: HashMap<TypeId, Box<dyn Any + Send + Sync>>,
}

impl Resources {
    /// Store a plugin's own state (one value per type).
    pub fn insert<T: Any + Send + Sync>(&mut self, value: T) {
        self.plugin_state.insert(TypeId::of::<T>(), Box::new(value));
    }

    /// The plugin state of type `T`, if one was inserted.
    pub fn get<T: Any + Send + Sync>(&self) -> Option<&T> {
        self.plugin_state.get(&TypeId::of::<T>()).and_then(|b| b.downcast_ref())
    }

    /// Take the plugin state of type `T` out, if one was inserted.
    pub fn remove<T: Any + Send + Sync>(&mut self) -> Option<T> {
        self.plugin_state.remove(&TypeId::of::<T>()).and_then(|b| b.downcast().ok()).map(|b| *b)
    }

    /// The plugin state of type `T`, mutably, if one was inserted.
    pub fn get_mut<T: Any + Send + Sync>(&mut self) -> Option<&mut T> {
        self.plugin_state.get_mut(&TypeId::of::<T>()).and_then(|b| b.downcast_mut())
    }

    /// The scene, or an error naming the stage that should have built it.
    pub fn scene(&self) -> Result<&Scene> {
        self.scene
            .as_ref()
            .ok_or_else(|| prism_core::error::PrismError::invalid("no scene: the BuildAccel stage did not run"))
    }
}
