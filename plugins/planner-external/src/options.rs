//! The plugin's options: which programs to run, from typed values or from configuration text.

use crate::error::ExternalError;

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

    /// Splits `text` at whitespace: the first word is the program, the rest its arguments.
    /// Quoting is not interpreted, so a path with spaces cannot be written this way (build the
    /// value directly instead).
    ///
    /// # Errors
    /// [`ExternalError::Options`] when `text` has no word.
    pub fn parse(text: &str) -> Result<Self, ExternalError> {
        let mut words = text.split_whitespace().map(str::to_string);
        let program = words.next().ok_or_else(|| ExternalError::Options {
            message: "a command needs at least a program".to_string(),
        })?;
        Ok(Self { program, arguments: words.collect() })
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
    /// Options from `(name, value)` pairs: `command` and `kstar-command` (a program and its
    /// arguments, split at whitespace) and `python` (an interpreter).
    ///
    /// # Errors
    /// [`ExternalError::Options`] for an unknown name, a repeated one or an empty value.
    pub fn from_pairs<'a>(
        pairs: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<Self, ExternalError> {
        let mut options = Self::default();
        let mut python = None;
        for (name, value) in pairs {
            let repeated = match name {
                COMMAND_OPTION => options.command.replace(CommandLine::parse(value)?).is_some(),
                KSTAR_COMMAND_OPTION => {
                    options.kstar_command.replace(CommandLine::parse(value)?).is_some()
                }
                PYTHON_OPTION => {
                    let interpreter = value.trim();
                    if interpreter.is_empty() {
                        return Err(ExternalError::Options {
                            message: "`python` needs an interpreter".to_string(),
                        });
                    }
                    python.replace(interpreter.to_string()).is_some()
                }
                other => {
                    return Err(ExternalError::Options {
                        message: format!(
                            "unknown option `{other}`; expected `{COMMAND_OPTION}`, \
                             `{KSTAR_COMMAND_OPTION}` or `{PYTHON_OPTION}`"
                        ),
                    });
                }
            };
            if repeated {
                return Err(ExternalError::Options {
                    message: format!("option `{name}` is given twice"),
                });
            }
        }
        if let Some(python) = python {
            options.python = python;
        }
        Ok(options)
    }

    /// Options from configuration text: one `name value` (or `name=value`) pair per line, blank
    /// lines and lines starting with `#` ignored. Empty text gives the defaults.
    ///
    /// # Errors
    /// [`ExternalError::Options`] for a line without a value, or as [`Self::from_pairs`].
    pub fn from_config(text: &str) -> Result<Self, ExternalError> {
        let mut pairs = Vec::new();
        for line in text.lines().map(str::trim) {
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let (name, value) = line
                .split_once(|c: char| c == '=' || c.is_whitespace())
                .ok_or_else(|| ExternalError::Options {
                    message: format!("`{line}` has no value; write `name value`"),
                })?;
            pairs.push((name.trim_end(), value.trim_start_matches('=')));
        }
        Self::from_pairs(pairs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn config_text_sets_each_option() {
        let options = ExternalOptions::from_config(
            "# a comment\ncommand python3 /opt/fd/fast-downward.py\n\nkstar-command=kstar\npython = py3",
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
        assert_eq!(ExternalOptions::from_config("").expect("empty"), ExternalOptions::default());
    }

    #[test]
    fn unknown_repeated_and_empty_options_are_refused() {
        for text in ["search astar", "command a\ncommand b", "command", "python  "] {
            let error = ExternalOptions::from_config(text).expect_err(text);
            assert!(matches!(error, ExternalError::Options { .. }), "{text}: {error:?}");
        }
        let message = ExternalOptions::from_config("timeout 3").expect_err("unknown").to_string();
        assert!(message.contains("`timeout`") && message.contains("`command`"), "{message}");
    }
}
