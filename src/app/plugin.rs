//! The plugin interface: a plugin adds systems to stages and registers integrators. It is public so crates outside
//! Prism can extend it (`tests/plugin.rs` registers an integrator defined outside the crate).

use super::App;

pub trait Plugin {
    /// Unique name; adding a plugin twice is a no-op.
    fn name(&self) -> &str;
    /// Register systems and integrators.
    fn build(&self, app: &mut App);
}
