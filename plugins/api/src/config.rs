//! A plugin's configuration: the bytes its creation receives are one JSON object of options
//! (`{"step": 0.2, "shortcuts": 50}`), the same whether the plugin is linked in or loaded from a
//! shared library. Empty bytes read as the empty object, so a host with nothing to say sends
//! nothing.
//!
//! A plugin takes each option it knows by name and type, then calls [`PluginConfig::finish`],
//! which refuses any key left over: a misspelt option is an error, never silently ignored.

use serde::de::DeserializeOwned;
use serde_json::{Map, Value};
use thiserror::Error;

use crate::PluginError;

/// Why a plugin refused its configuration.
#[derive(Clone, Debug, PartialEq, Eq, Error, miette::Diagnostic)]
#[diagnostic(
    code(lamp::plugin::config),
    help("a plugin's configuration is one JSON object of options, as docs/plugins.md lists them")
)]
pub enum ConfigError {
    /// The bytes are not a JSON document.
    #[error("the configuration is not JSON: {message}")]
    NotJson {
        /// The JSON reader's reason, with the line and column.
        message: String,
    },
    /// The document is JSON but not an object.
    #[error("the configuration is a JSON {found}, not an object of options")]
    NotAnObject {
        /// What it is instead (`array`, `string`, …).
        found: &'static str,
    },
    /// A key the plugin does not read.
    #[error("unknown option `{key}`; {}", known_options(.known))]
    UnknownKey {
        /// The key.
        key: String,
        /// The options the plugin reads, in the order it reads them.
        known: Vec<String>,
    },
    /// An option the plugin needs is absent.
    #[error("option `{key}` is required")]
    Missing {
        /// The key.
        key: String,
    },
    /// A value of the wrong JSON type.
    #[error("option `{key}` must be {expected}, not {found}")]
    WrongType {
        /// The key.
        key: String,
        /// What the plugin reads there (`a string`, `a whole number`, …).
        expected: &'static str,
        /// The value given, as JSON (shortened when long).
        found: String,
    },
    /// A value of the right type that the plugin cannot use.
    #[error("option `{key}`: {reason}")]
    BadValue {
        /// The key.
        key: String,
        /// Why the value cannot be used.
        reason: String,
    },
}

fn known_options(known: &[String]) -> String {
    if known.is_empty() {
        "this plugin reads no options".to_string()
    } else {
        let quoted: Vec<String> = known.iter().map(|key| format!("`{key}`")).collect();
        format!("it reads {}", quoted.join(", "))
    }
}

impl From<ConfigError> for PluginError {
    fn from(error: ConfigError) -> Self {
        PluginError::InvalidRequest { message: error.to_string() }
    }
}

/// A configuration being read: the options not taken yet, and the names of those taken.
#[derive(Clone, Debug, Default)]
pub struct PluginConfig {
    remaining: Map<String, Value>,
    known: Vec<String>,
}

/// The longest value quoted in a [`ConfigError::WrongType`].
const QUOTED_VALUE_CHARS: usize = 60;

impl PluginConfig {
    /// Reads configuration bytes: a JSON object, or nothing (only whitespace) for no options.
    ///
    /// # Errors
    /// [`ConfigError::NotJson`] for bytes that are not a JSON document (or not UTF-8), and
    /// [`ConfigError::NotAnObject`] for a document that is not an object.
    pub fn parse(bytes: &[u8]) -> Result<Self, ConfigError> {
        if bytes.iter().all(u8::is_ascii_whitespace) {
            return Ok(Self::default());
        }
        let value: Value = serde_json::from_slice(bytes)
            .map_err(|error| ConfigError::NotJson { message: error.to_string() })?;
        match value {
            Value::Object(remaining) => Ok(Self { remaining, known: Vec::new() }),
            other => Err(ConfigError::NotAnObject { found: json_type(&other) }),
        }
    }

    /// Takes `key`'s value as text.
    ///
    /// # Errors
    /// [`ConfigError::WrongType`] when the value is not a string.
    pub fn text(&mut self, key: &str) -> Result<Option<String>, ConfigError> {
        match self.take(key) {
            None => Ok(None),
            Some(Value::String(text)) => Ok(Some(text)),
            Some(other) => Err(wrong_type(key, "a string", &other)),
        }
    }

    /// Takes `key`'s value as a finite number.
    ///
    /// # Errors
    /// [`ConfigError::WrongType`] when the value is not a number.
    pub fn number(&mut self, key: &str) -> Result<Option<f64>, ConfigError> {
        match self.take(key) {
            None => Ok(None),
            Some(value) => {
                value.as_f64().map(Some).ok_or_else(|| wrong_type(key, "a number", &value))
            }
        }
    }

    /// Takes `key`'s value as a whole number, not negative (`4` and `4.0` alike, as a host that
    /// holds every number as `f64` writes them).
    ///
    /// # Errors
    /// [`ConfigError::WrongType`] when the value is not a number, and
    /// [`ConfigError::BadValue`] when it is negative, has a fraction or does not fit.
    pub fn count(&mut self, key: &str) -> Result<Option<usize>, ConfigError> {
        let Some(value) = self.take(key) else { return Ok(None) };
        if let Some(count) = value.as_u64() {
            return usize::try_from(count)
                .map(Some)
                .map_err(|_| bad_value(key, format!("{count} is too large")));
        }
        let number = value.as_f64().ok_or_else(|| wrong_type(key, "a whole number", &value))?;
        // Above 2^53 a float no longer holds every whole number, so it is not a count.
        let exact = 2f64.powi(f64::MANTISSA_DIGITS as i32);
        if number.fract() != 0.0 || number < 0.0 || number > exact {
            return Err(bad_value(key, format!("{number} is not a whole number, 0 or more")));
        }
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let count = number as u64;
        usize::try_from(count)
            .map(Some)
            .map_err(|_| bad_value(key, format!("{count} is too large")))
    }

    /// Takes `key`'s value as any JSON-readable type (a nested document such as a model).
    ///
    /// # Errors
    /// [`ConfigError::BadValue`] with the reader's reason when the value does not read as `T`.
    pub fn document<T: DeserializeOwned>(&mut self, key: &str) -> Result<Option<T>, ConfigError> {
        match self.take(key) {
            None => Ok(None),
            Some(value) => serde_json::from_value(value)
                .map(Some)
                .map_err(|error| bad_value(key, error.to_string())),
        }
    }

    /// Ends reading: every option given must have been taken.
    ///
    /// # Errors
    /// [`ConfigError::UnknownKey`] for the first key (in sorted order) that no reader took.
    pub fn finish(self) -> Result<(), ConfigError> {
        match self.remaining.into_iter().next() {
            None => Ok(()),
            Some((key, _)) => Err(ConfigError::UnknownKey { key, known: self.known }),
        }
    }

    fn take(&mut self, key: &str) -> Option<Value> {
        if !self.known.iter().any(|known| known == key) {
            self.known.push(key.to_string());
        }
        self.remaining.remove(key)
    }
}

/// [`ConfigError::Missing`] for `key`: for a required option, after its reader found nothing.
#[must_use]
pub fn missing(key: &str) -> ConfigError {
    ConfigError::Missing { key: key.to_string() }
}

/// [`ConfigError::BadValue`] for `key`: a plugin's own check of a value refused it.
#[must_use]
pub fn bad_value(key: &str, reason: impl Into<String>) -> ConfigError {
    ConfigError::BadValue { key: key.to_string(), reason: reason.into() }
}

fn wrong_type(key: &str, expected: &'static str, value: &Value) -> ConfigError {
    let mut found = value.to_string();
    if let Some((cut, _)) = found.char_indices().nth(QUOTED_VALUE_CHARS) {
        found.truncate(cut);
        found.push('…');
    }
    ConfigError::WrongType { key: key.to_string(), expected, found }
}

fn json_type(value: &Value) -> &'static str {
    match value {
        Value::Null => "null",
        Value::Bool(_) => "boolean",
        Value::Number(_) => "number",
        Value::String(_) => "string",
        Value::Array(_) => "array",
        Value::Object(_) => "object",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_bytes_are_no_options_and_each_reader_takes_its_type() {
        for empty in [&b""[..], b"  \n", b"{}"] {
            PluginConfig::parse(empty).unwrap().finish().unwrap();
        }
        let mut config = PluginConfig::parse(
            br#"{"name": "x", "step": 0.25, "count": 4, "whole": 7.0, "nested": [1, 2]}"#,
        )
        .unwrap();
        assert_eq!(config.text("name").unwrap().as_deref(), Some("x"));
        assert_eq!(config.number("step").unwrap(), Some(0.25));
        assert_eq!(config.count("count").unwrap(), Some(4));
        assert_eq!(config.count("whole").unwrap(), Some(7));
        assert_eq!(config.document::<Vec<u8>>("nested").unwrap(), Some(vec![1, 2]));
        assert_eq!(config.text("absent").unwrap(), None);
        config.finish().unwrap();
    }

    #[test]
    fn bad_documents_keys_and_values_are_typed_errors() {
        assert!(matches!(PluginConfig::parse(b"step=1"), Err(ConfigError::NotJson { .. })));
        assert!(matches!(PluginConfig::parse(b"\xff"), Err(ConfigError::NotJson { .. })));
        assert_eq!(
            PluginConfig::parse(b"[1]").unwrap_err(),
            ConfigError::NotAnObject { found: "array" }
        );
        let mut config =
            PluginConfig::parse(br#"{"a": "text", "b": -1, "c": 1.5, "d": 1, "e": "x"}"#).unwrap();
        assert!(matches!(
            config.number("a"),
            Err(ConfigError::WrongType { expected: "a number", .. })
        ));
        assert!(matches!(config.count("b"), Err(ConfigError::BadValue { .. })));
        assert!(matches!(config.count("c"), Err(ConfigError::BadValue { .. })));
        assert!(matches!(
            config.text("d"),
            Err(ConfigError::WrongType { expected: "a string", .. })
        ));
        let error = config.finish().unwrap_err();
        assert_eq!(
            error,
            ConfigError::UnknownKey {
                key: "e".to_string(),
                known: ["a", "b", "c", "d"].map(String::from).to_vec()
            }
        );
        assert_eq!(error.to_string(), "unknown option `e`; it reads `a`, `b`, `c`, `d`");
        let nothing = PluginConfig::parse(br#"{"x": 1}"#).unwrap().finish().unwrap_err();
        assert_eq!(nothing.to_string(), "unknown option `x`; this plugin reads no options");
        assert!(matches!(PluginError::from(nothing), PluginError::InvalidRequest { .. }));
    }

    #[test]
    fn a_long_wrong_value_is_quoted_shortened() {
        let long = format!(r#"{{"key": "{}"}}"#, "é".repeat(200));
        let mut config = PluginConfig::parse(long.as_bytes()).unwrap();
        let ConfigError::WrongType { found, .. } = config.number("key").unwrap_err() else {
            panic!("a wrong type")
        };
        assert_eq!(found.chars().count(), QUOTED_VALUE_CHARS + 1);
    }
}
