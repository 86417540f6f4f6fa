//! The physics check on small scenes: what rests stays, what overhangs or topples is named.

#![allow(clippy::unwrap_used)] // a failed step is a failed test

use lamp_geometry::{Pose, Shape, Vec3};
use lamp_physics::{MAX_SHIFT, MAX_TURN, PhysicsBody, first_unsettled, simulate};

/// The clearance lamp's scenes leave between a body at rest and its support.
const GAP: f64 = 0.001;

fn at(x: f64, y: f64, z: f64) -> Pose {
    Pose::translation(x, y, z)
}

fn cuboid(x: f64, y: f64, z: f64) -> Vec<(Pose, Shape)> {
    vec![(Pose::identity(), Shape::Box { half_extents: Vec3::new(x, y, z) })]
}

/// A can (radius 3.25 cm, 15 cm tall, frame at its bottom) as lamp's specs describe it.
fn can() -> Vec<(Pose, Shape)> {
    vec![(at(0.0, 0.0, 0.075), Shape::Cylinder { radius: 0.0325, half_height: 0.075 })]
}

/// A table whose top is at z = 0.75 and whose edge is at x = 0.45.
fn table() -> Vec<(Pose, Shape)> {
    cuboid(0.45, 0.45, 0.025)
}

fn table_body(parts: &[(Pose, Shape)]) -> PhysicsBody<'_> {
    PhysicsBody { name: "table", parts, pose: at(0.0, 0.0, 0.725), fixed: true }
}

#[test]
fn a_can_resting_on_a_table_stays() {
    let (table, can) = (table(), can());
    let bodies = [
        table_body(&table),
        PhysicsBody { name: "can", parts: &can, pose: at(0.1, 0.2, 0.751), fixed: false },
    ];
    let drifts = simulate(&bodies, GAP).unwrap();
    assert_eq!(drifts.len(), 1, "fixed bodies have no drift");
    let drift = &drifts[0];
    assert!(drift.at_rest(), "{drift:?}");
    // Lowered by its 1 mm gap onto the table, it stays there.
    assert!((drift.sink - GAP).abs() < 1e-6, "{drift:?}");
    assert!(drift.shift < 0.0005, "{drift:?}");
    assert!(drift.turn < 0.2 * MAX_TURN, "{drift:?}");
}

#[test]
fn a_can_higher_than_the_gap_is_not_lowered_but_falls() {
    let (table, can) = (table(), can());
    let bodies = [
        table_body(&table),
        PhysicsBody { name: "can", parts: &can, pose: at(0.1, 0.2, 0.754), fixed: false },
    ];
    let drift = &simulate(&bodies, GAP).unwrap()[0];
    assert_eq!(drift.sink, 0.0, "{drift:?}");
    // It falls its 4 mm in the simulation, which counts in its shift.
    assert!((drift.shift - 0.004).abs() < 0.0005, "{drift:?}");
}

#[test]
fn a_can_in_the_air_falls() {
    let (table, can) = (table(), can());
    let bodies = [
        table_body(&table),
        PhysicsBody { name: "can", parts: &can, pose: at(0.1, 0.2, 0.80), fixed: false },
    ];
    let drift = first_unsettled(&bodies, GAP).unwrap().expect("a floating can falls");
    assert_eq!(drift.sink, 0.0, "{drift:?}");
    assert!(drift.shift > 0.04, "{drift:?}");
}

#[test]
fn a_can_over_the_edge_beyond_its_centre_of_mass_is_named() {
    let (table, can) = (table(), can());
    let bodies = [
        table_body(&table),
        PhysicsBody { name: "steady", parts: &can, pose: at(0.0, 0.0, 0.751), fixed: false },
        PhysicsBody { name: "overhanging", parts: &can, pose: at(0.46, 0.0, 0.751), fixed: false },
    ];
    let drift = first_unsettled(&bodies, GAP).unwrap().expect("the overhanging can falls");
    assert_eq!(drift.name, "overhanging");
    assert!(drift.shift > 10.0 * MAX_SHIFT || drift.turn > 10.0 * MAX_TURN, "{drift:?}");
}

#[test]
fn a_tower_that_topples_is_named_and_a_straight_one_is_not() {
    let floor = cuboid(2.0, 2.0, 0.01);
    let block = cuboid(0.075, 0.025, 0.015);
    let tower = |offset: f64| {
        let mut bodies = vec![PhysicsBody {
            name: "floor",
            parts: &floor,
            pose: at(0.0, 0.0, -0.01),
            fixed: true,
        }];
        for (level, name) in ["block1", "block2", "block3", "block4"].into_iter().enumerate() {
            let z = 0.016 + level as f64 * 0.031;
            let x = level as f64 * offset;
            bodies.push(PhysicsBody { name, parts: &block, pose: at(x, 0.0, z), fixed: false });
        }
        first_unsettled(&bodies, GAP).unwrap()
    };
    assert_eq!(tower(0.0), None, "a straight tower stands");
    // Each block 6 cm further out than the one below: the top three overhang block1 by more
    // than their half length together, so the tower tips over at block2.
    let fallen = tower(0.06).expect("the leaning tower falls");
    assert_eq!(fallen.name, "block2");
}

#[test]
fn the_same_scene_drifts_the_same_way_every_time() {
    let (table, can) = (table(), can());
    let bodies = [
        table_body(&table),
        PhysicsBody { name: "a", parts: &can, pose: at(0.44, 0.0, 0.755), fixed: false },
        PhysicsBody { name: "b", parts: &can, pose: at(-0.2, 0.1, 0.7505), fixed: false },
    ];
    assert_eq!(simulate(&bodies, GAP).unwrap(), simulate(&bodies, GAP).unwrap());
}

/// A Jenga tower of `layers` layers of two blocks at the outer positions, each layer turned 90°
/// from the one below, 1 mm apart and 1 mm above the table.
fn jenga_tower(layers: usize) -> Vec<(String, Pose)> {
    let (width, height) = (0.0508, 0.03048);
    let mut blocks = Vec::new();
    for layer in 0..layers {
        let z = 0.75 + GAP + layer as f64 * (height + GAP) + height / 2.0;
        let turned = layer % 2 == 1;
        for side in [-1.0, 1.0] {
            let (x, y) = if turned { (side * width, 0.0) } else { (0.0, side * width) };
            let yaw = if turned { std::f64::consts::FRAC_PI_2 } else { 0.0 };
            let pose = Pose::new(Vec3::new(x, y, z), Vec3::new(0.0, 0.0, yaw));
            blocks.push((format!("b{layer}_{side}"), pose));
        }
    }
    blocks
}

#[test]
fn a_tower_of_fifteen_crossed_layers_stands() {
    let table = table();
    let block = cuboid(0.0762, 0.0254, 0.01524);
    let tower = jenga_tower(15);
    let mut bodies = vec![table_body(&table)];
    bodies.extend(tower.iter().map(|(name, pose)| PhysicsBody {
        name,
        parts: &block,
        pose: *pose,
        fixed: false,
    }));
    let drifts = simulate(&bodies, GAP).unwrap();
    let worst = drifts.iter().max_by(|a, b| a.shift.total_cmp(&b.shift)).unwrap();
    // Once on contact it sinks a little into its springy contacts, far less than the check
    // allows.
    assert!(worst.shift < 0.2 * MAX_SHIFT, "{worst:?}");
    // Every layer goes down by the gaps under it: 1 mm for the first, 15 mm for the top.
    for (drift, (name, _)) in drifts.iter().zip(&tower) {
        let layer: f64 = name[1..name.find('_').unwrap()].parse().unwrap();
        assert!((drift.sink - (layer + 1.0) * GAP).abs() < 1e-5, "{drift:?}");
    }
}
