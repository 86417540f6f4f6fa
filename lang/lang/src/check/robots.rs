//! `robot` declarations.

use std::collections::BTreeMap;

use super::{Checker, Declared, Dimension};
use crate::ast::{Item, Name, Quantity, RobotItem, Text};
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
        let mut fields = RobotFields::default();
        for (item, span) in &robot.items {
            self.robot_item(robot, item, *span, &mut fields, declared);
        }
        self.robot_complete(robot, &fields);
        if self.diagnostics.len() > errors_before {
            return None;
        }
        Some(lamp_spec::Robot {
            name: robot.name.text.clone(),
            urdf: fields.urdf?,
            kind: fields.kind?,
            mount: fields.mount.unwrap_or_else(lamp_spec::Pose::identity),
            parts: fields.parts,
            grab_distance: fields.grab,
            groups: fields.groups,
            configurations: fields.configurations,
            ignored_collisions: fields.ignored,
        })
    }

    /// Checks one item of a robot's block into `fields`.
    fn robot_item<'a>(
        &mut self,
        robot: &'a crate::ast::Robot,
        item: &'a RobotItem,
        span: Span,
        fields: &mut RobotFields<'a>,
        declared: &mut Declared,
    ) {
        match item {
            RobotItem::Urdf(path) => {
                if self.once(&mut fields.urdf_span, "`urdf`", span) {
                    fields.urdf = self.existing_file(path, "URDF");
                    fields.urdf_text = fields.urdf.as_ref().map(|_| path);
                }
            }
            RobotItem::Kind(name) => {
                if self.once(&mut fields.kind_span, "`kind`", span) {
                    fields.kind = self.robot_kind(name);
                }
            }
            RobotItem::Mount(pose) => {
                if self.once(&mut fields.mount_span, "`mount`", span) {
                    fields.mount = self.pose(pose);
                }
            }
            RobotItem::Part { name, link } => {
                if self.declare(&mut fields.part_names, "robot part", name) {
                    declared.relation_types.entry(name.text.clone()).or_insert(name.span);
                    fields.parts.push(lamp_spec::RobotPart {
                        type_name: name.text.clone(),
                        link: link.text.clone(),
                    });
                }
            }
            RobotItem::Grab { min, max } => {
                if self.once(&mut fields.grab_span, "`grab distance`", span) {
                    fields.grab = self.grab_range(min, max, span);
                    if fields.grab.is_some() {
                        self.places.add_grab_distance(&robot.name.text, span);
                    }
                }
            }
            RobotItem::Group { name, joints } => {
                if self.declare(&mut fields.group_names, "joint group", name) {
                    if joints.is_empty() {
                        self.missing(name.span, "the joints of this group", "List at least one joint name, e.g. `group arm = [\"shoulder_pan_joint\"]`.");
                    }
                    fields.groups.push(lamp_spec::JointGroup {
                        name: name.text.clone(),
                        joints: joints.iter().map(|joint| joint.text.clone()).collect(),
                    });
                }
            }
            RobotItem::Config { name, values } => {
                if self.declare(&mut fields.configuration_names, "configuration", name) {
                    let values = self.configuration_values(values);
                    fields
                        .configurations
                        .push(lamp_spec::NamedConfiguration { name: name.text.clone(), values });
                }
            }
            RobotItem::IgnoreCollision(first, second) => {
                fields.ignored.push((first.text.clone(), second.text.clone()));
            }
        }
    }

    fn robot_kind(&mut self, name: &Name) -> Option<lamp_spec::RobotKind> {
        match name.text.as_str() {
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
        }
    }

    /// The grab distance range `MIN .. MAX`, in metres.
    fn grab_range(&mut self, min: &Quantity, max: &Quantity, span: Span) -> Option<(f64, f64)> {
        let low = self.measure(min, Dimension::Length);
        let high = self.measure(max, Dimension::Length);
        let (low, high) = (low?, high?);
        let ok = 0.0 <= low && low <= high && high <= MAX_GRAB_DISTANCE;
        self.require(
            ok,
            span,
            "the grab distance range",
            &format!("a range `MIN .. MAX` with 0 ≤ MIN ≤ MAX ≤ {MAX_GRAB_DISTANCE} m"),
        )
        .then_some((low, high))
    }

    /// A named configuration's joint values, each joint named once.
    fn configuration_values(&mut self, values: &[(Name, Quantity)]) -> Vec<(String, f64)> {
        let mut joints = BTreeMap::new();
        let mut checked = Vec::new();
        for (joint, value) in values {
            self.declare(&mut joints, "joint value", joint);
            if let Some(value) = self.joint_value(value) {
                checked.push((joint.text.clone(), value));
            }
        }
        checked
    }

    /// What a robot's block must say, and what its kind allows.
    fn robot_complete(&mut self, robot: &crate::ast::Robot, fields: &RobotFields<'_>) {
        let name_span = robot.name.span;
        if fields.urdf_span.is_none() {
            self.missing(
                name_span,
                "the robot's `urdf`",
                "Add `urdf \"path/to/robot.urdf\"` (relative to the spec's folder).",
            );
        }
        if fields.kind_span.is_none() {
            self.missing(
                name_span,
                "the robot's `kind`",
                "Add `kind free_flying`, `kind fixed_arm` or `kind mobile_arm`.",
            );
        }
        if fields.parts.is_empty() {
            self.missing(name_span, "a robot `part`", "Name the gripper link, e.g. `part gripper = link \"gripper_link\"`: robot parts take part in relations.");
        }
        if let (Some(urdf), Some(kind)) = (fields.urdf_text, fields.kind) {
            self.robot_file_names(urdf, kind, &robot.items);
        }
        if let (Some(kind), Some(span)) = (fields.kind, fields.mount_span)
            && kind != lamp_spec::RobotKind::FixedArm
        {
            self.report(at(span, |at| SpecError::Conflict {
                    message: "only a fixed arm has a `mount`".to_string(),
                    at,
                    help: "Mobile and free-flying robots are placed per problem with `robot NAME at POSE` in the scene.".to_string(),
                }));
        }
    }

    /// A joint value: an angle (revolute) or a length (prismatic), in SI units.
    pub(crate) fn joint_value(&mut self, value: &Quantity) -> Option<f64> {
        match value.unit.map(|(unit, _)| super::units::unit_info(unit).0) {
            Some(Dimension::Length) => self.measure(value, Dimension::Length),
            _ => self.measure(value, Dimension::Angle),
        }
    }
}

/// What a robot's block says, as far as it checks, with where each once-only item first appears.
#[derive(Default)]
struct RobotFields<'a> {
    urdf: Option<std::path::PathBuf>,
    urdf_text: Option<&'a Text>,
    urdf_span: Option<Span>,
    kind: Option<lamp_spec::RobotKind>,
    kind_span: Option<Span>,
    mount: Option<lamp_spec::Pose>,
    mount_span: Option<Span>,
    grab: Option<(f64, f64)>,
    grab_span: Option<Span>,
    parts: Vec<lamp_spec::RobotPart>,
    part_names: BTreeMap<String, Span>,
    groups: Vec<lamp_spec::JointGroup>,
    group_names: BTreeMap<String, Span>,
    configurations: Vec<lamp_spec::NamedConfiguration>,
    configuration_names: BTreeMap<String, Span>,
    ignored: Vec<(String, String)>,
}
