//! Object types, demonstration sources, learning settings, relation aliases and structures.

use std::collections::{BTreeMap, BTreeSet};

use super::{Checker, Declared, Dimension};
use crate::ast::{DemoSource, Item, LearnItem, Name, Ros2Object, Ros2Robot, Text, TypeItem, Value};
use crate::diagnostics::{SpecError, at, did_you_mean};
use crate::source::Span;
use lamp_spec::limits;

/// The simulated demonstrators that ship with lamp.
pub(crate) const DEMONSTRATORS: [&str; 5] = ["cafe", "dinner", "jenga", "keva", "packing"];

impl Checker<'_> {
    pub(crate) fn object_types(
        &mut self,
        items: &[Item],
        declared: &mut Declared,
    ) -> Vec<lamp_spec::ObjectType> {
        let mut types = Vec::new();
        // Robot parts and object types share one namespace: both name types in relations.
        let mut seen = declared.relation_types.clone();
        for item in items {
            let Item::Type(decl) = item else { continue };
            if !self.declare(&mut seen, "type", &decl.name) {
                continue;
            }
            let errors_before = self.diagnostics.len();
            let mut mobility = None;
            let mut mobility_span = None;
            let mut world = false;
            let mut world_span = None;
            let mut shapes = Vec::new();
            for (item, span) in &decl.items {
                let (shape, origin) = match item {
                    TypeItem::Mobility(word) => {
                        if self.once(&mut mobility_span, "`movable`/`static`/`marker`", *span) {
                            mobility = Some(match word.text.as_str() {
                                "movable" => lamp_spec::Mobility::Movable,
                                "marker" => lamp_spec::Mobility::Marker,
                                _ => lamp_spec::Mobility::Static,
                            });
                        }
                        continue;
                    }
                    TypeItem::World => {
                        world = self.once(&mut world_span, "`world`", *span);
                        continue;
                    }
                    TypeItem::Box { size, at } => {
                        let size = self.length_vector(size).filter(|size| {
                            let ok = size.iter().all(|side| *side > 0.0);
                            self.require(ok, *span, "a box size", "positive along every axis")
                        });
                        (size.map(|size| lamp_spec::ShapeSpec::Box { size }), at)
                    }
                    TypeItem::Cylinder { radius, height, at } => {
                        let radius = self.positive_length(radius, "a cylinder radius");
                        let height = self.positive_length(height, "a cylinder height");
                        let shape = radius.zip(height).map(|(radius, height)| {
                            lamp_spec::ShapeSpec::Cylinder { radius, height }
                        });
                        (shape, at)
                    }
                    TypeItem::Sphere { radius, at } => {
                        let radius = self.positive_length(radius, "a sphere radius");
                        (radius.map(|radius| lamp_spec::ShapeSpec::Sphere { radius }), at)
                    }
                    TypeItem::Mesh { path, mode, at } => {
                        let path = self.existing_file(path, "mesh");
                        let mode = match mode.as_ref().map(|mode| mode.text.as_str()) {
                            Some("trimesh") => lamp_spec::MeshMode::TriMesh,
                            _ => lamp_spec::MeshMode::ConvexHull,
                        };
                        (path.map(|path| lamp_spec::ShapeSpec::Mesh { path, mode }), at)
                    }
                };
                let origin = match origin {
                    Some(pose) => self.pose(pose),
                    None => Some(lamp_spec::Pose::identity()),
                };
                if let (Some(shape), Some(origin)) = (shape, origin) {
                    shapes.push(lamp_spec::ShapePart { shape, origin });
                }
            }
            let name_span = decl.name.span;
            if mobility_span.is_none() {
                self.missing(
                    name_span,
                    "the type's mobility",
                    "Add `movable` (robots may move it), `static`, or `marker` (a pose with no geometry).",
                );
            }
            let shaped = |(item, _): &&(TypeItem, Span)| {
                !matches!(item, TypeItem::Mobility(_) | TypeItem::World)
            };
            if mobility == Some(lamp_spec::Mobility::Marker) {
                if let Some((_, span)) = decl.items.iter().find(shaped) {
                    self.report(at(*span, |at| SpecError::Conflict {
                        message: "a marker has no geometry".to_string(),
                        at,
                        help: "Remove the shape: a marker is a named pose that nothing collides with; declare a `static` type for a body with a shape.".to_string(),
                    }));
                }
                if let Some(span) = world_span {
                    self.report(at(span, |at| SpecError::Conflict {
                        message: "a marker cannot be the static world".to_string(),
                        at,
                        help: "Write `static world` on the type of the floor or ground every scene stands on.".to_string(),
                    }));
                }
            } else if !decl.items.iter().any(|item| shaped(&item)) {
                self.missing(name_span, "the type's geometry", "Add a shape, e.g. `box size (0.1, 0.1, 0.1) m` or `cylinder radius 0.03 m height 0.15 m`.");
            }
            if let (Some(lamp_spec::Mobility::Movable), Some(span)) = (mobility, world_span) {
                self.report(at(span, |at| SpecError::Conflict {
                    message: "the static world cannot be movable".to_string(),
                    at,
                    help: "Write `static world`: the world body is the fixed support every scene stands on.".to_string(),
                }));
            }
            let Some(mobility) = mobility else { continue };
            declared.object_types.insert(
                decl.name.text.clone(),
                (name_span, mobility == lamp_spec::Mobility::Movable),
            );
            if !world {
                declared.relation_types.insert(decl.name.text.clone(), name_span);
            }
            if mobility == lamp_spec::Mobility::Marker {
                declared.marker_types.insert(decl.name.text.clone(), name_span);
            }
            if self.diagnostics.len() == errors_before {
                types.push(lamp_spec::ObjectType {
                    name: decl.name.text.clone(),
                    mobility,
                    world,
                    shapes,
                });
            }
        }
        types
    }

    pub(crate) fn demonstrations(
        &mut self,
        items: &[Item],
        declared: &Declared,
    ) -> Vec<lamp_spec::DemoSource> {
        let mut sources = Vec::new();
        for item in items {
            let Item::Demonstrations { sources: written } = item else { continue };
            for source in written {
                match source {
                    DemoSource::Files(pattern) => {
                        if let Some(pattern) = self.demo_files(pattern) {
                            sources.push(lamp_spec::DemoSource::Files { pattern, ros2: None });
                        }
                    }
                    DemoSource::Ros2 { pattern, objects, robots } => {
                        let mapping = self.ros2_mapping(pattern, objects, robots, declared);
                        if let (Some(pattern), Some(mapping)) = (self.demo_files(pattern), mapping)
                        {
                            for object in objects {
                                let end =
                                    object.frame.as_ref().map_or(object.name.span, |f| f.span);
                                let span = Span { end: end.end, ..object.type_name.span };
                                self.places.add_mapped_object(&pattern, &object.name.text, span);
                            }
                            let ros2 = Some(mapping);
                            sources.push(lamp_spec::DemoSource::Files { pattern, ros2 });
                        }
                    }
                    DemoSource::Simulate { demonstrator, options, noise } => {
                        if let Some(source) = self.simulated(demonstrator, options, noise) {
                            sources.push(source);
                        }
                    }
                }
            }
        }
        sources
    }

    /// The pattern of a `files` source, relative to the spec's folder, if any file matches it.
    fn demo_files(&mut self, pattern: &Text) -> Option<String> {
        let path = self.spec_path(pattern);
        if self.glob(&path).is_empty() {
            self.report(at(pattern.span, |at| SpecError::MissingFile {
                path: pattern.text.clone(),
                at,
                help: "No file matches this pattern (relative to the spec's folder); `*` matches within one folder.".to_string(),
            }));
            return None;
        }
        Some(path.display().to_string())
    }

    /// The frame mapping of a `files … as ros2 { … }` source: declared types and robot, each
    /// object and frame once, at least one object, at most one robot.
    fn ros2_mapping(
        &mut self,
        pattern: &Text,
        objects: &[Ros2Object],
        robots: &[Ros2Robot],
        declared: &Declared,
    ) -> Option<lamp_spec::Ros2Mapping> {
        let errors_before = self.diagnostics.len();
        let (mut names, mut frames) = (BTreeMap::new(), BTreeMap::new());
        let mut mapped = Vec::new();
        for object in objects {
            let frame = object.frame.as_ref().map_or_else(
                || object.name.clone(),
                |frame| Name { text: frame.text.clone(), span: frame.span },
            );
            let known = self.object_type(declared, &object.type_name);
            if known
                & self.declare(&mut names, "object", &object.name)
                & self.declare(&mut frames, "tf frame", &frame)
            {
                mapped.push(lamp_spec::FrameObject {
                    frame: frame.text,
                    name: object.name.text.clone(),
                    type_name: object.type_name.text.clone(),
                });
            }
        }
        if objects.is_empty() {
            self.missing(
                pattern.span,
                "an `object` of the ros2 mapping",
                "Map each tf frame to an object: `object can can1 frame \"can_1\"`.",
            );
        }
        let mut robot = None;
        let mut first = None;
        for written in robots {
            if !self.once(&mut first, "the robot of a ros2 mapping", written.robot.span) {
                continue;
            }
            let name = &written.robot;
            if !declared.robots.contains_key(&name.text) {
                if !declared.invalid_robots.contains(&name.text) {
                    let help = did_you_mean(&name.text, declared.robots.keys().map(String::as_str));
                    self.report(at(name.span, |at| SpecError::UnknownRobot {
                        name: name.text.clone(),
                        at,
                        help,
                    }));
                }
                continue;
            }
            if let Some(topic) = written.held_topic.as_ref().filter(|t| !t.text.starts_with('/')) {
                self.report(at(topic.span, |at| SpecError::OutOfRange {
                    what: "the held topic".to_string(),
                    expected: "a ROS topic name starting with `/`".to_string(),
                    at,
                }));
                continue;
            }
            let grasp_joint = written.grasp_joint.as_ref().and_then(|(joint, value, span)| {
                let spec_robot = &declared.robots[&name.text];
                if spec_robot.grab_distance.is_none() {
                    self.report(at(*span, |at| SpecError::Conflict {
                        message: format!(
                            "robot `{}` has no grab distance to find the grasped object by",
                            name.text
                        ),
                        at,
                        help: "Add `grab distance MIN .. MAX` to the robot: when the joint closes, the gripper holds the movable object nearest it within that distance.".to_string(),
                    }));
                }
                self.grasp_joint_name(spec_robot, joint);
                let closed_below = self.joint_value(value)?;
                Some(lamp_spec::GraspJoint { joint: joint.text.clone(), closed_below })
            });
            let frame = Name { text: written.frame.text.clone(), span: written.frame.span };
            if self.declare(&mut frames, "tf frame", &frame) {
                robot = Some(lamp_spec::FrameRobot {
                    robot: name.text.clone(),
                    base_frame: frame.text,
                    held_topic: written.held_topic.as_ref().map(|topic| topic.text.clone()),
                    grasp_joint,
                });
            }
        }
        (self.diagnostics.len() == errors_before)
            .then_some(lamp_spec::Ros2Mapping { objects: mapped, robot })
    }

    fn simulated(
        &mut self,
        demonstrator: &crate::ast::Name,
        options: &[crate::ast::OptionEntry],
        noise_entries: &[crate::ast::NoiseEntry],
    ) -> Option<lamp_spec::DemoSource> {
        let errors_before = self.diagnostics.len();
        if !DEMONSTRATORS.contains(&demonstrator.text.as_str()) {
            self.report(at(demonstrator.span, |at| SpecError::UnknownWord {
                what: "demonstrator",
                word: demonstrator.text.clone(),
                at,
                expected: DEMONSTRATORS.join(", "),
                help: did_you_mean(&demonstrator.text, DEMONSTRATORS),
            }));
        }
        let mut count = None;
        let mut cut_fraction = 0.5;
        let mut objects = 1;
        let mut seed = None;
        let mut rate = None;
        let mut dropped = None;
        let mut seen: BTreeMap<String, Span> = BTreeMap::new();
        let mut noise = lamp_spec::TrackingNoise::NONE;
        for entry in noise_entries {
            if self.declare(&mut seen, "option", &entry.keyword) {
                noise = self.tracking_noise(entry).unwrap_or(noise);
            }
        }
        let mut extra = BTreeMap::new();
        for option in options {
            if !self.declare(&mut seen, "option", &option.key) {
                continue;
            }
            let number = match &option.value {
                Value::Quantity(quantity) => Some(quantity),
                _ => None,
            };
            match (option.key.text.as_str(), number) {
                ("count", Some(q)) => {
                    count =
                        self.limited_count(q, "the demonstration count", &limits::DEMONSTRATIONS)
                }
                ("cut", Some(q)) => {
                    cut_fraction =
                        self.fraction_closed(q, "the cut fraction").unwrap_or(cut_fraction)
                }
                ("objects", Some(q)) => {
                    objects = self.count(q, "the object count", 1).unwrap_or(objects)
                }
                ("seed", Some(q)) => {
                    seed = self.count(q, "the demonstrator seed", 0).map(u64::from)
                }
                ("dropped", Some(q)) => {
                    dropped = self.plain(q, "the share of dropped poses").and_then(|value| {
                        self.limited(
                            value,
                            q.span,
                            "the share of dropped poses",
                            &limits::DROPPED_POSES,
                        )
                    })
                }
                ("rate", Some(q)) => {
                    rate = self.measure(q, Dimension::Frequency).and_then(|value| {
                        self.limited(value, q.span, "the recording rate", &limits::RECORDING_RATE)
                    })
                }
                // `noise` with one value (or a word): the grammar's two-value form did not match.
                ("noise", number) => self.missing(
                    option.key.span,
                    if number.is_some() {
                        "the tracking noise's angle"
                    } else {
                        "the tracking noise's distance"
                    },
                    "Write the largest position error per axis and the largest turn, both with their units: `noise 2 mm 1 deg`.",
                ),
                ("count" | "cut" | "objects" | "seed" | "rate" | "dropped", None) => {
                    self.report(at(option.key.span, |at| SpecError::OutOfRange {
                        what: format!("`{}`", option.key.text),
                        expected: "a number".to_string(),
                        at,
                    }));
                }
                (key, _) => {
                    if let Some(value) = self.option_value(&option.value) {
                        extra.insert(key.to_string(), value);
                    }
                }
            }
        }
        if let Some(dropped) = dropped {
            noise.dropped = dropped;
        }
        let Some(count) = count else {
            if !seen.contains_key("count") {
                self.missing(
                    demonstrator.span,
                    "the demonstration `count`",
                    "Add `count 200` inside the braces.",
                );
            }
            return None;
        };
        (self.diagnostics.len() == errors_before).then(|| lamp_spec::DemoSource::Simulated {
            demonstrator: demonstrator.text.clone(),
            count,
            cut_fraction,
            objects,
            seed: seed.unwrap_or(0),
            noise,
            rate,
            options: extra,
        })
    }

    /// `noise D A`: a length and an angle, each within its limit; both are checked, so that one
    /// run reports a mistake in each.
    fn tracking_noise(
        &mut self,
        entry: &crate::ast::NoiseEntry,
    ) -> Option<lamp_spec::TrackingNoise> {
        let position = self.measure(&entry.distance, Dimension::Length).and_then(|value| {
            self.limited(
                value,
                entry.distance.span,
                "the tracking noise's distance",
                &limits::NOISE_POSITION,
            )
        });
        let rotation = self.measure(&entry.angle, Dimension::Angle).and_then(|value| {
            self.limited(
                value,
                entry.angle.span,
                "the tracking noise's angle",
                &limits::NOISE_ROTATION,
            )
        });
        Some(lamp_spec::TrackingNoise { position: position?, rotation: rotation?, dropped: 0.0 })
    }

    pub(crate) fn learning(
        &mut self,
        items: &[Item],
        declared: &Declared,
    ) -> Option<lamp_spec::Learning> {
        let errors_before = self.diagnostics.len();
        let mut defaults = lamp_spec::PairSettings::default();
        let mut pairs = BTreeMap::new();
        let mut ignored = BTreeSet::new();
        let mut block_seen = None;
        let mut symmetry = None;
        let mut symmetry_seen = None;
        let mut pair_spans: BTreeMap<(String, String), Span> = BTreeMap::new();
        let blocks: Vec<(&Vec<LearnItem>, Span)> = items
            .iter()
            .filter_map(|item| match item {
                Item::Learn { items, span } => Some((items, *span)),
                _ => None,
            })
            .collect();
        for (items, span) in &blocks {
            if !self.once(&mut block_seen, "the `learn` block", *span) {
                continue;
            }
            let mut settings = Settings::default();
            let overrides: Vec<_> = items
                .iter()
                .filter(|item| !matches!(item, LearnItem::Pair { .. } | LearnItem::IgnorePair(..)))
                .collect();
            self.settings(&overrides, &mut settings, &mut defaults);
            for item in items.iter() {
                match item {
                    LearnItem::Symmetry(switch, span)
                        if self.once(&mut symmetry_seen, "`symmetry`", *span) =>
                    {
                        symmetry = Some(*switch);
                    }
                    LearnItem::IgnorePair(first, second)
                        if self.relation_type(declared, first)
                            & self.relation_type(declared, second) =>
                    {
                        ignored.insert((first.text.clone(), second.text.clone()));
                        ignored.insert((second.text.clone(), first.text.clone()));
                    }
                    LearnItem::Pair { first, second, items, span } => {
                        let known = self.relation_type(declared, first)
                            & self.relation_type(declared, second);
                        let key = (first.text.clone(), second.text.clone());
                        let reversed = (second.text.clone(), first.text.clone());
                        if let Some(earlier) =
                            pair_spans.get(&key).or_else(|| pair_spans.get(&reversed)).copied()
                        {
                            self.report(at(*span, |at| SpecError::DuplicateSetting {
                                what: format!(
                                    "the override for pair {} {}",
                                    first.text, second.text
                                ),
                                at,
                                first: earlier.source_span(),
                            }));
                            continue;
                        }
                        pair_spans.insert(key.clone(), *span);
                        for nested in items {
                            if let LearnItem::Pair { span, .. }
                            | LearnItem::IgnorePair(crate::ast::Name { span, .. }, _) = nested
                            {
                                self.report(at(*span, |at| SpecError::Conflict {
                                    message: "pair settings cannot nest".to_string(),
                                    at,
                                    help: "Write `pair` and `ignore pair` at the top of the `learn` block.".to_string(),
                                }));
                            }
                            if let LearnItem::Symmetry(_, span) = nested {
                                self.report(at(*span, |at| SpecError::Conflict {
                                    message: "`symmetry` is a setting of the whole `learn` block, not of one pair".to_string(),
                                    at,
                                    help: "Write `symmetry on` at the top of the `learn` block.".to_string(),
                                }));
                            }
                        }
                        let flat: Vec<_> = items
                            .iter()
                            .filter(|item| {
                                !matches!(item, LearnItem::Pair { .. } | LearnItem::IgnorePair(..))
                            })
                            .collect();
                        let mut pair_settings = defaults.clone();
                        self.settings(&flat, &mut Settings::default(), &mut pair_settings);
                        if known {
                            pairs.insert(key, pair_settings);
                        }
                    }
                    _ => {}
                }
            }
        }
        // Overrides are merged over the final defaults, wherever the defaults were written.
        (self.diagnostics.len() == errors_before).then_some(lamp_spec::Learning {
            defaults,
            pairs,
            ignored_pairs: ignored,
            symmetry,
        })
    }

    fn settings(
        &mut self,
        items: &[&LearnItem],
        seen: &mut Settings,
        out: &mut lamp_spec::PairSettings,
    ) {
        for item in items {
            match item {
                LearnItem::Threshold(value, span) => {
                    if self.once(&mut seen.threshold, "`threshold`", *span)
                        && let Some(v) = self.fraction_open(value, "the threshold θ")
                    {
                        out.threshold = Some(v);
                    }
                }
                LearnItem::Position { bins, range, span } => {
                    if self.once(&mut seen.position, "`position`", *span) {
                        if let Some((_, unit_span)) = bins.unit {
                            self.report(at(unit_span, |at| SpecError::UnexpectedUnit {
                                what: "a bin count".to_string(),
                                at,
                            }));
                        }
                        let mut position_bins = [0; 3];
                        let mut every_axis = true;
                        for (axis, (value, number_span)) in
                            bins.values.iter().zip(bins.number_spans).enumerate()
                        {
                            match self.limited(
                                *value,
                                number_span,
                                "a position bin count",
                                &limits::POSITION_BINS,
                            ) {
                                // The limit allows only whole numbers up to ten thousand.
                                Some(v) => position_bins[axis] = v as u32,
                                None => every_axis = false,
                            }
                        }
                        if every_axis {
                            out.position_bins = Some(position_bins);
                        }
                        if let Some(range) = range
                            && let Some(values) = self.length_vector(range)
                        {
                            let mut every_axis = true;
                            for (value, number_span) in values.iter().zip(range.number_spans) {
                                every_axis &= self
                                    .limited(
                                        *value,
                                        number_span,
                                        "the position range",
                                        &limits::POSITION_RANGE,
                                    )
                                    .is_some();
                            }
                            if every_axis {
                                out.position_range = Some(values);
                            }
                        }
                    }
                }
                LearnItem::Rotation(value, span) => {
                    if self.once(&mut seen.rotation, "`rotation`", *span)
                        && let Some(v) = self.limited_count(
                            value,
                            "a rotation bin count",
                            &limits::ROTATION_BINS,
                        )
                    {
                        out.rotation_bins = Some(v);
                    }
                }
                LearnItem::Components(value, span) => {
                    if self.once(&mut seen.components, "`components`", *span)
                        && let Some(v) =
                            self.limited_count(value, "the component cap", &limits::COMPONENTS)
                    {
                        out.max_components = Some(v);
                    }
                }
                LearnItem::Likelihood(value, span) => {
                    if self.once(&mut seen.likelihood, "`likelihood`", *span)
                        && let Some(v) = self.fraction_open(value, "the likelihood cover")
                    {
                        out.likelihood_cover = Some(v);
                    }
                }
                LearnItem::Clear(switch, span) => {
                    if self.once(&mut seen.clear, "`clear`", *span) {
                        out.clear = Some(*switch);
                    }
                }
                LearnItem::Nowhere(switch, span) => {
                    if self.once(&mut seen.nowhere, "`nowhere`", *span) {
                        out.nowhere = Some(*switch);
                    }
                }
                LearnItem::Pair { .. } | LearnItem::IgnorePair(..) | LearnItem::Symmetry(..) => {}
            }
        }
    }

    pub(crate) fn relation_aliases(
        &mut self,
        items: &[Item],
        declared: &mut Declared,
    ) -> Vec<lamp_spec::RelationAlias> {
        let mut seen = BTreeMap::new();
        let mut aliases = Vec::new();
        for item in items {
            let Item::Relation(relation) = item else { continue };
            if !self.declare(&mut seen, "relation", &relation.name) {
                continue;
            }
            let errors_before = self.diagnostics.len();
            for name in relation.parameters.iter().chain([&relation.secondary, &relation.primary]) {
                self.relation_type(declared, name);
            }
            let written: BTreeSet<&str> =
                relation.parameters.iter().map(|p| p.text.as_str()).collect();
            let region: BTreeSet<&str> =
                [relation.secondary.text.as_str(), relation.primary.text.as_str()].into();
            if self.diagnostics.len() == errors_before && written != region {
                self.report(at(relation.secondary.span, |at| SpecError::Conflict {
                    message: "the region's types differ from the relation's parameters".to_string(),
                    at,
                    help: format!(
                        "Write `region of {} in {}` or change the parameters to match.",
                        relation.parameters[1].text, relation.parameters[0].text
                    ),
                }));
            }
            let example = self.pose(&relation.example);
            if let (true, Some(example)) = (self.diagnostics.len() == errors_before, example) {
                let alias = lamp_spec::RelationAlias {
                    name: relation.name.text.clone(),
                    parameters: relation.parameters.clone().map(|p| p.text),
                    primary: relation.primary.text.clone(),
                    secondary: relation.secondary.text.clone(),
                    example,
                };
                declared.aliases.insert(alias.name.clone(), alias.clone());
                aliases.push(alias);
            }
        }
        aliases
    }

    pub(crate) fn structures(
        &mut self,
        items: &[Item],
        declared: &mut Declared,
    ) -> Vec<lamp_spec::Structure> {
        let mut seen = BTreeMap::new();
        let mut structures = Vec::new();
        for item in items {
            let Item::Structure(structure) = item else { continue };
            if !self.declare(&mut seen, "structure", &structure.name) {
                continue;
            }
            declared.structures.insert(structure.name.text.clone(), structure.name.span);
            let mut objects = BTreeMap::new();
            let mut placements = Vec::new();
            for placement in &structure.placements {
                let known = self.object_type(declared, &placement.type_name);
                let new = self.declare(&mut objects, "structure object", &placement.object);
                if known && new {
                    let span = Span { end: placement.pose.span.end, ..placement.type_name.span };
                    self.places.add_structure_object(
                        &structure.name.text,
                        &placement.object.text,
                        span,
                    );
                }
                let what = format!(
                    "the place of `{}` in structure `{}`",
                    placement.object.text, structure.name.text
                );
                if let (true, true, Some(pose)) =
                    (known, new, self.structure_pose(&placement.pose, &what))
                {
                    placements.push(lamp_spec::Placement {
                        object: placement.object.text.clone(),
                        type_name: placement.type_name.text.clone(),
                        pose,
                    });
                }
            }
            declared.structure_objects.insert(
                structure.name.text.clone(),
                placements
                    .iter()
                    .map(|placement| (placement.object.clone(), placement.type_name.clone()))
                    .collect(),
            );
            structures.push(lamp_spec::Structure { name: structure.name.text.clone(), placements });
        }
        structures
    }

    /// An option value in SI units.
    pub(crate) fn option_value(&mut self, value: &Value) -> Option<lamp_spec::OptionValue> {
        Some(match value {
            Value::Text(text) => lamp_spec::OptionValue::Text(text.text.clone()),
            Value::Word(word) => lamp_spec::OptionValue::Word(word.text.clone()),
            Value::Quantity(quantity) => {
                match quantity.unit.map(|(unit, _)| super::units::unit_info(unit).0) {
                    None => {
                        lamp_spec::OptionValue::Number(self.finite(quantity.value, quantity.span)?)
                    }
                    Some(Dimension::Length) => {
                        lamp_spec::OptionValue::Length(self.measure(quantity, Dimension::Length)?)
                    }
                    Some(Dimension::Angle) => {
                        lamp_spec::OptionValue::Angle(self.measure(quantity, Dimension::Angle)?)
                    }
                    Some(Dimension::Duration) => lamp_spec::OptionValue::Duration(
                        self.measure(quantity, Dimension::Duration)?,
                    ),
                    // Hertz are SI already.
                    Some(Dimension::Frequency) => lamp_spec::OptionValue::Number(
                        self.measure(quantity, Dimension::Frequency)?,
                    ),
                }
            }
        })
    }
}

/// Where each learning setting was first given in one block.
#[derive(Default)]
struct Settings {
    threshold: Option<Span>,
    position: Option<Span>,
    rotation: Option<Span>,
    components: Option<Span>,
    likelihood: Option<Span>,
    clear: Option<Span>,
    nowhere: Option<Span>,
}
