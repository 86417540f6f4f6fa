//! The planner's options and their text form, the plugin's configuration bytes: a `key=value`
//! list separated by commas or whitespace, for example `step=0.2, shortcuts=50, iterations=2000`.

use lamp_plugin_api::PluginError;
use lamp_rrt::RrtConfig;

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
    /// Parses a `key=value` list (`step`, `shortcuts`, `iterations`), separated by commas or
    /// whitespace; keys not given keep their defaults, and the empty text gives the defaults.
    ///
    /// # Errors
    /// [`PluginError::InvalidRequest`] for an unknown or repeated key, a missing `=`, or a value
    /// out of range: `step` must be finite and positive, `iterations` at least 1.
    pub fn parse(text: &str) -> Result<Self, PluginError> {
        let mut options = Self::default();
        let mut seen: Vec<&str> = Vec::new();
        let items = text.split(|c: char| c == ',' || c.is_whitespace());
        for item in items.filter(|item| !item.is_empty()) {
            let Some((key, value)) = item.split_once('=') else {
                return Err(invalid(format!("`{item}` is not `key=value`")));
            };
            if seen.contains(&key) {
                return Err(invalid(format!("`{key}` is given twice")));
            }
            seen.push(key);
            match key {
                "step" => {
                    options.step = value
                        .parse::<f64>()
                        .ok()
                        .filter(|step| step.is_finite() && *step > 0.0)
                        .ok_or_else(|| {
                            invalid(format!("step `{value}` is not a positive number"))
                        })?;
                }
                "shortcuts" => options.shortcut_attempts = count(key, value)?,
                "iterations" => {
                    options.iterations = count(key, value)?;
                    if options.iterations == 0 {
                        return Err(invalid("iterations must be at least 1".to_string()));
                    }
                }
                other => {
                    return Err(invalid(format!(
                        "unknown option `{other}`; expected `step`, `shortcuts` or `iterations`"
                    )));
                }
            }
        }
        Ok(options)
    }

    /// The plugin's configuration bytes: UTF-8 text for [`parse`](Self::parse).
    ///
    /// # Errors
    /// As [`parse`](Self::parse), and [`PluginError::InvalidRequest`] for bytes that are not
    /// UTF-8.
    pub fn from_config(config: &[u8]) -> Result<Self, PluginError> {
        let text = std::str::from_utf8(config)
            .map_err(|_| invalid("the configuration is not UTF-8".to_string()))?;
        Self::parse(text)
    }
}

fn count(key: &str, value: &str) -> Result<usize, PluginError> {
    value.parse().map_err(|_| invalid(format!("{key} `{value}` is not a whole number")))
}

fn invalid(message: String) -> PluginError {
    PluginError::invalid_request(format!("rrt-connect options: {message}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_text_gives_lamp_rrts_defaults() {
        let options = RrtOptions::parse("").unwrap();
        let defaults = RrtConfig::default();
        assert_eq!(options.step, defaults.step);
        assert_eq!(options.shortcut_attempts, defaults.shortcut_attempts);
        assert_eq!(options.iterations, defaults.max_iterations);
        assert_eq!(RrtOptions::from_config(b" \n").unwrap(), options);
    }

    #[test]
    fn keys_override_their_defaults_in_any_separator_style() {
        let options = RrtOptions::parse("step=0.25, shortcuts=0\niterations=42").unwrap();
        assert_eq!(options, RrtOptions { step: 0.25, shortcut_attempts: 0, iterations: 42 });
        let partial = RrtOptions::parse("iterations=7").unwrap();
        assert_eq!(partial, RrtOptions { iterations: 7, ..RrtOptions::default() });
    }

    #[test]
    fn bad_options_are_refused_with_the_reason() {
        let message = |text: &str| match RrtOptions::parse(text) {
            Err(PluginError::InvalidRequest { message }) => message,
            other => panic!("{text}: expected a refusal, got {other:?}"),
        };
        assert!(message("speed=3").contains("unknown option `speed`"));
        assert!(message("step").contains("`step` is not `key=value`"));
        assert!(message("step=-1").contains("not a positive number"));
        assert!(message("step=NaN").contains("not a positive number"));
        assert!(message("shortcuts=1.5").contains("not a whole number"));
        assert!(message("iterations=0").contains("at least 1"));
        assert!(message("step=1 step=2").contains("given twice"));
        assert!(matches!(
            RrtOptions::from_config(b"\xff"),
            Err(PluginError::InvalidRequest { .. })
        ));
    }
}
