//! End to end on Café: real demonstrations made in memory, learned with lamp-build, and problems
//! that move cans between the tables and the counter solved with the first-party plugins linked
//! in. The trajectory is checked independently of the solver's own replay: nothing collides
//! along the way, the gripper ends empty, and every can stands upright on its goal surface's top.

#[path = "support/learned.rs"]
mod learned;

use lamp_tamp::Solution;
use learned::{CAFE, solve_problem};

/// Replays the trajectory in a fresh scene: no step collides; at the end every can stands on the
/// top its goal names, upright, its centre 5 cm inside the edges, at most 5 mm above it (the
/// learned region's height), released.
fn check_delivered(name: &str, solution: &Solution) {
    let problem = CAFE.spec.problems.iter().find(|p| p.name == name).expect("the problem exists");
    let scene = learned::replay_collision_free(&CAFE, name, solution);
    let grasps = learned::assert_fingers_grip(&CAFE, name, solution);
    assert!(grasps > 0, "{name}: the fingers close on every can");
    let steps = &solution.trajectory.steps;
    let last = steps.last().expect("a trajectory");
    assert_eq!(last.robots[0].held, vec![None], "{name}: the gripper ends empty");
    for atom in &problem.goal.atoms {
        assert_eq!(atom.relation, "on");
        let (can, surface) = (&atom.arguments[0], &atom.arguments[1]);
        let top = last.body_poses[scene.body_index(surface).expect("a surface")];
        let pose = top.inv_mul(&last.body_poses[scene.body_index(can).expect("a can")]);
        let t = pose.translation.vector;
        assert!(
            t.x.abs() <= 0.40 && t.y.abs() <= 0.40,
            "{name}: {can} within {surface}'s top: {t:?}"
        );
        assert!((0.0..=0.005).contains(&t.z), "{name}: {can} stands on {surface}: {t:?}");
        let up = pose.rotation * nalgebra::Vector3::z();
        assert!(up.z > 0.99, "{name}: {can} upright");
    }
}

/// The Fetch may start anywhere on the free floor, facing any way: a problem whose bundled start
/// is the origin facing +x solves from three starts around the room, each in another quarter of
/// the turn, and the trajectory starts there.
#[test]
fn the_fetch_may_start_anywhere_on_the_floor_facing_any_way() {
    let name = "cafe2_01";
    let starts = [(2.5, -2.4, 167.0), (-1.0, 1.2, -100.0), (4.2, -0.5, 80.0)];
    for solution in learned::solve_from_floor_starts(&CAFE, name, &starts) {
        check_delivered(name, &solution);
    }
}

#[test]
fn cans_move_between_tables_and_the_counter_and_the_trajectory_is_collision_free() {
    // cafe2_02 takes a can off the counter; cafe3_01 puts two on it.
    for name in ["cafe2_02", "cafe3_01"] {
        let solution =
            solve_problem(&CAFE, name, 1).unwrap_or_else(|error| panic!("{name}: {error}"));
        assert!(solution.summary.success);
        assert!(solution.summary.relaxed_goal.is_empty(), "{name}: the whole goal");
        check_delivered(name, &solution);
        // The Fetch's base and arm, continuous joints included, within their limits.
        let worst = learned::assert_executable(&CAFE, name, &solution);
        assert!(worst > 0.5, "{name}: some joint comes near its limit ({worst})");
    }
}
