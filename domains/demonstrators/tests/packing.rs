//! The Packing demonstrator: every recorded state replays valid, full demonstrations end with
//! the can in the box, cut ones are prefixes that stop before the retreat, and the bytes depend
//! only on the seed (not on the thread count).

mod support;

use std::sync::LazyLock;

use lamp_demonstrators::{Demonstration, Demonstrator, Simulation, generate, generate_all};
use lamp_spec::{Spec, TrackingNoise};
use lamp_trajectory::TrajectoryReader;
use lamp_world::SpecWorld;

static PACKING: LazyLock<(Spec, SpecWorld)> = LazyLock::new(|| support::domain("packing"));

fn simulation(count: u32, cut_fraction: f64) -> Simulation {
    Simulation {
        demonstrator: Demonstrator::Packing,
        count,
        cut_fraction,
        objects: 1,
        seed: 5,
        noise: TrackingNoise::NONE,
        rate: None,
    }
}

/// Four demonstrations of seed 5, generated once for all tests.
static DEMOS: LazyLock<Vec<Demonstration>> = LazyLock::new(|| {
    let (_, world) = &*PACKING;
    generate_all(world, &simulation(4, 0.5), |_| {}).expect("seed 5 generates")
});

#[test]
fn every_recorded_state_replays_valid() {
    let (_, world) = &*PACKING;
    for demo in DEMOS.iter() {
        support::replay(world, &demo.trajectory);
    }
}

#[test]
fn full_demonstrations_end_with_the_can_in_the_box_and_cut_ones_before_the_retreat() {
    let (_, world) = &*PACKING;
    let full = DEMOS.iter().filter(|demo| demo.cut_at.is_none()).count();
    assert!(full >= 1 && full < DEMOS.len(), "seed 5 gives both kinds: {full} full of 4");
    let uncut = generate_all(world, &simulation(4, 0.0), |_| {}).unwrap();
    for (demo, whole) in DEMOS.iter().zip(&uncut) {
        let header = &demo.trajectory.header;
        let (box1, can1) = (header.body_index("box1").unwrap(), header.body_index("can1").unwrap());
        let last = demo.trajectory.steps.last().unwrap();
        match demo.cut_at {
            None => {
                assert_eq!(demo, whole);
                assert_eq!(last.robots[0].held, vec![None]);
                let local = last.body_poses[box1].inverse() * last.body_poses[can1];
                let p = local.translation.vector;
                assert!(
                    p.x.abs() <= 0.0425 && p.y.abs() <= 0.0425,
                    "can at {p:?} in the box frame"
                );
                assert!((p.z - 0.001).abs() < 1e-6, "can at height {}", p.z);
                assert_eq!(header.provenance["cut_at"], "none");
                // The can started on the table, outside the box.
                let first = &demo.trajectory.steps[0];
                let start =
                    (first.body_poses[box1].inverse() * first.body_poses[can1]).translation.vector;
                assert!(start.x.abs() > 0.1 || start.y.abs() > 0.1);
            }
            Some(kept) => {
                assert_eq!(demo.trajectory.steps.len(), kept);
                assert!(kept <= demo.retreat_at && demo.retreat_at < whole.trajectory.steps.len());
                assert_eq!(
                    demo.trajectory.steps[..],
                    whole.trajectory.steps[..kept],
                    "a prefix of the whole"
                );
                assert_eq!(header.provenance["cut_at"], kept.to_string());
            }
        }
        // The grab and the release are steps of their own, at the same configuration.
        let steps = &whole.trajectory.steps;
        let changes: Vec<usize> = (1..steps.len())
            .filter(|&i| steps[i].robots[0].held != steps[i - 1].robots[0].held)
            .collect();
        assert_eq!(changes.len(), 2, "one grab, one release");
        for i in changes {
            assert_eq!(steps[i].robots[0].positions, steps[i - 1].robots[0].positions);
        }
        assert_eq!(header.provenance["demonstrator"], "packing");
        assert_eq!(header.provenance["demo_index"], demo.index.to_string());
        assert_eq!(header.provenance["seed"], "5");
    }
}

#[test]
fn bytes_depend_only_on_the_seed_not_on_the_thread_count() {
    let (_, world) = &*PACKING;
    let bytes = |demos: &[Demonstration]| -> Vec<Vec<u8>> {
        demos.iter().map(|d| d.to_bytes().unwrap()).collect()
    };
    let expected = bytes(&DEMOS);
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let again = pool.install(|| generate_all(world, &simulation(4, 0.5), |_| {}).unwrap());
        assert_eq!(bytes(&again), expected, "{threads} thread(s)");
    }
    // One demonstration on its own is the same as within the set.
    let third = generate(world, &simulation(4, 0.5), 2).unwrap();
    assert_eq!(third, DEMOS[2]);
    // And the files read back.
    for (demo, file) in DEMOS.iter().zip(&expected) {
        let read = TrajectoryReader::from_bytes(file, "demo").unwrap().read_all().unwrap();
        assert_eq!(read, demo.trajectory);
    }
    // Another seed, another demonstration.
    let other = generate(world, &Simulation { seed: 6, ..simulation(4, 0.5) }, 0).unwrap();
    assert_ne!(other.trajectory.steps, DEMOS[0].trajectory.steps);
}

#[test]
fn settings_come_from_the_spec_and_refuse_what_cannot_be_done() {
    let (spec, world) = &*PACKING;
    let simulation = Simulation::from_spec(spec).unwrap();
    assert_eq!(
        simulation,
        Simulation {
            demonstrator: Demonstrator::Packing,
            count: 200,
            cut_fraction: 0.5,
            objects: 1,
            seed: 11,
            noise: TrackingNoise::NONE,
            rate: Some(50.0),
        }
    );
    assert!(matches!(
        Demonstrator::from_name("kitchen"),
        Err(lamp_demonstrators::DemoError::UnknownDemonstrator { .. })
    ));
    let two = Simulation { objects: 2, ..simulation.clone() };
    assert!(matches!(
        generate(world, &two, 0),
        Err(lamp_demonstrators::DemoError::Unsupported { .. })
    ));
    let mut no_source = spec.clone();
    no_source.demonstrations.clear();
    assert!(matches!(
        Simulation::from_spec(&no_source),
        Err(lamp_demonstrators::DemoError::NoSimulator)
    ));
}
