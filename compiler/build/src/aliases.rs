//! Relation aliases: `relation NAME(T1, T2) = region of S in P containing POSE` bound to the learned
//! relation whose region contains the example pose, so that goals survive relearning.
//!
//! The example is the pose of an `S` in a `P`'s frame. The learner chooses the primary of a pair by
//! role, so the learned pair is either (P, S), used as is, or (S, P), for which the example is
//! inverted. Among the pair's regions (of either held flag) whose membership test accepts the example,
//! the one with the largest margin wins, ties to the smaller k: the same rule the abstraction uses,
//! so that a state with an object at the example pose satisfies the alias's atom.
//! Arguments follow the order written in `NAME(T1, T2)`; when T1 = T2 the first argument is the `S`
//! (`on(a, b)`: a in b's frame).

use std::collections::BTreeMap;

use lamp_learn::{Model, Pose, RegionClassifier};
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

/// Resolves every alias of a spec against a model, by alias name.
pub fn resolve_aliases(
    model: &Model,
    aliases: &[RelationAlias],
) -> Result<BTreeMap<String, ResolvedAlias>, BuildError> {
    aliases
        .iter()
        .map(|alias| resolve_alias(model, alias).map(|resolved| (alias.name.clone(), resolved)))
        .collect()
}

/// Resolves one alias.
pub fn resolve_alias(model: &Model, alias: &RelationAlias) -> Result<ResolvedAlias, BuildError> {
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
    let mut best: Option<(&str, f64)> = None;
    for region in &learned.regions {
        let margin = region.model.margin(&relative);
        if margin >= 0.0 && best.is_none_or(|(_, best_margin)| margin > best_margin) {
            best = Some((region.relation.as_str(), margin));
        }
    }
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
                .map(|region| describe_region(region, &relative))
                .collect::<Vec<_>>()
                .join("; "),
        }),
    }
}

fn describe_region(region: &lamp_learn::Region, relative: &Pose) -> String {
    let [x, y, z] = region.summary.centre;
    format!(
        "{} (held flag {}, centre ({x:.3}, {y:.3}, {z:.3}) m, margin of the example {:.1})",
        region.relation,
        region.summary.g,
        region.model.margin(relative)
    )
}
