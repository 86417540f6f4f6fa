//! End to end on Jenga: real demonstrations of at most three blocks made in memory, learned
//! with lamp-build, and a tower built from a structure goal with the first-party plugins linked
//! in. The trajectory is checked independently of the solver's own replay: nothing collides,
//! the gripper ends empty, the fingers close onto every block it holds and open before it lets
//! go, and every block ends within 5 mm and 3° of its pose in the structure.
//! No order is written anywhere: the learned actions order the tower.

#[path = "support/learned.rs"]
mod learned;

use learned::{JENGA, solve_problem};

#[test]
fn a_block_across_two_is_built_bottom_up_from_a_structure_goal() {
    let name = "tower_3";
    let solution = solve_problem(&JENGA, name, 1).unwrap_or_else(|error| panic!("{name}: {error}"));
    assert!(solution.summary.success);
    assert!(solution.summary.relaxed_goal.is_empty(), "{name}: the whole goal");
    let problem = JENGA.spec.problems.iter().find(|p| p.name == name).expect("the problem exists");
    let scene = learned::replay_collision_free(&JENGA, name, &solution);
    learned::assert_executable(&JENGA, name, &solution);
    assert_eq!(learned::assert_fingers_grip(&JENGA, name, &solution), 3, "{name}: grasps");
    let last = solution.trajectory.steps.last().expect("a trajectory");
    assert_eq!(last.robots[0].held, vec![None], "{name}: the gripper ends empty");
    let targets = JENGA.world.structure_targets(problem).expect("the structure is placed");
    assert_eq!(targets.len(), 3);
    for (block, target) in &targets {
        let pose = last.body_poses[scene.body_index(block).expect("the block")];
        let offset = target.inv_mul(&pose);
        assert!(
            offset.translation.vector.norm() <= 0.005,
            "{name}: {block} within 5 mm of its target: {:?}",
            offset.translation.vector
        );
        assert!(offset.rotation.angle() <= 3f64.to_radians(), "{name}: {block} within 3°");
    }
}
