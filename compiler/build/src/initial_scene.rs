//! The check of every problem's initial scene, before anything is learned: a scene the solver
//! cannot start from is a broken spec, refused with every finding named.
//!
//! Per problem, in this order: every object's and robot's placement is finite and within
//! [`MAX_DISTANCE`] of the origin (a scene that is not is not built further); bodies that touch
//! or overlap, where at least one can move, closer than [`CONTACT_TOLERANCE`]; every movable
//! object that touches nothing where it can rest by lamp-world's resting rule (not in the air, not
//! over an edge); every AtGoal target putting its object into no static body, and where it can
//! rest by the same rule, and no two targets putting their objects into each other; every robot's start configuration within its joint limits and free of
//! collision with the bodies and itself, at the same tolerance. Findings are listed in spec order
//! of problems, then in that order.

use std::collections::{BTreeMap, BTreeSet};

use crate::error::BuildError;
pub use crate::scene_issue::SceneIssue;
use crate::scene_issue::TARGET;
use lamp_geometry::Pose;
use lamp_spec::{Problem, RobotKind, Spec};
use lamp_world::{Contact, Scene, SpecWorld};

/// Bodies closer than this touch (1 µm). The solver counts touching as a collision, so for an
/// object placed exactly on its support (distance 0, up to the rounding of the pose arithmetic)
/// whether a check sees the contact is a matter of rounding: the same scene may solve, or fail
/// every candidate that moves the object. A tolerance well above rounding and far below any real
/// clearance (the bundled specs keep 1 mm) makes "exactly on" a finding instead.
/// The help of [`SceneIssue::Contact`] quotes it.
pub const CONTACT_TOLERANCE: f64 = 1e-6;

/// No object or robot is placed farther than this from the world origin (1 km). lamp's scenes
/// are rooms (the bundled ones fit in 20 m); positions far beyond that lose the millimetres
/// collision checking needs and make interpolation and recording take absurd numbers of steps.
pub const MAX_DISTANCE: f64 = 1000.0;

/// The build step: [`BuildError::InitialScenes`] with every finding of every problem, if any.
pub fn check_initial_scenes(spec: &Spec, world: &SpecWorld) -> Result<(), BuildError> {
    let issues = initial_scene_issues(spec, world);
    if issues.is_empty() {
        return Ok(());
    }
    let problems = spec
        .problems
        .iter()
        .filter(|problem| issues.iter().any(|issue| issue.problem() == problem.name))
        .count();
    Err(BuildError::InitialScenes { problems, issues })
}

/// Every finding of every problem's initial scene, in spec order; empty when all are fine.
pub fn initial_scene_issues(spec: &Spec, world: &SpecWorld) -> Vec<SceneIssue> {
    spec.problems.iter().flat_map(|problem| problem_scene_issues(spec, world, problem)).collect()
}

/// The findings of one problem's initial scene.
pub fn problem_scene_issues(spec: &Spec, world: &SpecWorld, problem: &Problem) -> Vec<SceneIssue> {
    let mut issues = placement_issues(spec, problem);
    if !issues.is_empty() {
        return issues;
    }
    let name = || problem.name.clone();
    let mut scene = match world.problem_scene(problem) {
        Ok(scene) => scene,
        Err(error) => {
            return vec![SceneIssue::Unbuildable { problem: name(), reason: error.to_string() }];
        }
    };
    scene.set_margin(CONTACT_TOLERANCE);
    let contacts = scene.body_contacts();
    let touching: BTreeSet<String> =
        contacts.iter().flat_map(|(first, second)| [first.clone(), second.clone()]).collect();
    for (first, second) in contacts {
        issues.push(SceneIssue::Contact { problem: name(), first, second });
    }
    // Every movable object starts at rest by the one resting rule (a touching one is named above).
    for (index, body) in scene.bodies().iter().enumerate() {
        if !body.movable || body.is_marker() || touching.contains(&body.name) {
            continue;
        }
        if let Err(reason) = scene.resting_pose(index) {
            let (object, reason) = (body.name.clone(), reason.to_string());
            issues.push(SceneIssue::Unsupported { problem: name(), object, reason });
        }
    }
    issues.extend(target_issues(world, problem));
    for (index, robot) in scene.robots().iter().enumerate() {
        let q = robot.configuration();
        let model = robot.robot();
        if let Some(coordinate) = model.first_outside_limits(q) {
            let limits = &model.coordinates()[coordinate];
            issues.push(SceneIssue::RobotLimits {
                problem: name(),
                robot: robot.name.clone(),
                coordinate: limits.name.clone(),
                value: q[coordinate],
                lower: limits.lower,
                upper: limits.upper,
            });
        } else if let Some(contact) = scene.first_contact(index, q) {
            debug_assert_ne!(contact, Contact::OutOfLimits, "limits are checked first");
            issues.push(SceneIssue::RobotCollision {
                problem: name(),
                robot: robot.name.clone(),
                contact: contact.to_string(),
            });
        }
    }
    issues
}

/// AtGoal targets that put their object into a static body (furniture, the floor), or where it
/// cannot rest: each object alone at its target among the problem's static bodies, judged by
/// the resting rule every release follows.
fn target_issues(world: &SpecWorld, problem: &Problem) -> Vec<SceneIssue> {
    let mut issues = Vec::new();
    for target in &problem.goal.at {
        let at_target = [(target.object.clone(), target.pose)];
        let scene = match objects_at_targets(world, problem, &at_target) {
            Ok(scene) => scene,
            Err(error) => {
                let reason = error.to_string();
                issues.push(SceneIssue::Unbuildable { problem: problem.name.clone(), reason });
                continue;
            }
        };
        let touched: Vec<String> = scene
            .body_contacts()
            .into_iter()
            .map(|(first, second)| if first == target.object { second } else { first })
            .collect();
        for body in &touched {
            issues.push(SceneIssue::TargetContact {
                problem: problem.name.clone(),
                object: target.object.clone(),
                body: body.clone(),
            });
        }
        let Some(body) = scene.body_index(&target.object) else { continue };
        if let (true, Err(reason)) = (touched.is_empty(), scene.resting_pose(body)) {
            issues.push(SceneIssue::TargetUnsupported {
                problem: problem.name.clone(),
                object: target.object.clone(),
                reason: reason.to_string(),
            });
        }
    }
    // Then all of them at once: two targets on one place can never both be reached.
    let all: Vec<(String, Pose)> =
        problem.goal.at.iter().map(|target| (target.object.clone(), target.pose)).collect();
    let targeted: BTreeSet<&str> = all.iter().map(|(object, _)| object.as_str()).collect();
    if targeted.len() > 1
        && let Ok(scene) = objects_at_targets(world, problem, &all)
    {
        for (first, second) in scene.body_contacts() {
            if targeted.contains(first.as_str()) && targeted.contains(second.as_str()) {
                issues.push(SceneIssue::TargetsOverlap {
                    problem: problem.name.clone(),
                    first,
                    second,
                });
            }
        }
    }
    issues
}

/// Objects of the problem's scene at target poses (a structure's, or one AtGoal's), with the
/// problem's static bodies and nothing else, checked at [`CONTACT_TOLERANCE`]: where a goal
/// would leave them, judged by the one resting rule (`Scene::resting_pose`).
pub(crate) fn objects_at_targets(
    world: &SpecWorld,
    problem: &Problem,
    targets: &[(String, Pose)],
) -> Result<Scene, lamp_world::WorldError> {
    let mut scene = Scene::new();
    let objects: BTreeMap<&str, &str> = problem
        .scene
        .objects
        .iter()
        .map(|object| (object.name.as_str(), object.type_name.as_str()))
        .collect();
    let placed: BTreeSet<&str> = targets.iter().map(|(object, _)| object.as_str()).collect();
    for object in &problem.scene.objects {
        if placed.contains(object.name.as_str()) {
            continue;
        }
        if let Some(body) = world.body(&object.name, &object.type_name)
            && !body.movable
            && !body.is_marker()
        {
            scene.add_body(body, object.pose)?;
        }
    }
    for (object, pose) in targets {
        let type_name = objects.get(object.as_str()).copied().unwrap_or_default();
        let body =
            world.body(object, type_name).ok_or_else(|| lamp_world::WorldError::Undeclared {
                problem: problem.name.clone(),
                name: type_name.to_string(),
            })?;
        scene.add_body(body, *pose)?;
    }
    scene.set_margin(CONTACT_TOLERANCE);
    Ok(scene)
}

/// Placements that are not finite or too far: objects at their poses, robots at their bases
/// (a fixed arm at its mount).
fn placement_issues(spec: &Spec, problem: &Problem) -> Vec<SceneIssue> {
    let objects =
        problem.scene.objects.iter().map(|object| ("object", &object.name, Some(object.pose)));
    let robots = problem.scene.robots.iter().map(|placement| {
        let mount = spec
            .robot(&placement.robot)
            .filter(|robot| robot.kind == RobotKind::FixedArm)
            .map(|robot| robot.mount);
        ("robot", &placement.robot, placement.base.or(mount))
    });
    let targets = problem.goal.at.iter().map(|target| (TARGET, &target.object, Some(target.pose)));
    objects
        .chain(robots)
        .chain(targets)
        .filter_map(|(what, name, pose)| {
            let pose = pose?;
            if !is_finite(&pose) {
                return Some(SceneIssue::NotFinite {
                    problem: problem.name.clone(),
                    what,
                    name: name.clone(),
                });
            }
            // Compared per coordinate first: the norm of (1e308, 1e308, 0) overflows.
            let position = pose.translation.vector;
            let far = position.amax() > MAX_DISTANCE || position.norm() > MAX_DISTANCE;
            far.then(|| SceneIssue::OutOfRange {
                problem: problem.name.clone(),
                what,
                name: name.clone(),
                position: format!(
                    "({}, {}, {})",
                    number(position.x),
                    number(position.y),
                    number(position.z)
                ),
                max: MAX_DISTANCE,
            })
        })
        .collect()
}

fn is_finite(pose: &Pose) -> bool {
    pose.translation.vector.iter().chain(pose.rotation.coords.iter()).all(|value| value.is_finite())
}

/// A coordinate as written in a spec: plain below a million, in exponent form above (1e308 m
/// would otherwise print 309 digits).
fn number(value: f64) -> String {
    if value.abs() < 1e6 { value.to_string() } else { format!("{value:e}") }
}
