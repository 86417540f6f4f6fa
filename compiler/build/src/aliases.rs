//! Relation aliases: `relation NAME(T1, T2) = region of S in P containing POSE` bound to the learned
//! relation whose region contains the example pose, so that goals survive relearning.
//!
//! The example is the pose of an `S` in a `P`'s frame. The learner chooses the primary of a pair by
//! role, so the learned pair is either (P, S), used as is, or (S, P), for which the example is
//! inverted. Among the pair's regions (of either held flag) whose membership test accepts the example,
//! the one with the largest margin wins, ties to the smaller k: the same rule the abstraction uses,
//! so that a state with an object at the example pose satisfies the alias's atom.
//!
//! An example pose stands for a placement, which symmetric shapes show as several poses: a cube
//! centred on another at yaw 0 is the same placement as at a quarter turn. Where the learner
//! compared the pair's poses as recorded (it folds them only where folding pays), its regions hold
//! the poses the demonstrations happened to show: twenty demonstrations may stack cubes only at a
//! quarter turn. So an example that no region holds is tried as every member of its orbit under
//! the shapes' turns (`LearnConfig::pair_symmetry`), a region's margin being its best member's.
//! Arguments follow the order written in `NAME(T1, T2)`; when T1 = T2 the first argument is the `S`
//! (`on(a, b)`: a in b's frame).

use std::collections::BTreeMap;

use lamp_abstraction::{Pose, RegionClassifier};
use lamp_learn::{LearnConfig, Model};
use lamp_spec::RelationAlias;

use crate::error::BuildError;

/// An alias bound to a learned relation.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ResolvedAlias {
    /// The alias's name.
    pub alias: String,
    /// The learned relation `<primary>_<secondary>_<k>`.
    pub relation: String,
    /// For the learned relation's (primary, secondary) arguments, the index of the alias argument
    /// that fills it.
    pub argument_order: [usize; 2],
}

impl ResolvedAlias {
    /// The learned relation's arguments for alias arguments `arguments` (two names).
    pub fn arguments(&self, arguments: &[String]) -> Vec<String> {
        self.argument_order.iter().filter_map(|&index| arguments.get(index).cloned()).collect()
    }
}

/// Resolves every alias of a spec against a model, by alias name, with the shapes' turns of
/// `symmetries` (the learning configuration's).
pub fn resolve_aliases(
    model: &Model,
    aliases: &[RelationAlias],
    symmetries: &LearnConfig,
) -> Result<BTreeMap<String, ResolvedAlias>, BuildError> {
    aliases
        .iter()
        .map(|alias| {
            resolve_alias(model, alias, symmetries).map(|resolved| (alias.name.clone(), resolved))
        })
        .collect()
}

/// Resolves one alias, its example tried up to the shapes' turns of `symmetries`.
pub fn resolve_alias(
    model: &Model,
    alias: &RelationAlias,
    symmetries: &LearnConfig,
) -> Result<ResolvedAlias, BuildError> {
    let (primary, secondary) = (alias.primary.as_str(), alias.secondary.as_str());
    let forward = model.pairs.iter().find(|learned| {
        learned.pair.pair.primary == primary && learned.pair.pair.secondary == secondary
    });
    let backward = model.pairs.iter().find(|learned| {
        learned.pair.pair.primary == secondary && learned.pair.pair.secondary == primary
    });
    let position = |type_name: &str, fallback: usize| {
        if alias.parameters[0] == alias.parameters[1] {
            fallback
        } else {
            usize::from(alias.parameters[1] == type_name)
        }
    };
    let (learned, relative, argument_order) = match (forward, backward) {
        (Some(learned), _) => {
            (learned, alias.example, [position(primary, 1), position(secondary, 0)])
        }
        (None, Some(learned)) => {
            (learned, alias.example.inverse(), [position(secondary, 0), position(primary, 1)])
        }
        (None, None) => {
            let learned: Vec<String> =
                model.pairs.iter().map(|p| p.pair.pair.to_string()).collect();
            return Err(BuildError::AliasPair {
                alias: alias.name.clone(),
                primary: primary.to_string(),
                secondary: secondary.to_string(),
                learned: if learned.is_empty() { "none".into() } else { learned.join(", ") },
            });
        }
    };
    let members: Vec<Pose> = match symmetries.pair_symmetry(&learned.pair.pair) {
        Some(symmetry) => symmetry.members(&relative, true).collect(),
        None => vec![relative],
    };
    // The example as written first: its orbit only when no region holds it, so that an example
    // the demonstrations show binds as it always has.
    let best = deepest_region(learned, &members[..1]).or_else(|| deepest_region(learned, &members));
    match best {
        Some((relation, _)) => Ok(ResolvedAlias {
            alias: alias.name.clone(),
            relation: relation.to_string(),
            argument_order,
        }),
        None => Err(BuildError::AliasRegion {
            alias: alias.name.clone(),
            primary: primary.to_string(),
            secondary: secondary.to_string(),
            regions: learned
                .regions
                .iter()
                .map(|region| describe_region(region, &members))
                .collect::<Vec<_>>()
                .join("; "),
        }),
    }
}

/// The region that holds one of `members` deepest, with that margin; ties to the smaller k.
fn deepest_region<'m>(
    learned: &'m lamp_learn::LearnedPair,
    members: &[Pose],
) -> Option<(&'m str, f64)> {
    let mut best: Option<(&str, f64)> = None;
    for region in &learned.regions {
        let margin = orbit_margin(region, members);
        if margin >= 0.0 && best.is_none_or(|(_, best_margin)| margin > best_margin) {
            best = Some((region.relation.as_str(), margin));
        }
    }
    best
}

/// A region's margin for the best of the example's orbit `members`.
fn orbit_margin(region: &lamp_learn::Region, members: &[Pose]) -> f64 {
    members.iter().map(|member| region.model.margin(member)).fold(f64::NEG_INFINITY, f64::max)
}

fn describe_region(region: &lamp_learn::Region, members: &[Pose]) -> String {
    let [x, y, z] = region.summary.centre;
    format!(
        "{} (held flag {}, centre ({x:.3}, {y:.3}, {z:.3}) m, margin of the example {:.1})",
        region.relation,
        region.summary.g,
        orbit_margin(region, members)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use lamp_learn::synthetic::{PLACED_YAW, PlaceTask, place_demonstrations};
    use nalgebra::{Translation3, UnitQuaternion};

    /// Blocks set down square on a target, at yaw 0 give or take a degree: the block–target
    /// region holds that yaw only, as learned with the poses compared as recorded.
    fn square_placements() -> Model {
        let task = PlaceTask {
            spots: vec![[0.0, 0.0, 0.05]],
            noise: 0.0,
            placed_yaw: PLACED_YAW,
            grasp_yaw: None,
        };
        let demonstrations = place_demonstrations(&task, 40, 5);
        lamp_learn::learn(&demonstrations, &LearnConfig::default(), &lamp_learn::NoShapes)
            .expect("learns")
    }

    /// A block on the target at a quarter turn.
    fn quarter_turned_on_target() -> RelationAlias {
        RelationAlias {
            name: "on".into(),
            parameters: ["block".into(), "target".into()],
            primary: "target".into(),
            secondary: "block".into(),
            example: Pose::from_parts(
                Translation3::new(0.0, 0.0, 0.05),
                UnitQuaternion::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_2),
            ),
        }
    }

    #[test]
    fn an_example_is_found_at_a_turn_of_a_symmetric_shape_the_demonstrations_did_not_show() {
        let model = square_placements();
        let alias = quarter_turned_on_target();
        let square = quarter_turn_symmetries("block");
        let resolved = resolve_alias(&model, &alias, &square).expect("found up to the turn");
        assert_eq!(resolved.relation, "target_block_1");
        // Without the block's turns, the quarter-turned example is in no region.
        let error = resolve_alias(&model, &alias, &LearnConfig::default())
            .expect_err("the learned region holds yaw 0 only");
        assert!(matches!(error, BuildError::AliasRegion { .. }), "{error}");
    }

    /// A learning configuration whose `type_name` maps onto itself under every quarter turn
    /// about its vertical axis, as a square block does.
    fn quarter_turn_symmetries(type_name: &str) -> LearnConfig {
        let turns = (0..4)
            .map(|k| {
                UnitQuaternion::from_euler_angles(
                    0.0,
                    0.0,
                    f64::from(k) * std::f64::consts::FRAC_PI_2,
                )
            })
            .collect();
        let mut config = LearnConfig::default();
        config.symmetries.insert(type_name.into(), turns);
        config
    }
}
