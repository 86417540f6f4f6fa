//! The bundled specs under `domains/`: each checks cleanly, and the Packing and Café test
//! problems are the promised ones (counts, names, goals) with sound initial scenes: no body
//! touches another, objects keep their clearances, and each robot starts collision-free.

use std::collections::BTreeMap;

use lamp_geometry::{Pose, Shape};
use lamp_spec::Problem;
use lamp_tests::workspace_root;
use lamp_world::{Scene, SpecWorld};

use lamp_test_support::{check, domain as bundled};

#[test]
fn every_bundled_spec_checks_cleanly() {
    let mut specs = Vec::new();
    for entry in std::fs::read_dir(workspace_root().join("domains")).expect("domains/") {
        let dir = entry.expect("a folder entry").path();
        for file in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            if file.path().extension().is_some_and(|e| e == "lamp") {
                specs.push(file.path());
            }
        }
    }
    specs.sort();
    assert!(specs.len() >= 5, "the five domains are bundled: {specs:?}");
    for path in specs {
        let spec = check(&path);
        assert!(!spec.problems.is_empty(), "{} has problems", path.display());
    }
}

/// The initial scene has no touching bodies and every robot's configuration is valid.
fn assert_sound(problem: &Problem, scene: &Scene) {
    assert_eq!(scene.body_contacts(), Vec::<(String, String)>::new(), "{}", problem.name);
    for (index, robot) in scene.robots().iter().enumerate() {
        let q = robot.configuration().to_vec();
        assert_eq!(
            scene.first_contact(index, &q),
            None,
            "{}: robot `{}` starts in collision",
            problem.name,
            robot.name
        );
    }
}

/// Pairs of bodies closer than `margin`, leaving out the pairs where one of them is `support`
/// (what the objects stand on, 1 mm below them).
fn close_pairs(scene: &Scene, margin: f64, supports: &[&str]) -> Vec<(String, String)> {
    let mut scene = scene.clone();
    scene.set_margin(margin);
    scene
        .body_contacts()
        .into_iter()
        .filter(|(a, b)| !supports.contains(&a.as_str()) && !supports.contains(&b.as_str()))
        .collect()
}

fn objects_of<'a>(problem: &'a Problem, type_name: &str) -> Vec<&'a str> {
    problem
        .scene
        .objects
        .iter()
        .filter(|o| o.type_name == type_name)
        .map(|o| o.name.as_str())
        .collect()
}

#[test]
fn packing_has_twelve_sound_four_can_problems() {
    let (spec, world) = bundled("packing");
    let names: Vec<&str> = spec.problems.iter().map(|p| p.name.as_str()).collect();
    let expected: Vec<String> = (1..=12).map(|k| format!("pack4_{k:02}")).collect();
    assert_eq!(names, expected);
    let mut box_poses: Vec<Pose> = Vec::new();
    for problem in &spec.problems {
        let cans = objects_of(problem, "can");
        assert_eq!(cans.len(), 4, "{}", problem.name);
        assert_eq!(objects_of(problem, "surface"), ["box1"], "{}", problem.name);
        let goals: Vec<(String, Vec<String>)> =
            problem.goal.atoms.iter().map(|a| (a.relation.clone(), a.arguments.clone())).collect();
        for can in &cans {
            assert!(
                goals.contains(&("in_box".to_string(), vec![can.to_string(), "box1".to_string()])),
                "{}: {can} goes into the box",
                problem.name
            );
        }
        let scene = world.problem_scene(problem).expect("the scene builds");
        assert_sound(problem, &scene);
        // 2 cm between cans and between a can and the box, so the gripper reaches each.
        assert_eq!(close_pairs(&scene, 0.0199, &["table1"]), Vec::new(), "{}", problem.name);
        for object in &problem.scene.objects {
            if object.type_name == "can" {
                let p = object.pose.translation.vector;
                assert!(
                    p.x.abs().max(p.y.abs()) + 0.0325 <= 0.45,
                    "{}: {} on the table",
                    problem.name,
                    object.name
                );
                assert!(
                    (p.z - 0.001).abs() < 1e-9,
                    "{}: {} stands on the table",
                    problem.name,
                    object.name
                );
            }
            if object.type_name == "surface" {
                let index = scene.body_index(&object.name).expect("the box is in the scene");
                box_poses.push(scene.body_pose(index));
            }
        }
    }
    // Different layouts: no two problems put the box in the same place.
    for (i, a) in box_poses.iter().enumerate() {
        for b in &box_poses[..i] {
            assert!((a.translation.vector - b.translation.vector).norm() > 0.05);
        }
    }
}

/// The Café layouts: the name prefix of their problems and the can counts, in the order of the
/// spec. The first is the bundled layout (axis-aligned); the others come from
/// `make_problems.py cafe-layouts` and have yawed surfaces.
const CAFE_LAYOUTS: [(&str, &[usize]); 4] = [
    ("cafe", &[2, 2, 3, 4, 4, 6, 8, 8, 10, 16, 17, 18]),
    ("cafe_l2_", &[4, 12, 24]),
    ("cafe_l3_", &[8, 18, 30]),
    ("cafe_l4_", &[6, 12, 18]),
];

/// How far (rad) a yaw may be from a multiple of 90° and still count as on that multiple: the
/// spec writes yaws in whole degrees, so anything off the grid is at least a degree off.
const GRID_YAW_TOLERANCE: f64 = 1e-6;

#[test]
fn cafe_has_sound_problems_on_four_layouts_with_the_promised_can_counts() {
    let (spec, world) = bundled("cafe");
    let total: usize = CAFE_LAYOUTS.iter().map(|(_, counts)| counts.len()).sum();
    assert_eq!(spec.problems.len(), total);
    let mut problems = spec.problems.iter();
    let mut yawed = Vec::new();
    for (prefix, counts) in CAFE_LAYOUTS {
        let group: Vec<&Problem> = problems.by_ref().take(counts.len()).collect();
        yawed.push(check_cafe_layout(&world, prefix, counts, &group));
    }
    // The bundled layout is axis-aligned (table2 turned by 90°); each other one is not.
    assert_eq!(yawed[0], 0, "surfaces off the 90° grid per layout: {yawed:?}");
    assert!(yawed[1..].iter().all(|&n| n > 0), "surfaces off the 90° grid per layout: {yawed:?}");
}

/// Checks the Café problems of one layout and returns how many of its surfaces are yawed at
/// an angle that is not a multiple of 90°.
fn check_cafe_layout(
    world: &SpecWorld,
    prefix: &str,
    expected_counts: &[usize],
    problems: &[&Problem],
) -> usize {
    let counts: Vec<usize> = problems.iter().map(|p| objects_of(p, "can").len()).collect();
    assert_eq!(counts, expected_counts, "the can counts of the `{prefix}` problems");
    let mut seen: BTreeMap<usize, usize> = BTreeMap::new();
    let furniture = |problem: &Problem| -> Vec<(String, String, Pose)> {
        let mut list: Vec<_> = problem
            .scene
            .objects
            .iter()
            .filter(|o| o.type_name != "can")
            .map(|o| (o.name.clone(), o.type_name.clone(), o.pose))
            .collect();
        list.sort_by(|a, b| a.0.cmp(&b.0));
        list
    };
    let layout = furniture(problems[0]);
    let surfaces: Vec<_> = layout.iter().filter(|(_, t, _)| t == "surface").collect();
    assert!((4..=6).contains(&surfaces.len()), "{prefix}: 4 to 6 surfaces");
    let tables = surfaces.iter().filter(|(name, _, _)| name.starts_with("table")).count();
    assert!(tables >= 3, "{prefix}: at least three tables");
    assert!(surfaces.iter().any(|(name, _, _)| name.starts_with("counter")), "{prefix}: a counter");
    for (name, _, pose) in &surfaces {
        let height = if name.starts_with("table") { 0.73 } else { 0.9 };
        assert!((pose.translation.vector.z - height).abs() < 1e-9, "{prefix}: {name} height");
        let (stand, suffix) = if name.starts_with("table") {
            ("table_leg", "leg")
        } else {
            ("counter_cabinet", "cabinet")
        };
        let under = format!("{name}_{suffix}");
        assert!(
            layout.iter().any(|(n, t, p)| *n == under && t == stand && p == pose),
            "{prefix}: a {stand} {under} under {name}"
        );
    }
    let yawed = surfaces
        .iter()
        .filter(|(_, _, pose)| {
            let (_, _, yaw) = pose.rotation.euler_angles();
            let quarter = std::f64::consts::FRAC_PI_2;
            (yaw / quarter - (yaw / quarter).round()).abs() * quarter > GRID_YAW_TOLERANCE
        })
        .count();
    let top_half = |type_name: &str| match &world.type_parts[type_name][0].1 {
        Shape::Box { half_extents } => (half_extents.x, half_extents.y),
        other => panic!("the top of a {type_name} is a box, not {other:?}"),
    };

    for (problem, count) in problems.iter().zip(&counts) {
        let k = seen.entry(*count).or_insert(0);
        *k += 1;
        assert_eq!(problem.name, format!("{prefix}{count}_{:02}", *k));
        assert_eq!(furniture(problem), layout, "{}: the same furniture everywhere", problem.name);
        let robot = &problem.scene.robots[0];
        assert_eq!(robot.configuration.as_deref(), Some("tuck"));

        let scene = world.problem_scene(problem).expect("the scene builds");
        assert_sound(problem, &scene);
        let supports: Vec<&str> = surfaces.iter().map(|(name, _, _)| name.as_str()).collect();
        // 3 cm between cans.
        assert_eq!(close_pairs(&scene, 0.0299, &supports), Vec::new(), "{}", problem.name);

        let mut moving = 0;
        for can in problem.scene.objects.iter().filter(|o| o.type_name == "can") {
            // The surface the can stands on, 5 cm clear of its edges.
            let support = surfaces.iter().find(|(_, type_name, pose)| {
                let local = pose.inverse() * can.pose;
                let (hx, hy) = top_half(type_name);
                let p = local.translation.vector;
                (p.z - 0.001).abs() < 1e-9
                    && p.x.abs() + 0.045 + 0.05 <= hx + 1e-9
                    && p.y.abs() + 0.045 + 0.05 <= hy + 1e-9
            });
            let Some((support, _, _)) = support else {
                panic!(
                    "{}: {} does not stand on a surface, 5 cm from its edges",
                    problem.name, can.name
                )
            };
            let goal = problem
                .goal
                .atoms
                .iter()
                .find(|a| a.arguments.first() == Some(&can.name))
                .unwrap_or_else(|| panic!("{}: {} has a goal", problem.name, can.name));
            let target = &goal.arguments[1];
            assert_eq!(goal.relation, "on");
            if target != support {
                moving += 1;
            }
        }
        assert!(2 * moving >= *count, "{}: {moving} of {count} cans move", problem.name);
    }
    yawed
}

/// The Dinner problems: the promised object counts (and one mixed goal); sound initial scenes; and every target a
/// place where the object could stand: with every object moved to its target, no body touches
/// another (nor a marker's neighbour), and each object rests 1 mm above a dining table's top.
#[test]
fn dinner_has_twelve_sound_table_settings_whose_targets_rest_on_dining_tables() {
    let (spec, world) = bundled("dinner");
    let counts: Vec<usize> = spec.problems.iter().map(|problem| problem.goal.at.len()).collect();
    // The twelve settings, then the problem that mixes an `at` goal with a learned relation.
    assert_eq!(counts, [2, 2, 3, 4, 4, 5, 6, 6, 7, 8, 8, 12, 1]);
    let mixed = spec.problems.last().expect("problems");
    assert_eq!((mixed.name.as_str(), mixed.goal.atoms.len()), ("set_table_mixed", 1));
    assert!(spec.problems.iter().any(|problem| problem.name == "set_table_8"));
    assert!(spec.problems.iter().any(|problem| problem.name == "set_table_12"));
    for problem in &spec.problems {
        let scene = world.problem_scene(problem).expect("the scene builds");
        assert_sound(problem, &scene);
        let mut set = scene.clone();
        for target in &problem.goal.at {
            let body = set.body_index(&target.object).expect("the object is in the scene");
            set.set_body_pose(body, target.pose);
        }
        let tops: Vec<&str> = problem
            .scene
            .objects
            .iter()
            .filter(|object| object.name.starts_with("dining"))
            .map(|object| object.name.as_str())
            .collect();
        assert_eq!(
            close_pairs(&set, 0.0, &tops),
            Vec::<(String, String)>::new(),
            "{}",
            problem.name
        );
        for target in &problem.goal.at {
            let on_a_top =
                problem.scene.objects.iter().filter(|o| tops.contains(&o.name.as_str())).any(
                    |top| {
                        let p = (top.pose.inverse() * target.pose).translation.vector;
                        p.x.abs() < 0.45 && p.y.abs() < 0.45 && (p.z - 0.001).abs() < 1e-9
                    },
                );
            assert!(on_a_top, "{}: `{}` is not set on a dining table", problem.name, target.object);
        }
    }
}

/// Keva and Jenga: the promised structure problems (names carry the object count), each scene
/// sound, every object of the spec's structure in the scene, and the finished structure clear of
/// the objects that are not part of it. That each structure stands at its anchor is checked with
/// the build's own structure check (compiler/build/tests/structure_goals.rs).
#[test]
fn keva_and_jenga_have_the_promised_structure_problems() {
    let expected: [(&str, &str, Vec<&str>); 2] = [
        (
            "keva",
            "plank",
            vec![
                "pi_tower_3",
                "flat_tower_4",
                "two_pi_6",
                "house_2d_6",
                "pi_tower_6",
                "pi_tower_9",
                "pi_row_9",
                "flat_tower_12",
                "flat_twin_16",
                "stonehenge_18",
                "three_tower_24",
                "twin_stacked_pi_30",
            ],
        ),
        (
            "jenga",
            "block",
            vec![
                "tower_2",
                "tower_3",
                "tower_4",
                "tower_6",
                "tower_6_b",
                "tower_8",
                "tower_10",
                "tower_12",
                "tower_12_b",
                "tower_14",
                "tower_16",
                "tower_18",
                "tower_24",
                "tower_30",
            ],
        ),
    ];
    for (domain, kind, names) in expected {
        let (spec, world) = bundled(domain);
        let found: Vec<&str> = spec.problems.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(found, names, "{domain}");
        let mut anchors = Vec::new();
        for problem in &spec.problems {
            let goal = problem.goal.structure.as_ref().expect("a structure goal");
            let structure = spec.structure(&goal.structure).expect("the structure");
            let count: usize = problem.name.rsplit('_').find_map(|part| part.parse().ok()).unwrap();
            assert_eq!(structure.placements.len(), count, "{}", problem.name);
            assert_eq!(objects_of(problem, kind).len(), count, "{}", problem.name);
            let scene = world.problem_scene(problem).expect("the scene builds");
            assert_sound(problem, &scene);
            // A solve holds each object to its structure pose, within 5 mm and 3°.
            let targets = world.placement_targets(problem).expect("the targets");
            assert_eq!(targets.len(), count, "{}", problem.name);
            assert!(targets.iter().all(|t| t.position_tolerance == 0.005
                && (t.angle_tolerance.to_degrees() - 3.0).abs() < 1e-9
                && (t.marker_type.is_empty() || scene.body_index(&t.marker_name()).is_some())));
            let mut built = scene.clone();
            for (object, pose) in world.structure_targets(problem).expect("the targets") {
                let body = built.body_index(&object).expect("the object is in the scene");
                built.set_body_pose(body, pose);
            }
            assert_eq!(built.body_contacts(), Vec::<(String, String)>::new(), "{}", problem.name);
            let anchor = problem.scene.objects.iter().find(|o| o.name == goal.anchor).unwrap();
            anchors.push(anchor.pose);
        }
        if domain == "jenga" {
            // Different anchors: no two problems build at the same place and turn.
            for (index, a) in anchors.iter().enumerate() {
                for b in &anchors[..index] {
                    let apart = (a.translation.vector - b.translation.vector).norm() > 1e-6
                        || a.rotation.angle_to(&b.rotation) > 1e-6;
                    assert!(apart, "two Jenga problems share an anchor");
                }
            }
        }
    }
}
