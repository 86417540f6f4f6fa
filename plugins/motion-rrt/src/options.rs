//! The planner's options and the plugin's configuration: the JSON object
//! `{"step": 0.2, "shortcuts": 50, "iterations": 2000}`, every key optional.

use lamp_plugin_api::config::{self, ConfigError, PluginConfig};
use lamp_rrt::RrtConfig;

/// The configuration key of [`RrtOptions::step`].
pub const STEP_OPTION: &str = "step";
/// The configuration key of [`RrtOptions::shortcut_attempts`].
pub const SHORTCUTS_OPTION: &str = "shortcuts";
/// The configuration key of [`RrtOptions::iterations`].
pub const ITERATIONS_OPTION: &str = "iterations";

/// How the RRT-Connect search runs; every field defaults to lamp-rrt's [`RrtConfig`].
#[derive(Clone, Debug, PartialEq)]
pub struct RrtOptions {
    /// The longest edge one extension adds, in the host's distance (`step`).
    pub step: f64,
    /// Shortcutting attempts after a path is found; 0 disables shortcutting (`shortcuts`).
    pub shortcut_attempts: usize,
    /// Iterations when the request sets no iteration budget (`iterations`).
    pub iterations: usize,
}

impl Default for RrtOptions {
    fn default() -> Self {
        let defaults = RrtConfig::default();
        Self {
            step: defaults.step,
            shortcut_attempts: defaults.shortcut_attempts,
            iterations: defaults.max_iterations,
        }
    }
}

impl RrtOptions {
    /// The options of the plugin's configuration: a JSON object with `step` (a number),
    /// `shortcuts` and `iterations` (whole numbers); keys not given keep their defaults, and the
    /// empty configuration gives the defaults.
    ///
    /// # Errors
    /// A [`ConfigError`] for bytes that are not a JSON object, an unknown key, a value of the
    /// wrong type, or one out of range: `step` must be finite and positive, `iterations` at
    /// least 1.
    pub fn from_config(bytes: &[u8]) -> Result<Self, ConfigError> {
        let mut config = PluginConfig::parse(bytes)?;
        let mut options = Self::default();
        if let Some(step) = config.number(STEP_OPTION)? {
            if !(step.is_finite() && step > 0.0) {
                return Err(config::bad_value(STEP_OPTION, format!("{step} is not positive")));
            }
            options.step = step;
        }
        if let Some(shortcuts) = config.count(SHORTCUTS_OPTION)? {
            options.shortcut_attempts = shortcuts;
        }
        if let Some(iterations) = config.count(ITERATIONS_OPTION)? {
            if iterations == 0 {
                return Err(config::bad_value(ITERATIONS_OPTION, "must be at least 1"));
            }
            options.iterations = iterations;
        }
        config.finish()?;
        Ok(options)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_configuration_gives_lamp_rrts_defaults() {
        let options = RrtOptions::from_config(b"").unwrap();
        let defaults = RrtConfig::default();
        assert_eq!(options.step, defaults.step);
        assert_eq!(options.shortcut_attempts, defaults.shortcut_attempts);
        assert_eq!(options.iterations, defaults.max_iterations);
        assert_eq!(RrtOptions::from_config(b" {} ").unwrap(), options);
    }

    #[test]
    fn keys_override_their_defaults() {
        let options =
            RrtOptions::from_config(br#"{"step": 0.25, "shortcuts": 0, "iterations": 42}"#)
                .unwrap();
        assert_eq!(options, RrtOptions { step: 0.25, shortcut_attempts: 0, iterations: 42 });
        let partial = RrtOptions::from_config(br#"{"iterations": 7.0}"#).unwrap();
        assert_eq!(partial, RrtOptions { iterations: 7, ..RrtOptions::default() });
    }

    #[test]
    fn bad_options_are_refused_with_the_reason() {
        let message = |text: &str| match RrtOptions::from_config(text.as_bytes()) {
            Err(error) => error.to_string(),
            Ok(options) => panic!("{text}: expected a refusal, got {options:?}"),
        };
        assert!(message(r#"{"speed": 3}"#).contains("unknown option `speed`"));
        assert!(message("step=1").contains("not JSON"));
        assert!(message(r#"{"step": -1}"#).contains("not positive"));
        assert!(message(r#"{"step": "fast"}"#).contains("must be a number"));
        assert!(message(r#"{"shortcuts": 1.5}"#).contains("not a whole number"));
        assert!(message(r#"{"iterations": 0}"#).contains("at least 1"));
        assert!(matches!(RrtOptions::from_config(b"\xff"), Err(ConfigError::NotJson { .. })));
    }
}
