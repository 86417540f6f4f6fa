//! The names a robot block takes from its robot file (links of parts and ignored pairs, joints of
//! groups and configurations), checked against the names the loader reads from that file.

use super::Checker;
use crate::ast::{RobotItem, Text};
use crate::diagnostics::{SpecError, at, did_you_mean};
use crate::source::Span;

/// How many of a robot file's names a help text lists when none is close to a misspelt one.
const MAX_LISTED_NAMES: usize = 12;

/// Where a joint name is used, which decides what it may name.
#[derive(Clone, Copy)]
enum JointUse {
    /// A joint group takes joints and coordinates (`base_x`, …).
    Group,
    /// A configuration sets one value per name: coordinates only (a revolute or prismatic
    /// joint's coordinate has the joint's name).
    Config,
}

impl Checker<'_> {
    /// Checks every link and joint name of a robot block against the robot file `urdf`, loaded
    /// as a robot of `kind`; a file that does not load is reported at its path.
    pub(crate) fn robot_file_names(
        &mut self,
        urdf: &Text,
        kind: lamp_spec::RobotKind,
        items: &[(RobotItem, Span)],
    ) {
        let full = self.base_dir.join(self.spec_path(urdf));
        let names = match self.loader.robot_names(&full, kind) {
            Ok(Some(names)) => names,
            Ok(None) => return,
            Err(reason) => {
                self.report(at(urdf.span, |at| SpecError::RobotFile {
                    path: urdf.text.clone(),
                    reason,
                    at,
                }));
                return;
            }
        };
        let file = urdf.text.as_str();
        for (item, _) in items {
            match item {
                RobotItem::Part { link, .. } => self.link_name(&names, file, link),
                RobotItem::IgnoreCollision(first, second) => {
                    self.link_name(&names, file, first);
                    self.link_name(&names, file, second);
                }
                RobotItem::Group { joints, .. } => {
                    for joint in joints {
                        self.joint_name(&names, file, &joint.text, joint.span, JointUse::Group);
                    }
                }
                RobotItem::Config { values, .. } => {
                    for (joint, _) in values {
                        self.joint_name(&names, file, &joint.text, joint.span, JointUse::Config);
                    }
                }
                RobotItem::Urdf(_)
                | RobotItem::Kind(_)
                | RobotItem::Mount(_)
                | RobotItem::Grab { .. } => {}
            }
        }
    }

    /// Checks that `joint` is a joint of `robot`'s file with one coordinate, whose value is on
    /// `/joint_states` under this name (a `grasp joint` of a ros2 mapping). A file that does not
    /// load was reported with the robot.
    pub(crate) fn grasp_joint_name(&mut self, robot: &lamp_spec::Robot, joint: &Text) {
        let full = self.base_dir.join(&robot.urdf);
        let Ok(Some(names)) = self.loader.robot_names(&full, robot.kind) else { return };
        let file = robot.urdf.display().to_string();
        self.joint_name(&names, &file, &joint.text, joint.span, JointUse::Config);
    }

    fn link_name(&mut self, names: &lamp_spec::RobotNames, file: &str, link: &Text) {
        if names.links.contains(&link.text) {
            return;
        }
        let help = names_help(&link.text, &names.links, "links", file);
        self.report(at(link.span, |at| SpecError::UnknownLink {
            name: link.text.clone(),
            file: file.to_string(),
            at,
            help,
        }));
    }

    fn joint_name(
        &mut self,
        names: &lamp_spec::RobotNames,
        file: &str,
        name: &str,
        span: Span,
        usage: JointUse,
    ) {
        let is_joint = names.joints.iter().any(|joint| joint == name);
        let is_coordinate = names.coordinates.iter().any(|coordinate| coordinate == name);
        match usage {
            JointUse::Group if is_joint || is_coordinate => return,
            JointUse::Config if is_coordinate => return,
            JointUse::Config if is_joint => {
                self.report(at(span, |at| SpecError::Conflict {
                    message: format!("joint `{name}` of `{file}` has no single value to set"),
                    at,
                    help: "A fixed joint has no value, and a joint that moves in several coordinates is set through the coordinates' own names.".to_string(),
                }));
                return;
            }
            JointUse::Group | JointUse::Config => {}
        }
        let (candidates, label, what) = match usage {
            JointUse::Group => {
                let mut both = names.joints.clone();
                both.extend(
                    names.coordinates.iter().filter(|c| !names.joints.contains(c)).cloned(),
                );
                (both, "not a joint or coordinate of the robot file", "joints and coordinates")
            }
            JointUse::Config => (
                names.coordinates.clone(),
                "not a joint coordinate of the robot file",
                "coordinates",
            ),
        };
        let help = names_help(name, &candidates, what, file);
        self.report(at(span, |at| SpecError::UnknownJoint {
            name: name.to_string(),
            file: file.to_string(),
            at,
            label,
            help,
        }));
    }
}

/// "Did you mean …?" when a name of the file is close, else the file's names (the first few).
fn names_help(word: &str, candidates: &[String], what: &str, file: &str) -> String {
    if let Some(suggestion) = did_you_mean(word, candidates.iter().map(String::as_str)) {
        return suggestion;
    }
    if candidates.is_empty() {
        return format!("`{file}` defines no {what}.");
    }
    let shown: Vec<String> =
        candidates.iter().take(MAX_LISTED_NAMES).map(|name| format!("`{name}`")).collect();
    let more = candidates.len().saturating_sub(MAX_LISTED_NAMES);
    let more = if more > 0 { format!(" and {more} more") } else { String::new() };
    format!("The {what} of `{file}` are {}{more}.", shown.join(", "))
}
