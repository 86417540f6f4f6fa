//! Packing learned from demonstrations recorded as a robot's logger and a motion-capture system
//! write them, at the bundled spec's fixed rate (50 Hz) and with a tracker's noise (`noise 2 mm
//! 1 deg`) and misses (`dropped 0.05`: one pose in twenty is the one before), with default
//! settings, learns the actions it learns from noise-free ones: the same add and delete effects,
//! action for action, since the learner steadies the objects between grasps (`docs/learning.md`,
//! "Objects move only when held").

mod support;

use std::collections::BTreeSet;

use lamp_learn::{LiftedAtom, Model};
use lamp_spec::{DemoSource, TrackingNoise};

use support::{DEMOS, PACKING_BUILD, demo_files, packing, simulated};

/// An action by what it does: its add and its delete effects, as the domain writes them.
type Effects = (Vec<String>, Vec<String>);

fn written(atoms: &[LiftedAtom]) -> Vec<String> {
    atoms.iter().map(ToString::to_string).collect()
}

fn effects(model: &Model) -> BTreeSet<Effects> {
    model.actions.iter().map(|action| (written(&action.add), written(&action.delete))).collect()
}

/// Every region as `relation: centre`, to tell renumbered relations from changed ones.
fn regions(model: &Model) -> Vec<String> {
    let mut lines = Vec::new();
    for pair in &model.pairs {
        for region in &pair.regions {
            let [x, y, z] = region.summary.centre;
            lines.push(format!("{}: ({x:.3}, {y:.3}, {z:.3})", region.relation));
        }
    }
    lines
}

#[test]
fn noise_of_a_motion_capture_system_learns_the_noise_free_actions() {
    let (mut spec, world) = packing();
    for source in &mut spec.demonstrations {
        if let DemoSource::Simulated { noise, rate, .. } = source {
            assert!(rate.is_some(), "the bundled spec records at a fixed rate");
            *noise = TrackingNoise { position: 0.002, rotation: 1f64.to_radians(), dropped: 0.05 };
        }
    }
    let count = u32::try_from(DEMOS).expect("a small count");
    let files = demo_files("packing", simulated(&spec, &world, count));
    let (noisy, _) = lamp_build::build(&spec, "packing.lamp", &world, &files)
        .unwrap_or_else(|error| panic!("the noisy demonstrations build: {error}"));
    let (clean, _) = &*PACKING_BUILD;
    let (noisy_effects, clean_effects) = (effects(&noisy), effects(clean));
    let only = |a: &BTreeSet<Effects>, b: &BTreeSet<Effects>| -> Vec<String> {
        a.difference(b).map(|(add, delete)| format!("add {add:?} delete {delete:?}")).collect()
    };
    assert!(
        noisy_effects == clean_effects,
        "learned only with noise:\n{}\nlearned only without:\n{}\nregions with noise:\n{}\nregions without:\n{}",
        only(&noisy_effects, &clean_effects).join("\n"),
        only(&clean_effects, &noisy_effects).join("\n"),
        regions(&noisy).join("\n"),
        regions(clean).join("\n"),
    );
    assert_eq!(noisy.actions.len(), clean.actions.len(), "no action is learned twice");
}
