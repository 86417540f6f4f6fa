//! Object types, demonstration sources, relation aliases and reference structures.

use std::collections::BTreeMap;
use std::path::PathBuf;

use crate::{OptionValue, Pose};

/// Whether bodies of a type can be moved by a robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Mobility {
    Static,
    Movable,
    /// A named pose with no geometry (a goal location): static, in relations like any object,
    /// never in a collision. AtGoal goals place one at each target pose.
    Marker,
}

/// An object type declared with `type NAME { … }`.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectType {
    pub name: String,
    pub mobility: Mobility,
    /// The static world body: present in scenes and collisions, excluded from relations.
    pub world: bool,
    /// The type's geometry as a compound of shapes placed in the object's frame.
    pub shapes: Vec<ShapePart>,
}

/// One shape of a type, placed at `origin` in the object's frame.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapePart {
    pub shape: ShapeSpec,
    pub origin: Pose,
}

/// Geometry in metres. Primitives are centred on their origin; cylinders run along z.
#[derive(Clone, Debug, PartialEq)]
pub enum ShapeSpec {
    Box { size: [f64; 3] },
    Cylinder { radius: f64, height: f64 },
    Sphere { radius: f64 },
    Mesh { path: PathBuf, mode: MeshMode },
}

/// How a mesh is used for collision.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshMode {
    ConvexHull,
    TriMesh,
}

/// Which tf frame of a ROS 2 bag is which object.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FrameObject {
    /// The tf frame id, for example `can_1`.
    pub frame: String,
    /// The object's name in the demonstration.
    pub name: String,
    /// The object's type.
    pub type_name: String,
}

/// Which tf frame of a ROS 2 bag carries a robot, and where its grasps are read from.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameRobot {
    /// The spec robot.
    pub robot: String,
    /// The tf frame of the robot's root link; the robot's mount coordinates are read from its
    /// world pose, its joints from `/joint_states` by their URDF names.
    pub base_frame: String,
    /// A `std_msgs/msg/String` topic naming the frame the robot's gripper holds (empty: none).
    pub held_topic: Option<String>,
    /// Grasps read from a gripper joint on `/joint_states` instead of a topic.
    pub grasp_joint: Option<GraspJoint>,
}

/// `grasp joint "JOINT" below VALUE`: the gripper holds an object while this joint's value is
/// below `closed_below`; the object is the movable one nearest the gripper, within the robot's
/// grab distance, when the joint closes.
#[derive(Clone, Debug, PartialEq)]
pub struct GraspJoint {
    /// The URDF name of the joint, as on `/joint_states`.
    pub joint: String,
    /// Radians or metres, as the joint's values.
    pub closed_below: f64,
}

/// How a ROS 2 bag of standard messages maps to a demonstration: which frames are the objects
/// and the robot.
#[derive(Clone, Debug, PartialEq)]
pub struct Ros2Mapping {
    /// The objects, in the order the demonstration lists them.
    pub objects: Vec<FrameObject>,
    pub robot: Option<FrameRobot>,
}

/// Where demonstrations come from.
#[derive(Clone, Debug, PartialEq)]
pub enum DemoSource {
    /// Recorded files matching a glob pattern relative to the spec's folder: lamp trajectory
    /// files, or, with a mapping, ROS 2 bags of standard messages (`files … as ros2 { … }`).
    Files { pattern: String, ros2: Option<Ros2Mapping> },
    /// A simulated demonstrator shipped with lamp.
    Simulated {
        demonstrator: String,
        count: u32,
        /// Fraction of demonstrations cut short at a random point.
        cut_fraction: f64,
        /// Number of objects of the manipulated type per demonstration.
        objects: u32,
        seed: u64,
        /// The tracking noise the recorded object poses carry (`noise D A`, `dropped F`); none
        /// by default.
        noise: TrackingNoise,
        /// The rate at which steps are recorded, in hertz (`rate R Hz`): the timed motion
        /// sampled every 1/R seconds. None: one step per state of each planned path, 10 ms apart.
        rate: Option<f64>,
        /// Demonstrator-specific options, by name.
        options: BTreeMap<String, OptionValue>,
    },
}

/// The noise of a tracking system (motion capture, a perception pipeline) that a simulated
/// demonstrator adds to every recorded object pose: at each step, each coordinate of the
/// position moves by a uniform draw from `[-position, position]`, and the orientation turns by a
/// uniform angle from `[0, rotation]` about a uniformly random axis; and with probability
/// `dropped` the tracker misses the object at that step, whose recorded pose is then the one
/// recorded at the step before.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TrackingNoise {
    /// The largest offset along each world axis, in metres.
    pub position: f64,
    /// The largest turn, in radians.
    pub rotation: f64,
    /// The chance that a tracked pose is missed at a step (`dropped F`), from 0 to 1.
    pub dropped: f64,
}

impl TrackingNoise {
    /// No noise: poses are recorded as simulated.
    pub const NONE: TrackingNoise = TrackingNoise { position: 0.0, rotation: 0.0, dropped: 0.0 };

    /// Whether recording with this noise changes nothing.
    #[must_use]
    pub fn is_none(&self) -> bool {
        self.position == 0.0 && self.rotation == 0.0 && self.dropped == 0.0
    }
}

/// `relation NAME(T1, T2) = region of S in P containing POSE`: a stable name for a learned
/// region, bound by an example pose of `secondary` in `primary`'s frame.
#[derive(Clone, Debug, PartialEq)]
pub struct RelationAlias {
    pub name: String,
    /// Argument types in the order the alias is written with.
    pub parameters: [String; 2],
    pub primary: String,
    pub secondary: String,
    pub example: Pose,
}

/// A reference structure: object poses relative to an anchor.
#[derive(Clone, Debug, PartialEq)]
pub struct Structure {
    pub name: String,
    pub placements: Vec<Placement>,
}

/// An object of a type at a pose relative to the structure's anchor.
#[derive(Clone, Debug, PartialEq)]
pub struct Placement {
    pub object: String,
    pub type_name: String,
    pub pose: Pose,
}
