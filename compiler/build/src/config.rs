//! The spec's `learn { … }` block as the learner's configuration.
//!
//! The spec resolves defaults and per-pair overrides; this maps them field by field. The spec
//! language has no minimum support, rotation share or sample count yet, so those keep
//! lamp-learn's defaults (see `docs/learning.md`).

use lamp_learn::{LearnConfig, PairSettings, Switch, TypePair};

/// The learner's configuration for a spec: its pair settings, ignored pairs and seed.
pub fn learn_config(spec: &lamp_spec::Spec) -> LearnConfig {
    let learning = &spec.learning;
    LearnConfig {
        default: pair_settings(&learning.defaults),
        pairs: learning
            .pairs
            .iter()
            .map(|((primary, secondary), settings)| {
                (TypePair::new(primary.clone(), secondary.clone()), pair_settings(settings))
            })
            .collect(),
        ignored: learning
            .ignored_pairs
            .iter()
            .map(|(first, second)| TypePair::new(first.clone(), second.clone()))
            .collect(),
        seed: spec.seed,
        ..LearnConfig::default()
    }
}

fn pair_settings(settings: &lamp_spec::PairSettings) -> PairSettings {
    PairSettings {
        position_bins: settings.position_bins.map(|bins| bins as usize),
        half_range: settings.position_range,
        rotation_bins: settings.rotation_bins as usize,
        threshold: settings.threshold,
        max_components: settings.max_components as usize,
        cover: settings.likelihood_cover,
        clear: switch(settings.clear),
        nowhere: switch(settings.nowhere),
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
        let mut override_settings = lamp_spec::PairSettings::DEFAULT;
        override_settings.position_bins = [9, 9, 6];
        override_settings.threshold = 0.2;
        override_settings.clear = lamp_spec::Switch::Off;
        override_settings.nowhere = lamp_spec::Switch::On;
        let learning = lamp_spec::Learning {
            defaults: lamp_spec::PairSettings::DEFAULT,
            pairs: BTreeMap::from([(("surface".into(), "can".into()), override_settings)]),
            ignored_pairs: BTreeSet::from([("can".into(), "can".into())]),
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
        assert_eq!(config.default.position_bins, [35, 35, 35]);
        assert_eq!(config.default.rotation_bins, 61);
        assert_eq!(config.default.max_components, 6);
        let surface_can = config.settings(&TypePair::new("can", "surface"));
        assert_eq!((surface_can.position_bins, surface_can.threshold), ([9, 9, 6], 0.2));
        assert_eq!((surface_can.clear, surface_can.nowhere), (Switch::Off, Switch::On));
        assert_eq!((config.default.clear, config.default.nowhere), (Switch::Auto, Switch::Auto));
        assert!(config.is_ignored(&TypePair::new("can", "can")));
        assert_eq!(config.validate(), Ok(()));
    }
}
