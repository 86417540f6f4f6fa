//! Drawings of scenes, trajectories and regions: what they show, at which scale, in which order,
//! and that the same input gives the same text.

use lamp_geometry::{Pose, Shape, Vec3};
use lamp_render::{
    RegionPlot, RenderError, RenderOptions, SampleSet, render_regions, render_scene,
    render_trajectory,
};
use lamp_trajectory::{
    BodyDescription, RobotDescription, RobotState, Step, Trajectory, TrajectoryHeader,
};
use lamp_world::{Body, Scene, SpecWorld};

use lamp_test_support::domain as bundled;

fn cube(name: &str, half: f64, movable: bool, world: bool) -> Body {
    Body {
        name: name.to_string(),
        type_name: "cube".to_string(),
        movable,
        world,
        parts: vec![(Pose::identity(), Shape::Box { half_extents: Vec3::new(half, half, half) })],
    }
}

/// Every `points="…"` of polygons in the SVG, in document order, as page coordinates.
fn polygons(svg: &str) -> Vec<Vec<(f64, f64)>> {
    svg.lines()
        .filter(|line| line.starts_with("<polygon"))
        .map(|line| {
            let start = line.find("points=\"").expect("points") + 8;
            let end = start + line[start..].find('"').expect("closing quote");
            line[start..end]
                .split(' ')
                .map(|pair| {
                    let (x, y) = pair.split_once(',').expect("x,y");
                    (x.parse().expect("x"), y.parse().expect("y"))
                })
                .collect()
        })
        .collect()
}

fn size(points: &[(f64, f64)]) -> (f64, f64) {
    let (mut lo, mut hi) = ((f64::MAX, f64::MAX), (f64::MIN, f64::MIN));
    for &(x, y) in points {
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    }
    (hi.0 - lo.0, hi.1 - lo.1)
}

#[test]
fn both_views_share_one_scale() {
    let mut scene = Scene::new();
    // A 0.2 m cube whose x extent equals its y and z extents in both views.
    scene.add_body(cube("block", 0.1, true, false), Pose::translation(0.3, -0.2, 0.5)).unwrap();
    let svg = render_scene(&scene, &RenderOptions::default());
    let shapes = polygons(&svg);
    assert_eq!(shapes.len(), 2, "one outline per view");
    let (top, side) = (size(&shapes[0]), size(&shapes[1]));
    assert!((top.0 - top.1).abs() < 0.02, "a square from above: {top:?}");
    assert!((side.0 - side.1).abs() < 0.02, "a square from the front: {side:?}");
    assert!((top.0 - side.0).abs() < 0.02, "same scale in both views");
    // The cube alone fills the view (less the padding): 480 px over 0.2 m padded by 6 %.
    let expected = 480.0 / (0.2 * 1.12);
    assert!((top.0 - 0.2 * expected).abs() < 0.05, "{} vs {}", top.0, 0.2 * expected);
}

#[test]
fn painters_draw_far_things_first() {
    let mut scene = Scene::new();
    let table = Body {
        parts: vec![(
            Pose::translation(0.0, 0.0, -0.025),
            Shape::Box { half_extents: Vec3::new(0.45, 0.45, 0.025) },
        )],
        ..cube("table", 0.0, false, true)
    };
    // Added after the can, so document order comes from depth and not from insertion.
    scene.add_body(cube("can", 0.03, true, false), Pose::translation(0.0, -0.3, 0.031)).unwrap();
    scene.add_body(table, Pose::identity()).unwrap();
    let svg = render_scene(&scene, &RenderOptions::default());
    let shapes = polygons(&svg);
    assert_eq!(shapes.len(), 4);
    // Top view: the table (lower top) first; side view: the table (farther back) first.
    for view in [&shapes[0..2], &shapes[2..4]] {
        let (first, second) = (size(&view[0]), size(&view[1]));
        assert!(first.0 > second.0, "the wide table is painted before the small can");
    }
}

#[test]
fn a_huge_backdrop_does_not_set_the_scale() {
    let mut scene = Scene::new();
    scene.add_body(cube("floor", 10.0, false, true), Pose::translation(0.0, 0.0, -10.0)).unwrap();
    scene.add_body(cube("can", 0.05, true, false), Pose::translation(1.0, 1.0, 0.05)).unwrap();
    let svg = render_scene(&scene, &RenderOptions::default());
    let shapes = polygons(&svg);
    let can = shapes.iter().map(|s| size(s).0).fold(f64::MAX, f64::min);
    assert!(can > 100.0, "the can is drawn large ({can} px), the floor is cut to fit");
    assert!(!svg.contains(">floor<"), "a cut backdrop is not labelled");
    assert!(svg.contains(">can<"));
}

#[test]
fn the_packing_scene_shows_every_body_and_the_robot() {
    let (spec, world) = bundled("packing");
    let problem = &spec.problems[0];
    let scene = world.problem_scene(problem).unwrap();
    let options = RenderOptions { title: Some("packing".into()), ..RenderOptions::default() };
    let svg = render_scene(&scene, &options);
    assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
    assert!(svg.ends_with("</svg>\n"));
    for name in ["table1", "box1", "can1", "can2", "can3", "can4", "gripper"] {
        assert_eq!(svg.matches(&format!(">{name}<")).count(), 2, "{name} labelled in both views");
    }
    assert!(svg.contains("top view (x\u{2013}y)") && svg.contains("side view (x\u{2013}z)"));
    assert!(svg.contains(">x (m)<") && svg.contains(">0.2 m<"));
    // Table 1 + box 5 + cans 4 + gripper 1 parts, in each view.
    assert_eq!(polygons(&svg).len(), 2 * 11);
    assert_eq!(svg.matches("<text").count(), svg.matches("</text>").count());
    assert_eq!(svg, render_scene(&scene, &options), "deterministic");
}

/// Marked bodies (what a failed solve found in the way) get a thick red outline in both views,
/// and nothing else does.
#[test]
fn marked_bodies_are_outlined() {
    let (spec, world) = bundled("packing");
    let scene = world.problem_scene(&spec.problems[0]).unwrap();
    let mark = "stroke=\"#d62728\" stroke-width=\"2.4\"";
    assert!(!render_scene(&scene, &RenderOptions::default()).contains(mark));
    let options =
        RenderOptions { marked: vec!["can2".into(), "box1".into()], ..RenderOptions::default() };
    let svg = render_scene(&scene, &options);
    // The can is one part, the box five, in each view.
    assert_eq!(svg.matches(mark).count(), 2 * (1 + 5), "{svg}");
}

#[test]
fn the_cafe_scene_draws_the_fetch_links() {
    let (spec, world) = bundled("cafe");
    let scene = world.problem_scene(&spec.problems[0]).unwrap();
    let svg = render_scene(&scene, &RenderOptions::default());
    let links = scene.robots()[0].robot().collision_geometry().len();
    let robot_polygons = svg.lines().filter(|l| l.contains("fill=\"#5b7fb0\"")).count();
    assert_eq!(robot_polygons, 2 * links);
}

fn packing_motion(world: &SpecWorld) -> Trajectory {
    let model = &world.robots["gripper"];
    let coordinates = model.coordinate_names().to_vec();
    let header = TrajectoryHeader {
        domain: "packing".into(),
        seed: 1,
        provenance: Default::default(),
        bodies: vec![
            BodyDescription { name: "table1".into(), type_name: "table".into() },
            BodyDescription { name: "can1".into(), type_name: "can".into() },
        ],
        robots: vec![RobotDescription {
            name: "gripper".into(),
            coordinates,
            grippers: vec!["gripper".into()],
        }],
    };
    let steps = (0..5u32)
        .map(|i| {
            let x = -0.2 + 0.1 * f64::from(i);
            let gripper = Pose::translation(x, 0.0, 0.4);
            let mut q = model.neutral_configuration();
            model.mount().write_coordinates(&gripper, &mut q);
            Step {
                time_nanoseconds: u64::from(i) * 500_000_000,
                body_poses: vec![Pose::identity(), Pose::translation(x, 0.0, 0.2)],
                robots: vec![RobotState { positions: q, held: vec![Some(1)] }],
            }
        })
        .collect();
    Trajectory { header, steps }
}

#[test]
fn a_trajectory_shows_the_first_step_faded_and_the_gripper_path() {
    let (_, world) = bundled("packing");
    let trajectory = packing_motion(&world);
    let svg = render_trajectory(&world, &trajectory, None, &RenderOptions::default()).unwrap();
    assert!(svg.contains("packing \u{b7} step 4 of 0\u{2013}4 (t = 2.00 s)"));
    assert_eq!(svg.matches("<polyline").count(), 2, "the path in both views");
    // Faded: the first step's can and gripper (not the table), in both views.
    assert_eq!(svg.matches("stroke-dasharray").count(), 2 * 2);
    // The path runs along x from -0.2 to 0.2 m: in the top view it is a horizontal line.
    let line = svg.lines().find(|l| l.starts_with("<polyline")).unwrap();
    let start = line.find("points=\"").unwrap() + 8;
    let ys: Vec<&str> = line[start..]
        .split('"')
        .next()
        .unwrap()
        .split(' ')
        .map(|p| p.split(',').nth(1).unwrap())
        .collect();
    assert_eq!(ys.len(), 5);
    assert!(ys.iter().all(|y| *y == ys[0]), "{ys:?}");

    let first = render_trajectory(&world, &trajectory, Some(0), &RenderOptions::default()).unwrap();
    assert!(!first.contains("stroke-dasharray"), "step 0 has nothing earlier to fade");
}

#[test]
fn trajectories_that_do_not_fit_the_spec_are_refused() {
    let (_, world) = bundled("packing");
    let options = RenderOptions::default();
    let trajectory = packing_motion(&world);
    let error = render_trajectory(&world, &trajectory, Some(9), &options).unwrap_err();
    assert!(matches!(error, RenderError::StepOutOfRange { step: 9, count: 5 }), "{error}");

    let mut wrong_type = trajectory.clone();
    wrong_type.header.bodies[1].type_name = "plank".into();
    let error = render_trajectory(&world, &wrong_type, None, &options).unwrap_err();
    assert!(matches!(error, RenderError::UnknownType { .. }), "{error}");

    let mut wrong_robot = trajectory.clone();
    wrong_robot.header.robots[0].name = "fetch".into();
    let error = render_trajectory(&world, &wrong_robot, None, &options).unwrap_err();
    assert!(matches!(error, RenderError::UnknownRobot { .. }), "{error}");

    let mut wrong_coordinates = trajectory.clone();
    wrong_coordinates.header.robots[0].coordinates[0] = "elbow".into();
    let error = render_trajectory(&world, &wrong_coordinates, None, &options).unwrap_err();
    assert!(matches!(error, RenderError::Coordinates { .. }), "{error}");

    let mut short_step = trajectory.clone();
    short_step.steps[2].body_poses.pop();
    let error = render_trajectory(&world, &short_step, None, &options).unwrap_err();
    assert!(matches!(error, RenderError::Inconsistent { step: 2, .. }), "{error}");

    let empty = Trajectory { steps: Vec::new(), ..trajectory };
    let error = render_trajectory(&world, &empty, None, &options).unwrap_err();
    assert!(matches!(error, RenderError::Empty), "{error}");
}

#[test]
fn a_region_plot_has_one_dot_per_sample_around_the_primary() {
    let (_, world) = bundled("packing");
    let samples = |x: f64| -> Vec<Pose> {
        (0..20).map(|i| Pose::translation(x, -0.05 + 0.005 * f64::from(i), 0.001)).collect()
    };
    let plot = RegionPlot {
        primary: "surface".into(),
        secondary: "can".into(),
        primary_parts: world.type_parts["surface"].clone(),
        sets: vec![
            SampleSet { label: "surface_can_1".into(), poses: samples(0.02) },
            SampleSet { label: "surface_can_2".into(), poses: samples(0.3) },
        ],
    };
    let svg = render_regions(&plot, &RenderOptions::default());
    assert!(svg.contains("can relative to surface"));
    assert!(svg.contains(">surface_can_1 (20 samples)<"));
    assert!(svg.contains(">surface_can_2 (20 samples)<"));
    // 40 samples and the origin, in both views, plus three legend markers.
    assert_eq!(svg.matches("<circle").count(), 2 * 41 + 3);
    // The box's five parts in both views.
    assert_eq!(polygons(&svg).len(), 10);
    assert_eq!(svg, render_regions(&plot, &RenderOptions::default()));
}
