//! An arm motion between two gripper poses down among objects, which the motion planner does not
//! find, is planned again from above its ends: the gripper goes straight up, the motion planner
//! plans above the objects, and the gripper comes straight down.

#![allow(clippy::unwrap_used)] // a failed step is a failed test

use lamp_geometry::{Pose, Shape, Vec3};
use lamp_plugin_api::{
    Candidate, HostServices, MotionBudget, MotionOutcome, MotionPlanner, MotionRequest,
    NoPathReason, PlanBudget, PluginError, RobotTarget,
};
use lamp_robot::IkConfig;
use lamp_tamp::execute::{LIFT_HEIGHT, MotionCounts, Rejection, execute};
use lamp_tamp::{MotionSettings, SolveSettings};
use lamp_test_support::domain;
use lamp_world::{
    Body, LinkGoal, MotionConfig, Recorder, RobotSpace, Scene, Space, reach, straight_line,
};
use nalgebra::{Translation3, UnitQuaternion};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// A motion planner that tries the straight edge in configuration space and nothing else: it
/// finds a path only where nothing is in the way, as a sampling planner out of budget does.
struct StraightEdgeOnly;

impl MotionPlanner for StraightEdgeOnly {
    fn plan_path(
        &mut self,
        request: &MotionRequest,
        host: &dyn HostServices,
    ) -> Result<MotionOutcome, PluginError> {
        let (robot, start, goal) = (&request.robot, &request.start, &request.goal);
        Ok(if host.edge_is_valid(robot, start, goal)? {
            MotionOutcome::Path(vec![start.clone(), goal.clone()])
        } else {
            let message = "the straight edge collides".to_string();
            MotionOutcome::NoPath { reason: NoPathReason::BudgetExhausted, message }
        })
    }
}

fn pose(x: f64, y: f64, z: f64) -> Pose {
    Pose::from_parts(Translation3::new(x, y, z), UnitQuaternion::identity())
}

/// The café scene with the Fetch parked in front of table1 and a low wall standing on the table
/// between two gripper poses 7 cm above the top: the arm at the first, the second its goal.
fn fetch_beside_a_wall() -> (Scene, usize, Vec<f64>, Vec<f64>) {
    let (spec, world) = domain("cafe");
    let mut scene = world.problem_scene(&spec.problems[0]).unwrap();
    let fetch = scene.robot_index("fetch").unwrap();
    let robot = scene.robots()[fetch].robot().clone();
    let mut tucked = scene.robots()[fetch].configuration().to_vec();
    robot.mount().write_coordinates(&pose(1.3, -1.0, 0.0), &mut tucked);
    scene.set_configuration(fetch, &tucked);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let ik = IkConfig::new();
    let target = pose(1.95, -1.12, 0.80);
    let goal = LinkGoal { robot: fetch, group: "arm", link: None, target: &target, start: &tucked };
    let start = reach(&scene, &goal, &ik, &mut rng).unwrap();
    // The goal on the start's branch of the arm's solutions, where a straight line leads before
    // the wall is put up.
    let target = pose(1.95, -0.88, 0.80);
    let line = LinkGoal { robot: fetch, group: "arm", link: None, target: &target, start: &start };
    let goal = straight_line(&scene, &line, &MotionConfig::default(), &ik).unwrap().pop().unwrap();
    scene.add_body(wall(Vec3::new(0.08, 0.01, 0.05)), pose(1.96, -1.0, 0.781)).unwrap();
    scene.set_configuration(fetch, &start);
    (scene, fetch, start, goal)
}

/// Carries out the candidate that moves `robot` to `goal` with [`StraightEdgeOnly`], asserting
/// that it is accepted: the recorded states and the motion counts.
fn carried_out(scene: &mut Scene, robot: &str, goal: &[f64]) -> (Recorder, MotionCounts) {
    let settings = SolveSettings {
        seed: 1,
        plan_count: 1,
        planner_budget: PlanBudget::default(),
        rounds: 1,
        max_refused: 1,
        motion: MotionSettings {
            config: MotionConfig::default(),
            budget: MotionBudget::default(),
            grab_ranges: Vec::new(),
        },
        relax_goal: false,
        cancelled: &|| false,
    };
    let candidate = Candidate {
        targets: vec![RobotTarget { robot: robot.to_string(), configuration: goal.to_vec() }],
        object_poses: Vec::new(),
        releases: Vec::new(),
        grabs: Vec::new(),
    };
    let mut recorder = Recorder::default();
    let mut counts = MotionCounts::default();
    let outcome =
        execute(scene, &candidate, &mut recorder, &mut StraightEdgeOnly, &settings, 3, &mut counts);
    if let Err(Rejection::Candidate { why, .. }) = &outcome {
        panic!("refused: {why}");
    }
    assert!(outcome.is_ok());
    (recorder, counts)
}

/// A wall standing on the table between a start and a goal pose.
fn wall(half_extents: Vec3) -> Body {
    Body {
        name: "wall".to_string(),
        type_name: "wall".to_string(),
        movable: false,
        world: true,
        parts: vec![(Pose::identity(), Shape::Box { half_extents })],
    }
}

#[test]
fn an_arm_motion_blocked_down_among_objects_is_planned_from_above() {
    let (mut scene, fetch, start, goal) = fetch_beside_a_wall();
    let config = MotionConfig::default();
    // Down at the table the wall is in the way, so the motion planner alone finds nothing.
    let space = RobotSpace::new(&scene, fetch, "arm", &start, &goal, &config).unwrap();
    assert!(!space.edge_is_valid(&start, &goal));

    let before = scene.clone();
    let (recorder, counts) = carried_out(&mut scene, "fetch", &goal);
    // The first call failed down at the table; the second, between the lifted ends, found the
    // way over the wall.
    assert_eq!((counts.calls, counts.failures), (2, 1));
    assert_eq!(scene.robots()[fetch].configuration(), goal.as_slice());

    // Every recorded state is collision-free, and the gripper went up by the lift on the way.
    let robot = before.robots()[fetch].robot().clone();
    let gripper = robot.link_id("gripper_link").unwrap();
    let start_height = robot.link_pose(&start, gripper).translation.z;
    let mut highest = f64::NEG_INFINITY;
    for step in &recorder.steps {
        let q = &step.robots[0].positions;
        assert!(before.is_valid(fetch, q), "{:?}", before.first_contact(fetch, q));
        highest = highest.max(robot.link_pose(q, gripper).translation.z);
    }
    assert!(highest > start_height + LIFT_HEIGHT - 1e-3, "highest {highest}, start {start_height}");
}

/// A free-flying gripper's motion is its mount's, and is lifted like an arm's: down beside a wall
/// that stands between its start and its goal, it goes up over the wall and comes down again.
#[test]
fn a_free_flying_gripper_blocked_down_among_objects_is_lifted_over() {
    let (spec, world) = domain("packing");
    let mut scene = world.problem_scene(&spec.problems[0]).unwrap();
    let gripper = scene.robot_index("gripper").unwrap();
    let robot = scene.robots()[gripper].robot().clone();
    let down = UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0);
    let at = |y: f64| {
        let mut q = scene.robots()[gripper].configuration().to_vec();
        let root = Pose::from_parts(Translation3::new(0.0, y, 0.2), down);
        robot.mount().write_coordinates(&root, &mut q);
        q
    };
    let (start, goal) = (at(0.2), at(0.4));
    // The gripper's box reaches 5.6 cm below its origin: the wall's top, 22 cm up, is in its way
    // down at 20 cm, and below it once lifted.
    scene.add_body(wall(Vec3::new(0.08, 0.01, 0.11)), pose(0.0, 0.3, 0.11)).unwrap();
    scene.set_configuration(gripper, &start);
    let before = scene.clone();
    assert!(before.is_valid(gripper, &start) && before.is_valid(gripper, &goal));
    let config = MotionConfig::default();
    let space = RobotSpace::new(&scene, gripper, "all", &start, &goal, &config).unwrap();
    assert!(!space.edge_is_valid(&start, &goal));

    let (recorder, counts) = carried_out(&mut scene, "gripper", &goal);
    assert_eq!((counts.calls, counts.failures), (2, 1));
    assert_eq!(scene.robots()[gripper].configuration(), goal.as_slice());
    let link = robot.link_id("gripper_link").unwrap();
    let mut highest = f64::NEG_INFINITY;
    for step in &recorder.steps {
        let q = &step.robots[0].positions;
        assert!(before.is_valid(gripper, q), "{:?}", before.first_contact(gripper, q));
        highest = highest.max(robot.link_pose(q, link).translation.z);
    }
    assert!(highest > 0.2 + LIFT_HEIGHT - 1e-3, "highest {highest}");
}
