//! The plugin interface: a plugin adds systems to stages and registers integrators. It is public so crates outside
//! Prism can extend it (`tests/plugin.rs` registers an integrator defined outside the crate).

use super::App;

/// An extension of the app: systems in stages, integrators by name.
pub trait Plugin {
    /// Unique name; adding a plugin twice is a no-op.
    fn name(&self) -> &str;
    /// Register systems and integrators.
    fn build(&self, app: &mut App);
}

/// A plugin by reference is the plugin (so code can be handed `&dyn Plugin` and add it).
impl<P: Plugin + ?Sized> Plugin for &P {
    fn name(&self) -> &str {
        (**self).name()
    }

    fn build(&self, app: &mut App) {
        (**self).build(app)
    }
}
