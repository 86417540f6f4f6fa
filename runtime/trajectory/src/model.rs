//! The in-memory data model of a trajectory file: the per-file header and one step per message.
//!
//! Steps are compact: bodies and robots appear in the order the header lists them, so a step
//! carries only numbers, and held bodies are indices into the header's body list.

use std::collections::{BTreeMap, BTreeSet};

use nalgebra::Isometry3;

/// A body (object) that appears in a file: its unique name and the name of its object type.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BodyDescription {
    /// Unique within the file, for example `can_0`.
    pub name: String,
    /// The object type, for example `can`; the learner pairs bodies by type.
    pub type_name: String,
}

/// A robot that appears in a file: its name, the names of its configuration coordinates in the
/// order a step stores them, and the names of its grippers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RobotDescription {
    /// Unique within the file.
    pub name: String,
    /// One name per configuration coordinate, in storage order (the robot crate owns the layout).
    pub coordinates: Vec<String>,
    /// One name per gripper; each step says which body each gripper holds.
    pub grippers: Vec<String>,
}

/// What a file is about and what appears in it; written once, before the first step.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TrajectoryHeader {
    /// The spec or domain name, for example `packing`.
    pub domain: String,
    /// The seed the producer ran with.
    pub seed: u64,
    /// Free provenance, for example `demonstrator`, `demo_index`, `cut_at`; sorted by key.
    pub provenance: BTreeMap<String, String>,
    /// Every body, in the order each step stores its pose.
    pub bodies: Vec<BodyDescription>,
    /// Every robot, in the order each step stores its state.
    pub robots: Vec<RobotDescription>,
}

/// The state of one robot at one step.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotState {
    /// Configuration values in the order of the robot's `coordinates` (metres and radians).
    pub positions: Vec<f64>,
    /// For each of the robot's grippers, the index in the header's body list of the body it
    /// holds, or `None`.
    pub held: Vec<Option<usize>>,
}

/// One time step: every body's world pose and every robot's state.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// Time since the start of the recording, in nanoseconds (exact; see [`Step::time_seconds`]).
    pub time_nanoseconds: u64,
    /// World pose of each body, in the header's body order.
    pub body_poses: Vec<Isometry3<f64>>,
    /// State of each robot, in the header's robot order.
    pub robots: Vec<RobotState>,
}

impl Step {
    /// The step's time in seconds (rounded to the nearest `f64`).
    pub fn time_seconds(&self) -> f64 {
        // Precision loss only beyond 2^53 ns (about 104 days), far longer than any recording.
        #[allow(clippy::cast_precision_loss)]
        let seconds = self.time_nanoseconds as f64 * 1e-9;
        seconds
    }

    /// Whether some gripper holds something else in `next` than in this step: a grasp or a
    /// release between the two, which ends one motion and begins the next.
    pub fn grasp_changes_to(&self, next: &Step) -> bool {
        self.robots.iter().zip(&next.robots).any(|(a, b)| a.held != b.held)
    }
}

/// A whole file in memory: its header and all its steps.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// The file's header.
    pub header: TrajectoryHeader,
    /// Every step, in time order.
    pub steps: Vec<Step>,
}

impl TrajectoryHeader {
    /// The index of the body with this name.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|body| body.name == name)
    }

    /// The index of the robot with this name.
    pub fn robot_index(&self, name: &str) -> Option<usize> {
        self.robots.iter().position(|robot| robot.name == name)
    }

    /// Checks that every name can be stored and read back unambiguously: names are non-empty,
    /// contain no whitespace or control characters (the metadata record separates them by
    /// spaces and newlines), and are unique where they must be.
    pub(crate) fn check(&self) -> Result<(), String> {
        check_text("domain", &self.domain, true)?;
        for key in self.provenance.keys() {
            check_name("provenance key", key)?;
        }
        let mut body_names = BTreeSet::new();
        for body in &self.bodies {
            check_name("body name", &body.name)?;
            check_name("body type name", &body.type_name)?;
            if !body_names.insert(body.name.as_str()) {
                return Err(format!("body `{}` is listed twice", body.name));
            }
        }
        let mut robot_names = BTreeSet::new();
        for robot in &self.robots {
            check_name("robot name", &robot.name)?;
            if !robot_names.insert(robot.name.as_str()) {
                return Err(format!("robot `{}` is listed twice", robot.name));
            }
            check_unique_names(&robot.name, "coordinate", &robot.coordinates)?;
            check_unique_names(&robot.name, "gripper", &robot.grippers)?;
        }
        Ok(())
    }
}

fn check_unique_names(robot: &str, what: &str, names: &[String]) -> Result<(), String> {
    let mut seen = BTreeSet::new();
    for name in names {
        check_name(what, name)?;
        if !seen.insert(name.as_str()) {
            return Err(format!("robot `{robot}` lists {what} `{name}` twice"));
        }
    }
    Ok(())
}

fn check_name(what: &str, name: &str) -> Result<(), String> {
    check_text(what, name, false)
}

/// A name may not be empty or contain whitespace; the domain may contain inner spaces.
fn check_text(what: &str, text: &str, spaces_allowed: bool) -> Result<(), String> {
    if text.is_empty() {
        return Err(format!("the {what} is empty"));
    }
    let bad = text.chars().find(|c| c.is_control() || (!spaces_allowed && c.is_whitespace()));
    match bad {
        Some(c) => {
            Err(format!("the {what} `{}` contains the character {c:?}", text.escape_debug()))
        }
        None => Ok(()),
    }
}
