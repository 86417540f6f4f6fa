//! Problems: a scene and a goal.

use crate::Pose;

/// A task to solve.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    pub name: String,
    pub scene: Scene,
    pub goal: Goal,
}

/// The initial world: object instances and robot placements.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Scene {
    pub objects: Vec<ObjectInstance>,
    pub robots: Vec<RobotPlacement>,
}

/// A body of a declared type at a world pose.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectInstance {
    pub name: String,
    pub type_name: String,
    pub pose: Pose,
}

/// Where a robot starts: its base pose (mobile and free-flying kinds) and a named configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct RobotPlacement {
    pub robot: String,
    pub base: Option<Pose>,
    pub configuration: Option<String>,
}

/// What must hold at the end. The three kinds may be combined.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Goal {
    /// Invented-predicate atoms: learned relation names or aliases.
    pub atoms: Vec<GoalAtom>,
    /// World-frame target poses with tolerances.
    pub at: Vec<AtGoal>,
    /// A reference structure transcribed at an anchor.
    pub structure: Option<StructureGoal>,
}

/// `relation(arg, …)`; `relation` is a learned name (`t1_t2_k`, `clear_t1_t2_k`) or an alias.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GoalAtom {
    pub relation: String,
    pub arguments: Vec<String>,
}

/// `at OBJECT POSE within DISTANCE ANGLE`: the object's world pose within the distance and
/// the angle of `pose` at the end. It is solved through markers of `marker_type`, one where the
/// object starts ([`AtGoal::start_marker_name`]) and one at `pose` ([`AtGoal::marker_name`]),
/// and the learned relation that puts an object of the object's type onto a marker.
#[derive(Clone, Debug, PartialEq)]
pub struct AtGoal {
    pub object: String,
    pub pose: Pose,
    pub position_tolerance: f64,
    pub angle_tolerance: f64,
    /// The spec's marker type (its only one).
    pub marker_type: String,
}

impl AtGoal {
    /// The name of the marker at the target: `goal_<object>`.
    pub fn marker_name(&self) -> String {
        marker_name(&self.object)
    }

    /// The name of the marker where the object starts: `start_<object>`.
    pub fn start_marker_name(&self) -> String {
        start_marker_name(&self.object)
    }
}

/// The name of the marker an AtGoal on `object` places at its target.
pub fn marker_name(object: &str) -> String {
    format!("goal_{object}")
}

/// The name of the marker an AtGoal on `object` places where the object starts.
pub fn start_marker_name(object: &str) -> String {
    format!("start_{object}")
}

/// `structure NAME at ANCHOR offset POSE`.
#[derive(Clone, Debug, PartialEq)]
pub struct StructureGoal {
    pub structure: String,
    pub anchor: String,
    pub offset: Pose,
}
