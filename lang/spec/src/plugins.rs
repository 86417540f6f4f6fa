//! Plugin selection for the planner, the refiner and the motion planner.

use std::collections::BTreeMap;
use std::path::PathBuf;

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
