//! The Jenga demonstrator: the fixed Fetch reaches every block it must, every recorded state
//! replays valid, placed blocks sit on their markers, and the bytes depend only on the seed.

mod support;

use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::LazyLock;

use lamp_demonstrators::{Demonstration, Demonstrator, Simulation, generate, generate_all};
use lamp_geometry::{Pose, Rotation, Vec3};
use lamp_physics::{PhysicsBody, first_unsettled};
use lamp_robot::{ARM_GROUP, IkConfig};
use lamp_spec::{Spec, TrackingNoise};
use lamp_world::{LinkGoal, RESTING_GAP, Scene, SpecWorld, reach};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

static JENGA: LazyLock<(Spec, SpecWorld)> = LazyLock::new(|| support::domain("jenga"));

/// A Jenga block: 0.1524 × 0.0508 × 0.03048 m.
const WIDTH: f64 = 0.0508;
const HEIGHT: f64 = 0.03048;

fn pose(x: f64, y: f64, z: f64, yaw: f64) -> Pose {
    Pose::from_parts(Vec3::new(x, y, z).into(), Rotation::from_euler_angles(0.0, 0.0, yaw))
}

/// The tables of the spec's largest problem (the table and the side tables beside the Fetch),
/// alone with the Fetch in `tuck`, and the table top's pose (the table's frame is the centre of its
/// top face).
fn table_scene() -> (Scene, usize, Pose) {
    let (spec, world) = &*JENGA;
    let largest = spec.problems.last().expect("problems");
    let mut scene = Scene::new();
    let mut top = None;
    for table in largest.scene.objects.iter().filter(|o| o.type_name.ends_with("table")) {
        let body = world.body(&table.name, &table.type_name).expect("the table types");
        scene.add_body(body, table.pose).expect("tables apart");
        if table.type_name == "table" {
            top = Some(table.pose);
        }
    }
    let q = world.placement_configuration("fetch", None, Some("tuck")).expect("`tuck`");
    let robot = world.add_robot(&mut scene, "fetch", q.clone()).expect("the Fetch");
    assert!(scene.is_valid(robot, &q), "{:?}", scene.first_contact(robot, &q));
    (scene, robot, top.expect("a table"))
}

/// Whether the arm reaches a top grasp of a block at `block` (the gripper 1.8 cm above its
/// centre, pointing down, fingers across its width), collision-free, from the fixed base.
fn reaches_top_grasp(scene: &Scene, robot: usize, block: &Pose) -> bool {
    let (_, world) = &*JENGA;
    let seed = world.placement_configuration("fetch", None, Some("tuck")).expect("`tuck`");
    let down =
        Pose::from_parts(Vec3::zeros().into(), Rotation::from_euler_angles(0.0, FRAC_PI_2, 0.0));
    let grasp = block * pose(0.0, 0.0, 0.018, 0.0) * down;
    let mut config = IkConfig::new();
    config.restarts = 100;
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    reach(
        scene,
        &LinkGoal { robot, group: ARM_GROUP, link: None, target: &grasp, start: &seed },
        &config,
        &mut rng,
    )
    .is_ok()
}

#[test]
fn the_fixed_arm_reaches_the_top_of_a_thirty_block_tower_and_every_supply_spot() {
    let (scene, robot, top) = table_scene();
    // The top layer of nine (18 blocks) anchored anywhere the demonstrator anchors one (8 cm
    // along the table's depth, 12 cm across), and 22 cm across, where problems may anchor one;
    // and of fifteen (30 blocks) near the middle; at any yaw, both slots.
    let layer = |k: f64| RESTING_GAP + HEIGHT / 2.0 + k * (HEIGHT + RESTING_GAP);
    let mut missed = Vec::new();
    let anchors = [
        (-0.08, -0.12, 8.0),
        (-0.08, 0.12, 8.0),
        (0.08, -0.12, 8.0),
        (0.08, 0.12, 8.0),
        (0.0, 0.0, 8.0),
        (0.05, -0.22, 8.0),
        (0.05, 0.22, 8.0),
        (-0.1, 0.22, 8.0),
        (-0.04, -0.09, 14.0),
        (0.04, 0.09, 14.0),
    ];
    for (x, y, k) in anchors {
        for yaw in [0.0, FRAC_PI_2, PI / 4.0, -PI / 3.0] {
            for side in [1.0, -1.0] {
                let block = top * pose(x, y, 0.0, yaw) * pose(0.0, side * WIDTH, layer(k), 0.0);
                if !reaches_top_grasp(&scene, robot, &block) {
                    missed.push(format!("layer {k} at ({x}, {y}) yaw {yaw:.2}, side {side}"));
                }
            }
        }
    }
    // Blocks lying on the table within ±0.2 m along its depth and ±0.4 m across (the supply
    // grid of the bundled problems), and on the side tables.
    let mut lying: Vec<(f64, f64)> = Vec::new();
    for x in [-0.2, 0.0, 0.2] {
        lying.extend([-0.4, -0.3, -0.15, 0.15, 0.3, 0.4].map(|y| (x, y)));
    }
    for x in [-0.415, -0.25, -0.085] {
        lying.extend([-0.69, -0.59, 0.59, 0.69].map(|y| (x, y)));
    }
    for (x, y) in lying {
        for yaw in [0.0, FRAC_PI_2] {
            let block = top * pose(x, y, layer(0.0), yaw);
            if !reaches_top_grasp(&scene, robot, &block) {
                missed.push(format!("lying at ({x}, {y}) yaw {yaw:.2}"));
            }
        }
    }
    assert!(missed.is_empty(), "{} missed:\n{}", missed.len(), missed.join("\n"));
}

fn simulation(count: u32, cut_fraction: f64) -> Simulation {
    Simulation {
        demonstrator: Demonstrator::Jenga,
        count,
        cut_fraction,
        objects: 3,
        seed: 7,
        noise: TrackingNoise::NONE,
        rate: None,
    }
}

/// Four demonstrations of seed 7, generated once for all tests.
static DEMOS: LazyLock<Vec<Demonstration>> = LazyLock::new(|| {
    let (_, world) = &*JENGA;
    generate_all(world, &simulation(4, 0.5), |_| {}).expect("seed 7 generates")
});

/// `demo` as it would be had it not been cut short.
fn uncut(world: &SpecWorld, demo: &Demonstration) -> Demonstration {
    match demo.cut_at {
        None => demo.clone(),
        Some(_) => generate(world, &simulation(4, 0.0), demo.index).expect("seed 7 generates"),
    }
}

#[test]
fn every_recorded_state_replays_valid() {
    let (_, world) = &*JENGA;
    for demo in DEMOS.iter() {
        support::replay(world, &demo.trajectory);
    }
}

#[test]
fn every_placed_block_ends_on_its_own_marker_and_only_placed_blocks_have_one() {
    let (_, world) = &*JENGA;
    for demo in DEMOS.iter() {
        // The full demonstration: where the moved block comes to rest.
        let whole = uncut(world, demo);
        let header = &whole.trajectory.header;
        let last = whole.trajectory.steps.last().expect("steps");
        let markers: Vec<_> = header.bodies.iter().filter(|body| body.type_name == "loc").collect();
        let blocks: Vec<_> =
            header.bodies.iter().filter(|body| body.type_name == "block").collect();
        assert_eq!(blocks.len(), 3);
        assert!((1..=3).contains(&markers.len()), "{} markers", markers.len());
        for marker in markers {
            let block = marker.name.strip_prefix("loc_").expect("loc_<block>");
            let at = |name: &str| last.body_poses[header.body_index(name).expect("a body")];
            let offset = at(&marker.name).inverse() * at(block);
            let p = offset.translation.vector;
            assert!(p.x.abs() < 0.002 && p.y.abs() < 0.002 && p.z.abs() < 0.001, "{p:?}");
            assert!(offset.rotation.angle() < 0.02, "{}", offset.rotation.angle());
        }
        // The same header in the cut demonstration: markers are known from the start.
        assert_eq!(demo.trajectory.header.bodies, whole.trajectory.header.bodies);
    }
}

#[test]
fn the_same_seed_gives_the_same_bytes() {
    let (_, world) = &*JENGA;
    let again = generate(world, &simulation(4, 0.5), 1).expect("seed 7 generates");
    assert_eq!(again.to_bytes().unwrap(), DEMOS[1].to_bytes().unwrap());
}

/// The first free body that does not stay put under gravity among the table of the spec's first
/// problem (fixed) and blocks at `blocks`.
fn unsettled_blocks(blocks: &[(String, Pose)]) -> Option<lamp_physics::Drift> {
    let (spec, world) = &*JENGA;
    let table = spec.problems[0]
        .scene
        .objects
        .iter()
        .find(|o| o.type_name == "table")
        .expect("a table in the first problem");
    let table_body = world.body(&table.name, "table").expect("the table type");
    let block_body = world.body("block", "block").expect("the block type");
    let mut bodies = vec![PhysicsBody {
        name: "table",
        parts: &table_body.parts,
        pose: table.pose,
        fixed: true,
    }];
    for (name, pose) in blocks {
        bodies.push(PhysicsBody { name, parts: &block_body.parts, pose: *pose, fixed: false });
    }
    first_unsettled(&bodies, RESTING_GAP).expect("blocks simulate")
}

#[test]
fn what_every_full_demonstration_builds_stands_under_gravity() {
    let (_, world) = &*JENGA;
    for demo in DEMOS.iter() {
        let whole = uncut(world, demo);
        let header = &whole.trajectory.header;
        let last = whole.trajectory.steps.last().expect("steps");
        let blocks: Vec<(String, Pose)> = header
            .bodies
            .iter()
            .zip(&last.body_poses)
            .filter(|(body, _)| body.type_name == "block")
            .map(|(body, pose)| (body.name.clone(), *pose))
            .collect();
        assert_eq!(unsettled_blocks(&blocks), None, "demonstration {}", demo.index);
    }
}

#[test]
fn more_blocks_than_the_table_holds_or_a_spec_without_markers_is_refused() {
    let (_, world) = &*JENGA;
    let five = Simulation { objects: 5, ..simulation(1, 0.5) };
    assert!(matches!(
        generate(world, &five, 0),
        Err(lamp_demonstrators::DemoError::Unsupported { .. })
    ));
    // Packing has no fixed arm (nor markers): named, not a panic.
    let (_, packing) = support::domain("packing");
    match generate(&packing, &simulation(1, 0.5), 0) {
        Err(lamp_demonstrators::DemoError::SpecMismatch { what, .. }) => {
            assert!(what.contains("fixed-arm"), "{what}");
        }
        other => panic!("expected a spec mismatch, got {other:?}"),
    }
}
