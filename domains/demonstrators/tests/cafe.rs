//! The Café demonstrator: every recorded state replays valid, full demonstrations end with the
//! can resting on the goal surface, cut ones are prefixes that stop before the retreat, and the
//! bytes depend only on the seed.

mod support;

use std::sync::LazyLock;

use lamp_demonstrators::{Demonstration, Demonstrator, Simulation, generate, generate_all};
use lamp_spec::{Spec, TrackingNoise};
use lamp_trajectory::{Trajectory, TrajectoryReader};
use lamp_world::SpecWorld;

static CAFE: LazyLock<(Spec, SpecWorld)> = LazyLock::new(|| support::domain("cafe"));

fn simulation(count: u32, cut_fraction: f64) -> Simulation {
    Simulation {
        demonstrator: Demonstrator::Cafe,
        count,
        cut_fraction,
        objects: 1,
        seed: 3,
        noise: TrackingNoise::NONE,
        rate: None,
    }
}

/// Three demonstrations of seed 3, generated once for all tests (a Café demonstration is a few
/// thousand steps: the tests keep the count small).
static DEMOS: LazyLock<Vec<Demonstration>> = LazyLock::new(|| {
    let (_, world) = &*CAFE;
    generate_all(world, &simulation(3, 0.5), |_| {}).expect("seed 3 generates")
});

/// The same three with nothing cut: the cut ones generated again, the full ones as they are.
static WHOLE: LazyLock<Vec<Demonstration>> = LazyLock::new(|| {
    let (_, world) = &*CAFE;
    DEMOS
        .iter()
        .map(|demo| match demo.cut_at {
            None => demo.clone(),
            Some(_) => generate(world, &simulation(3, 0.0), demo.index).expect("seed 3 generates"),
        })
        .collect()
});

#[test]
fn every_recorded_state_replays_valid() {
    let (_, world) = &*CAFE;
    for demo in DEMOS.iter() {
        support::replay(world, &demo.trajectory);
    }
}

/// The surface (name, footprint half extents) the can rests on at `step`, if any: in its
/// footprint, upright, its origin 1 mm above the top.
fn resting_on(trajectory: &Trajectory, step: usize) -> Option<String> {
    let header = &trajectory.header;
    let can = header.body_index("can1").expect("a can");
    let poses = &trajectory.steps[step].body_poses;
    let footprint = |type_name: &str| match type_name {
        "surface" => Some((0.45, 0.45)),
        _ => None,
    };
    header.bodies.iter().enumerate().find_map(|(index, body)| {
        let (half_x, half_y) = footprint(&body.type_name)?;
        let local = poses[index].inverse() * poses[can];
        let p = local.translation.vector;
        let up = (local.rotation * nalgebra::Vector3::z()).z;
        let inside = p.x.abs() <= half_x - 0.045 && p.y.abs() <= half_y - 0.045;
        (inside && (p.z - 0.001).abs() < 5e-4 && up > 0.999).then(|| body.name.clone())
    })
}

#[test]
fn full_demonstrations_carry_the_can_to_another_surface_and_cut_ones_stop_before_the_retreat() {
    let full = DEMOS.iter().filter(|demo| demo.cut_at.is_none()).count();
    assert!(full >= 1 && full < DEMOS.len(), "seed 3 gives both kinds: {full} full of 3");
    for (demo, whole) in DEMOS.iter().zip(WHOLE.iter()) {
        let header = &demo.trajectory.header;
        let steps = &demo.trajectory.steps;
        let start = resting_on(&demo.trajectory, 0).expect("the can starts on a surface");
        match demo.cut_at {
            None => {
                let last = steps.last().unwrap();
                assert_eq!(last.robots[0].held, vec![None], "released");
                let goal = resting_on(&demo.trajectory, steps.len() - 1)
                    .expect("the can ends resting on a surface");
                assert_ne!(goal, start, "on another surface");
                assert_eq!(header.provenance["cut_at"], "none");
            }
            Some(kept) => {
                assert_eq!(steps.len(), kept);
                assert!(kept <= demo.retreat_at && demo.retreat_at < whole.trajectory.steps.len());
                assert_eq!(steps[..], whole.trajectory.steps[..kept], "a prefix of the whole");
                assert_eq!(header.provenance["cut_at"], kept.to_string());
            }
        }
        // One grab and one release, steps of their own; the release ends what a cut may keep.
        let steps = &whole.trajectory.steps;
        let changes: Vec<usize> = (1..steps.len())
            .filter(|&i| steps[i].robots[0].held != steps[i - 1].robots[0].held)
            .collect();
        assert_eq!(changes.len(), 2, "one grab, one release");
        assert_eq!(changes[1] + 1, whole.retreat_at);
        for &i in &changes {
            assert_eq!(steps[i].robots[0].positions, steps[i - 1].robots[0].positions);
        }
        // The base stands still while the arm moves and the arm rests while the base moves
        // (angles compared modulo a turn: interpolation may write π as -π).
        for pair in steps.windows(2) {
            let (a, b) = (&pair[0].robots[0].positions, &pair[1].robots[0].positions);
            let moved = |i: usize| lamp_robot::wrap_angle(b[i] - a[i]).abs() > 1e-9;
            let base_moves = (0..3).any(moved);
            let arm_moves = (3..11).any(moved);
            assert!(!(base_moves && arm_moves), "base and arm move together");
        }
        assert_eq!(header.provenance["demonstrator"], "cafe");
        assert_eq!(header.provenance["demo_index"], demo.index.to_string());
    }
}

#[test]
fn bytes_depend_only_on_the_seed_not_on_the_thread_count() {
    let (_, world) = &*CAFE;
    let bytes = |demos: &[Demonstration]| -> Vec<Vec<u8>> {
        demos.iter().map(|d| d.to_bytes().unwrap()).collect()
    };
    let expected = bytes(&DEMOS);
    // Generated on its own, on one thread, a demonstration is the one generated within the set
    // on rayon's pool.
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let again = pool.install(|| generate(world, &simulation(3, 0.5), 1).unwrap());
    assert_eq!(again.to_bytes().unwrap(), expected[1]);
    for (demo, file) in DEMOS.iter().zip(&expected) {
        let read = TrajectoryReader::from_bytes(file, "demo").unwrap().read_all().unwrap();
        assert_eq!(read, demo.trajectory);
    }
}

#[test]
fn settings_come_from_the_spec() {
    let (spec, _) = &*CAFE;
    let simulation = Simulation::from_spec(spec).unwrap();
    assert_eq!(
        simulation,
        Simulation {
            demonstrator: Demonstrator::Cafe,
            count: 200,
            cut_fraction: 0.5,
            objects: 1,
            seed: 21,
            noise: TrackingNoise::NONE,
            rate: Some(50.0),
        }
    );
}
