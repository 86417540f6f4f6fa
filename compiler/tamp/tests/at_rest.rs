//! The bundled problems' initial scenes of the domains the solver handles are at rest: every
//! movable object rests by lamp-world's rule where it stands, and the physics check lets the
//! whole scene stand. A solution's final scene is judged by the same two rules, so a scene that
//! failed them from the start could never be solved.

use lamp_tamp::at_rest::check_at_rest;
use lamp_test_support::domain;

#[test]
fn every_initial_scene_of_packing_cafe_and_dinner_is_at_rest() {
    for name in ["packing", "cafe", "dinner"] {
        let (spec, world) = domain(name);
        for problem in &spec.problems {
            let scene = world.problem_scene(problem).expect("the scene loads");
            for (index, body) in scene.bodies().iter().enumerate() {
                if body.movable && !body.is_marker() {
                    let rest = scene.resting_pose(index);
                    assert!(
                        rest.is_ok(),
                        "{name} {}: {}",
                        problem.name,
                        rest.err().map_or_else(String::new, |e| e.to_string())
                    );
                }
            }
            if let Err(error) = check_at_rest(&scene, None) {
                panic!("{name} {}: {error}", problem.name);
            }
        }
    }
}
