//! End to end on Dinner: real demonstrations made in memory (one glass or bowl each, from a start
//! marker to a target marker), learned with lamp-build, and place settings solved from AtGoal
//! goals with the first-party plugins linked in. The trajectory is checked independently of the
//! solver's own replay: nothing collides, the gripper ends empty, and every object stands
//! upright within its goal's tolerance of its target pose.

#[path = "support/learned.rs"]
mod learned;

use lamp_tamp::Solution;
use learned::{DINNER, solve_problem};

fn check_set(name: &str, solution: &Solution) {
    let problem = DINNER.spec.problems.iter().find(|p| p.name == name).expect("the problem exists");
    let scene = learned::replay_collision_free(&DINNER, name, solution);
    let last = solution.trajectory.steps.last().expect("a trajectory");
    assert_eq!(last.robots[0].held, vec![None], "{name}: the gripper ends empty");
    assert!(!problem.goal.at.is_empty(), "{name}: AtGoal goals");
    for target in &problem.goal.at {
        let pose = last.body_poses[scene.body_index(&target.object).expect("the object")];
        let offset = target.pose.inv_mul(&pose);
        let t = offset.translation.vector;
        assert!(
            t.xy().norm() <= target.position_tolerance,
            "{name}: {} within {} m of its target: {t:?}",
            target.object,
            target.position_tolerance
        );
        assert!(
            t.z.abs() <= 0.005,
            "{name}: {} stands at its target's height: {t:?}",
            target.object
        );
        let up = pose.rotation * nalgebra::Vector3::z();
        assert!(up.z > 0.99, "{name}: {} upright", target.object);
    }
}

#[test]
fn place_settings_are_set_from_at_goals_and_the_trajectory_is_collision_free() {
    // One setting (a glass and a bowl 16 cm apart), and two settings side by side: the base
    // stands before several markers at once.
    for name in ["set_table_2", "set_table_4"] {
        let solution =
            solve_problem(&DINNER, name, 1).unwrap_or_else(|error| panic!("{name}: {error}"));
        assert!(solution.summary.success);
        assert!(solution.summary.relaxed_goal.is_empty(), "{name}: the whole goal");
        check_set(name, &solution);
    }
}
