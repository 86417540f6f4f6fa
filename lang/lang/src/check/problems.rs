//! `problem` declarations: scenes and the three kinds of goal.

use std::collections::BTreeMap;

use super::{Checker, Declared, Dimension};
use crate::ast::{GoalItem, Item, Name, ProblemItem, SceneItem};
use crate::diagnostics::{SpecError, at, did_you_mean};
use crate::parse::parse_scene_file;
use crate::source::Span;

/// Objects a goal may mention: name → type; `None` for an object whose type was already
/// reported as unknown, so that goals mentioning it stay silent.
type Objects = BTreeMap<String, Option<String>>;

impl Checker<'_> {
    pub(crate) fn problems(
        &mut self,
        items: &[Item],
        declared: &Declared,
    ) -> Vec<lamp_spec::Problem> {
        let mut seen = BTreeMap::new();
        let mut problems = Vec::new();
        for item in items {
            let Item::Problem(problem) = item else { continue };
            if !self.declare(&mut seen, "problem", &problem.name) {
                continue;
            }
            let length = problem.name.text.len();
            if length > lamp_spec::limits::MAX_PROBLEM_NAME_BYTES {
                self.report(at(problem.name.span, |at| SpecError::NameTooLong {
                    kind: "problem",
                    length,
                    max: lamp_spec::limits::MAX_PROBLEM_NAME_BYTES,
                    at,
                }));
                continue;
            }
            if let Some(problem) = self.problem(problem, declared) {
                problems.push(problem);
            }
        }
        problems
    }

    fn problem(
        &mut self,
        problem: &crate::ast::Problem,
        declared: &Declared,
    ) -> Option<lamp_spec::Problem> {
        let errors_before = self.diagnostics.len();
        let mut scene_span = None;
        let mut goal_span = None;
        let mut scene = lamp_spec::Scene::default();
        let mut objects = Objects::new();
        let mut goal_items: &[GoalItem] = &[];
        let mut scene_ok = true;
        for item in &problem.items {
            match item {
                ProblemItem::Scene { items, span } => {
                    if self.once(&mut scene_span, "the scene", *span) {
                        scene = self.scene(&problem.name.text, items, declared, &mut objects);
                    }
                }
                ProblemItem::SceneFile(path) => {
                    if self.once(&mut scene_span, "the scene", path.span) {
                        let parsed =
                            self.load(path).map(|(file, text)| parse_scene_file(file, &text));
                        match parsed {
                            Some(Ok(items)) => {
                                scene =
                                    self.scene(&problem.name.text, &items, declared, &mut objects)
                            }
                            Some(Err(diagnostic)) => {
                                self.report(diagnostic);
                                scene_ok = false;
                            }
                            None => scene_ok = false,
                        }
                    }
                }
                ProblemItem::Goal { items, span } => {
                    if self.once(&mut goal_span, "the goal", *span) {
                        goal_items = items;
                    }
                }
            }
        }
        if scene_span.is_none() {
            self.missing(
                problem.name.span,
                "the problem's scene",
                "Add `scene { … }` or `scene \"file.lamp\"` with the objects and robots.",
            );
        }
        let goal = match goal_span {
            None => {
                self.missing(
                    problem.name.span,
                    "the problem's goal",
                    "Add `goal { … }` with relation atoms, `at` poses or a `structure`.",
                );
                None
            }
            Some(span) if goal_items.is_empty() => {
                self.missing(
                    span,
                    "a goal condition",
                    "Write at least one condition inside `goal { … }`.",
                );
                None
            }
            Some(_) if !scene_ok => None,
            Some(_) => {
                for item in goal_items {
                    if let GoalItem::At { object, .. } = item {
                        let end = item_span(item).end;
                        let span = Span { end, ..object.span };
                        self.places.add_at_goal(&problem.name.text, &object.text, span);
                    }
                    if let GoalItem::Structure { .. } = item {
                        self.places.add_structure_goal(&problem.name.text, item_span(item));
                    }
                }
                self.goal(goal_items, declared, &scene, &objects)
            }
        };
        (self.diagnostics.len() == errors_before).then(|| lamp_spec::Problem {
            name: problem.name.text.clone(),
            scene,
            goal: goal.unwrap_or_default(),
        })
    }

    fn scene(
        &mut self,
        problem: &str,
        items: &[SceneItem],
        declared: &Declared,
        objects: &mut Objects,
    ) -> lamp_spec::Scene {
        let mut scene = lamp_spec::Scene::default();
        let mut names: BTreeMap<String, Span> = BTreeMap::new();
        let mut placed_robots: BTreeMap<String, Span> = BTreeMap::new();
        for item in items {
            match item {
                SceneItem::Object(placement) => {
                    let known = self.object_type(declared, &placement.type_name);
                    let new = self.declare(&mut names, "object", &placement.object);
                    let pose = self.pose(&placement.pose);
                    if !known {
                        objects.insert(placement.object.text.clone(), None);
                    }
                    if known && new {
                        // Known even when its pose has an error (reported already): the goals
                        // that name it are still checked, and not reported again.
                        objects.insert(
                            placement.object.text.clone(),
                            Some(placement.type_name.text.clone()),
                        );
                    }
                    if let (true, true, Some(pose)) = (known, new, pose) {
                        let span =
                            Span { end: placement.pose.span.end, ..placement.type_name.span };
                        self.places.add_scene_placement(problem, &placement.object.text, span);
                        scene.objects.push(lamp_spec::ObjectInstance {
                            name: placement.object.text.clone(),
                            type_name: placement.type_name.text.clone(),
                            pose,
                        });
                    }
                }
                SceneItem::Robot { name, at: base, config } => {
                    if declared.invalid_robots.contains(&name.text) {
                        continue;
                    }
                    let Some(robot) = declared.robots.get(&name.text) else {
                        let help =
                            did_you_mean(&name.text, declared.robots.keys().map(String::as_str));
                        self.report(at(name.span, |at| SpecError::UnknownRobot {
                            name: name.text.clone(),
                            at,
                            help,
                        }));
                        continue;
                    };
                    if !self.declare(&mut placed_robots, "robot placement", name) {
                        continue;
                    }
                    let end = [
                        base.as_ref().map(|pose| pose.span.end),
                        config.as_ref().map(|c| c.span.end),
                    ]
                    .into_iter()
                    .flatten()
                    .fold(name.span.end, usize::max);
                    let written = Span { end, ..name.span };
                    let base = match base {
                        Some(pose) if robot.kind == lamp_spec::RobotKind::FixedArm => {
                            self.report(at(pose.span, |at| SpecError::Conflict {
                                message: format!("`{}` is a fixed arm and cannot be placed", name.text),
                                at,
                                help: "A fixed arm's base is set once by `mount` in the robot declaration.".to_string(),
                            }));
                            None
                        }
                        Some(pose) => self.pose(pose),
                        None => None,
                    };
                    if let Some(config) = config
                        && robot.configuration(&config.text).is_none()
                    {
                        let help = did_you_mean(
                            &config.text,
                            robot.configurations.iter().map(|c| c.name.as_str()),
                        );
                        self.report(at(config.span, |at| SpecError::UnknownConfiguration {
                            robot: name.text.clone(),
                            name: config.text.clone(),
                            at,
                            help,
                        }));
                    }
                    for part in &robot.parts {
                        let instance = part_instance(&robot.name, &part.type_name);
                        objects.insert(instance, Some(part.type_name.clone()));
                    }
                    self.places.add_scene_placement(problem, &name.text, written);
                    scene.robots.push(lamp_spec::RobotPlacement {
                        robot: name.text.clone(),
                        base,
                        configuration: config.as_ref().map(|c| c.text.clone()),
                    });
                }
            }
        }
        scene
    }

    /// The marker type an `at` goal on `object` places at its target: the spec's only marker
    /// type. The marker's name must not be taken by a scene object.
    fn at_goal_marker(
        &mut self,
        object: &Name,
        declared: &Declared,
        scene: &lamp_spec::Scene,
    ) -> Option<String> {
        let mut markers = declared.marker_types.keys();
        let (Some(marker_type), None) = (markers.next(), markers.next()) else {
            let several = declared.marker_types.len() > 1;
            self.report(at(object.span, |at| SpecError::Conflict {
                message: if several {
                    format!(
                        "an `at` goal needs one marker type, and the spec declares {} ({})",
                        declared.marker_types.len(),
                        declared.marker_types.keys().cloned().collect::<Vec<_>>().join(", ")
                    )
                } else {
                    "an `at` goal needs a marker type, and the spec declares none".to_string()
                },
                at,
                help: "An `at` goal is solved by placing a marker at the target and reaching the learned relation of the object on a marker: declare one marker type (`type place { marker }`) and demonstrations that put objects onto markers.".to_string(),
            }));
            return None;
        };
        // Markers are placed where every movable object starts (see `start_markers_named`)
        // and at each target.
        let markers = [lamp_spec::marker_name(&object.text)];
        if let Some(marker) =
            markers.iter().find(|marker| scene.objects.iter().any(|other| &other.name == *marker))
        {
            self.report(at(object.span, |at| SpecError::Conflict {
                message: format!(
                    "the `at` goal on `{}` places a marker named `{marker}`, and a scene object has that name",
                    object.text
                ),
                at,
                help: format!("Rename the scene object `{marker}`."),
            }));
            return None;
        }
        Some(marker_type.clone())
    }

    fn goal(
        &mut self,
        items: &[GoalItem],
        declared: &Declared,
        scene: &lamp_spec::Scene,
        objects: &Objects,
    ) -> Option<lamp_spec::Goal> {
        let errors_before = self.diagnostics.len();
        let mut goal = lamp_spec::Goal::default();
        let mut structure_span = None;
        let mut structure_item = None;
        let mut first_at = None;
        for item in items {
            match item {
                GoalItem::Atom { relation, arguments, span } => {
                    if let Some(atom) = self.atom(relation, arguments, *span, declared, objects) {
                        goal.atoms.push(atom);
                    }
                }
                GoalItem::At { object, pose, distance, angle } => {
                    let object_type = self.scene_object(object, objects, declared).flatten();
                    // A type that is no object type is a robot part's: the robot moves itself.
                    let movable = object_type.map(|ty| {
                        declared.object_types.get(ty).is_some_and(|(_, movable)| *movable)
                    });
                    if let (Some(false), Some(type_name)) = (movable, object_type.cloned()) {
                        let marker = declared.marker_types.contains_key(&type_name);
                        let part = !declared.object_types.contains_key(&type_name);
                        let (kind, label) = if part {
                            ("a robot's part, not an object of the scene", "a robot's part")
                        } else if marker {
                            ("a marker (a named pose that nothing picks up)", "a marker")
                        } else {
                            ("static", "a static object")
                        };
                        self.report(at(object.span, |at| SpecError::NotMovable {
                            object: object.text.clone(),
                            type_name,
                            kind,
                            at,
                            label,
                        }));
                    }
                    let pose = self.pose(pose);
                    let distance = self.positive_length(distance, "the position tolerance");
                    let angle = self.measure(angle, Dimension::Angle).filter(|angle| {
                        self.require(
                            *angle > 0.0,
                            item_span(item),
                            "the angle tolerance",
                            "a positive angle",
                        )
                    });
                    // A goal on a static object or a marker is already refused; its marker would add noise.
                    let marker_type = match movable {
                        Some(false) => None,
                        _ => self.at_goal_marker(object, declared, scene),
                    };
                    if let (Some(pose), Some(distance), Some(angle), Some(marker_type)) =
                        (pose, distance, angle, marker_type)
                    {
                        if goal.at.iter().any(|other| other.object == object.text) {
                            self.report(at(object.span, |at| SpecError::Conflict {
                                message: format!("`{}` has two `at` goals", object.text),
                                at,
                                help: "Give each object one target pose.".to_string(),
                            }));
                            continue;
                        }
                        first_at.get_or_insert(object.span);
                        goal.at.push(lamp_spec::AtGoal {
                            object: object.text.clone(),
                            pose,
                            position_tolerance: distance,
                            angle_tolerance: angle,
                            marker_type,
                        });
                    }
                }
                GoalItem::Structure { name, anchor, offset, span } => {
                    if !self.once(&mut structure_span, "a structure goal", *span) {
                        continue;
                    }
                    if !declared.structures.contains_key(&name.text) {
                        let help = did_you_mean(
                            &name.text,
                            declared.structures.keys().map(String::as_str),
                        );
                        self.report(at(name.span, |at| SpecError::UnknownStructure {
                            name: name.text.clone(),
                            at,
                            help,
                        }));
                    }
                    let anchored = scene.objects.iter().any(|object| object.name == anchor.text);
                    if !anchored {
                        self.scene_object(anchor, objects, declared);
                    }
                    let offset = match offset {
                        Some(pose) => self.structure_pose(
                            pose,
                            &format!("the offset of structure `{}`", name.text),
                        ),
                        None => Some(lamp_spec::Pose::identity()),
                    };
                    structure_item = Some((name, anchor, item_span(item)));
                    if let Some(offset) = offset {
                        goal.structure = Some(lamp_spec::StructureGoal {
                            structure: name.text.clone(),
                            anchor: anchor.text.clone(),
                            offset,
                        });
                    }
                }
            }
        }
        if let Some((name, anchor, span)) = structure_item {
            self.structure_bound(name, anchor, span, declared, scene, &goal);
        }
        // Start markers are placed for `at` goals; named once.
        if let Some(first) = first_at {
            self.start_markers_named(first, declared, scene);
        }
        (self.diagnostics.len() == errors_before).then_some(goal)
    }

    /// A structure goal binds each structure object to the scene object of the same name and
    /// type, which it moves to its place; the anchor stays where it is. Reported at the goal.
    fn structure_bound(
        &mut self,
        name: &Name,
        anchor: &Name,
        span: Span,
        declared: &Declared,
        scene: &lamp_spec::Scene,
        goal: &lamp_spec::Goal,
    ) {
        let Some(objects) = declared.structure_objects.get(&name.text) else { return };
        let mut report = |object: &str, problem: String, help: String| {
            self.report(at(span, |at| SpecError::StructureObject {
                structure: name.text.clone(),
                object: object.to_string(),
                problem,
                at,
                help,
            }));
        };
        for (object, type_name) in objects {
            let found = scene.objects.iter().find(|instance| &instance.name == object);
            match found {
                None => report(
                    object,
                    "and the scene has no object of that name".to_string(),
                    format!(
                        "A structure goal moves the scene's objects of the structure's names into place: add `{type_name} {object} at …` to the scene where it starts."
                    ),
                ),
                Some(instance) if &instance.type_name != type_name => report(
                    object,
                    format!(
                        "a {type_name}, and the scene's `{object}` is a {}",
                        instance.type_name
                    ),
                    format!(
                        "Give the scene object the structure's type `{type_name}`, or rename one of them."
                    ),
                ),
                Some(_) if object == &anchor.text => report(
                    object,
                    format!("and `{object}` is also the anchor the structure is placed at"),
                    "The anchor stays where it is and the structure is built around it: anchor the structure at an object that is not one of its own, such as an area on the table.".to_string(),
                ),
                Some(_) if goal.at.iter().any(|target| &target.object == object) => report(
                    object,
                    format!("and an `at` goal gives `{object}` another target"),
                    "Give each object one target: drop its `at` goal or take it out of the structure.".to_string(),
                ),
                Some(_) => {
                    let marker = lamp_spec::marker_name(object);
                    if scene.objects.iter().any(|other| other.name == marker) {
                        report(
                            object,
                            format!(
                                "whose target gets a marker named `{marker}`, and a scene object has that name"
                            ),
                            format!("Rename the scene object `{marker}`."),
                        );
                    }
                }
            }
        }
        if declared.marker_types.len() > 1 {
            let types = declared.marker_types.keys().cloned().collect::<Vec<_>>().join(", ");
            self.report(at(span, |at| SpecError::Conflict {
                message: format!(
                    "a structure goal needs one marker type, and the spec declares {} ({types})",
                    declared.marker_types.len()
                ),
                at,
                help: "A structure goal is solved by placing a marker at each object's target: keep one marker type.".to_string(),
            }));
        }
    }

    /// A problem with `at` goals places a marker where every movable object starts
    /// (`start_<object>`), as the demonstrations mark theirs: those names must not be taken by
    /// scene objects. Reported at the problem's first `at` goal.
    fn start_markers_named(
        &mut self,
        first_at: Span,
        declared: &Declared,
        scene: &lamp_spec::Scene,
    ) {
        let movable = |type_name: &str| {
            declared.object_types.get(type_name).is_some_and(|(_, movable)| *movable)
        };
        for object in scene.objects.iter().filter(|object| movable(&object.type_name)) {
            let marker = lamp_spec::start_marker_name(&object.name);
            if scene.objects.iter().any(|other| other.name == marker) {
                self.report(at(first_at, |at| SpecError::Conflict {
                    message: format!(
                        "the goal places a marker named `{marker}` where `{}` starts, and a scene object has that name",
                        object.name
                    ),
                    at,
                    help: format!("Rename the scene object `{marker}`."),
                }));
            }
        }
    }

    /// The type of a scene object (`Some(None)` if already reported), reporting a missing one.
    fn scene_object<'o>(
        &mut self,
        name: &Name,
        objects: &'o Objects,
        declared: &Declared,
    ) -> Option<Option<&'o String>> {
        let found = objects.get(&name.text).map(Option::as_ref);
        if found.is_none()
            && let Some(robot) = declared.robots.get(&name.text)
        {
            // The robot is in the scene, so "not in the scene" would send the user looking for a
            // typo: what a goal can name of a robot is one of its parts.
            let parts: Vec<String> = robot
                .parts
                .iter()
                .map(|part| format!("`{}`", part_instance(&robot.name, &part.type_name)))
                .collect();
            let help = if parts.is_empty() {
                format!(
                    "Robot `{}` declares no `part`, so a goal cannot name any of it.",
                    robot.name
                )
            } else {
                format!(
                    "A goal names a robot's parts as `<robot>_<part type>`; `{}` has {}.",
                    robot.name,
                    parts.join(", ")
                )
            };
            self.report(at(name.span, |at| SpecError::RobotAsObject {
                name: name.text.clone(),
                at,
                help,
            }));
        } else if found.is_none() {
            let help = did_you_mean(&name.text, objects.keys().map(String::as_str));
            self.report(at(name.span, |at| SpecError::UnknownObject {
                name: name.text.clone(),
                at,
                help,
            }));
        }
        found
    }

    fn atom(
        &mut self,
        relation: &Name,
        arguments: &[Name],
        span: Span,
        declared: &Declared,
        objects: &Objects,
    ) -> Option<lamp_spec::GoalAtom> {
        let Some(signature) = signature(&relation.text, declared) else {
            let help = "Goal relations are learned names `<primary>_<secondary>_<k>`, `clear_<primary>_<secondary>_<k>` and `nowhere_<primary>_<secondary>_<k>` over declared types, or aliases declared with `relation`.".to_string();
            let help =
                match did_you_mean(&relation.text, declared.aliases.keys().map(String::as_str)) {
                    Some(suggestion) => format!("{suggestion} {help}"),
                    None => help,
                };
            self.report(at(relation.span, |at| SpecError::UnknownRelation {
                name: relation.text.clone(),
                at,
                help,
            }));
            return None;
        };
        let written = format!("`{}({})`", relation.text, signature.join(", "));
        let signature_help = format!("The relation is {written}.");
        if arguments.len() != signature.len() {
            self.report(at(span, |at| SpecError::Arity {
                relation: relation.text.clone(),
                expected: signature.len(),
                found: arguments.len(),
                signature: signature_help,
                at,
            }));
            return None;
        }
        let errors_before = self.diagnostics.len();
        for (argument, expected) in arguments.iter().zip(&signature) {
            let Some(Some(found)) = self.scene_object(argument, objects, declared) else {
                continue;
            };
            if found != expected {
                self.report(at(argument.span, |at| SpecError::ArgumentType {
                    argument: argument.text.clone(),
                    relation: relation.text.clone(),
                    expected: expected.clone(),
                    found: found.clone(),
                    signature: signature_help.clone(),
                    at,
                }));
            }
        }
        (self.diagnostics.len() == errors_before).then(|| lamp_spec::GoalAtom {
            relation: relation.text.clone(),
            arguments: arguments.iter().map(|a| a.text.clone()).collect(),
        })
    }
}

/// The PDDL object name of a robot part: `<robot>_<part>`.
pub(crate) fn part_instance(robot: &str, part: &str) -> String {
    format!("{robot}_{part}")
}

/// Argument types of a goal relation: an alias, `clear_<t1>_<t2>_<k>` (a t1), `nowhere_<t1>_<t2>_<k>` (a t2) or
/// `<t1>_<t2>_<k>`.
fn signature(name: &str, declared: &Declared) -> Option<Vec<String>> {
    if let Some(alias) = declared.aliases.get(name) {
        return Some(alias.parameters.to_vec());
    }
    if let Some(rest) = name.strip_prefix("clear_")
        && let Some((primary, _)) = split_pair(rest, declared)
    {
        return Some(vec![primary]);
    }
    if let Some(rest) = name.strip_prefix("nowhere_")
        && let Some((_, secondary)) = split_pair(rest, declared)
    {
        return Some(vec![secondary]);
    }
    split_pair(name, declared).map(|(primary, secondary)| vec![primary, secondary])
}

/// Splits `<t1>_<t2>_<k>` into its two declared types; type names may contain underscores.
fn split_pair(name: &str, declared: &Declared) -> Option<(String, String)> {
    let (pair, index) = name.rsplit_once('_')?;
    if index.is_empty() || !index.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    pair.match_indices('_').find_map(|(position, _)| {
        let (primary, secondary) = (&pair[..position], &pair[position + 1..]);
        let known = |t: &str| declared.relation_types.contains_key(t);
        (known(primary) && known(secondary)).then(|| (primary.to_string(), secondary.to_string()))
    })
}

fn item_span(item: &GoalItem) -> Span {
    match item {
        GoalItem::At { angle, .. } => angle.span,
        // The item's span runs on over the space after it; the goal ends with its last word.
        GoalItem::Structure { anchor, offset, span, .. } => {
            Span { end: offset.as_ref().map_or(anchor.span.end, |pose| pose.span.end), ..*span }
        }
        GoalItem::Atom { span, .. } => *span,
    }
}
