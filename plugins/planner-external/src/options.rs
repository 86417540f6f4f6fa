//! The plugin's options: which programs to run, from typed values or from the plugin's
//! configuration, the JSON object `{"command": "...", "kstar-command": "...", "python": "..."}`.

use lamp_plugin_api::config::{self, ConfigError, PluginConfig};

/// A program and the arguments that come before the planner's own (domain, problem, search).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CommandLine {
    /// The program: a path, or a name looked up on `PATH`.
    pub program: String,
    /// Arguments passed first, for example the driver script of `python3 fast-downward.py`.
    pub arguments: Vec<String>,
}

impl CommandLine {
    /// A program with no arguments of its own.
    #[must_use]
    pub fn program(program: impl Into<String>) -> Self {
        Self { program: program.into(), arguments: Vec::new() }
    }

    /// Splits `text` at whitespace: the first word is the program, the rest its arguments, or
    /// `None` when `text` has no word. Quoting is not interpreted, so a path with spaces cannot
    /// be written this way (build the value directly instead).
    #[must_use]
    pub fn parse(text: &str) -> Option<Self> {
        let mut words = text.split_whitespace().map(str::to_string);
        let program = words.next()?;
        Some(Self { program, arguments: words.collect() })
    }

    /// The command as one line, for messages.
    #[must_use]
    pub fn display(&self) -> String {
        std::iter::once(self.program.as_str())
            .chain(self.arguments.iter().map(String::as_str))
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// Option name: the Fast Downward driver command (one plan per call).
pub const COMMAND_OPTION: &str = "command";
/// Option name: the K* driver command (the top-k plans when more than one is asked for).
pub const KSTAR_COMMAND_OPTION: &str = "kstar-command";
/// Option name: the Python interpreter used to find and run the pip packages.
pub const PYTHON_OPTION: &str = "python";

/// The interpreter used when the `python` option is not given.
pub const DEFAULT_PYTHON: &str = "python3";

/// What the plugin runs. Every field is optional: unset commands are found as documented in
/// [`crate::ExternalPlanner`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExternalOptions {
    /// A Fast Downward driver (`fast-downward.py` or anything taking its arguments).
    pub command: Option<CommandLine>,
    /// A K* driver (Fast Downward's driver of the K* fork, taking the same arguments).
    pub kstar_command: Option<CommandLine>,
    /// The Python interpreter for the pip packages `up-fast-downward` and `kstar-planner`.
    pub python: String,
}

impl Default for ExternalOptions {
    fn default() -> Self {
        Self { command: None, kstar_command: None, python: DEFAULT_PYTHON.to_string() }
    }
}

impl ExternalOptions {
    /// The options of the plugin's configuration: a JSON object whose keys, all optional, are
    /// `command` and `kstar-command` (a program and its arguments, split at whitespace) and
    /// `python` (an interpreter). The empty configuration gives the defaults.
    ///
    /// # Errors
    /// A [`ConfigError`] for bytes that are not a JSON object, an unknown key, a value that is
    /// not a string, or an empty one.
    pub fn from_config(bytes: &[u8]) -> Result<Self, ConfigError> {
        let mut config = PluginConfig::parse(bytes)?;
        let mut command = |key: &str| -> Result<Option<CommandLine>, ConfigError> {
            match config.text(key)? {
                None => Ok(None),
                Some(text) => CommandLine::parse(&text)
                    .map(Some)
                    .ok_or_else(|| config::bad_value(key, "a command needs at least a program")),
            }
        };
        let options = Self {
            command: command(COMMAND_OPTION)?,
            kstar_command: command(KSTAR_COMMAND_OPTION)?,
            python: match config.text(PYTHON_OPTION)? {
                None => DEFAULT_PYTHON.to_string(),
                Some(interpreter) if interpreter.trim().is_empty() => {
                    return Err(config::bad_value(PYTHON_OPTION, "needs an interpreter"));
                }
                Some(interpreter) => interpreter.trim().to_string(),
            },
        };
        config.finish()?;
        Ok(options)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_configuration_sets_each_option() {
        let options = ExternalOptions::from_config(
            br#"{"command": "python3 /opt/fd/fast-downward.py", "kstar-command": "kstar", "python": " py3 "}"#,
        )
        .expect("valid options");
        assert_eq!(
            options.command,
            Some(CommandLine {
                program: "python3".into(),
                arguments: vec!["/opt/fd/fast-downward.py".into()]
            })
        );
        assert_eq!(options.kstar_command, Some(CommandLine::program("kstar")));
        assert_eq!(options.python, "py3");
        assert_eq!(ExternalOptions::from_config(b"").expect("empty"), ExternalOptions::default());
    }

    #[test]
    fn unknown_mistyped_and_empty_options_are_refused() {
        for text in [
            r#"{"search": "astar"}"#,
            r#"{"command": ["a", "b"]}"#,
            r#"{"command": " "}"#,
            r#"{"python": ""}"#,
            "command a",
        ] {
            assert!(ExternalOptions::from_config(text.as_bytes()).is_err(), "{text}");
        }
        let message =
            ExternalOptions::from_config(br#"{"timeout": 3}"#).expect_err("unknown").to_string();
        assert!(message.contains("`timeout`") && message.contains("`command`"), "{message}");
    }
}
