//! The one table of the plugins built into lampc: each built-in name with the factory that makes
//! it from its configuration, the JSON object a shared library of the same plugin receives and
//! reads with the same `PluginFactory::create`. A name may stand for a plugin with an option set
//! (`topk` is the built-in planner with `{"algorithm": "topk"}`).
//!
//! The names are the spec's too (`lamp_spec::PluginKind::builtins`, which the checker knows
//! without linking any plugin); a test keeps the two lists equal.

use lamp_motion_rrt::RrtConnectPlanner;
use lamp_planner_builtin::{ALGORITHM_OPTION, BuiltinPlanner};
use lamp_planner_external::ExternalPlanner;
use lamp_plugin_api::{MotionPlanner, Planner, PluginError, Refiner};
use lamp_plugin_sdk::PluginFactory;
use lamp_refiner_gmm::GmmRefiner;
use lamp_spec::PluginKind;

/// The key under which every refiner, built in or a library, receives the build's sampler
/// artifact: the `gmm` refiner's.
pub(crate) const ARTIFACT_KEY: &str = lamp_refiner_gmm::ARTIFACT_OPTION;

/// Makes a plugin of trait `P` from configuration bytes.
pub(crate) type Make<P> = fn(&[u8]) -> Result<Box<P>, PluginError>;

/// Makes one kind of plugin from configuration bytes.
#[derive(Clone, Copy)]
pub(crate) enum Factory {
    Planner(Make<dyn Planner>),
    Refiner(Make<dyn Refiner>),
    Motion(Make<dyn MotionPlanner>),
}

impl Factory {
    pub(crate) fn kind(self) -> PluginKind {
        match self {
            Factory::Planner(_) => PluginKind::Planner,
            Factory::Refiner(_) => PluginKind::Refiner,
            Factory::Motion(_) => PluginKind::Motion,
        }
    }
}

/// A built-in plugin: its name, the options its name sets, and its factory.
pub(crate) struct Builtin {
    pub(crate) name: &'static str,
    /// Options written into the configuration before the spec's (which may not repeat them).
    pub(crate) preset: &'static [(&'static str, &'static str)],
    pub(crate) factory: Factory,
}

fn planner<T: PluginFactory + Planner + 'static>(
    config: &[u8],
) -> Result<Box<dyn Planner>, PluginError> {
    Ok(Box::new(T::create(config)?))
}

fn refiner<T: PluginFactory + Refiner + 'static>(
    config: &[u8],
) -> Result<Box<dyn Refiner>, PluginError> {
    Ok(Box::new(T::create(config)?))
}

fn motion<T: PluginFactory + MotionPlanner + 'static>(
    config: &[u8],
) -> Result<Box<dyn MotionPlanner>, PluginError> {
    Ok(Box::new(T::create(config)?))
}

/// Every built-in plugin, by kind and then as the spec lists them.
pub(crate) const BUILTINS: &[Builtin] = &[
    Builtin {
        name: "gbfs-ff",
        preset: &[(ALGORITHM_OPTION, "gbfs-ff")],
        factory: Factory::Planner(planner::<BuiltinPlanner>),
    },
    Builtin {
        name: "topk",
        preset: &[(ALGORITHM_OPTION, "topk")],
        factory: Factory::Planner(planner::<BuiltinPlanner>),
    },
    Builtin {
        name: "external",
        preset: &[],
        factory: Factory::Planner(planner::<ExternalPlanner>),
    },
    Builtin { name: "gmm", preset: &[], factory: Factory::Refiner(refiner::<GmmRefiner>) },
    Builtin {
        name: "rrt-connect",
        preset: &[],
        factory: Factory::Motion(motion::<RrtConnectPlanner>),
    },
];

/// The built-in `name` of `kind`.
pub(crate) fn find(kind: PluginKind, name: &str) -> Option<&'static Builtin> {
    BUILTINS.iter().find(|builtin| builtin.factory.kind() == kind && builtin.name == name)
}

/// The names of `kind`'s built-ins, for messages.
pub(crate) fn names(kind: PluginKind) -> Vec<&'static str> {
    BUILTINS
        .iter()
        .filter(|builtin| builtin.factory.kind() == kind)
        .map(|builtin| builtin.name)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const KINDS: [PluginKind; 3] = [PluginKind::Planner, PluginKind::Refiner, PluginKind::Motion];

    #[test]
    fn the_table_names_exactly_the_built_ins_the_spec_knows() {
        for kind in KINDS {
            assert_eq!(names(kind), kind.builtins(), "{kind:?}");
            assert!(find(kind, kind.default_builtin()).is_some(), "{kind:?}");
        }
    }

    #[test]
    fn every_built_in_is_made_from_its_preset_alone_and_refuses_an_unknown_option() {
        let artifact = serde_json::json!({
            "version": lamp_abstraction::SAMPLER_ARTIFACT_VERSION,
            "seed": 0,
            "pairs": [],
        });
        for builtin in BUILTINS {
            let mut config: serde_json::Map<String, serde_json::Value> = builtin
                .preset
                .iter()
                .map(|(key, value)| ((*key).to_string(), serde_json::json!(value)))
                .collect();
            if builtin.factory.kind() == PluginKind::Refiner {
                config.insert(ARTIFACT_KEY.to_string(), artifact.clone());
            }
            let bytes = serde_json::Value::Object(config.clone()).to_string();
            let made = match builtin.factory {
                Factory::Planner(make) => make(bytes.as_bytes()).map(drop),
                Factory::Refiner(make) => make(bytes.as_bytes()).map(drop),
                Factory::Motion(make) => make(bytes.as_bytes()).map(drop),
            };
            assert_eq!(made, Ok(()), "{}", builtin.name);

            config.insert("no-such-option".to_string(), serde_json::json!(1));
            let bytes = serde_json::Value::Object(config).to_string();
            let refused = match builtin.factory {
                Factory::Planner(make) => make(bytes.as_bytes()).map(drop),
                Factory::Refiner(make) => make(bytes.as_bytes()).map(drop),
                Factory::Motion(make) => make(bytes.as_bytes()).map(drop),
            };
            assert!(
                matches!(&refused, Err(PluginError::InvalidRequest { message })
                    if message.starts_with("unknown option `no-such-option`")),
                "{}: {refused:?}",
                builtin.name
            );
        }
    }
}
