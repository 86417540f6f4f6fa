//! Collision queries with known answers: touching, separated by a millimetre, penetrating; the
//! cylinder axis convention; compounds; and the broad phase agreeing with brute force.

#![allow(clippy::unwrap_used)] // a failed step is a failed test

use lamp_geometry::{
    BodyId, CollisionShape, CollisionWorld, GeometryError, Point3, Pose, Shape, Vec3,
    closest_points, distance, intersects, penetration_depth, within_margin,
};

fn cube(half: f64) -> CollisionShape {
    CollisionShape::new(&Shape::Box { half_extents: Vec3::new(half, half, half) }).unwrap()
}

fn at(x: f64, y: f64, z: f64) -> Pose {
    Pose::translation(x, y, z)
}

#[test]
fn boxes_touching_separated_and_penetrating() {
    let a = cube(0.05);
    let b = cube(0.05);
    // Faces exactly in contact.
    assert!(intersects(&a, &at(0.0, 0.0, 0.0), &b, &at(0.1, 0.0, 0.0)));
    // One millimetre apart.
    assert!(!intersects(&a, &at(0.0, 0.0, 0.0), &b, &at(0.101, 0.0, 0.0)));
    let gap = distance(&a, &at(0.0, 0.0, 0.0), &b, &at(0.101, 0.0, 0.0));
    assert!((gap - 0.001).abs() < 1e-9, "gap {gap}");
    assert!(within_margin(&a, &at(0.0, 0.0, 0.0), &b, &at(0.101, 0.0, 0.0), 0.002));
    assert!(!within_margin(&a, &at(0.0, 0.0, 0.0), &b, &at(0.101, 0.0, 0.0), 0.0005));
    // Penetrating by 1 cm.
    assert!(intersects(&a, &at(0.0, 0.0, 0.0), &b, &at(0.09, 0.0, 0.0)));
    assert_eq!(distance(&a, &at(0.0, 0.0, 0.0), &b, &at(0.09, 0.0, 0.0)), 0.0);
}

#[test]
fn penetration_depth_is_the_shortest_way_out_of_the_deepest_part() {
    let a = cube(0.05);
    let b = cube(0.05);
    let origin = at(0.0, 0.0, 0.0);
    // 1 cm into each other along x: 1 cm to separate, the way out along x.
    let depth = penetration_depth(&a, &origin, &b, &at(0.09, 0.0, 0.0));
    assert!((depth - 0.01).abs() < 1e-9, "depth {depth}");
    // Deeper along y than along x: the shorter way out counts.
    let depth = penetration_depth(&a, &origin, &b, &at(0.07, 0.02, 0.0));
    assert!((depth - 0.03).abs() < 1e-9, "depth {depth}");
    // Touching and apart are no overlap.
    assert_eq!(penetration_depth(&a, &origin, &b, &at(0.1, 0.0, 0.0)), 0.0);
    assert_eq!(penetration_depth(&a, &origin, &b, &at(0.2, 0.0, 0.0)), 0.0);
    // A compound overlaps as deep as its deepest part.
    let two = CollisionShape::compound(&[
        (at(-0.2, 0.0, 0.0), Shape::Box { half_extents: Vec3::new(0.05, 0.05, 0.05) }),
        (at(0.2, 0.0, 0.0), Shape::Box { half_extents: Vec3::new(0.05, 0.05, 0.05) }),
    ])
    .unwrap();
    let depth = penetration_depth(&two, &origin, &b, &at(0.28, 0.0, 0.0));
    assert!((depth - 0.02).abs() < 1e-9, "depth {depth}");

    let mut world = CollisionWorld::new();
    world.insert(cube(0.05), at(0.09, 0.0, 0.0));
    world.insert(cube(0.05), at(-0.07, 0.0, 0.0));
    assert_eq!(world.first_overlap_deeper_than(&a, &origin, 0.02, |_| false), Some(BodyId(1)));
    assert_eq!(world.first_overlap_deeper_than(&a, &origin, 0.005, |_| false), Some(BodyId(0)));
    assert_eq!(
        world.first_overlap_deeper_than(&a, &origin, 0.005, |id| id.0 == 0),
        Some(BodyId(1))
    );
    assert_eq!(world.first_overlap_deeper_than(&a, &origin, 0.03, |_| false), None);
}

#[test]
fn rotated_box_reaches_further() {
    // A cube turned 45° about z reaches half the diagonal along x: 0.05·√2 ≈ 0.0707.
    let a = cube(0.05);
    let turned = Pose::from_parts(
        nalgebra::Translation3::new(0.0, 0.0, 0.0),
        nalgebra::UnitQuaternion::from_axis_angle(&Vec3::z_axis(), std::f64::consts::FRAC_PI_4),
    );
    assert!(intersects(&a, &turned, &a, &at(0.12, 0.0, 0.0)));
    assert!(!intersects(&a, &turned, &a, &at(0.122, 0.0, 0.0)));
}

#[test]
fn cylinders_run_along_local_z() {
    let can = CollisionShape::new(&Shape::Cylinder { radius: 0.05, half_height: 0.1 }).unwrap();
    let ball = CollisionShape::new(&Shape::Sphere { radius: 0.01 }).unwrap();
    let origin = Pose::identity();
    // Above the top face (z = 0.1) by 5 mm, and beside the round side by 5 mm.
    let above = distance(&can, &origin, &ball, &at(0.0, 0.0, 0.115));
    let beside = distance(&can, &origin, &ball, &at(0.065, 0.0, 0.0));
    assert!((above - 0.005).abs() < 1e-6, "above {above}");
    assert!((beside - 0.005).abs() < 1e-6, "beside {beside}");
    // Along y at 0.09 m: outside the radius, but inside if the axis were parry's y.
    assert!(!intersects(&can, &origin, &ball, &at(0.0, 0.09, 0.0)));
    assert!(intersects(&can, &origin, &ball, &at(0.0, 0.0, 0.105)));
}

#[test]
fn closest_points_lie_on_the_facing_surfaces_in_the_world_frame() {
    // A magnet-like box 12 mm above a can's top face, both away from the origin and the can
    // turned (parry's cylinder runs along y; ours along z).
    let can = CollisionShape::new(&Shape::Cylinder { radius: 0.0325, half_height: 0.075 }).unwrap();
    let magnet =
        CollisionShape::new(&Shape::Box { half_extents: Vec3::new(0.0125, 0.0125, 0.056) })
            .unwrap();
    let can_pose = Pose::from_parts(
        nalgebra::Translation3::new(0.3, -0.2, 0.075),
        nalgebra::UnitQuaternion::from_axis_angle(&Vec3::z_axis(), 0.7),
    );
    let magnet_pose = at(0.31, -0.2, 0.15 + 0.012 + 0.056);
    let (on_magnet, on_can) = closest_points(&magnet, &magnet_pose, &can, &can_pose, 0.1).unwrap();
    assert!((on_magnet.z - 0.162).abs() < 1e-9, "on the magnet's bottom face: {on_magnet}");
    assert!((on_can.z - 0.15).abs() < 1e-9, "on the can's top face: {on_can}");
    assert!(((on_magnet - on_can).norm() - 0.012).abs() < 1e-9);
    assert!((on_can.x - on_magnet.x).abs() < 1e-9 && (on_can.y - on_magnet.y).abs() < 1e-9);
    // Farther apart than asked, touching, and overlapping: no points.
    assert_eq!(closest_points(&magnet, &magnet_pose, &can, &can_pose, 0.01), None);
    let touching = at(0.31, -0.2, 0.15 + 0.056);
    assert_eq!(closest_points(&magnet, &touching, &can, &can_pose, 0.1), None);
    let inside = at(0.31, -0.2, 0.14 + 0.056);
    assert_eq!(closest_points(&magnet, &inside, &can, &can_pose, 0.1), None);
}

#[test]
fn compound_bodies_collide_through_any_part() {
    // An open box: a floor and one wall; a small cube fits inside without touching.
    let floor = (at(0.0, 0.0, -0.0025), Shape::Box { half_extents: Vec3::new(0.08, 0.08, 0.0025) });
    let wall = (at(0.08, 0.0, 0.05), Shape::Box { half_extents: Vec3::new(0.005, 0.08, 0.05) });
    let open_box = CollisionShape::compound(&[floor, wall]).unwrap();
    let small = cube(0.02);
    let placed = at(0.3, 0.1, 0.0);
    assert!(!intersects(&open_box, &placed, &small, &(placed * at(0.0, 0.0, 0.021))));
    assert!(intersects(&open_box, &placed, &small, &(placed * at(0.0, 0.0, 0.019))));
    assert!(intersects(&open_box, &placed, &small, &(placed * at(0.06, 0.0, 0.05))));
    let aabb = open_box.aabb(&placed);
    assert!((aabb.maxs.x - 0.385).abs() < 1e-9 && (aabb.mins.z + 0.005).abs() < 1e-9);
}

#[test]
fn convex_hull_of_a_cube_matches_the_box() {
    let corners: Vec<Point3> = (0..8)
        .map(|i| {
            let s = |bit: i32| if i & bit == 0 { -0.05 } else { 0.05 };
            Point3::new(s(1), s(2), s(4))
        })
        .collect();
    let hull = CollisionShape::new(&Shape::ConvexHull { points: corners }).unwrap();
    let gap = distance(&hull, &Pose::identity(), &cube(0.05), &at(0.101, 0.0, 0.0));
    assert!((gap - 0.001).abs() < 1e-9);
}

#[test]
fn unusable_shapes_are_errors() {
    let flat =
        vec![Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 1.0, 0.0)];
    assert!(matches!(
        CollisionShape::new(&Shape::ConvexHull { points: flat }),
        Err(GeometryError::DegenerateHull { .. })
    ));
    assert!(matches!(
        CollisionShape::new(&Shape::Sphere { radius: -1.0 }),
        Err(GeometryError::BadDimension { .. })
    ));
    assert!(matches!(
        CollisionShape::new(&Shape::Box { half_extents: Vec3::new(0.1, f64::NAN, 0.1) }),
        Err(GeometryError::BadDimension { .. })
    ));
    assert!(matches!(CollisionShape::compound(&[]), Err(GeometryError::EmptyBody)));
}

#[test]
fn broad_phase_agrees_with_brute_force() {
    // A deterministic scatter of boxes and spheres; every query's answer must equal the exact
    // test over all bodies.
    let mut world = CollisionWorld::new();
    let mut bodies = Vec::new();
    let mut state: u64 = 12345;
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for i in 0..40 {
        let shape = if i % 2 == 0 {
            Shape::Box { half_extents: Vec3::new(0.02 + 0.05 * next(), 0.02 + 0.05 * next(), 0.05) }
        } else {
            Shape::Sphere { radius: 0.02 + 0.04 * next() }
        };
        let pose = at(next() * 2.0 - 1.0, next() * 2.0 - 1.0, next() * 0.5);
        let collision = CollisionShape::new(&shape).unwrap();
        world.insert(collision.clone(), pose);
        bodies.push((collision, pose));
    }
    let probe = cube(0.06);
    for _ in 0..300 {
        let pose = at(next() * 2.0 - 1.0, next() * 2.0 - 1.0, next() * 0.5);
        for margin in [0.0, 0.01] {
            let expected = bodies
                .iter()
                .position(|(shape, body)| within_margin(&probe, &pose, shape, body, margin));
            let found = world.first_contact(&probe, &pose, margin, |_| false).map(|id| id.0);
            assert_eq!(found, expected);
        }
    }
}

#[test]
fn a_bounding_box_holds_the_exact_one_and_the_bodies_near_a_group_answer_for_each() {
    let mut state: u64 = 777;
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let turned = |next: &mut dyn FnMut() -> f64| {
        let rotation = nalgebra::UnitQuaternion::from_euler_angles(
            next() * 6.3 - 3.15,
            next() * 6.3 - 3.15,
            next() * 6.3 - 3.15,
        );
        Pose::from_parts(
            nalgebra::Translation3::new(next() - 0.5, next() - 0.5, next() * 0.3),
            rotation,
        )
    };
    let shapes = [
        CollisionShape::new(&Shape::Box { half_extents: Vec3::new(0.03, 0.06, 0.01) }).unwrap(),
        CollisionShape::new(&Shape::Cylinder { radius: 0.03, half_height: 0.07 }).unwrap(),
        CollisionShape::new(&Shape::Sphere { radius: 0.04 }).unwrap(),
        CollisionShape::compound(&[
            (at(0.0, 0.0, 0.1), Shape::Box { half_extents: Vec3::new(0.02, 0.02, 0.05) }),
            (
                Pose::from_parts(
                    nalgebra::Translation3::new(0.05, 0.0, 0.0),
                    nalgebra::UnitQuaternion::from_euler_angles(0.4, 0.0, 0.9),
                ),
                Shape::Cylinder { radius: 0.01, half_height: 0.04 },
            ),
        ])
        .unwrap(),
    ];
    let mut world = CollisionWorld::new();
    for i in 0..40 {
        world.insert(shapes[i % shapes.len()].clone(), turned(&mut next));
    }
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..300 {
        // A group of three shapes standing together, like a robot's links.
        let group: Vec<(&CollisionShape, Pose)> = (0..3)
            .map(|k| {
                let pose = turned(&mut next);
                let near = Pose::from_parts(
                    nalgebra::Translation3::from(pose.translation.vector * 0.1),
                    pose.rotation,
                );
                (&shapes[(k + 1) % shapes.len()], if k == 0 { pose } else { near })
            })
            .collect();
        let boxes: Vec<_> = group.iter().map(|(shape, pose)| shape.bounding_box(pose)).collect();
        for ((shape, pose), bounding) in group.iter().zip(&boxes) {
            let exact = shape.aabb(pose);
            for axis in 0..3 {
                assert!(bounding.mins[axis] <= exact.mins[axis]);
                assert!(bounding.maxs[axis] >= exact.maxs[axis]);
            }
        }
        let all = boxes.iter().skip(1).fold(boxes[0], |all, one| all.union(one));
        for margin in [0.0, 0.01] {
            let near = world.bodies_near(&all, margin);
            for ((shape, pose), bounding) in group.iter().zip(&boxes) {
                let expected = world.first_contact(shape, pose, margin, |_| false);
                let among =
                    world.first_contact_among(&near, shape, pose, bounding, margin, |_| false);
                assert_eq!(among, expected);
                if expected.is_some() { hits += 1 } else { misses += 1 }
            }
        }
    }
    assert!(hits > 50 && misses > 50, "{hits} hits, {misses} misses");
}

#[test]
fn disabled_and_skipped_bodies_are_ignored() {
    let mut world = CollisionWorld::new();
    let a = world.insert(cube(0.05), at(0.0, 0.0, 0.0));
    let b = world.insert(cube(0.05), at(0.05, 0.0, 0.0));
    let probe = cube(0.01);
    let pose = at(0.03, 0.0, 0.0);
    assert_eq!(world.first_contact(&probe, &pose, 0.0, |_| false), Some(a));
    assert_eq!(world.first_contact(&probe, &pose, 0.0, |id| id == a), Some(b));
    world.set_enabled(b, false);
    assert_eq!(world.first_contact(&probe, &pose, 0.0, |id| id == a), None);
    world.set_pose(a, at(5.0, 0.0, 0.0));
    assert_eq!(world.first_contact(&probe, &pose, 0.0, |_| false), None);
    assert_eq!(world.contacts_between_bodies(0.0), Vec::new());
}

#[test]
fn markers_keep_their_id_and_pose_but_meet_nothing() {
    let mut world = CollisionWorld::new();
    let marker = world.insert_marker(at(0.0, 0.0, 0.0));
    let body = world.insert(cube(0.05), at(0.0, 0.0, 0.0));
    assert_eq!((marker.0, body.0), (0, 1));
    assert!(world.shape(marker).is_none());
    let probe = cube(0.01);
    assert_eq!(world.first_contact(&probe, &at(0.0, 0.0, 0.0), 0.0, |_| false), Some(body));
    assert_eq!(world.first_contact(&probe, &at(0.0, 0.0, 0.0), 0.0, |id| id == body), None);
    world.set_pose(marker, at(1.0, 2.0, 3.0));
    assert_eq!(world.pose(marker), Some(&at(1.0, 2.0, 3.0)));
    assert_eq!(world.contacts_between_bodies(0.0), Vec::new());
}

#[test]
fn the_box_test_before_gjk_never_changes_an_answer() {
    // Two thin planks side by side, both turned 45° about z: their world boxes overlap, their
    // own boxes are 5 mm apart.
    let plank =
        CollisionShape::new(&Shape::Box { half_extents: Vec3::new(0.1, 0.01, 0.01) }).unwrap();
    let turn = nalgebra::UnitQuaternion::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_4);
    let first = Pose::from_parts(nalgebra::Translation3::new(0.0, 0.0, 0.0), turn);
    let side = turn * Vec3::new(0.0, 0.025, 0.0);
    let second = Pose::from_parts(nalgebra::Translation3::from(side), turn);
    assert!(plank.aabb(&first).overlaps(&plank.aabb(&second), 0.0));
    assert!(!intersects(&plank, &first, &plank, &second));
    assert!(!within_margin(&plank, &first, &plank, &second, 0.004));
    assert!(within_margin(&plank, &first, &plank, &second, 0.006));

    // Shapes at random turns, close enough to touch half the time: every answer is the one
    // parry's distance gives, which no box test comes before.
    let mut state: u64 = 4242;
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let shapes = [
        plank.clone(),
        CollisionShape::new(&Shape::Cylinder { radius: 0.02, half_height: 0.08 }).unwrap(),
        CollisionShape::new(&Shape::Sphere { radius: 0.03 }).unwrap(),
        CollisionShape::compound(&[
            (at(0.0, 0.0, 0.06), Shape::Box { half_extents: Vec3::new(0.01, 0.01, 0.04) }),
            (at(0.05, 0.0, 0.0), Shape::Sphere { radius: 0.015 }),
        ])
        .unwrap(),
    ];
    let (mut touching, mut apart) = (0, 0);
    for k in 0..4000 {
        let mut pose = || {
            let rotation = nalgebra::UnitQuaternion::from_euler_angles(
                next() * 6.3,
                next() * 6.3,
                next() * 6.3,
            );
            let place = nalgebra::Translation3::new(
                0.14 * next() - 0.07,
                0.14 * next() - 0.07,
                0.14 * next() - 0.07,
            );
            Pose::from_parts(place, rotation)
        };
        let (a, b) = (&shapes[k % 4], &shapes[(k / 4) % 4]);
        let (pose_a, pose_b) = (pose(), pose());
        let gap = distance(a, &pose_a, b, &pose_b);
        assert_eq!(intersects(a, &pose_a, b, &pose_b), gap == 0.0, "pair {k}");
        for margin in [0.002, 0.01] {
            assert_eq!(within_margin(a, &pose_a, b, &pose_b, margin), gap <= margin, "pair {k}");
        }
        if gap == 0.0 { touching += 1 } else { apart += 1 }
    }
    assert!(touching > 500 && apart > 500, "{touching} touching, {apart} apart");
}
