//! Structure transcription on a model learned in memory: synthetic demonstrations in which a
//! magnetic gripper puts one block on the table or onto another (a marker where it ends, none
//! where blocks start, as a structure problem's scene has) teach "on a marker" and "on a block"; a two-layer structure at an
//! anchor becomes those relations between its blocks and their markers, and broken structures
//! are refused with the finding that names the object.

use std::collections::BTreeMap;
use std::sync::LazyLock;

use lamp_abstraction::{Participant, RegionClassifier, Role, Snapshot};
use lamp_build::problems::ProblemContext;
use lamp_build::{Adapter, ProblemOutcome, StructureIssue, problem_pddl};
use lamp_geometry::Pose;
use lamp_learn::{Demonstration, Model};
use lamp_spec::Spec;
use lamp_world::SpecWorld;
use nalgebra::{Translation3, UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Demonstrations learned from: enough for both placements to be seen often.
const DEMOS: usize = 40;
/// The block's half height and the 1 mm the scenes keep above a support.
const HALF_HEIGHT: f64 = 0.015;
const GAP: f64 = 0.001;

fn fixture() -> (Spec, SpecWorld) {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/stacking.lamp");
    lamp_test_support::load(&path)
}

static MODEL: LazyLock<(Spec, SpecWorld, Model)> = LazyLock::new(|| {
    let (spec, world) = fixture();
    let demonstrations: Vec<Demonstration> = (0..DEMOS).map(demonstration).collect();
    let model = lamp_build::learn_model(&spec, &world, &demonstrations)
        .unwrap_or_else(|error| panic!("the synthetic demonstrations learn: {error}"));
    (spec, world, model)
});

fn pose(x: f64, y: f64, z: f64, yaw: f64) -> Pose {
    Pose::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw),
    )
}

/// Demonstration `index`: `b1` lies on the table, `b2` elsewhere; the gripper carries `b2` onto
/// `b1` (even indices) or to another place on the table (odd ones), with a millimetre and a
/// degree of placement noise.
fn demonstration(index: usize) -> Demonstration {
    let mut rng = ChaCha8Rng::seed_from_u64(1000 + index as u64);
    let spot = |rng: &mut ChaCha8Rng| {
        (rng.random_range(-0.3..0.3), rng.random_range(-0.3..0.3), rng.random_range(-3.1..3.1))
    };
    let (x1, y1, yaw1) = spot(&mut rng);
    let b1 = pose(x1, y1, HALF_HEIGHT + GAP, yaw1);
    let (x2, y2, yaw2) = loop {
        let candidate = spot(&mut rng);
        if (candidate.0 - x1).hypot(candidate.1 - y1) > 0.2 {
            break candidate;
        }
    };
    let start = pose(x2, y2, HALF_HEIGHT + GAP, yaw2);
    let noise = |rng: &mut ChaCha8Rng| {
        pose(
            rng.random_range(-0.001..0.001),
            rng.random_range(-0.001..0.001),
            0.0,
            rng.random_range(-1.0_f64..1.0).to_radians(),
        )
    };
    let target = if index.is_multiple_of(2) {
        b1 * pose(0.0, 0.0, 2.0 * HALF_HEIGHT + GAP, 0.0) * noise(&mut rng)
    } else {
        let (x, y, yaw) = loop {
            let candidate = spot(&mut rng);
            let far = |x: f64, y: f64| (candidate.0 - x).hypot(candidate.1 - y) > 0.2;
            if far(x1, y1) && far(x2, y2) {
                break candidate;
            }
        };
        pose(x, y, HALF_HEIGHT + GAP, yaw) * noise(&mut rng)
    };
    let participants = vec![
        participant("hand_gripper", "gripper", Role::RobotPart { gripper: true }),
        participant("b1", "block", Role::Object { movable: true }),
        participant("b2", "block", Role::Object { movable: true }),
        participant("goal_b2", "loc", Role::Object { movable: false }),
    ];
    // The gripper points down, 10 cm above a block it holds.
    let above = |block: &Pose, height: f64| {
        block
            * Pose::from_parts(
                Translation3::new(0.0, 0.0, height),
                UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0),
            )
    };
    let home = pose(0.0, 0.0, 0.5, 0.0) * above(&Pose::identity(), 0.0);
    let mut steps = Vec::new();
    let snapshot = |gripper: Pose, b2: Pose, held: bool| {
        let poses = vec![gripper, b1, b2, target];
        Snapshot { poses, held: if held { vec![(0, 2)] } else { Vec::new() } }
    };
    let lerp = |from: &Pose, to: &Pose, t: f64| {
        let position = from.translation.vector.lerp(&to.translation.vector, t);
        let rotation = from.rotation.slerp(&to.rotation, t);
        Pose::from_parts(position.into(), rotation)
    };
    let legs = [
        (home, above(&start, 0.2), None),
        (above(&start, 0.2), above(&start, 0.1), None),
        (above(&start, 0.1), above(&start, 0.2), Some(true)),
        (above(&start, 0.2), above(&target, 0.2), Some(true)),
        (above(&target, 0.2), above(&target, 0.1), Some(true)),
        (above(&target, 0.1), above(&target, 0.25), None),
    ];
    for (from, to, held) in legs {
        for step in 0..=5 {
            let gripper = lerp(&from, &to, f64::from(step) / 5.0);
            let carried = held.is_some();
            let block = if carried {
                gripper
                    * Pose::from_parts(
                        Translation3::new(0.0, 0.0, 0.1),
                        UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0),
                    )
            } else if steps.len() < 18 {
                start
            } else {
                target
            };
            steps.push(snapshot(gripper, block, carried));
        }
    }
    Demonstration { id: format!("stack_{index:03}"), participants, steps }
}

fn participant(name: &str, type_name: &str, role: Role) -> Participant {
    Participant { name: name.into(), type_name: type_name.into(), role }
}

/// The fixture edited, its world loaded again (the world places structures as its spec says),
/// and its problem `stack_2`.
fn problem_with(
    spec: &Spec,
    edit: impl FnOnce(&mut Spec),
) -> (Spec, SpecWorld, lamp_spec::Problem) {
    let mut spec = spec.clone();
    edit(&mut spec);
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
    let world = SpecWorld::load(&dir, &spec).expect("the world loads");
    let problem = spec.problem("stack_2").expect("the fixture's problem").clone();
    (spec, world, problem)
}

/// What `problem_pddl` makes of a problem against `model`.
fn outcome(
    spec: &Spec,
    world: &SpecWorld,
    model: &Model,
    problem: &lamp_spec::Problem,
) -> ProblemOutcome {
    let domain = lamp_learn::domain(model, &spec.domain).expect("the domain writes");
    let adapter = Adapter::new(spec, &world.robots).expect("the adapter");
    let aliases = BTreeMap::new();
    let header = vec!["structure transcription test".to_string()];
    let context = ProblemContext {
        model,
        domain: &domain,
        world,
        adapter: &adapter,
        aliases: &aliases,
        header: &header,
    };
    problem_pddl(&context, problem).unwrap_or_else(|error| panic!("the problem writes: {error}"))
}

fn written(outcome: ProblemOutcome) -> String {
    match outcome {
        ProblemOutcome::Written { text, .. } => text,
        other => panic!("the problem is written: {other:?}"),
    }
}

fn refused(outcome: ProblemOutcome) -> Vec<StructureIssue> {
    match outcome {
        ProblemOutcome::Refused { issues, .. } => issues,
        other => panic!("the problem is refused: {other:?}"),
    }
}

/// The goal section of a PDDL problem.
fn goal_of(text: &str) -> &str {
    &text[text.find("(:goal").expect("a goal")..]
}

/// The relation among `model`'s regions of `primary`–`secondary` that holds a `secondary` at
/// `relative` in `primary`'s frame.
fn relation_at(model: &Model, primary: &str, secondary: &str, relative: &Pose) -> String {
    let pair = model
        .pairs
        .iter()
        .find(|pair| pair.pair.pair.primary == primary && pair.pair.pair.secondary == secondary)
        .unwrap_or_else(|| panic!("a {primary}–{secondary} pair is learned"));
    pair.regions
        .iter()
        .map(|region| (region.model.margin(relative), region))
        .filter(|(margin, _)| *margin >= 0.0)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, region)| region.relation.clone())
        .unwrap_or_else(|| panic!("a {primary}–{secondary} region holds {relative:?}"))
}

#[test]
fn a_two_layer_structure_becomes_its_blocks_on_their_markers_and_on_each_other() {
    let (spec, world, model) = &*MODEL;
    let problem = spec.problem("stack_2").expect("the fixture's problem");
    let text = written(outcome(spec, world, model, problem));
    let goal = goal_of(&text);
    let on_marker = relation_at(model, "loc", "block", &Pose::identity());
    let on_block = relation_at(model, "block", "block", &pose(0.0, 0.0, 0.031, 0.0));
    for atom in [
        format!("({on_marker} goal_b1 b1)"),
        format!("({on_marker} goal_b2 b2)"),
        format!("({on_block} b1 b2)"),
    ] {
        assert!(goal.contains(&atom), "{atom} is a goal:\n{goal}");
    }
    // Only region relations among the blocks and their own markers, and the hand empty as it
    // starts: no `_0`, no clear relation of a block, no robot relation.
    let atoms: Vec<&str> = goal
        .lines()
        .map(str::trim)
        .filter(|line| line.starts_with("(") && !line.starts_with("(:"))
        .collect();
    assert_eq!(atoms.len(), 5, "{goal}");
    for atom in atoms {
        let hands_free =
            atom.starts_with("(clear_gripper_block_") && atom.ends_with(" hand_gripper)");
        let related =
            !atom.contains("_0 ") && !atom.starts_with("(clear_") && !atom.contains("hand_gripper");
        assert!(hands_free || related, "{atom} belongs in the goal:\n{goal}");
    }
    // The markers are objects of the problem, the targets where the structure puts the blocks.
    assert!(text.contains("goal_b1 - loc") && text.contains("goal_b2 - loc"), "{text}");
    let targets = world.structure_targets(problem).expect("the targets");
    let anchor = pose(0.1, 0.1, 0.0, 0.0);
    assert_eq!(targets[1].0, "b2");
    let expected = anchor * pose(0.0, 0.0, 0.047, 0.0);
    assert!((targets[1].1.translation.vector - expected.translation.vector).norm() < 1e-12);
    insta::assert_snapshot!("stack_2_problem", text);
}

#[test]
fn transcription_is_deterministic() {
    let (spec, world, model) = &*MODEL;
    let problem = spec.problem("stack_2").expect("the fixture's problem");
    let first = written(outcome(spec, world, model, problem));
    let second = written(outcome(spec, world, model, problem));
    assert_eq!(first, second);
}

#[test]
fn a_structure_whose_blocks_overlap_is_refused_naming_both() {
    let (spec, _, model) = &*MODEL;
    let (spec, world, problem) = problem_with(spec, |spec| {
        spec.structures[0].placements[1].pose = pose(0.02, 0.0, 0.016, 0.0);
    });
    let issues = refused(outcome(&spec, &world, model, &problem));
    assert_eq!(
        issues,
        [StructureIssue::Contact {
            problem: "stack_2".into(),
            structure: "two_layers".into(),
            object: "b1".into(),
            other: "b2".into(),
        }]
    );
    let message = issues[0].to_string();
    assert!(message.contains("`b1` and `b2` touch or overlap"), "{message}");
}

#[test]
fn a_floating_block_is_refused_by_the_resting_rule() {
    let (spec, _, model) = &*MODEL;
    let (spec, world, problem) = problem_with(spec, |spec| {
        spec.structures[0].placements[1].pose = pose(0.0, 0.0, 0.067, 0.0);
    });
    let issues = refused(outcome(&spec, &world, model, &problem));
    let [StructureIssue::Unsupported { object, reason, .. }] = issues.as_slice() else {
        panic!("one unsupported block: {issues:?}");
    };
    assert_eq!(object, "b2");
    assert!(reason.contains("would drop 20.0 mm onto `b1`"), "{reason}");
    // Hanging over the edge of the block below is refused too, by the same rule.
    let (spec, world, problem) = problem_with(&spec, |spec| {
        spec.structures[0].placements[1].pose = pose(0.05, 0.0, 0.047, 0.0);
    });
    let issues = refused(outcome(&spec, &world, model, &problem));
    assert!(
        matches!(issues.as_slice(), [StructureIssue::Unsupported { object, reason, .. }]
            if object == "b2" && reason.contains("not supported")),
        "{issues:?}"
    );
}

#[test]
fn a_block_with_no_learned_relation_at_its_place_gets_no_goal_atom() {
    let (spec, _, model) = &*MODEL;
    // Without a marker type nothing marks where `b1` goes on the table, and it touches no block.
    let (spec, world, problem) = problem_with(spec, |spec| {
        spec.object_types.retain(|kind| kind.name != "loc");
        spec.structures[0].placements[1].pose = pose(0.0, 0.1, 0.016, 0.0);
    });
    let issues = refused(outcome(&spec, &world, model, &problem));
    let objects: Vec<&str> = issues
        .iter()
        .map(|issue| match issue {
            StructureIssue::NoGoalAtom { object, .. } => object.as_str(),
            other => panic!("only objects without goal atoms: {other:?}"),
        })
        .collect();
    assert_eq!(objects, ["b1", "b2"]);
    assert!(issues[0].to_string().contains("the spec declares no marker type"), "{}", issues[0]);
}

#[test]
fn a_goal_relation_no_action_adds_is_named_with_its_relative_pose() {
    let (spec, world, model) = &*MODEL;
    let on_block = relation_at(model, "block", "block", &pose(0.0, 0.0, 0.031, 0.0));
    let mut model = model.clone();
    model.actions.retain(|action| !action.add.iter().any(|atom| atom.predicate == on_block));
    let problem = spec.problem("stack_2").expect("the fixture's problem");
    let issues = refused(outcome(spec, world, &model, problem));
    // Both blocks are named: `b2` on `b1`, and `b1` under `b2` where that is a relation too.
    let unlearned: Vec<(&str, &str, &str)> = issues
        .iter()
        .map(|issue| match issue {
            StructureIssue::Unlearned { object, atom, primary_type, secondary_type, .. } => {
                assert_eq!((primary_type.as_str(), secondary_type.as_str()), ("block", "block"));
                (object.as_str(), atom.as_str(), issue_pose(issue))
            }
            other => panic!("only unlearned relations: {other:?}"),
        })
        .collect();
    let expected = format!("({on_block} b1 b2)");
    assert!(
        unlearned.contains(&("b2", expected.as_str(), "(0, 0, 0.031) m rpy (0, 0, 0) deg")),
        "{unlearned:?}"
    );
    let message =
        issues.iter().find(|issue| issue_pose(issue).starts_with("(0, 0, 0.031)")).expect("b2");
    assert!(
        message.to_string().contains("no demonstration puts a block at (0, 0, 0.031) m rpy (0, 0, 0) deg in the frame of a block"),
        "{message}"
    );
}

fn issue_pose(issue: &StructureIssue) -> &str {
    match issue {
        StructureIssue::Unlearned { pose, .. } => pose,
        _ => "",
    }
}

/// Every bundled structure stands at its problem's anchor: no two of its objects touch, none
/// touches the table, and each rests by the resting rule, as the build checks it.
#[test]
fn every_bundled_structure_stands_at_its_anchor() {
    for domain in ["keva", "jenga"] {
        let (spec, world) = lamp_test_support::domain(domain);
        let mut checked = 0;
        for problem in spec.problems.iter().filter(|problem| problem.goal.structure.is_some()) {
            let issues = lamp_build::placed_structure_issues(&world, problem)
                .unwrap_or_else(|error| panic!("{domain} {}: {error}", problem.name));
            assert_eq!(issues, [], "{domain} {}", problem.name);
            checked += 1;
        }
        assert!(checked >= 12, "{domain}: {checked} structure problems");
    }
}

/// The fixture's problem without its structure goal: an `at` goal puts `b1` at `target`, and the
/// relation goal `on_marker(l1, b1)` puts it on the marker `l1`, placed at `marker`.
fn at_goal_and_relation_goal(target: Pose, marker: Pose) -> (Spec, SpecWorld, lamp_spec::Problem) {
    let (spec, _, model) = &*MODEL;
    let on_marker = relation_at(model, "loc", "block", &Pose::identity());
    problem_with(spec, |spec| {
        let problem = &mut spec.problems[0];
        problem.goal.structure = None;
        problem.scene.objects.push(lamp_spec::ObjectInstance {
            name: "l1".into(),
            type_name: "loc".into(),
            pose: marker,
        });
        problem.goal.at.push(lamp_spec::AtGoal {
            object: "b1".into(),
            pose: target,
            position_tolerance: 0.005,
            angle_tolerance: 0.1,
            marker_type: "loc".into(),
        });
        problem.goal.atoms.push(lamp_spec::GoalAtom {
            relation: on_marker,
            arguments: vec!["l1".into(), "b1".into()],
        });
    })
}

/// An `at` goal and a relation goal that put the same block on two markers 42 cm apart were
/// written as they are, and the solve could only miss the target; the build refuses them as a
/// contradiction that names both goals.
#[test]
fn an_at_goal_and_a_relation_goal_on_another_marker_contradict_each_other() {
    let (_, _, model) = &*MODEL;
    let target = pose(0.2, -0.2, 0.016, 0.0);
    let (spec, world, problem) = at_goal_and_relation_goal(target, pose(-0.2, -0.3, 0.016, 0.0));
    let domain = lamp_learn::domain(model, &spec.domain).expect("the domain writes");
    let adapter = Adapter::new(&spec, &world.robots).expect("the adapter");
    let aliases = BTreeMap::new();
    let header = vec!["contradiction test".to_string()];
    let context = ProblemContext {
        model,
        domain: &domain,
        world: &world,
        adapter: &adapter,
        aliases: &aliases,
        header: &header,
    };
    let error = problem_pddl(&context, &problem).expect_err("the goals contradict");
    let on_marker = relation_at(model, "loc", "block", &Pose::identity());
    assert!(
        matches!(&error, lamp_build::BuildError::AtGoalContradiction { object, relation_goal, .. }
            if object == "b1" && *relation_goal == format!("{on_marker}(l1, b1)")),
        "{error}"
    );
    let code = miette::Diagnostic::code(&error).map(|code| code.to_string());
    assert_eq!(code.as_deref(), Some("lamp::build::at_goal_contradiction"));
    let message = error.to_string();
    assert!(
        message.contains(&format!(
            "the `at` goal on `b1` and the goal `{on_marker}(l1, b1)` contradict each other"
        )),
        "{message}"
    );
    assert!(
        message.contains("within 5.0 mm of its target, which lies 412.3 mm from `l1`"),
        "{message}"
    );
    assert!(message.contains(&format!("outside the region `{on_marker}`")), "{message}");
    let help = miette::Diagnostic::help(&error).map(|help| help.to_string()).unwrap_or_default();
    assert!(help.contains("drop one of the two goals"), "{help}");
    assert!(!help.contains("loosen"), "{help}");
    // With the marker at the target the two goals say the same, and the problem is written.
    let (spec, world, problem) = at_goal_and_relation_goal(target, target);
    let text = written(outcome(&spec, &world, model, &problem));
    assert!(text.contains(&format!("({on_marker} l1 b1)")), "{text}");
    assert!(text.contains(&format!("({on_marker} goal_b1 b1)")), "{text}");
}

/// A block placed `1e300 m` from the structure's anchor was reported as a structure that
/// intersects itself; it is out of range, named with its position.
#[test]
fn a_structure_object_placed_absurdly_far_is_out_of_range_not_intersecting() {
    let (spec, _, model) = &*MODEL;
    let (spec, world, problem) = problem_with(spec, |spec| {
        spec.structures[0].placements[1].pose = pose(1e300, 0.0, 0.047, 0.0);
    });
    let issues = refused(outcome(&spec, &world, model, &problem));
    assert!(
        matches!(issues.as_slice(), [StructureIssue::OutOfRange { object, position, .. }]
            if object == "b2" && position.starts_with("(1e300, ")),
        "{issues:?}"
    );
    let code = miette::Diagnostic::code(&issues[0]).map(|code| code.to_string());
    assert_eq!(code.as_deref(), Some("lamp::build::structure_range"));
    let message = issues[0].to_string();
    assert!(message.contains("more than 1000 m from the origin"), "{message}");
    assert!(!message.contains("intersects itself"), "{message}");
}
