//! Turning the spec's plugin choices (or the command line's) into plugin trait objects: built-in
//! plugins are constructed directly, libraries are opened through lamp-plugin-host.
//!
//! Options the runtime itself reads are taken out first: the planner's `timeout` and `plans`, the
//! motion planner's `resolution` (a length or an angle: the checking resolution) and `timeout`.
//! Every number taken is checked by the rule the spec checker applied (`lamp_spec::limits`), so
//! a value that reaches here unchecked is refused all the same, never turned into a panic.
//! The rest go to the plugin: built-in plugins take them typed; a library receives them as a JSON
//! object (numbers in SI units, words and text as strings), the `gmm` refiner's sampler artifact
//! included under `artifact`.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Duration;

use lamp_learn::SamplerArtifact;
use lamp_plugin_api::{MotionPlanner, Planner, Refiner};
use lamp_plugin_host::PluginLibrary;
use lamp_spec::limits::{self, Limit};
use lamp_spec::{OptionValue, PluginChoice, PluginSource};

/// Options the runtime reads itself, out of the plugin blocks.
#[derive(Clone, Debug, Default)]
pub(crate) struct RuntimeOptions {
    pub(crate) planner_timeout: Option<Duration>,
    pub(crate) plan_count: Option<usize>,
    pub(crate) linear_resolution: Option<f64>,
    pub(crate) angular_resolution: Option<f64>,
    pub(crate) motion_timeout: Option<Duration>,
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
) -> Result<Option<Duration>, String> {
    match options.remove(key) {
        None => Ok(None),
        Some(OptionValue::Duration(seconds)) => {
            limits::duration(seconds).map(Some).map_err(|error| format!("option `{key}`: {error}"))
        }
        Some(other) => Err(format!("option `{key}` must be a duration, not {other:?}")),
    }
}

/// A count within `limit`, taken out of `options`.
fn take_count(
    options: &mut BTreeMap<String, OptionValue>,
    key: &str,
    limit: &Limit,
) -> Result<Option<usize>, String> {
    match options.remove(key) {
        None => Ok(None),
        Some(OptionValue::Number(value)) => {
            let count = limit.count(value).map_err(|error| format!("option `{key}`: {error}"))?;
            usize::try_from(count).map(Some).map_err(|_| format!("option `{key}` is too large"))
        }
        Some(other) => Err(format!("option `{key}` must be a whole number, not {other:?}")),
    }
}

/// A length within `limit`, taken out of `options`.
fn take_length(
    options: &mut BTreeMap<String, OptionValue>,
    key: &str,
    limit: &Limit,
) -> Result<Option<f64>, String> {
    match options.remove(key) {
        None => Ok(None),
        Some(OptionValue::Length(value)) => {
            limit.check(value).map(Some).map_err(|error| format!("option `{key}`: {error}"))
        }
        Some(other) => Err(format!("option `{key}` must be a length, not {other:?}")),
    }
}

fn json_options(
    options: &BTreeMap<String, OptionValue>,
) -> serde_json::Map<String, serde_json::Value> {
    options
        .iter()
        .map(|(key, value)| {
            let value = match value {
                OptionValue::Number(v)
                | OptionValue::Length(v)
                | OptionValue::Angle(v)
                | OptionValue::Duration(v) => {
                    serde_json::json!(v)
                }
                OptionValue::Text(text) | OptionValue::Word(text) => serde_json::json!(text),
            };
            (key.clone(), value)
        })
        .collect()
}

fn open(path: &Path) -> Result<PluginLibrary, String> {
    PluginLibrary::open(path).map_err(|error| crate::diagnostics::render_error(&error, false))
}

/// The planner.
pub(crate) fn planner(
    choice: &PluginChoice,
    runtime: &mut RuntimeOptions,
) -> Result<Box<dyn Planner>, String> {
    let mut options = choice.options.clone();
    runtime.planner_timeout = take_seconds(&mut options, "timeout")?;
    runtime.plan_count = take_count(&mut options, "plans", &limits::PLANS)?;
    match &choice.source {
        PluginSource::Builtin(name) => match name.as_str() {
            "gbfs-ff" | "topk" => {
                no_options(name, &options)?;
                let algorithm = if name == "topk" {
                    lamp_planner_builtin::BuiltinAlgorithm::TopK
                } else {
                    lamp_planner_builtin::BuiltinAlgorithm::GbfsFf
                };
                Ok(Box::new(lamp_planner_builtin::BuiltinPlanner::new(algorithm)))
            }
            "external" => {
                let pairs: Vec<(String, String)> = options
                    .iter()
                    .map(|(key, value)| match value {
                        OptionValue::Text(text) | OptionValue::Word(text) => {
                            Ok((key.clone(), text.clone()))
                        }
                        other => {
                            Err(format!("option `{key}` of `external` must be text, not {other:?}"))
                        }
                    })
                    .collect::<Result<_, _>>()?;
                let options = lamp_planner_external::ExternalOptions::from_pairs(
                    pairs.iter().map(|(k, v)| (k.as_str(), v.as_str())),
                )
                .map_err(|error| error.to_string())?;
                Ok(Box::new(lamp_planner_external::ExternalPlanner::new(options)))
            }
            other => Err(unknown("planner", other, &["gbfs-ff", "topk", "external"])),
        },
        PluginSource::Library(path) => {
            let config = serde_json::Value::Object(json_options(&options)).to_string();
            open(path)?
                .create_planner(config.as_bytes())
                .map_err(|error| crate::diagnostics::render_error(&error, false))
        }
    }
}

/// The refiner; the `gmm` refiner samples `artifact`.
pub(crate) fn refiner(
    choice: &PluginChoice,
    artifact: &SamplerArtifact,
) -> Result<Box<dyn Refiner>, String> {
    let mut options = choice.options.clone();
    match &choice.source {
        PluginSource::Builtin(name) if name == "gmm" => {
            let mut refiner_options = lamp_refiner_gmm::RefinerOptions::default();
            if let Some(samples) = take_count(&mut options, "samples", &limits::SAMPLES)? {
                refiner_options.samples = samples;
            }
            if let Some(draws) = take_count(&mut options, "draws", &limits::DRAWS)? {
                refiner_options.draws = draws;
            }
            if let Some(length) = take_length(&mut options, "displacement", &limits::DISPLACEMENT)?
            {
                refiner_options.displacement = length;
            }
            no_options(name, &options)?;
            let refiner = lamp_refiner_gmm::GmmRefiner::new(artifact.clone(), refiner_options)
                .map_err(|error| error.to_string())?;
            Ok(Box::new(refiner))
        }
        PluginSource::Builtin(other) => Err(unknown("refiner", other, &["gmm"])),
        PluginSource::Library(path) => {
            let mut config = json_options(&options);
            let artifact = serde_json::to_value(artifact).map_err(|error| error.to_string())?;
            config.insert("artifact".to_string(), artifact);
            let config = serde_json::Value::Object(config).to_string();
            open(path)?
                .create_refiner(config.as_bytes())
                .map_err(|error| crate::diagnostics::render_error(&error, false))
        }
    }
}

/// The motion planner.
pub(crate) fn motion(
    choice: &PluginChoice,
    runtime: &mut RuntimeOptions,
) -> Result<Box<dyn MotionPlanner>, String> {
    let mut options = choice.options.clone();
    let resolution = |limit: &Limit, value: f64| {
        limit.check(value).map(Some).map_err(|error| format!("option `resolution`: {error}"))
    };
    match options.remove("resolution") {
        None => {}
        Some(OptionValue::Angle(v)) => {
            runtime.angular_resolution = resolution(&limits::ANGULAR_RESOLUTION, v)?;
        }
        Some(OptionValue::Length(v)) => {
            runtime.linear_resolution = resolution(&limits::LINEAR_RESOLUTION, v)?;
        }
        Some(other) => {
            return Err(format!("option `resolution` must be a length or an angle, not {other:?}"));
        }
    }
    runtime.motion_timeout = take_seconds(&mut options, "timeout")?;
    let text: Vec<String> = options
        .iter()
        .map(|(key, value)| match value {
            OptionValue::Number(v) => format!("{key}={v}"),
            OptionValue::Length(v) | OptionValue::Angle(v) | OptionValue::Duration(v) => {
                format!("{key}={v}")
            }
            OptionValue::Text(text) | OptionValue::Word(text) => format!("{key}={text}"),
        })
        .collect();
    match &choice.source {
        PluginSource::Builtin(name) if name == "rrt-connect" => {
            let options = lamp_motion_rrt::RrtOptions::parse(&text.join(","))
                .map_err(|error| error.to_string())?;
            Ok(Box::new(lamp_motion_rrt::RrtConnectPlanner::new(options)))
        }
        PluginSource::Builtin(other) => Err(unknown("motion planner", other, &["rrt-connect"])),
        PluginSource::Library(path) => {
            let config = serde_json::Value::Object(json_options(&options)).to_string();
            open(path)?
                .create_motion_planner(config.as_bytes())
                .map_err(|error| crate::diagnostics::render_error(&error, false))
        }
    }
}

fn no_options(name: &str, options: &BTreeMap<String, OptionValue>) -> Result<(), String> {
    match options.keys().next() {
        None => Ok(()),
        Some(key) => Err(format!("plugin `{name}` has no option `{key}`")),
    }
}

fn unknown(kind: &str, name: &str, known: &[&str]) -> String {
    format!(
        "there is no built-in {kind} `{name}`; built in: {}; or give a library path",
        known.join(", ")
    )
}
