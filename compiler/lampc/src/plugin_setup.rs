//! Turning the spec's plugin choices (or the command line's) into plugin trait objects: a
//! built-in is made by its factory in `builtin_plugins`' table, a library is opened through
//! lamp-plugin-host; both receive the same configuration, one JSON object (docs/plugins.md).
//!
//! Options the runtime itself reads are taken out first: the planner's `timeout` and `plans`, the
//! motion planner's `resolution` (a length or an angle: the checking resolution) and `timeout`.
//! Every number taken is checked by the rule the spec checker applied (`lamp_spec::limits`), so
//! a value that reaches here unchecked is refused all the same, never turned into a panic.
//! The rest go to the plugin as that JSON object (numbers in SI units, words and text as
//! strings), a refiner's sampler artifact included under `artifact`.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Duration;

use lamp_abstraction::SamplerArtifact;
use lamp_plugin_api::{MotionPlanner, Planner, PluginError, Refiner};
use lamp_plugin_host::{LoadError, PluginLibrary};
use lamp_spec::limits::{self, Limit, RangeError};
use lamp_spec::{OptionKind, OptionValue, PluginChoice, PluginKind, PluginSource};

use crate::builtin_plugins::{self, ARTIFACT_KEY, Builtin, Factory};

/// Options the runtime reads itself, out of the plugin blocks.
#[derive(Clone, Debug, Default)]
pub(crate) struct RuntimeOptions {
    pub(crate) planner_timeout: Option<Duration>,
    pub(crate) plan_count: Option<usize>,
    pub(crate) linear_resolution: Option<f64>,
    pub(crate) angular_resolution: Option<f64>,
    pub(crate) motion_timeout: Option<Duration>,
}

/// Why a plugin could not be set up from its choice and options.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub(crate) enum SetupError {
    #[error("option `{key}`: {range}")]
    #[diagnostic(code(lamp::plugin::option))]
    OutOfRange { key: String, range: RangeError },
    #[error("option `{key}` must be {expected}, not {found}")]
    #[diagnostic(code(lamp::plugin::option))]
    WrongKind { key: String, expected: &'static str, found: String },
    #[error("option `{key}` is too large")]
    #[diagnostic(code(lamp::plugin::option))]
    TooLarge { key: String },
    #[error("option `{key}` is set by the plugin's name already")]
    #[diagnostic(
        code(lamp::plugin::option),
        help("leave the option out: the built-in's name sets it, or choose the plain built-in")
    )]
    SetByName { key: String },
    #[error("there is no built-in {kind} `{name}`; built in: {builtins}; or give a library path")]
    #[diagnostic(code(lamp::plugin::unknown))]
    UnknownBuiltin { kind: &'static str, name: String, builtins: String },
    /// A built-in's table row holds another kind's factory: the table is wrong, not the input.
    #[error("the built-in `{name}` is listed with another kind's factory")]
    #[diagnostic(code(lamp::plugin::table))]
    WrongFactory { name: &'static str },
    #[error("the configuration cannot be written as JSON: {0}")]
    #[diagnostic(code(lamp::plugin::configuration))]
    Configuration(String),
    #[error(transparent)]
    #[diagnostic(transparent)]
    Library(#[from] LoadError),
    #[error(transparent)]
    #[diagnostic(transparent)]
    Refused(#[from] PluginError),
}

/// The spec's choice, or the command line's name or path instead (keeping no options).
pub(crate) fn chosen(
    spec_choice: &PluginChoice,
    spec_dir: &Path,
    flag: Option<&str>,
) -> PluginChoice {
    match flag {
        None => match &spec_choice.source {
            PluginSource::Library(path) => PluginChoice {
                source: PluginSource::Library(spec_dir.join(path)),
                options: spec_choice.options.clone(),
            },
            PluginSource::Builtin(_) => spec_choice.clone(),
        },
        Some(name) if name.contains('/') || name.ends_with(".so") || name.ends_with(".dylib") => {
            PluginChoice { source: PluginSource::Library(name.into()), options: BTreeMap::new() }
        }
        Some(name) => PluginChoice {
            source: PluginSource::Builtin(name.to_string()),
            options: BTreeMap::new(),
        },
    }
}

/// A time limit, taken out of `options`.
fn take_seconds(
    options: &mut BTreeMap<String, OptionValue>,
    key: &str,
) -> Result<Option<Duration>, SetupError> {
    match options.remove(key) {
        None => Ok(None),
        Some(OptionValue::Duration(seconds)) => {
            limits::duration(seconds).map(Some).map_err(|source| out_of_range(key, source))
        }
        Some(other) => Err(wrong_kind(key, "a duration", &other)),
    }
}

fn out_of_range(key: &str, range: RangeError) -> SetupError {
    SetupError::OutOfRange { key: key.to_string(), range }
}

fn wrong_kind(key: &str, expected: &'static str, found: &OptionValue) -> SetupError {
    SetupError::WrongKind { key: key.to_string(), expected, found: format!("{found:?}") }
}

/// A count within `limit`, taken out of `options`.
fn take_count(
    options: &mut BTreeMap<String, OptionValue>,
    key: &str,
    limit: &Limit,
) -> Result<Option<usize>, SetupError> {
    match options.remove(key) {
        None => Ok(None),
        Some(OptionValue::Number(value)) => {
            let count = limit.count(value).map_err(|source| out_of_range(key, source))?;
            let too_large = |_| SetupError::TooLarge { key: key.to_string() };
            usize::try_from(count).map(Some).map_err(too_large)
        }
        Some(other) => Err(wrong_kind(key, "a whole number", &other)),
    }
}

/// A plugin's configuration: the JSON object of docs/plugins.md. Numbers are in SI units (whole
/// numbers written as integers), words and text are strings; `preset` and `extra` come first.
fn configuration(
    preset: &[(&str, &str)],
    options: &BTreeMap<String, OptionValue>,
    extra: Option<(&str, serde_json::Value)>,
) -> Result<Vec<u8>, SetupError> {
    let mut object: serde_json::Map<String, serde_json::Value> =
        preset.iter().map(|(key, value)| ((*key).to_string(), serde_json::json!(value))).collect();
    if let Some((key, value)) = extra {
        object.insert(key.to_string(), value);
    }
    for (key, value) in options {
        let value = match value {
            OptionValue::Number(v) if is_whole(*v) => {
                // Exact: `is_whole` bounds it to the integers an f64 holds exactly.
                #[allow(clippy::cast_possible_truncation)]
                let whole = *v as i64;
                serde_json::json!(whole)
            }
            OptionValue::Number(v)
            | OptionValue::Length(v)
            | OptionValue::Angle(v)
            | OptionValue::Duration(v) => serde_json::json!(v),
            OptionValue::Text(text) | OptionValue::Word(text) => serde_json::json!(text),
        };
        if object.insert(key.clone(), value).is_some() {
            return Err(SetupError::SetByName { key: key.clone() });
        }
    }
    serde_json::to_vec(&serde_json::Value::Object(object))
        .map_err(|error| SetupError::Configuration(error.to_string()))
}

/// Whether `value` is a whole number that an `f64` and an `i64` both hold exactly.
fn is_whole(value: f64) -> bool {
    let exact = 2f64.powi(f64::MANTISSA_DIGITS as i32);
    value.fract() == 0.0 && value.abs() <= exact
}

/// A built-in's options checked by the rules the spec checker applies to them, so that a value
/// that reaches here unchecked is refused all the same; options no rule names are left to the
/// plugin, which refuses what it does not read.
fn check_builtin_options(
    kind: PluginKind,
    name: &str,
    options: &BTreeMap<String, OptionValue>,
) -> Result<(), SetupError> {
    let rules = kind.builtin_options(name).unwrap_or_default();
    for (key, value) in options {
        let Some(rule) = rules.iter().find(|rule| rule.name == key) else { continue };
        let in_range = |checked: Option<RangeError>| match checked {
            Some(range) => Err(out_of_range(key, range)),
            None => Ok(()),
        };
        match (rule.kind, value) {
            (OptionKind::Count(limit), OptionValue::Number(v)) => in_range(limit.count(*v).err())?,
            (OptionKind::Number(limit), OptionValue::Number(v))
            | (OptionKind::Length(limit), OptionValue::Length(v)) => {
                in_range(limit.check(*v).err())?;
            }
            (OptionKind::Text, OptionValue::Text(_) | OptionValue::Word(_)) => {}
            (expected, other) => return Err(wrong_kind(key, describe(expected), other)),
        }
    }
    Ok(())
}

fn describe(kind: OptionKind) -> &'static str {
    match kind {
        OptionKind::Seconds => "a duration",
        OptionKind::Count(_) => "a whole number",
        OptionKind::Number(_) => "a number",
        OptionKind::Length(_) => "a length",
        OptionKind::Resolution => "a length or an angle",
        OptionKind::Text => "text",
    }
}

/// Where a plugin is made: a built-in's factory, or a library's `create`.
enum Maker {
    Builtin(&'static Builtin),
    Library(PluginLibrary),
}

impl Maker {
    /// The maker of `choice`, with the configuration it receives: the options, then `extra`.
    fn of(
        kind: PluginKind,
        choice: &PluginChoice,
        options: &BTreeMap<String, OptionValue>,
        extra: Option<(&str, serde_json::Value)>,
    ) -> Result<(Maker, Vec<u8>), SetupError> {
        match &choice.source {
            PluginSource::Builtin(name) => {
                let builtin = builtin_plugins::find(kind, name).ok_or_else(|| {
                    SetupError::UnknownBuiltin {
                        kind: kind_name(kind),
                        name: name.clone(),
                        builtins: builtin_plugins::names(kind).join(", "),
                    }
                })?;
                check_builtin_options(kind, name, options)?;
                let config = configuration(builtin.preset, options, extra)?;
                Ok((Maker::Builtin(builtin), config))
            }
            PluginSource::Library(path) => {
                let library = PluginLibrary::open(path)?;
                Ok((Maker::Library(library), configuration(&[], options, extra)?))
            }
        }
    }
}

fn kind_name(kind: PluginKind) -> &'static str {
    match kind {
        PluginKind::Planner => "planner",
        PluginKind::Refiner => "refiner",
        PluginKind::Motion => "motion planner",
    }
}

fn wrong_factory(builtin: &Builtin) -> SetupError {
    SetupError::WrongFactory { name: builtin.name }
}

/// The planner.
pub(crate) fn planner(
    choice: &PluginChoice,
    runtime: &mut RuntimeOptions,
) -> Result<Box<dyn Planner>, SetupError> {
    let mut options = choice.options.clone();
    runtime.planner_timeout = take_seconds(&mut options, "timeout")?;
    runtime.plan_count = take_count(&mut options, "plans", &limits::PLANS)?;
    match Maker::of(PluginKind::Planner, choice, &options, None)? {
        (Maker::Builtin(builtin), config) => match builtin.factory {
            Factory::Planner(make) => Ok(make(&config)?),
            _ => Err(wrong_factory(builtin)),
        },
        (Maker::Library(library), config) => Ok(library.create_planner(&config)?),
    }
}

/// The refiner; it receives `artifact` under the `artifact` key.
pub(crate) fn refiner(
    choice: &PluginChoice,
    artifact: &SamplerArtifact,
) -> Result<Box<dyn Refiner>, SetupError> {
    let artifact = serde_json::to_value(artifact)
        .map_err(|error| SetupError::Configuration(error.to_string()))?;
    let extra = Some((ARTIFACT_KEY, artifact));
    match Maker::of(PluginKind::Refiner, choice, &choice.options, extra)? {
        (Maker::Builtin(builtin), config) => match builtin.factory {
            Factory::Refiner(make) => Ok(make(&config)?),
            _ => Err(wrong_factory(builtin)),
        },
        (Maker::Library(library), config) => Ok(library.create_refiner(&config)?),
    }
}

/// The motion planner.
pub(crate) fn motion(
    choice: &PluginChoice,
    runtime: &mut RuntimeOptions,
) -> Result<Box<dyn MotionPlanner>, SetupError> {
    let mut options = choice.options.clone();
    let resolution = |limit: &Limit, value: f64| {
        limit.check(value).map(Some).map_err(|source| out_of_range("resolution", source))
    };
    match options.remove("resolution") {
        None => {}
        Some(OptionValue::Angle(v)) => {
            runtime.angular_resolution = resolution(&limits::ANGULAR_RESOLUTION, v)?;
        }
        Some(OptionValue::Length(v)) => {
            runtime.linear_resolution = resolution(&limits::LINEAR_RESOLUTION, v)?;
        }
        Some(other) => return Err(wrong_kind("resolution", "a length or an angle", &other)),
    }
    runtime.motion_timeout = take_seconds(&mut options, "timeout")?;
    match Maker::of(PluginKind::Motion, choice, &options, None)? {
        (Maker::Builtin(builtin), config) => match builtin.factory {
            Factory::Motion(make) => Ok(make(&config)?),
            _ => Err(wrong_factory(builtin)),
        },
        (Maker::Library(library), config) => Ok(library.create_motion_planner(&config)?),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(entries: &[(&str, OptionValue)]) -> BTreeMap<String, OptionValue> {
        entries.iter().map(|(key, value)| ((*key).to_string(), value.clone())).collect()
    }

    #[test]
    fn the_configuration_is_one_json_object_with_whole_numbers_as_integers() {
        let given = options(&[
            ("draws", OptionValue::Number(2000.0)),
            ("step", OptionValue::Number(0.25)),
            ("displacement", OptionValue::Length(1.0)),
            ("command", OptionValue::Text("fd --x".to_string())),
        ]);
        let config = configuration(&[("algorithm", "topk")], &given, None).unwrap();
        assert_eq!(
            String::from_utf8(config).unwrap(),
            r#"{"algorithm":"topk","command":"fd --x","displacement":1.0,"draws":2000,"step":0.25}"#
        );
        let clash = options(&[("algorithm", OptionValue::Word("gbfs-ff".to_string()))]);
        assert!(configuration(&[("algorithm", "topk")], &clash, None).is_err());
    }

    #[test]
    fn built_in_options_are_held_to_the_spec_rules_and_unknown_names_listed() {
        let bad = options(&[("samples", OptionValue::Number(0.0))]);
        let message =
            check_builtin_options(PluginKind::Refiner, "gmm", &bad).unwrap_err().to_string();
        assert!(message.starts_with("option `samples`"), "{message}");
        let typed = options(&[("step", OptionValue::Length(0.1))]);
        let message = check_builtin_options(PluginKind::Motion, "rrt-connect", &typed)
            .unwrap_err()
            .to_string();
        assert!(message.contains("must be a number"), "{message}");

        let choice = PluginChoice {
            source: PluginSource::Builtin("astar".to_string()),
            options: BTreeMap::new(),
        };
        let Err(error) = planner(&choice, &mut RuntimeOptions::default()) else {
            panic!("an unknown built-in is refused")
        };
        assert_eq!(
            error.to_string(),
            "there is no built-in planner `astar`; built in: gbfs-ff, topk, external; or give a library path"
        );
    }
}
