//! Integrator names to factories. A factory receives the scene's `PluginConfig` (name + parameter text) and
//! parses its own parameter struct with `PluginConfig::parse_params`.

use super::Integrator;
use crate::error::{PrismError, Result};
use crate::settings::PluginConfig;
use std::collections::BTreeMap;

/// Makes an integrator from its config (name and parameter text); errors are bad parameters.
pub type IntegratorFactory = Box<dyn Fn(&PluginConfig) -> Result<Box<dyn Integrator>> + Send + Sync>;

/// The integrators a render can name, each by its factory.
#[derive(Default)]
pub struct IntegratorRegistry {
    factories: BTreeMap<String, IntegratorFactory>,
}

impl IntegratorRegistry {
    /// Make `name` available, replacing a factory registered under it before.
    pub fn register(&mut self, name: &str, factory: IntegratorFactory) {
        self.factories.insert(name.to_string(), factory);
    }

    /// The registered names, sorted.
    pub fn names(&self) -> Vec<&str> {
        self.factories.keys().map(String::as_str).collect()
    }

    /// Whether an integrator is registered as `name`.
    pub fn contains(&self, name: &str) -> bool {
        self.factories.contains_key(name)
    }

    /// Instantiate the integrator a config names.
    pub fn create(&self, config: &PluginConfig) -> Result<Box<dyn Integrator>> {
        let factory = self.factories.get(&config.name).ok_or_else(|| {
            PrismError::invalid(format!(
                "unknown integrator '{}' (available: {})",
                config.name,
                self.names().join(", ")
            ))
        })?;
        factory(config)
    }
}
