//! Robots: a URDF plus how lamp uses it.

use std::path::PathBuf;

use crate::Pose;

/// How the robot's root is attached to the world.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RobotKind {
    /// A gripper flying freely in 6-DoF (the mount is a floating joint).
    FreeFlying,
    /// An arm bolted to the world at `Robot::mount`.
    FixedArm,
    /// A mobile base moving in the plane (x, y, yaw) carrying an arm.
    MobileArm,
}

/// A robot declared with `robot NAME { … }`.
#[derive(Clone, Debug, PartialEq)]
pub struct Robot {
    pub name: String,
    /// The URDF file, relative to the spec's folder.
    pub urdf: PathBuf,
    pub kind: RobotKind,
    /// Where a fixed arm is bolted (identity for the other kinds).
    pub mount: Pose,
    /// Links that act as pseudo objects in relations (`part gripper = link "…"`).
    pub parts: Vec<RobotPart>,
    /// Distance range (metres) between the gripper link and an object's origin at which a grab succeeds.
    pub grab_distance: Option<(f64, f64)>,
    pub groups: Vec<JointGroup>,
    pub configurations: Vec<NamedConfiguration>,
    /// Extra link pairs whose collisions are ignored, by link name.
    pub ignored_collisions: Vec<(String, String)>,
}

impl Robot {
    /// The part that grabs objects: the one named `gripper`, else the first part.
    pub fn gripper_part(&self) -> Option<&RobotPart> {
        self.parts.iter().find(|part| part.type_name == "gripper").or(self.parts.first())
    }

    /// The named configuration with this name.
    pub fn configuration(&self, name: &str) -> Option<&NamedConfiguration> {
        self.configurations.iter().find(|config| config.name == name)
    }
}

/// A robot link used as a relation participant; `type_name` is its type in relations.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RobotPart {
    pub type_name: String,
    pub link: String,
}

/// A named set of joints.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct JointGroup {
    pub name: String,
    pub joints: Vec<String>,
}

/// A named configuration: joint name → value (radians or metres), in declaration order.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedConfiguration {
    pub name: String,
    pub values: Vec<(String, f64)>,
}

/// The names a robot file defines, which a robot declaration refers to: the spec checker compares
/// the names in `part`, `group`, `config` and `ignore collision` with them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RobotNames {
    /// Every link.
    pub links: Vec<String>,
    /// Every joint, fixed ones included.
    pub joints: Vec<String>,
    /// The configuration coordinates of the robot mounted as its kind says: the mount's own
    /// (`base_x`, …) and those of the moving joints (a revolute or prismatic joint's one
    /// coordinate has the joint's name).
    pub coordinates: Vec<String>,
}
