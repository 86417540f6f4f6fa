//! The check of every problem's initial scene, before anything is learned: a scene the solver
//! cannot start from is a broken spec, refused with every finding named.
//!
//! Per problem, in this order: every object's and robot's placement is finite and within
//! [`MAX_DISTANCE`] of the origin (a scene that is not is not built further); bodies that touch
//! or overlap, where at least one can move, closer than [`CONTACT_TOLERANCE`]; every robot's
//! start configuration within its joint limits and free of collision with the bodies and itself,
//! at the same tolerance; every AtGoal target finite, in range, putting its object into no
//! static body, and over one (within [`TARGET_SUPPORT_GAP`] below it). Findings are listed in spec order of problems, then in that order.

use crate::error::BuildError;
pub use crate::scene_issue::SceneIssue;
use lamp_geometry::Pose;
use lamp_spec::{Problem, RobotKind, Spec};
use lamp_world::{Contact, SpecWorld};

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

/// The most an AtGoal target may leave between its object and the static body it stands on
/// (5 mm): the bundled specs put targets 1 mm above their tables, and a learned "on the marker"
/// region is a few millimetres high; a target with nothing this close below it would leave its
/// object in the air, where no solve can put it.
pub const TARGET_SUPPORT_GAP: f64 = 0.005;

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
    for (first, second) in scene.body_contacts() {
        issues.push(SceneIssue::Contact { problem: name(), first, second });
    }
    issues.extend(target_contacts(&mut scene, problem));
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

/// AtGoal targets that put their object into a static body (furniture, the floor), or over
/// none: each object alone at its target, the rest of the scene as it starts; `placed` is left
/// as it was.
fn target_contacts(placed: &mut lamp_world::Scene, problem: &Problem) -> Vec<SceneIssue> {
    let mut issues = Vec::new();
    for target in &problem.goal.at {
        let Some(body) = placed.body_index(&target.object) else { continue };
        let start = placed.body_pose(body);
        placed.set_body_pose(body, target.pose);
        let touched = static_bodies_touching(placed, &target.object);
        for other in &touched {
            issues.push(SceneIssue::TargetContact {
                problem: problem.name.clone(),
                object: target.object.clone(),
                body: other.clone(),
            });
        }
        if touched.is_empty() {
            let mut lowered = target.pose;
            lowered.translation.z -= TARGET_SUPPORT_GAP;
            placed.set_body_pose(body, lowered);
            if static_bodies_touching(placed, &target.object).is_empty() {
                issues.push(SceneIssue::TargetUnsupported {
                    problem: problem.name.clone(),
                    object: target.object.clone(),
                    gap_mm: TARGET_SUPPORT_GAP * 1000.0,
                });
            }
        }
        placed.set_body_pose(body, start);
    }
    issues
}

/// The static bodies `object` touches or overlaps, in contact order.
fn static_bodies_touching(placed: &lamp_world::Scene, object: &str) -> Vec<String> {
    let static_body =
        |name: &str| placed.body_index(name).is_some_and(|index| !placed.bodies()[index].movable);
    placed
        .body_contacts()
        .into_iter()
        .filter_map(|(first, second)| {
            if first == object {
                Some(second)
            } else if second == object {
                Some(first)
            } else {
                None
            }
        })
        .filter(|other| static_body(other))
        .collect()
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
    let targets =
        problem.goal.at.iter().map(|target| ("the target of", &target.object, Some(target.pose)));
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
