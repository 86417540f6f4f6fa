//! Demonstrations recorded at a fixed rate, as a robot's logger writes them (`rate 50 Hz`: the
//! timed motion sampled every 20 ms, easing into and out of every stop, half a second at rest for
//! each grasp and release), learn the domain the same demonstrations learn recorded one step per
//! planned state: the learner tells a slow sample from noise by how the step changes, and a rest
//! in which the whole scene waits out a grasp makes no place (`docs/learning.md`, "Keyframes").

mod support;

use lamp_spec::{DemoSource, Spec};

use support::{artifact, demo_files, simulated};

/// The domain without its comment lines (the header names the build's inputs).
fn domain_text(artifacts: &lamp_build::Artifacts) -> String {
    artifact(artifacts, "domain.pddl")
        .lines()
        .filter(|line| !line.trim_start().starts_with(';'))
        .collect::<Vec<_>>()
        .join("\n")
}

fn record_at(spec: &mut Spec, hertz: f64) {
    for source in &mut spec.demonstrations {
        if let DemoSource::Simulated { rate, .. } = source {
            *rate = Some(hertz);
        }
    }
}

/// The domain learned from the first `count` demonstrations of a bundled spec's own `simulate`
/// source, recorded one step per planned state (`None`) or at `hertz`.
fn learned(domain: &str, count: u32, hertz: Option<f64>) -> String {
    let (mut spec, world) = lamp_test_support::domain(domain);
    if let Some(hertz) = hertz {
        record_at(&mut spec, hertz);
    }
    // The domain is what these tests compare; the spec's problems are not.
    spec.problems.clear();
    let files = demo_files(domain, simulated(&spec, &world, count));
    let (_, artifacts) = lamp_build::build(&spec, &format!("{domain}.lamp"), &world, &files)
        .unwrap_or_else(|error| panic!("the {domain} demonstrations build: {error}"));
    domain_text(&artifacts)
}

/// Packing's full set: from 200 demonstrations the gripper's half-second waits over every can
/// it picked up made a wide region of the gripper over the box (±0.74 m) that every action
/// then required.
#[test]
fn packing_recorded_at_fifty_hertz_learns_the_domain_of_one_step_per_state() {
    assert_eq!(learned("packing", 200, Some(50.0)), learned("packing", 200, None));
}

/// A Fetch arm's: from 60 demonstrations the arm's stops at its grasps made one more region of
/// the gripper relative to a block, and actions that needed it.
#[test]
fn jenga_recorded_at_fifty_hertz_learns_the_domain_of_one_step_per_state() {
    assert_eq!(learned("jenga", 60, Some(50.0)), learned("jenga", 60, None));
}
