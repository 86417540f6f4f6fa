//! The checked spec: plain data that the compiler and the runtime consume.
//!
//! A `Spec` is produced by `lamp-lang` only when a `.lamp` file has no errors.
//! Every quantity is in SI units (metres, radians, seconds), poses are
//! `nalgebra::Isometry3<f64>`, and paths are relative to the spec's folder as written.
//! Lists keep declaration order; maps are ordered by key.

mod learning;
pub mod limits;
mod plugins;
mod problem;
mod robot;
mod world;

pub use learning::{Learning, PairSettings, Switch, TypePair};
pub use plugins::{
    OptionKind, OptionRule, OptionValue, PluginChoice, PluginKind, PluginSource, Plugins,
};
pub use problem::{
    AtGoal, Goal, GoalAtom, ObjectInstance, Problem, RobotPlacement, Scene, StructureGoal,
    marker_name, start_marker_name,
};
pub use robot::{JointGroup, NamedConfiguration, Robot, RobotKind, RobotNames, RobotPart};
pub use world::{
    DemoSource, FrameObject, FrameRobot, GraspJoint, MeshMode, Mobility, ObjectType, Placement,
    RelationAlias, Ros2Mapping, ShapePart, ShapeSpec, Structure, TrackingNoise,
};

use std::collections::BTreeMap;

/// A rigid transform in SI units.
pub type Pose = nalgebra::Isometry3<f64>;

/// A checked `.lamp` specification.
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    /// The domain name (`domain NAME`).
    pub domain: String,
    /// The one seed that drives all randomness.
    pub seed: u64,
    pub robots: Vec<Robot>,
    pub object_types: Vec<ObjectType>,
    pub demonstrations: Vec<DemoSource>,
    pub learning: Learning,
    pub relation_aliases: Vec<RelationAlias>,
    pub structures: Vec<Structure>,
    pub problems: Vec<Problem>,
    pub plugins: Plugins,
}

impl Spec {
    /// The robot with this name.
    pub fn robot(&self, name: &str) -> Option<&Robot> {
        self.robots.iter().find(|robot| robot.name == name)
    }

    /// The object type with this name.
    pub fn object_type(&self, name: &str) -> Option<&ObjectType> {
        self.object_types.iter().find(|ty| ty.name == name)
    }

    /// The structure with this name.
    pub fn structure(&self, name: &str) -> Option<&Structure> {
        self.structures.iter().find(|structure| structure.name == name)
    }

    /// The problem with this name.
    pub fn problem(&self, name: &str) -> Option<&Problem> {
        self.problems.iter().find(|problem| problem.name == name)
    }

    /// Every type that can take part in a relation: robot parts first (they are always the
    /// primary of a pair), then object types that are not the static world, by name.
    pub fn relation_types(&self) -> BTreeMap<String, RelationRole> {
        let mut types = BTreeMap::new();
        for robot in &self.robots {
            for part in &robot.parts {
                types.insert(part.type_name.clone(), RelationRole::RobotPart);
            }
        }
        for ty in self.object_types.iter().filter(|ty| !ty.world) {
            types.insert(ty.name.clone(), RelationRole::Object(ty.mobility));
        }
        types
    }
}

/// How a type takes part in relations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RelationRole {
    /// A named link of a robot (gripper, base).
    RobotPart,
    /// An object type with its mobility.
    Object(Mobility),
}
