//! The check of every problem's initial scene: the bundled specs' problems, and one problem per
//! kind of finding, each named with its problem and bodies.

use lamp_build::{BuildError, SceneIssue, check_initial_scenes, initial_scene_issues};
use lamp_spec::{Pose, Spec};
use lamp_world::SpecWorld;
use nalgebra::{Translation3, UnitQuaternion};

/// Every finding for a bundled spec, as the user reads it.
fn findings(spec: &Spec, world: &SpecWorld) -> Vec<String> {
    initial_scene_issues(spec, world).iter().map(ToString::to_string).collect()
}

/// A bundled spec with its world, with only its first problem kept, changed by `change`.
fn first_problem(name: &str, change: impl FnOnce(&mut Spec)) -> (Spec, SpecWorld) {
    let (mut spec, _) = lamp_test_support::domain(name);
    spec.problems.truncate(1);
    change(&mut spec);
    let folder = lamp_test_support::spec_path(name).parent().expect("a folder").to_path_buf();
    let world = SpecWorld::load(&folder, &spec).expect("the bundled world loads");
    (spec, world)
}

fn at(x: f64, y: f64, z: f64) -> Pose {
    Pose::from_parts(Translation3::new(x, y, z), UnitQuaternion::identity())
}

#[test]
fn bundled_problems_start_from_valid_scenes() {
    for name in ["packing", "cafe", "dinner"] {
        let (spec, world) = lamp_test_support::domain(name);
        assert_eq!(findings(&spec, &world), Vec::<String>::new(), "{name}");
        assert!(check_initial_scenes(&spec, &world).is_ok());
    }
}

/// Keva's and Jenga's scenes (planks and blocks 1 mm above the table, the table clear of the
/// arm) pass the check like every other bundled spec's.
#[test]
fn the_keva_and_jenga_scenes_pass_the_check() {
    for name in ["keva", "jenga"] {
        let (spec, world) = lamp_test_support::domain(name);
        assert_eq!(findings(&spec, &world), Vec::<String>::new(), "{name}");
    }
}

#[test]
fn an_object_exactly_on_its_support_touches_it() {
    let (spec, world) = first_problem("packing", |spec| {
        let can = &mut spec.problems[0].scene.objects[2];
        can.pose.translation.z = 0.0;
    });
    let issues = initial_scene_issues(&spec, &world);
    assert_eq!(
        issues,
        [SceneIssue::Contact {
            problem: "pack4_01".into(),
            first: "table1".into(),
            second: "can1".into()
        }]
    );
    // 1 µm above is still touching; the bundled 1 mm is not.
    let (spec, world) = first_problem("packing", |spec| {
        spec.problems[0].scene.objects[2].pose.translation.z = 0.5e-6;
    });
    assert_eq!(initial_scene_issues(&spec, &world).len(), 1);
}

/// A can floating 2.5 m above the table would fall at the first step: the scene is refused, not
/// "solved" with the can left in the air.
#[test]
fn an_object_in_the_air_or_over_an_edge_cannot_rest_and_is_named() {
    let (spec, world) = first_problem("packing", |spec| {
        spec.problems[0].scene.objects[2].pose.translation.z = 2.5;
        // can2 with its centre 2 cm past the table's edge (the top is 0.9 by 0.9 m about the
        // origin), its base still partly on it.
        let can2 = &mut spec.problems[0].scene.objects[3];
        can2.pose.translation.x = 0.47;
    });
    let found = findings(&spec, &world);
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(
        found[0].starts_with("problem `pack4_01`: `can1` cannot rest where the scene places it: `can1` would drop 2499.0 mm onto `table1`"),
        "{found:?}"
    );
    assert!(found[1].starts_with("problem `pack4_01`: `can2` cannot rest"), "{found:?}");
    let code =
        miette::Diagnostic::code(&initial_scene_issues(&spec, &world)[0]).map(|c| c.to_string());
    assert_eq!(code.as_deref(), Some("lamp::build::scene_unsupported"));
}

#[test]
fn overlapping_objects_are_named() {
    let (spec, world) = first_problem("packing", |spec| {
        let objects = &mut spec.problems[0].scene.objects;
        objects[3].pose = objects[2].pose * at(0.03, 0.0, 0.0);
    });
    assert_eq!(findings(&spec, &world), ["problem `pack4_01`: `can1` and `can2` touch or overlap"]);
}

#[test]
fn a_far_away_or_non_finite_placement_is_refused_before_any_geometry() {
    let (spec, world) = first_problem("packing", |spec| {
        let scene = &mut spec.problems[0].scene;
        scene.objects[2].pose = at(1e308, 0.0, 0.001);
        scene.objects[3].pose.translation.y = f64::NAN;
        scene.robots[0].base = Some(at(0.0, 1500.0, 0.45));
    });
    assert_eq!(
        findings(&spec, &world),
        [
            "problem `pack4_01`: object `can1` is placed at (1e308, 0, 0.001) m, farther than 1000 m from the origin",
            "problem `pack4_01`: the pose of object `can2` is not finite",
            "problem `pack4_01`: robot `gripper` is placed at (0, 1500, 0.45) m, farther than 1000 m from the origin",
        ]
    );
}

#[test]
fn a_robot_starting_in_an_object_is_named_with_its_link() {
    let (spec, world) = first_problem("packing", |spec| {
        let scene = &mut spec.problems[0].scene;
        let can = scene.objects[2].pose;
        scene.robots[0].base = Some(can * at(0.0, 0.0, 0.1));
    });
    let issues = initial_scene_issues(&spec, &world);
    assert!(
        matches!(&issues[..], [SceneIssue::RobotCollision { robot, contact, .. }]
            if robot == "gripper" && contact.contains("`can1`")),
        "{issues:?}"
    );
}

#[test]
fn a_robot_outside_its_joint_limits_names_the_joint() {
    let (spec, world) = first_problem("cafe", |spec| {
        let tuck = &mut spec.robots[0].configurations[0];
        let torso = tuck.values.iter_mut().find(|(joint, _)| joint == "torso_lift_joint");
        torso.expect("the tuck configuration sets the torso").1 = 5.0;
    });
    let issues = initial_scene_issues(&spec, &world);
    assert!(
        matches!(&issues[..], [SceneIssue::RobotLimits { robot, coordinate, value, .. }]
            if robot == "fetch" && coordinate == "torso_lift_joint" && *value == 5.0),
        "{issues:?}"
    );
}

#[test]
fn the_build_refuses_a_bad_scene_before_reading_any_demonstration() {
    let (spec, world) = first_problem("packing", |spec| {
        spec.problems[0].scene.objects[2].pose.translation.z = 0.0;
    });
    match lamp_build::build(&spec, "packing.lamp", &world, &[]) {
        Err(BuildError::InitialScenes { problems: 1, issues }) => assert_eq!(issues.len(), 1),
        other => panic!("expected the scene to be refused, got {:?}", other.map(|_| ())),
    }
}

#[test]
fn a_target_inside_the_table_names_the_object_and_the_table() {
    let (spec, world) = first_problem("dinner", |spec| {
        let target = &mut spec.problems[0].goal.at[0];
        target.pose.translation.z -= 0.001; // exactly on the top: touching
    });
    let object = spec.problems[0].goal.at[0].object.clone();
    let issues = initial_scene_issues(&spec, &world);
    assert_eq!(
        issues,
        vec![SceneIssue::TargetContact {
            problem: "set_table_2".into(),
            object: object.clone(),
            body: "dining1".into(),
        }]
    );
    let (spec, world) = first_problem("dinner", |spec| {
        spec.problems[0].goal.at[0].pose.translation.z += 0.30; // 30 cm above the table
    });
    match &initial_scene_issues(&spec, &world)[..] {
        [SceneIssue::TargetUnsupported { problem, object: named, reason }] => {
            assert_eq!((problem.as_str(), named), ("set_table_2", &object));
            // The resting rule's own words: it would drop 30 cm onto the table.
            assert!(reason.contains("would drop 300.0 mm onto `dining1`"), "{reason}");
        }
        other => panic!("expected one unsupported target, got {other:?}"),
    }
    // Over the table's edge, its centre 1 cm beyond it: the top is within a millimetre below
    // part of its base, but it would tip off.
    let (spec, world) = first_problem("dinner", |spec| {
        let dining = spec.problems[0].scene.objects.iter().find(|o| o.name == "dining1");
        let edge =
            dining.expect("the dining table").pose * nalgebra::Translation3::new(0.46, 0.0, 0.0);
        let target = &mut spec.problems[0].goal.at[0].pose;
        target.translation.x = edge.translation.x;
        target.translation.y = edge.translation.y;
    });
    match &initial_scene_issues(&spec, &world)[..] {
        [SceneIssue::TargetUnsupported { reason, .. }] => {
            assert!(reason.contains("is not supported"), "{reason}");
        }
        other => panic!("expected one unsupported target, got {other:?}"),
    }
    let (spec, world) = first_problem("dinner", |spec| {
        spec.problems[0].goal.at[0].pose.translation.x += 8.0; // beside the table, in the air
    });
    assert!(matches!(
        &initial_scene_issues(&spec, &world)[..],
        [SceneIssue::TargetUnsupported { .. }]
    ));
    let (spec, world) = first_problem("dinner", |spec| {
        spec.problems[0].goal.at[1].pose.translation.x = 5000.0;
    });
    let far = initial_scene_issues(&spec, &world);
    assert!(matches!(&far[..], [SceneIssue::OutOfRange { what: "the target of", .. }]), "{far:?}");
}

/// Two `at` goals on one pose (a copied line, its pose left unchanged) can never both be met:
/// refused with both objects named, instead of a solve that searches until it gives up.
#[test]
fn two_targets_on_one_place_are_named() {
    let (spec, world) = first_problem("dinner", |spec| {
        let goal = &mut spec.problems[0].goal.at;
        goal[1].pose = goal[0].pose;
    });
    let goal = &spec.problems[0].goal.at;
    let (first, second) = (goal[0].object.clone(), goal[1].object.clone());
    let issues = initial_scene_issues(&spec, &world);
    assert_eq!(issues.len(), 1, "{issues:?}");
    let SceneIssue::TargetsOverlap { problem, first: a, second: b } = &issues[0] else {
        panic!("expected overlapping targets, got {issues:?}");
    };
    assert_eq!(problem, "set_table_2");
    let mut named = [a.clone(), b.clone()];
    named.sort();
    let mut expected = [first, second];
    expected.sort();
    assert_eq!(named, expected);
    assert!(issues[0].to_string().contains("where they touch or overlap"));
}
