//! Stages and the systems registered in them.

use super::Resources;
use hecs::World;
use prism_core::error::Result;

/// The named stages, in execution order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stage {
    /// Parse the scene and spawn entities.
    Load,
    /// Compose nested transforms into `WorldFromLocal`.
    Propagate,
    /// Flatten shapes into primitives and build the accelerator.
    BuildAccel,
    /// Per-plugin set-up: lights, samplers, the integrator, the film.
    Prepare,
    /// One progressive pass.
    Render,
    /// Merge the pass into the film; decide whether another pass runs.
    Accumulate,
    /// Write images and statistics.
    Output,
}

impl Stage {
    /// Every stage, in execution order.
    pub const ALL: [Stage; 7] = [
        Stage::Load,
        Stage::Propagate,
        Stage::BuildAccel,
        Stage::Prepare,
        Stage::Render,
        Stage::Accumulate,
        Stage::Output,
    ];

    fn index(self) -> usize {
        Self::ALL.iter().position(|&s| s == self).unwrap_or(0)
    }
}

type SystemFn = Box<dyn FnMut(&mut World, &mut Resources) -> Result<()> + Send>;

/// A named system: a function over the world and the resources.
pub struct System {
    /// The system's name (listed by [`Schedule::system_names`]).
    pub name: &'static str,
    run: SystemFn,
}

impl System {
    /// The system `run` under `name`.
    pub fn new(name: &'static str, run: impl FnMut(&mut World, &mut Resources) -> Result<()> + Send + 'static) -> Self {
        System { name, run: Box::new(run) }
    }
}

/// The systems of every stage, each stage's in the order they were added.
#[derive(Default)]
pub struct Schedule {
    stages: [Vec<System>; 7],
}

impl Schedule {
    /// Append `system` to `stage`.
    pub fn add(&mut self, stage: Stage, system: System) {
        self.stages[stage.index()].push(system);
    }

    /// Names of the systems of a stage, in order.
    pub fn system_names(&self, stage: Stage) -> Vec<&'static str> {
        self.stages[stage.index()].iter().map(|s| s.name).collect()
    }

    /// Run `stage`'s systems once, in order; the first error stops the stage and is returned.
    pub fn run_stage(&mut self, stage: Stage, world: &mut World, res: &mut Resources) -> Result<()> {
        for system in &mut self.stages[stage.index()] {
            (system.run)(world, res)?;
        }
        Ok(())
    }
}
