//! Plugin selection for the planner, the refiner and the motion planner.

use std::collections::BTreeMap;
use std::path::PathBuf;

use crate::limits::{self, Limit};

/// The three plugin kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum PluginKind {
    Planner,
    Refiner,
    Motion,
}

impl PluginKind {
    /// The built-in plugin used when the spec names none.
    pub fn default_builtin(self) -> &'static str {
        match self {
            PluginKind::Planner => "gbfs-ff",
            PluginKind::Refiner => "gmm",
            PluginKind::Motion => "rrt-connect",
        }
    }

    /// The built-in plugins of this kind.
    pub fn builtins(self) -> &'static [&'static str] {
        match self {
            PluginKind::Planner => &["gbfs-ff", "topk", "external"],
            PluginKind::Refiner => &["gmm"],
            PluginKind::Motion => &["rrt-connect"],
        }
    }

    /// The options lamp's runtime reads itself out of this kind's block, whichever plugin is
    /// chosen (a library plugin included): the planner's `timeout` and `plans`, the motion
    /// planner's `resolution` and `timeout`.
    pub fn runtime_options(self) -> &'static [OptionRule] {
        match self {
            PluginKind::Planner => PLANNER_RUNTIME,
            PluginKind::Refiner => &[],
            PluginKind::Motion => MOTION_RUNTIME,
        }
    }

    /// The options the built-in plugin `name` of this kind reads, beside the runtime's; `None`
    /// for a name that is not a built-in of this kind.
    pub fn builtin_options(self, name: &str) -> Option<&'static [OptionRule]> {
        Some(match (self, name) {
            (PluginKind::Planner, "gbfs-ff" | "topk") => BUILTIN_PLANNER,
            (PluginKind::Planner, "external") => EXTERNAL,
            (PluginKind::Refiner, "gmm") => GMM,
            (PluginKind::Motion, "rrt-connect") => RRT_CONNECT,
            _ => return None,
        })
    }
}

const PLANNER_RUNTIME: &[OptionRule] = &[
    OptionRule::new("timeout", OptionKind::Seconds, "the time limit of one planner call"),
    OptionRule::new("plans", OptionKind::Count(limits::PLANS), "the plans asked for (k)"),
];

const MOTION_RUNTIME: &[OptionRule] = &[
    OptionRule::new("resolution", OptionKind::Resolution, "the checking resolution"),
    OptionRule::new("timeout", OptionKind::Seconds, "the time limit of one motion call"),
];

const BUILTIN_PLANNER: &[OptionRule] = &[OptionRule::new(
    "operators",
    OptionKind::Count(limits::OPERATORS),
    "the most ground operators (default 2,000,000)",
)];

const EXTERNAL: &[OptionRule] = &[
    OptionRule::new("command", OptionKind::Text, "the Fast Downward driver command"),
    OptionRule::new("kstar-command", OptionKind::Text, "the K* driver command"),
    OptionRule::new("python", OptionKind::Text, "the Python interpreter"),
];

const GMM: &[OptionRule] = &[
    OptionRule::new("samples", OptionKind::Count(limits::SAMPLES), "candidates per action"),
    OptionRule::new("draws", OptionKind::Count(limits::DRAWS), "region draws per action"),
    OptionRule::new(
        "displacement",
        OptionKind::Length(limits::DISPLACEMENT),
        "the longest random move of a link",
    ),
];

const RRT_CONNECT: &[OptionRule] = &[
    OptionRule::new("step", OptionKind::Number(limits::RRT_STEP), "the longest extension"),
    OptionRule::new("shortcuts", OptionKind::Count(limits::SHORTCUTS), "shortcutting attempts"),
    OptionRule::new(
        "iterations",
        OptionKind::Count(limits::ITERATIONS),
        "iterations when a call sets none",
    ),
];

/// What an option's value must be.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OptionKind {
    /// A duration within [`limits::SECONDS`].
    Seconds,
    /// A plain whole number within the limit.
    Count(Limit),
    /// A plain number within the limit.
    Number(Limit),
    /// A length within the limit.
    Length(Limit),
    /// A length within [`limits::LINEAR_RESOLUTION`] or an angle within
    /// [`limits::ANGULAR_RESOLUTION`].
    Resolution,
    /// Text in quotes or a word.
    Text,
}

/// One option a plugin block may hold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OptionRule {
    pub name: &'static str,
    pub kind: OptionKind,
    /// What it sets, for messages.
    pub meaning: &'static str,
}

impl OptionRule {
    const fn new(name: &'static str, kind: OptionKind, meaning: &'static str) -> OptionRule {
        OptionRule { name, kind, meaning }
    }
}

/// Built in by name, or a shared library by path (relative to the spec's folder).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PluginSource {
    Builtin(String),
    Library(PathBuf),
}

/// One plugin with its options.
#[derive(Clone, Debug, PartialEq)]
pub struct PluginChoice {
    pub source: PluginSource,
    pub options: BTreeMap<String, OptionValue>,
}

impl PluginChoice {
    /// The default built-in plugin of a kind, without options.
    pub fn default_for(kind: PluginKind) -> PluginChoice {
        PluginChoice {
            source: PluginSource::Builtin(kind.default_builtin().to_string()),
            options: BTreeMap::new(),
        }
    }
}

/// The plugin of each kind.
#[derive(Clone, Debug, PartialEq)]
pub struct Plugins {
    pub planner: PluginChoice,
    pub refiner: PluginChoice,
    pub motion: PluginChoice,
}

/// A key/value option; quantities are converted to SI units.
#[derive(Clone, Debug, PartialEq)]
pub enum OptionValue {
    Number(f64),
    Length(f64),
    Angle(f64),
    Duration(f64),
    Text(String),
    Word(String),
}
