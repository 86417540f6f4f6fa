//! What a plugin says it is: its kind and its self-description, as the host checked them.

use std::fmt;

/// What a plugin is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PluginKind {
    /// A task planner.
    Planner,
    /// A refiner.
    Refiner,
    /// A motion planner.
    MotionPlanner,
}

impl fmt::Display for PluginKind {
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        formatter.write_str(match self {
            PluginKind::Planner => "planner",
            PluginKind::Refiner => "refiner",
            PluginKind::MotionPlanner => "motion planner",
        })
    }
}

/// A plugin's self-description, read and checked before any of its code ran.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PluginInfo {
    /// Its kind.
    pub kind: PluginKind,
    /// Its name.
    pub name: String,
    /// Its own version.
    pub version: String,
    /// One line on what it does.
    pub description: String,
    /// The ABI major it was built for (equal to the host's).
    pub abi_major: u32,
    /// The ABI minor it was built for (not newer than the host's).
    pub abi_minor: u32,
    /// Where it came from: the library's path, or `in-process`.
    pub origin: String,
}
