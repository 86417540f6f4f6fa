//! The resting rule: a released object is settled straight down to rest on what is below it,
//! refused when it would drop too far or touches something, and kept only when its centre of
//! mass is over the contacts that hold it up.

#![allow(clippy::unwrap_used)] // a failed step is a failed test

mod support;

use lamp_geometry::{Shape, Vec3};
use lamp_world::{Body, MAX_SETTLE_DROP, RESTING_GAP, RestError, Scene};
use support::pose;

const CAN_RADIUS: f64 = 0.0325;
const CAN_HEIGHT: f64 = 0.15;
/// The table's top is at z = 0.75, its edge at x = 0.45.
const TABLE_TOP: f64 = 0.75;
const TABLE_EDGE: f64 = 0.45;

fn body(name: &str, movable: bool, parts: Vec<(lamp_geometry::Pose, Shape)>) -> Body {
    Body { name: name.into(), type_name: name.into(), movable, world: !movable, parts }
}

fn block(name: &str, half: (f64, f64, f64), movable: bool) -> Body {
    let half_extents = Vec3::new(half.0, half.1, half.2);
    body(name, movable, vec![(lamp_geometry::Pose::identity(), Shape::Box { half_extents })])
}

/// A table and a can whose bottom is `height` above the top, its axis at (x, 0).
fn can_over_table(x: f64, height: f64) -> (Scene, usize) {
    let mut scene = Scene::new();
    let table = block("table", (TABLE_EDGE, 0.45, 0.025), false);
    scene.add_body(table, pose(0.0, 0.0, TABLE_TOP - 0.025, 0.0, 0.0, 0.0)).unwrap();
    let cylinder = Shape::Cylinder { radius: CAN_RADIUS, half_height: CAN_HEIGHT / 2.0 };
    let can = body("can", true, vec![(pose(0.0, 0.0, CAN_HEIGHT / 2.0, 0.0, 0.0, 0.0), cylinder)]);
    let index = scene.add_body(can, pose(x, 0.0, TABLE_TOP + height, 0.0, 0.0, 0.0)).unwrap();
    (scene, index)
}

/// The height of a can's bottom above the table top.
fn bottom(pose: &lamp_geometry::Pose) -> f64 {
    pose.translation.vector.z - TABLE_TOP
}

#[test]
fn a_can_resting_on_a_table_stays_where_it_is() {
    let (scene, can) = can_over_table(0.0, RESTING_GAP);
    let rest = scene.resting_pose(can).unwrap();
    assert_eq!(rest, scene.body_pose(can), "a body already at rest is not moved");
}

#[test]
fn a_can_released_3_mm_up_is_settled_to_rest() {
    let (scene, can) = can_over_table(0.1, 0.003);
    let rest = scene.resting_pose(can).unwrap();
    assert!((bottom(&rest) - RESTING_GAP).abs() < 1e-9, "{rest}");
    let start = scene.body_pose(can);
    assert_eq!(rest.rotation, start.rotation, "settling is straight down");
    assert_eq!(rest.translation.vector.xy(), start.translation.vector.xy());
}

#[test]
fn a_can_released_3_cm_up_is_refused_with_the_drop_and_what_is_below() {
    let (scene, can) = can_over_table(0.0, 0.03);
    let error = scene.resting_pose(can).unwrap_err();
    match &error {
        RestError::TooHigh { object, below, drop } => {
            assert_eq!((object.as_str(), below.as_str()), ("can", "table"));
            assert!((drop - (0.03 - RESTING_GAP)).abs() < 1e-9, "{drop}");
        }
        other => panic!("expected TooHigh, got {other:?}"),
    }
    assert!(error.to_string().contains("29.0 mm onto `table`"), "{error}");
    // Just within the limit is settled.
    let (scene, can) = can_over_table(0.0, RESTING_GAP + MAX_SETTLE_DROP - 1e-4);
    assert!(scene.resting_pose(can).is_ok());
}

/// A can whose lowest rim point is `height` above the table, tilted `lean` radians about x.
fn tilted_can(lean: f64, height: f64) -> (Scene, usize) {
    let (mut scene, can) = can_over_table(0.0, 0.0);
    // Turned about its bottom centre, the low rim point drops by radius · sin(lean).
    let drop = CAN_RADIUS * lean.sin();
    let pose = pose(0.0, 0.0, TABLE_TOP + height + drop, lean, 0.0, 0.0);
    scene.set_body_pose(can, pose);
    (scene, can)
}

#[test]
fn a_can_let_go_of_slightly_tilted_seats_itself_level_on_its_base() {
    let lean = 3.7_f64.to_radians();
    let (scene, can) = tilted_can(lean, 0.002);
    let released = scene.body_pose(can);
    let rest = scene.resting_pose(can).unwrap();
    assert!(rest.rotation.angle() < 1e-9, "level: {}", rest.rotation.angle());
    assert!((bottom(&rest) - RESTING_GAP).abs() < 1e-9, "{rest}");
    // It turned about the low edge of its base, which stays where it landed: the base's centre
    // moves by radius · (1 − cos lean), a twentieth of a millimetre.
    let moved = rest.translation.vector.xy() - released.translation.vector.xy();
    assert!(moved.norm() < 1e-4, "{moved}");
}

#[test]
fn a_can_let_go_of_leaning_far_is_not_set_level_and_falls_over() {
    let (scene, can) = tilted_can(10_f64.to_radians(), 0.002);
    assert!(matches!(scene.resting_pose(can), Err(RestError::Unsupported { .. })));
}

/// A Keva plank (7 × 23 × 117 mm here: its thickness along x, its length up z, its frame at the
/// centre of its lower end) standing over a floor, leaning `lean` radians about the y axis
/// (toward +x, its thin side), its low edge 1.5 mm above the floor.
fn leaning_upright_plank(lean: f64) -> (Scene, usize) {
    let mut scene = Scene::new();
    scene
        .add_body(block("floor", (1.0, 1.0, 0.01), false), pose(0.0, 0.0, -0.01, 0.0, 0.0, 0.0))
        .unwrap();
    let half_extents = Vec3::new(0.0035, 0.0115, 0.0585);
    let parts = vec![(pose(0.0, 0.0, 0.0585, 0.0, 0.0, 0.0), Shape::Box { half_extents })];
    let plank = body("plank", true, parts);
    let low_edge_drop = 0.0035 * lean.abs().sin();
    let placed = pose(0.0, 0.0, 0.0015 + low_edge_drop, 0.0, lean, 0.0);
    let index = scene.add_body(plank, placed).unwrap();
    (scene, index)
}

/// An upright plank 7 mm thick and 117 mm tall tips toward its thin side at atan(3.5 / 58.5),
/// 3.4°: let go of leaning less it seats itself on its end, leaning more it falls over, and the
/// refusal says so with the angle it would have had to stay under.
#[test]
fn an_upright_plank_seats_itself_within_its_tipping_angle_and_tips_over_beyond_it() {
    let (scene, plank) = leaning_upright_plank(3_f64.to_radians());
    let rest = scene.resting_pose(plank).expect("3° is within the tipping angle");
    assert!(rest.rotation.angle() < 1e-9, "seated upright: {}", rest.rotation.angle());
    assert!((rest.translation.vector.z - RESTING_GAP).abs() < 1e-9, "{rest}");
    let (scene, plank) = leaning_upright_plank(4_f64.to_radians());
    match scene.resting_pose(plank) {
        Err(error @ RestError::TipsOver { .. }) => {
            let RestError::TipsOver { lean, tipping, .. } = &error else { unreachable!() };
            assert!((lean.to_degrees() - 4.0).abs() < 1e-6, "{lean}");
            let expected = (0.0035_f64 / 0.0585).atan().to_degrees();
            assert!((tipping.to_degrees() - expected).abs() < 1e-6, "{tipping} against {expected}");
            let message = error.to_string();
            assert!(message.contains("would tip over") && message.contains("3.4°"), "{message}");
        }
        other => panic!("expected TipsOver, got {other:?}"),
    }
    // Leaning the other way by as much, the low edge is on the side of the centre of mass.
    let (scene, plank) = leaning_upright_plank(-4_f64.to_radians());
    assert!(matches!(scene.resting_pose(plank), Err(RestError::TipsOver { .. })));
}

#[test]
fn a_tilted_drop_is_measured_at_the_first_point_to_land() {
    // The low rim 5.5 mm up: too high, though the seated can's base would drop less.
    let (scene, can) = tilted_can(4_f64.to_radians(), RESTING_GAP + MAX_SETTLE_DROP + 0.0005);
    assert!(matches!(scene.resting_pose(can), Err(RestError::TooHigh { .. })));
}

#[test]
fn a_can_beside_the_table_has_nothing_below() {
    let (scene, can) = can_over_table(TABLE_EDGE + 0.1, 0.002);
    assert_eq!(scene.resting_pose(can), Err(RestError::NothingBelow { object: "can".into() }));
}

#[test]
fn a_can_sunk_into_the_table_is_refused_not_lifted() {
    let (scene, can) = can_over_table(0.0, -0.002);
    assert_eq!(
        scene.resting_pose(can),
        Err(RestError::Touching { object: "can".into(), body: "table".into() })
    );
}

#[test]
fn a_can_hanging_over_the_edge_beyond_its_centre_falls_and_one_short_of_it_stands() {
    // Axis 5 mm beyond the edge: the centre of mass is over nothing.
    let (scene, can) = can_over_table(TABLE_EDGE + 0.005, 0.002);
    match scene.resting_pose(can) {
        Err(RestError::Unsupported { object, outside, supports }) => {
            assert_eq!(object, "can");
            assert_eq!(supports, vec!["table".to_string()]);
            assert!(outside > 0.004 && outside < 0.006, "{outside}");
        }
        other => panic!("expected Unsupported, got {other:?}"),
    }
    // Axis 5 mm inside the edge: most of the can overhangs, but its centre is over the table.
    let (scene, can) = can_over_table(TABLE_EDGE - 0.005, 0.002);
    let rest = scene.resting_pose(can).unwrap();
    assert!((bottom(&rest) - RESTING_GAP).abs() < 1e-9);
}

#[test]
fn a_can_in_an_open_box_settles_onto_its_floor_not_its_walls() {
    let mut scene = Scene::new();
    let wall = |x: f64, y: f64, hx: f64, hy: f64| {
        (pose(x, y, 0.05, 0.0, 0.0, 0.0), Shape::Box { half_extents: Vec3::new(hx, hy, 0.05) })
    };
    let floor = (
        pose(0.0, 0.0, -0.0025, 0.0, 0.0, 0.0),
        Shape::Box { half_extents: Vec3::new(0.085, 0.085, 0.0025) },
    );
    let open_box = body(
        "box",
        false,
        vec![
            floor,
            wall(0.08, 0.0, 0.005, 0.085),
            wall(-0.08, 0.0, 0.005, 0.085),
            wall(0.0, 0.08, 0.085, 0.005),
            wall(0.0, -0.08, 0.085, 0.005),
        ],
    );
    scene.add_body(open_box, pose(0.0, 0.0, 0.0, 0.0, 0.0, 0.5)).unwrap();
    let cylinder = Shape::Cylinder { radius: CAN_RADIUS, half_height: CAN_HEIGHT / 2.0 };
    let can = body("can", true, vec![(pose(0.0, 0.0, CAN_HEIGHT / 2.0, 0.0, 0.0, 0.0), cylinder)]);
    // Near a corner, 5 mm above the floor (the top of the learned "in the box" voxels).
    let can = scene.add_body(can, pose(0.03, 0.02, 0.005, 0.0, 0.0, 0.0)).unwrap();
    let rest = scene.resting_pose(can).unwrap();
    assert!((rest.translation.vector.z - RESTING_GAP).abs() < 1e-9, "{rest}");
}

#[test]
fn a_plank_across_two_blocks_is_held_by_both_and_one_off_a_single_block_is_not() {
    let mut scene = Scene::new();
    scene
        .add_body(block("floor", (1.0, 1.0, 0.01), false), pose(0.0, 0.0, -0.01, 0.0, 0.0, 0.0))
        .unwrap();
    for (name, x) in [("left", -0.1), ("right", 0.1)] {
        scene
            .add_body(block(name, (0.01, 0.02, 0.05), true), pose(x, 0.0, 0.051, 0.0, 0.0, 0.0))
            .unwrap();
    }
    // The lintel spans both legs; its centre of mass is over the gap between them.
    let lintel = scene
        .add_body(block("lintel", (0.12, 0.02, 0.005), true), pose(0.0, 0.0, 0.109, 0.0, 0.0, 0.0))
        .unwrap();
    let rest = scene.resting_pose(lintel).unwrap();
    assert!((rest.translation.vector.z - (0.101 + 0.001 + 0.005)).abs() < 1e-9, "{rest}");

    // The same plank on the right leg alone, its centre 10 cm from it: it would tip off.
    let mut scene = Scene::new();
    scene
        .add_body(block("floor", (1.0, 1.0, 0.01), false), pose(0.0, 0.0, -0.01, 0.0, 0.0, 0.0))
        .unwrap();
    scene
        .add_body(block("right", (0.01, 0.02, 0.05), true), pose(0.1, 0.0, 0.051, 0.0, 0.0, 0.0))
        .unwrap();
    let plank = scene
        .add_body(block("plank", (0.12, 0.02, 0.005), true), pose(0.0, 0.0, 0.108, 0.0, 0.0, 0.0))
        .unwrap();
    match scene.resting_pose(plank) {
        Err(RestError::Unsupported { supports, outside, .. }) => {
            assert_eq!(supports, vec!["right".to_string()]);
            assert!((outside - 0.09).abs() < 1e-6, "{outside}");
        }
        other => panic!("expected Unsupported, got {other:?}"),
    }
}

/// Two cubes stacked on a floor: taking the lower one away leaves the upper one in the air (it
/// would drop onto the floor), taking the upper one leaves the lower one at rest, and a cube
/// standing apart is not asked.
#[test]
fn taking_what_another_object_rests_on_is_named() {
    // Packing's scene gives a gripper; the cubes stand on a floor of their own, far from it (a
    // grab here does not ask for the gripper to be near).
    let (mut scene, gripper, ..) = support::gripper_over_can();
    let floor = block("floor", (1.0, 1.0, 0.01), false);
    scene.add_body(floor, pose(10.0, 0.0, -0.01, 0.0, 0.0, 0.0)).unwrap();
    let cube = |name: &str| block(name, (0.02, 0.02, 0.02), true);
    let lower = scene.add_body(cube("lower"), pose(10.0, 0.0, 0.021, 0.0, 0.0, 0.0)).unwrap();
    let upper = scene.add_body(cube("upper"), pose(10.0, 0.0, 0.062, 0.0, 0.0, 0.0)).unwrap();
    let apart = scene.add_body(cube("apart"), pose(10.3, 0.0, 0.021, 0.0, 0.0, 0.0)).unwrap();
    for (taken, left) in [(lower, Some("upper")), (upper, None), (apart, None)] {
        let mut scene = scene.clone();
        scene.grab(gripper, taken).unwrap();
        match (scene.rests_without(taken), left) {
            (Ok(()), None) => {}
            (Err(left), Some(expected)) => {
                assert_eq!(left.object, expected);
                assert!(left.reason.contains("would drop 41.0 mm onto `floor`"), "{left}");
                assert!(left.to_string().contains("left without its support"), "{left}");
            }
            (outcome, expected) => panic!("taking {taken}: {outcome:?}, expected {expected:?}"),
        }
    }
}

#[test]
fn a_release_settles_the_can_it_lets_go_of_or_keeps_holding_it() {
    let (mut scene, gripper, can, q, grasp) = support::gripper_over_can();
    let robot = scene.robots()[gripper].robot().clone();
    let start = scene.body_pose(can);
    scene.grab(gripper, can).unwrap();
    let lifted = |height: f64| {
        let mut lifted = q.clone();
        robot.mount().write_coordinates(
            &(pose(0.0, 0.0, height, 0.0, 0.0, 0.0) * start * grasp),
            &mut lifted,
        );
        lifted
    };
    // 3 cm up: refused, and the can is still held where it was.
    let high = lifted(0.03);
    scene.set_configuration(gripper, &high);
    let held_at = scene.body_pose(can);
    assert!(matches!(scene.release_at_rest(gripper), Err(RestError::TooHigh { .. })));
    assert_eq!(scene.held(gripper).map(|h| h.body), Some(can));
    assert_eq!(scene.body_pose(can), held_at);
    // 3 mm up: let go of and settled back to where the scene put it, 1 mm above the table.
    let low = lifted(0.003);
    scene.set_configuration(gripper, &low);
    assert_eq!(scene.release_at_rest(gripper), Ok(Some(can)));
    assert_eq!(scene.held(gripper), None);
    let rest = scene.body_pose(can);
    assert!(
        (rest.translation.vector - start.translation.vector).norm() < 1e-9,
        "{rest} vs {start}"
    );
    // An empty gripper lets go of nothing.
    assert_eq!(scene.release_at_rest(gripper), Ok(None));
}

/// A carry rises until the object's bottom is the clearance above every body it overlaps
/// across: the table under it, and a wall beside it (boxes grown by the clearance).
#[test]
fn a_carried_can_rises_clear_of_the_table_and_of_a_wall_beside_it() {
    let clearance = 0.02;
    let (scene, can) = can_over_table(0.0, RESTING_GAP);
    let at = scene.body_pose(can);
    // Only the table: its top is 1 mm under the can's bottom.
    let rise = scene.rise_to_clear(can, &at, clearance);
    assert!((rise - (clearance - RESTING_GAP)).abs() < 1e-9, "{rise}");
    let (mut scene, can) = can_over_table(0.0, RESTING_GAP);
    // A wall 10 cm tall on the table, 1.5 cm beside the can: within the clearance.
    let wall = block("wall", (0.005, 0.2, 0.05), false);
    let wall_x = CAN_RADIUS + 0.015 + 0.005;
    scene.add_body(wall, pose(wall_x, 0.0, TABLE_TOP + 0.05, 0.0, 0.0, 0.0)).unwrap();
    let rise = scene.rise_to_clear(can, &at, clearance);
    assert!((rise - (0.1 + clearance - RESTING_GAP)).abs() < 1e-9, "{rise}");
    // Farther from the wall than the clearance, only the table counts.
    let away = pose(-0.01, 0.0, TABLE_TOP + RESTING_GAP, 0.0, 0.0, 0.0);
    let rise = scene.rise_to_clear(can, &away, clearance);
    assert!((rise - (clearance - RESTING_GAP)).abs() < 1e-9, "{rise}");
}
