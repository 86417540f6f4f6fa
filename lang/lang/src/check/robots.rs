//! `robot` declarations.

use std::collections::BTreeMap;

use super::{Checker, Declared, Dimension};
use crate::ast::{Item, RobotItem};
use crate::diagnostics::{SpecError, at, did_you_mean};
use crate::source::Span;
use lamp_spec::limits::MAX_GRAB_DISTANCE;

const ROBOT_KINDS: [&str; 3] = ["free_flying", "fixed_arm", "mobile_arm"];

impl Checker<'_> {
    pub(crate) fn robots(
        &mut self,
        items: &[Item],
        declared: &mut Declared,
    ) -> Vec<lamp_spec::Robot> {
        let mut seen = BTreeMap::new();
        let mut robots = Vec::new();
        for item in items {
            let Item::Robot(robot) = item else { continue };
            let new = self.declare(&mut seen, "robot", &robot.name);
            match self.robot(robot, declared) {
                Some(checked) if new => {
                    declared.robots.insert(checked.name.clone(), checked.clone());
                    robots.push(checked);
                }
                Some(_) => {}
                None => {
                    declared.invalid_robots.insert(robot.name.text.clone());
                }
            }
        }
        robots
    }

    fn robot(
        &mut self,
        robot: &crate::ast::Robot,
        declared: &mut Declared,
    ) -> Option<lamp_spec::Robot> {
        let errors_before = self.diagnostics.len();
        let mut urdf = None;
        let mut urdf_span = None;
        let mut kind = None;
        let mut kind_span = None;
        let mut mount = None;
        let mut mount_span: Option<Span> = None;
        let mut grab = None;
        let mut grab_span = None;
        let mut parts = Vec::new();
        let mut part_names = BTreeMap::new();
        let mut groups = Vec::new();
        let mut group_names = BTreeMap::new();
        let mut configurations = Vec::new();
        let mut configuration_names = BTreeMap::new();
        let mut ignored = Vec::new();
        let mut urdf_text = None;

        for (item, span) in &robot.items {
            match item {
                RobotItem::Urdf(path) => {
                    if self.once(&mut urdf_span, "`urdf`", *span) {
                        urdf = self.existing_file(path, "URDF");
                        urdf_text = urdf.as_ref().map(|_| path);
                    }
                }
                RobotItem::Kind(name) => {
                    if self.once(&mut kind_span, "`kind`", *span) {
                        kind = match name.text.as_str() {
                            "free_flying" => Some(lamp_spec::RobotKind::FreeFlying),
                            "fixed_arm" => Some(lamp_spec::RobotKind::FixedArm),
                            "mobile_arm" => Some(lamp_spec::RobotKind::MobileArm),
                            other => {
                                self.report(at(name.span, |at| SpecError::UnknownWord {
                                    what: "robot kind",
                                    word: other.to_string(),
                                    at,
                                    expected: ROBOT_KINDS.join(", "),
                                    help: did_you_mean(other, ROBOT_KINDS),
                                }));
                                None
                            }
                        };
                    }
                }
                RobotItem::Mount(pose) => {
                    if self.once(&mut mount_span, "`mount`", *span) {
                        mount = self.pose(pose);
                    }
                }
                RobotItem::Part { name, link } => {
                    if self.declare(&mut part_names, "robot part", name) {
                        declared.relation_types.entry(name.text.clone()).or_insert(name.span);
                        parts.push(lamp_spec::RobotPart {
                            type_name: name.text.clone(),
                            link: link.text.clone(),
                        });
                    }
                }
                RobotItem::Grab { min, max } => {
                    if self.once(&mut grab_span, "`grab distance`", *span) {
                        let low = self.measure(min, Dimension::Length);
                        let high = self.measure(max, Dimension::Length);
                        if let (Some(low), Some(high)) = (low, high) {
                            let ok = 0.0 <= low && low <= high && high <= MAX_GRAB_DISTANCE;
                            if self.require(
                                ok,
                                *span,
                                "the grab distance range",
                                &format!(
                                    "a range `MIN .. MAX` with 0 ≤ MIN ≤ MAX ≤ {MAX_GRAB_DISTANCE} m"
                                ),
                            ) {
                                grab = Some((low, high));
                                self.places.add_grab_distance(&robot.name.text, *span);
                            }
                        }
                    }
                }
                RobotItem::Group { name, joints } => {
                    if self.declare(&mut group_names, "joint group", name) {
                        if joints.is_empty() {
                            self.missing(name.span, "the joints of this group", "List at least one joint name, e.g. `group arm = [\"shoulder_pan_joint\"]`.");
                        }
                        groups.push(lamp_spec::JointGroup {
                            name: name.text.clone(),
                            joints: joints.iter().map(|joint| joint.text.clone()).collect(),
                        });
                    }
                }
                RobotItem::Config { name, values } => {
                    if self.declare(&mut configuration_names, "configuration", name) {
                        let mut joints = BTreeMap::new();
                        let mut checked = Vec::new();
                        for (joint, value) in values {
                            self.declare(&mut joints, "joint value", joint);
                            if let Some(value) = self.joint_value(value) {
                                checked.push((joint.text.clone(), value));
                            }
                        }
                        configurations.push(lamp_spec::NamedConfiguration {
                            name: name.text.clone(),
                            values: checked,
                        });
                    }
                }
                RobotItem::IgnoreCollision(first, second) => {
                    ignored.push((first.text.clone(), second.text.clone()));
                }
            }
        }

        let name_span = robot.name.span;
        if urdf_span.is_none() {
            self.missing(
                name_span,
                "the robot's `urdf`",
                "Add `urdf \"path/to/robot.urdf\"` (relative to the spec's folder).",
            );
        }
        if kind_span.is_none() {
            self.missing(
                name_span,
                "the robot's `kind`",
                "Add `kind free_flying`, `kind fixed_arm` or `kind mobile_arm`.",
            );
        }
        if parts.is_empty() {
            self.missing(name_span, "a robot `part`", "Name the gripper link, e.g. `part gripper = link \"gripper_link\"`: robot parts take part in relations.");
        }
        if let (Some(urdf), Some(kind)) = (urdf_text, kind) {
            self.robot_file_names(urdf, kind, &robot.items);
        }
        if let (Some(kind), Some(span)) = (kind, mount_span)
            && kind != lamp_spec::RobotKind::FixedArm
        {
            self.report(at(span, |at| SpecError::Conflict {
                    message: "only a fixed arm has a `mount`".to_string(),
                    at,
                    help: "Mobile and free-flying robots are placed per problem with `robot NAME at POSE` in the scene.".to_string(),
                }));
        }
        if self.diagnostics.len() > errors_before {
            return None;
        }
        Some(lamp_spec::Robot {
            name: robot.name.text.clone(),
            urdf: urdf?,
            kind: kind?,
            mount: mount.unwrap_or_else(lamp_spec::Pose::identity),
            parts,
            grab_distance: grab,
            groups,
            configurations,
            ignored_collisions: ignored,
        })
    }

    /// A joint value: an angle (revolute) or a length (prismatic), in SI units.
    pub(crate) fn joint_value(&mut self, value: &crate::ast::Quantity) -> Option<f64> {
        match value.unit.map(|(unit, _)| super::units::unit_info(unit).0) {
            Some(Dimension::Length) => self.measure(value, Dimension::Length),
            _ => self.measure(value, Dimension::Angle),
        }
    }
}
