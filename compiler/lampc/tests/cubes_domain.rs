//! The Cubes domain end to end, as a user builds one: `domains/cubes/record.py`, a pybullet script
//! that knows nothing of lamp, records demonstrations as plain ROS 2 bags; `lampc build` learns
//! from them with an empty `learn` block, and `lampc solve` stacks towers of two, four and six
//! cubes, bottom up: the learned pick asks that nothing rests on the cube it takes (a cube taken
//! from under another is refused by the solver, and a plan that needed it would not be solved).
//! A cube out of the arm's reach, the tutorial's failing problem (`docs/new-domain.md`), fails
//! saying so. Skipped unless python3 has pybullet and mcap-ros2-support (tests/oracles.txt).

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::lampc;

fn domains() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains")
}

fn run(output: Output, what: &str) -> String {
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "{what} failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

/// The bundled spec in `scratch`, its robot file found where it is; its demonstrations are then
/// `scratch/build/bags/*.mcap`, where the spec looks for them.
fn spec_in(scratch: &Path) -> PathBuf {
    let robots = domains().join("robots");
    let text = std::fs::read_to_string(domains().join("cubes/cubes.lamp"))
        .expect("the bundled spec")
        .replace("\"../robots/", &format!("\"{}/", robots.display()));
    let path = scratch.join("cubes.lamp");
    std::fs::write(&path, text).expect("writes the spec");
    path
}

/// The cube's world position in the solution's last step.
fn final_position(trajectory: &lamp_trajectory::Trajectory, name: &str) -> nalgebra::Vector3<f64> {
    let index = trajectory
        .header
        .bodies
        .iter()
        .position(|body| body.name == name)
        .unwrap_or_else(|| panic!("the trajectory lists {name}"));
    trajectory.steps.last().expect("steps").body_poses[index].translation.vector
}

#[test]
fn towers_are_stacked_with_a_model_learned_from_plain_ros2_bags() {
    if !lamp_test_support::python_oracle("pybullet", "pybullet")
        || !lamp_test_support::python_oracle("mcap_ros2", "mcap-ros2-support")
    {
        return;
    }
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let spec = spec_in(scratch.path());
    let bags = scratch.path().join("build/bags");
    let recorded = Command::new("python3")
        .arg(domains().join("cubes/record.py"))
        .args(["--count", "30", "--seed", "1", "--out"])
        .arg(&bags)
        .output()
        .expect("python3 runs");
    run(recorded, "record.py");

    let checked = lampc(["check".as_ref(), spec.as_os_str()]);
    let said = String::from_utf8_lossy(&checked.stderr);
    assert!(checked.status.success(), "{said}");
    assert!(said.contains("cubes.lamp: ok (domain `cubes`, 3 problem(s))"), "{said}");
    let built = run(lampc(["build".as_ref(), spec.as_os_str()]), "lampc build");
    // The spec's `on` names the learned region of a cube resting on another.
    assert!(built.contains("alias           on = cube_cube_"), "{built}");
    let model = scratch.path().join("build/model");
    let vocabulary = std::fs::read_to_string(model.join("vocabulary.md")).expect("the report");
    assert!(vocabulary.contains("### `cube_cube`: cube relative to cube"), "{vocabulary}");
    assert!(vocabulary.contains("## Actions"), "{vocabulary}");

    let validator = lamp_test_support::python_oracle("unified_planning", "unified-planning");
    for (problem, tower) in [("tower_2", 2), ("tower_4", 4), ("tower_6", 6)] {
        let out = scratch.path().join(problem);
        let solved = run(
            lampc([
                "solve".as_ref(),
                spec.as_os_str(),
                "--problem".as_ref(),
                problem.as_ref(),
                "--out".as_ref(),
                out.as_os_str(),
            ]),
            problem,
        );
        assert!(solved.contains(&format!("{problem}: solved")), "{solved}");
        assert!(solved.contains("validated by replay"), "{solved}");
        // One placement per cube, no replan: each pick and put is the plan's own.
        assert!(solved.contains(", 0 replans"), "{problem}: {solved}");

        let bytes = std::fs::read(out.join("trajectory.mcap")).expect("a trajectory");
        let trajectory = lamp_trajectory::Trajectory::from_bytes(&bytes, "trajectory.mcap")
            .expect("it reads back");
        // Each cube of the goal ends square on the one below: centred within a few millimetres,
        // its bottom 1 mm above the lower cube's top (a cube is 4 cm high).
        for upper in 2..=tower {
            let (lower, upper) = (format!("c{}", upper - 1), format!("c{upper}"));
            let offset = final_position(&trajectory, &upper) - final_position(&trajectory, &lower);
            assert!(offset.xy().norm() < 0.01, "{problem}: {upper} is beside {lower}: {offset}");
            assert!((offset.z - 0.041).abs() < 0.002, "{problem}: {upper} over {lower}: {offset}");
        }

        if validator {
            let checked = Command::new("python3")
                .arg(domains().join("tools/validate_plan.py"))
                .arg(model.join("domain.pddl"))
                .arg(model.join("problems").join(format!("{problem}.pddl")))
                .arg(&out)
                .output()
                .expect("python3 runs");
            let verdict = run(checked, "validate_plan.py");
            assert!(verdict.contains("reaches the goal"), "{verdict}");
        }
    }

    // The tutorial's failing problem (docs/new-domain.md, section 6), taken from the page itself,
    // so that the page cannot drift from what lampc says.
    let page = std::fs::read_to_string(domains().join("../docs/new-domain.md")).expect("the page");
    let section = &page[page.find("## 6. When a solve fails").expect("the section")..];
    let block = &section[section.find("```lamp\n").expect("a spec block") + 8..];
    let problem = &block[..block.find("```").expect("the block ends")];
    let mut text = std::fs::read_to_string(&spec).expect("the spec");
    text.push('\n');
    text.push_str(problem);
    std::fs::write(&spec, text).expect("writes the spec");
    run(lampc(["build".as_ref(), spec.as_os_str()]), "lampc build with tower_far");
    let failed =
        lampc(["solve".as_ref(), spec.as_os_str(), "--problem".as_ref(), "tower_far".as_ref()]);
    let stderr = String::from_utf8_lossy(&failed.stderr);
    assert_eq!(failed.status.code(), Some(1), "{stderr}");
    let said = "`yumi` cannot reach where the step puts `gripper_l_base` (short by at least";
    let words = |text: &str| text.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(words(section).contains(said), "the page quotes what lampc says");
    assert!(words(&stderr).contains(said), "{stderr}");
    let report = scratch.path().join("build/solutions/tower_far.failed/failure.json");
    assert!(report.is_file(), "the failure report is written: {stderr}");
}
