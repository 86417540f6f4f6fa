//! Motion planning: RRT-Connect on a known 2-D maze and on the bundled robots in cluttered
//! scenes; every state of every returned path, at the checking resolution, is collision-free.

#![allow(clippy::unwrap_used)] // a failed step is a failed test

mod support;

use std::f64::consts::PI;

use lamp_robot::{IkConfig, IkError, IkGoal, solve_ik};
use lamp_world::{
    Contact, LinkGoal, MAX_EDGE_STEPS, MotionConfig, MotionError, ReachError, RobotSpace,
    RrtConfig, RrtError, Scene, Space, StraightLineError, densify, plan_motion, reach,
    reach_observed, rrt_connect, straight_line,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use support::{domain, pose};

/// A point in the unit square; walls are axis-aligned rectangles.
struct Maze {
    walls: Vec<[f64; 4]>,
}

impl Space for Maze {
    fn sample(&self, rng: &mut ChaCha8Rng, out: &mut [f64]) {
        use rand::RngExt;
        out[0] = rng.random();
        out[1] = rng.random();
    }
    fn distance(&self, a: &[f64], b: &[f64]) -> f64 {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
    }
    fn interpolate(&self, a: &[f64], b: &[f64], t: f64, out: &mut [f64]) {
        out[0] = a[0] + t * (b[0] - a[0]);
        out[1] = a[1] + t * (b[1] - a[1]);
    }
    fn is_valid(&self, q: &[f64]) -> bool {
        (0.0..=1.0).contains(&q[0])
            && (0.0..=1.0).contains(&q[1])
            && !self
                .walls
                .iter()
                .any(|w| q[0] >= w[0] && q[0] <= w[2] && q[1] >= w[1] && q[1] <= w[3])
    }
    fn edge_steps(&self, a: &[f64], b: &[f64]) -> usize {
        (self.distance(a, b) / 0.002).ceil().max(1.0) as usize
    }
}

fn path_is_valid(space: &impl Space, path: &[Vec<f64>]) -> bool {
    path.iter().all(|q| space.is_valid(q))
        && path.windows(2).all(|w| space.edge_is_valid(&w[0], &w[1]))
}

fn small_steps() -> RrtConfig {
    RrtConfig { step: 0.1, max_iterations: 3_000, timeout: None, shortcut_attempts: 100 }
}

#[test]
fn rrt_connect_threads_a_maze_deterministically() {
    // Two walls with gaps at opposite ends force an S-shaped path.
    let maze = Maze { walls: vec![[0.3, 0.0, 0.35, 0.8], [0.65, 0.2, 0.7, 1.0]] };
    let (start, goal) = ([0.1, 0.1], [0.9, 0.9]);
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (path, stats) = rrt_connect(&maze, &start, &goal, &small_steps(), &mut rng).unwrap();
    assert_eq!(path.first().unwrap().as_slice(), &start);
    assert_eq!(path.last().unwrap().as_slice(), &goal);
    assert!(path_is_valid(&maze, &path));
    assert!(stats.waypoints <= stats.raw_waypoints);
    // It went around the walls: through the first gap (y > 0.8) and the second (y < 0.2).
    let crossings = |x: f64| {
        path.windows(2)
            .filter(|w| (w[0][0] - x) * (w[1][0] - x) <= 0.0)
            .map(|w| w[0][1] + (x - w[0][0]) / (w[1][0] - w[0][0]) * (w[1][1] - w[0][1]))
            .collect::<Vec<_>>()
    };
    assert!(crossings(0.325).iter().all(|&y| y > 0.8));
    assert!(crossings(0.675).iter().all(|&y| y < 0.2));

    let mut again = ChaCha8Rng::seed_from_u64(7);
    let (same, _) = rrt_connect(&maze, &start, &goal, &small_steps(), &mut again).unwrap();
    assert_eq!(path, same);
}

#[test]
fn rrt_connect_reports_no_path_and_invalid_endpoints() {
    // The goal is walled in.
    let walls = vec![[0.6, 0.6, 1.0, 0.62], [0.6, 0.6, 0.62, 1.0]];
    let maze = Maze { walls };
    let config = RrtConfig { max_iterations: 300, ..small_steps() };
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let error = rrt_connect(&maze, &[0.1, 0.1], &[0.9, 0.9], &config, &mut rng).unwrap_err();
    assert!(matches!(error, RrtError::NoPath { iterations: 300, .. }), "{error:?}");
    let error = rrt_connect(&maze, &[0.61, 0.7], &[0.9, 0.9], &config, &mut rng).unwrap_err();
    assert_eq!(error, RrtError::InvalidStart);
    let error = rrt_connect(&maze, &[0.1, 0.1], &[2.0, 0.9], &config, &mut rng).unwrap_err();
    assert_eq!(error, RrtError::InvalidGoal);
}

/// Every state along the path at the checking resolution is valid, and the ends are right.
fn assert_path_collision_free(
    scene: &Scene,
    robot: usize,
    path: &[Vec<f64>],
    config: &MotionConfig,
) {
    let model = scene.robots()[robot].robot().clone();
    let states = densify(&model, path, config).expect("a path of ordinary length");
    for (index, q) in states.iter().enumerate() {
        assert!(scene.is_valid(robot, q), "state {index}: {:?}", scene.first_contact(robot, q));
    }
    for pair in states.windows(2) {
        assert!(
            lamp_world::edge_steps(
                &model,
                &pair[0],
                &pair[1],
                config.linear_resolution,
                config.angular_resolution
            ) <= 1
        );
    }
}

/// The Fetch arm's gripper link (the group's own) at `target`, from `start`.
fn fetch_arm<'a>(fetch: usize, target: &'a lamp_geometry::Pose, start: &'a [f64]) -> LinkGoal<'a> {
    LinkGoal { robot: fetch, group: "arm", link: None, target, start }
}

/// The café scene with the Fetch parked in front of table1, arm tucked.
fn fetch_at_table() -> (Scene, usize, Vec<f64>) {
    let (spec, world) = domain("cafe");
    let problem = &spec.problems[0];
    let mut scene = world.problem_scene(problem).unwrap();
    let fetch = scene.robot_index("fetch").unwrap();
    let robot = scene.robots()[fetch].robot().clone();
    let mut q = scene.robots()[fetch].configuration().to_vec();
    robot.mount().write_coordinates(&pose(1.3, -1.0, 0.0, 0.0, 0.0, 0.0), &mut q);
    assert!(scene.is_valid(fetch, &q), "{:?}", scene.first_contact(fetch, &q));
    scene.set_configuration(fetch, &q);
    (scene, fetch, q)
}

#[test]
fn collision_free_ik_reaches_over_the_table_within_tolerance() {
    let (scene, fetch, tucked) = fetch_at_table();
    let robot = scene.robots()[fetch].robot().clone();
    let target = pose(1.85, -1.0, 0.95, 0.0, 0.0, 0.0);
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let q = reach(&scene, &fetch_arm(fetch, &target, &tucked), &IkConfig::new(), &mut rng).unwrap();
    assert!(scene.is_valid(fetch, &q));
    let gripper = robot.link_id("gripper_link").unwrap();
    let (position, orientation) =
        lamp_robot::pose_error_norms(&robot.link_pose(&q, gripper), &target);
    assert!(position < 1e-3 && orientation < 1e-2, "errors {position} m, {orientation} rad");

    // Inside the table top there is nothing collision-free to find.
    let inside = pose(2.0, -1.0, 0.68, 0.0, 0.0, 0.0);
    let error = reach(&scene, &fetch_arm(fetch, &inside, &tucked), &IkConfig::new(), &mut rng);
    assert!(error.is_err());
}

#[test]
fn a_gripper_inside_an_obstacle_is_refused_before_any_search_leaving_the_same_draws() {
    let (scene, fetch, tucked) = fetch_at_table();
    let inside = pose(2.0, -1.0, 0.68, 0.0, 0.0, 0.0);
    let config = IkConfig::new();
    let mut screened = ChaCha8Rng::seed_from_u64(11);
    let mut met = Vec::new();
    let goal = fetch_arm(fetch, &inside, &tucked);
    let error =
        reach_observed(&scene, &goal, &config, &mut screened, &mut |contact| met.push(contact))
            .unwrap_err();
    assert!(matches!(error, ReachError::Ik(IkError::TargetRefused { .. })), "{error}");
    assert_eq!(
        met,
        [Contact::LinkBody { link: "gripper_link".into(), body: "table1".into() }],
        "what is in the way is said once"
    );

    // The search the screen spared: every restart tried, every converged one refused.
    let robot = scene.robots()[fetch].robot().clone();
    let link = robot.link_id("gripper_link").unwrap();
    let full = IkGoal {
        robot: &robot,
        group: robot.group("arm").unwrap(),
        link,
        target: &inside,
        seed: &tucked,
    };
    let mut searched = ChaCha8Rng::seed_from_u64(11);
    let searched_error =
        solve_ik(&full, &config, &mut searched, &mut |q| scene.is_valid(fetch, q)).unwrap_err();
    assert!(matches!(searched_error, IkError::NoSolution { .. }), "{searched_error}");
    assert_eq!(screened.get_word_pos(), searched.get_word_pos(), "the same draws follow");

    // A gripper that only grazes the table top, by less than the tolerances let it move, is
    // left to the search: some configuration within them may clear it.
    let grazing = pose(1.85, -1.0, 0.95, 0.0, 0.0, 0.0);
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    assert!(reach(&scene, &fetch_arm(fetch, &grazing, &tucked), &config, &mut rng).is_ok());
}

#[test]
fn an_edge_checked_on_two_threads_has_the_answer_of_its_states_checked_in_turn() {
    let (scene, fetch, tucked) = fetch_at_table();
    let robot = scene.robots()[fetch].robot().clone();
    let over_table = pose(1.85, -1.0, 0.95, 0.0, 0.0, 0.0);
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let start =
        reach(&scene, &fetch_arm(fetch, &over_table, &tucked), &IkConfig::new(), &mut rng).unwrap();
    let config = MotionConfig::default();
    let space = RobotSpace::new(&scene, fetch, "arm", &start, &start, &config).unwrap();
    let pool = |threads| rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    let (one, two) = (pool(1), pool(2));
    let (mut sampled, mut end, mut kinds, mut long) =
        (start.clone(), start.clone(), [0_usize; 2], 0);
    for trial in 0..60 {
        // Part of the way from the gripper over the table to a random configuration: short
        // edges are mostly free, long ones mostly touch the table, its cans or the robot.
        space.sample(&mut rng, &mut sampled);
        robot.interpolate(&start, &sampled, 0.05 + 0.01 * f64::from(trial), &mut end);
        let steps = space.edge_steps(&start, &end);
        if steps > MAX_EDGE_STEPS {
            continue;
        }
        // Every inner state, in order, by the scene's own check.
        let mut q = start.clone();
        let in_turn = (1..steps).all(|i| {
            robot.interpolate(&start, &end, i as f64 / steps as f64, &mut q);
            scene.is_valid(fetch, &q)
        });
        assert_eq!(one.install(|| space.edge_is_valid(&start, &end)), in_turn);
        assert_eq!(two.install(|| space.edge_is_valid(&start, &end)), in_turn);
        kinds[usize::from(in_turn)] += 1;
        // Only an edge of at least 64 inner states is shared between threads.
        long += usize::from(steps > 64);
    }
    assert!(kinds[0] >= 10 && kinds[1] >= 10, "invalid and valid edges: {kinds:?}");
    assert!(long >= 20, "{long} edges long enough to be shared");
}

#[test]
fn fetch_arm_paths_into_a_cluttered_table_are_collision_free() {
    let (scene, fetch, tucked) = fetch_at_table();
    let target = pose(1.85, -0.95, 0.95, 0.0, 0.0, 0.0);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let goal =
        reach(&scene, &fetch_arm(fetch, &target, &tucked), &IkConfig::new(), &mut rng).unwrap();
    let config = MotionConfig::default();
    let plan = plan_motion(&scene, fetch, "arm", &tucked, &goal, &config, &mut rng).unwrap();
    assert_eq!(plan.waypoints.first().unwrap(), &tucked);
    assert_eq!(plan.waypoints.last().unwrap(), &goal);
    assert_path_collision_free(&scene, fetch, &plan.waypoints, &config);

    let mut again = ChaCha8Rng::seed_from_u64(5);
    let goal_again =
        reach(&scene, &fetch_arm(fetch, &target, &tucked), &IkConfig::new(), &mut again).unwrap();
    let replan =
        plan_motion(&scene, fetch, "arm", &tucked, &goal_again, &config, &mut again).unwrap();
    assert_eq!(plan, replan, "same seed, same path");

    // Moving a coordinate outside the group is refused, not silently planned.
    let mut elsewhere = goal.clone();
    elsewhere[0] += 0.5;
    assert!(plan_motion(&scene, fetch, "arm", &tucked, &elsewhere, &config, &mut rng).is_err());
}

#[test]
fn a_straight_move_keeps_the_gripper_on_the_line_and_stops_at_the_table() {
    let (scene, fetch, tucked) = fetch_at_table();
    let robot = scene.robots()[fetch].robot().clone();
    let gripper = robot.link_id("gripper_link").unwrap();
    let above = pose(1.85, -1.0, 0.95, 0.0, 0.0, 0.0);
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let ik = IkConfig::new();
    let start = reach(&scene, &fetch_arm(fetch, &above, &tucked), &ik, &mut rng).unwrap();
    let config = MotionConfig::default();

    // Down 12 cm: every solution is on the vertical line through the start, and so is every
    // state between them, to within the IK tolerance plus the chord of one small step.
    let lower = pose(1.85, -1.0, 0.83, 0.0, 0.0, 0.0);
    let path = straight_line(&scene, &fetch_arm(fetch, &lower, &start), &config, &ik).unwrap();
    assert_eq!(path.first().unwrap(), &start);
    assert!(path.len() >= 24, "a solution every 5 mm: {}", path.len());
    let (position, _) =
        lamp_robot::pose_error_norms(&robot.link_pose(path.last().unwrap(), gripper), &lower);
    assert!(position < 1e-3);
    assert_path_collision_free(&scene, fetch, &path, &config);
    for q in densify(&robot, &path, &config).expect("a path of ordinary length") {
        let p = robot.link_pose(&q, gripper).translation.vector;
        let off_line = ((p.x - 1.85).powi(2) + (p.y + 1.0).powi(2)).sqrt();
        assert!(off_line < 2e-3, "{off_line} m off the line at z = {}", p.z);
    }

    // Down into the table top: refused part of the way, with nothing to follow.
    let inside = pose(1.85, -1.0, 0.70, 0.0, 0.0, 0.0);
    match straight_line(&scene, &fetch_arm(fetch, &inside, &start), &config, &ik) {
        Err(StraightLineError::Collision { percent, contact }) => {
            assert!(percent > 50.0 && percent < 100.0, "{percent} %");
            assert!(contact.contains("table1"), "{contact}");
        }
        other => panic!("expected a collision, got {other:?}"),
    }
}

#[test]
fn fetch_base_drives_around_furniture() {
    let (spec, world) = domain("cafe");
    let scene = world.problem_scene(&spec.problems[0]).unwrap();
    let fetch = scene.robot_index("fetch").unwrap();
    let robot = scene.robots()[fetch].robot().clone();
    let start = scene.robots()[fetch].configuration().to_vec();
    // From the origin to the far side of table1 (at x = 2.0, y = -1.0), facing it.
    let mut goal = start.clone();
    robot.mount().write_coordinates(&pose(2.7, -1.0, 0.0, 0.0, 0.0, PI), &mut goal);
    let config = MotionConfig::default();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let plan = plan_motion(&scene, fetch, "base", &start, &goal, &config, &mut rng).unwrap();
    assert_path_collision_free(&scene, fetch, &plan.waypoints, &config);
}

#[test]
fn the_free_flying_gripper_carries_a_can_into_the_box() {
    let (mut scene, gripper, can, start, grasp) = support::gripper_over_can();
    let robot = scene.robots()[gripper].robot().clone();
    scene.grab(gripper, can).unwrap();

    let box_pose = scene.body_pose(scene.body_index("box1").unwrap());
    let mut goal = start.clone();
    robot
        .mount()
        .write_coordinates(&(box_pose * pose(0.0, 0.0, 0.001, 0.0, 0.0, 0.3) * grasp), &mut goal);
    assert!(scene.is_valid(gripper, &goal), "{:?}", scene.first_contact(gripper, &goal));
    let config = MotionConfig::default();
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let plan = plan_motion(&scene, gripper, "all", &start, &goal, &config, &mut rng).unwrap();
    assert!(plan.waypoints.len() >= 3, "the box walls are in the way of a straight line");
    assert_path_collision_free(&scene, gripper, &plan.waypoints, &config);
}

#[test]
fn a_move_too_long_to_record_is_refused_not_allocated() {
    let (scene, gripper, _, q, _) = support::gripper_over_can();
    let robot = scene.robots()[gripper].robot().clone();
    let config = MotionConfig::default();
    let mut far = q.clone();
    robot.mount().write_coordinates(&pose(99_999.0, 0.0, 0.45, PI, 0.0, 0.0), &mut far);
    match densify(&robot, &[q.clone(), far.clone()], &config) {
        Err(MotionError::TooManySteps { steps, limit, distance }) => {
            assert_eq!(limit, MAX_EDGE_STEPS);
            assert!(steps > 1.9e7, "{steps}");
            assert!(distance.ends_with(" m"), "{distance}");
        }
        other => panic!("expected a refusal, got {:?}", other.map(|states| states.len())),
    }
    // Checking such an edge looks at a bounded number of states, and never finds it valid.
    let steps = lamp_world::edge_steps(&robot, &q, &far, 0.005, 0.01);
    assert_eq!(steps, MAX_EDGE_STEPS + 1);
    // A move of ordinary length is densified at the resolution.
    let mut near = q.clone();
    robot.mount().write_coordinates(&pose(0.1, 0.0, 0.45, PI, 0.0, 0.0), &mut near);
    let states = densify(&robot, &[q, near], &config).expect("an ordinary move");
    assert!(states.len() > 10 && states.len() < 1_000, "{}", states.len());
}

/// A densified path ends on each waypoint exactly, not on an interpolation that may differ from
/// it in the last bit: the scene is left where the recording ends, and an object let go of
/// there must settle where the replay settles it.
#[test]
fn densified_paths_end_exactly_on_their_waypoints() {
    let (scene, fetch, tucked) = fetch_at_table();
    let robot = scene.robots()[fetch].robot().clone();
    let mut goal = tucked.clone();
    // 1.6 + 1 · (0.123456789 − 1.6) is 0.12345678900000001.
    goal[3] = 0.123_456_789;
    let mut from = tucked.clone();
    from[3] = 1.6;
    let states = densify(&robot, &[from, goal.clone()], &MotionConfig::default()).unwrap();
    assert_eq!(states.last().unwrap(), &goal);
}
