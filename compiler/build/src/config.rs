//! The spec's `learn { … }` block as the learner's configuration.
//!
//! The spec keeps what it writes: block-level settings and per-pair overrides merged over them,
//! each setting `None` where the spec leaves it out. This maps them field by field to lamp-learn's
//! pinned settings; the learner chooses or defaults the rest (see `docs/learning.md`). The spec
//! language has no minimum support, rotation share or sample count yet, so those keep
//! lamp-learn's defaults.

use lamp_abstraction::TypePair;
use lamp_learn::{LearnConfig, PinnedSettings, Switch};

/// The learner's configuration for a spec: its pinned pair settings, ignored pairs and seed.
pub fn learn_config(spec: &lamp_spec::Spec) -> LearnConfig {
    let learning = &spec.learning;
    LearnConfig {
        default: pinned_settings(&learning.defaults),
        pairs: learning
            .pairs
            .iter()
            .map(|((primary, secondary), settings)| {
                (TypePair::new(primary.clone(), secondary.clone()), pinned_settings(settings))
            })
            .collect(),
        ignored: learning
            .ignored_pairs
            .iter()
            .map(|(first, second)| TypePair::new(first.clone(), second.clone()))
            .collect(),
        seed: spec.seed,
        // What the world lets a released object drop by is what a region must tolerate.
        release_tolerance: lamp_world::MAX_SETTLE_DROP,
        ..LearnConfig::default()
    }
}

fn pinned_settings(settings: &lamp_spec::PairSettings) -> PinnedSettings {
    PinnedSettings {
        position_bins: settings.position_bins.map(|bins| bins.map(|count| count as usize)),
        half_range: settings.position_range,
        rotation_bins: settings.rotation_bins.map(|bins| bins as usize),
        threshold: settings.threshold,
        max_components: settings.max_components.map(|cap| cap as usize),
        cover: settings.likelihood_cover,
        clear: settings.clear.map(switch),
        nowhere: settings.nowhere.map(switch),
    }
}

fn switch(switch: lamp_spec::Switch) -> Switch {
    match switch {
        lamp_spec::Switch::On => Switch::On,
        lamp_spec::Switch::Off => Switch::Off,
        lamp_spec::Switch::Auto => Switch::Auto,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::{BTreeMap, BTreeSet};

    #[test]
    fn every_spec_setting_reaches_the_learner() {
        // The block writes a rotation bin count and a component cap; the pair writes its grid,
        // threshold and switches over them.
        let defaults = lamp_spec::PairSettings {
            rotation_bins: Some(61),
            max_components: Some(4),
            ..lamp_spec::PairSettings::default()
        };
        let override_settings = lamp_spec::PairSettings {
            position_bins: Some([9, 9, 6]),
            position_range: Some([0.2, 0.2, 0.05]),
            threshold: Some(0.2),
            likelihood_cover: Some(0.95),
            clear: Some(lamp_spec::Switch::Off),
            nowhere: Some(lamp_spec::Switch::On),
            ..defaults.clone()
        };
        let learning = lamp_spec::Learning {
            defaults,
            pairs: BTreeMap::from([(("surface".into(), "can".into()), override_settings)]),
            ignored_pairs: BTreeSet::from([("can".into(), "can".into())]),
            symmetry: None,
        };
        let spec = lamp_spec::Spec {
            domain: "d".into(),
            seed: 42,
            robots: vec![],
            object_types: vec![],
            demonstrations: vec![],
            learning,
            relation_aliases: vec![],
            structures: vec![],
            problems: vec![],
            plugins: lamp_spec::Plugins {
                planner: lamp_spec::PluginChoice::default_for(lamp_spec::PluginKind::Planner),
                refiner: lamp_spec::PluginChoice::default_for(lamp_spec::PluginKind::Refiner),
                motion: lamp_spec::PluginChoice::default_for(lamp_spec::PluginKind::Motion),
            },
        };
        let config = learn_config(&spec);
        assert_eq!(config.seed, 42);
        // Written at block level: pinned for every pair.
        assert_eq!(config.default.rotation_bins, Some(61));
        assert_eq!(config.default.max_components, Some(4));
        // Left out: not given, for the learner to choose or default.
        assert_eq!(config.default.position_bins, None);
        assert_eq!(config.default.half_range, None);
        assert_eq!(config.default.threshold, None);
        assert_eq!(config.default.cover, None);
        assert_eq!((config.default.clear, config.default.nowhere), (None, None));
        // The pair's entry, found in either order.
        let surface_can = config.pinned(&TypePair::new("can", "surface"));
        assert_eq!(surface_can.position_bins, Some([9, 9, 6]));
        assert_eq!(surface_can.half_range, Some([0.2, 0.2, 0.05]));
        assert_eq!(surface_can.threshold, Some(0.2));
        assert_eq!(surface_can.cover, Some(0.95));
        assert_eq!((surface_can.rotation_bins, surface_can.max_components), (Some(61), Some(4)));
        assert_eq!((surface_can.clear, surface_can.nowhere), (Some(Switch::Off), Some(Switch::On)));
        // A pair without an entry has the block-level settings only.
        let other = config.pinned(&TypePair::new("gripper", "can"));
        assert_eq!(other, config.default);
        assert!(config.is_ignored(&TypePair::new("can", "can")));
        assert_eq!(config.validate(), Ok(()));
    }
}
