//! Action induction (paper App. C): transitions between consecutive distinct abstract states (consecutive entries
//! of one held object into regions taken as one, module `placements`), lifted and clustered by their changes,
//! become actions with learned preconditions and effects.
//!
//! Lifting is canonical: the changed objects are renamed `?<type>_p<k>` by the bijection (per type) that makes the
//! sorted lifted (added, deleted) lists smallest, so isomorphic transitions always share a key.
//! Objects linked to the changed ones become extra parameters `?<type>_extra_p<k>`, named in order of
//! (type, the sorted lifted atoms linking them to changed objects, object name).
//! Actions are numbered `a1`, `a2`, … in order of their (lifted added, lifted deleted) lists.

use std::collections::{BTreeMap, BTreeSet};

use crate::abstraction::Fact;
use crate::demo::{Participant, Role};
use crate::existential::{Complements, quantify_lone_extras};
pub use crate::lifted::{LiftedAtom, Parameter};
use crate::placements;
use crate::relations::{PairVocabulary, Symbol, symbol_name};

/// Above this many candidate renamings, the changed objects are renamed in name order instead.
const MAX_CANONICAL_RENAMINGS: usize = 5040;

/// Where a transition was observed: the demonstration and the index of its pre-state.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct TransitionRef {
    /// The demonstration's id.
    pub demonstration: String,
    /// The step of the state before the change.
    pub step: usize,
}

/// An induced action.
#[derive(Debug, Clone, PartialEq)]
pub struct Action {
    /// `a<n>`.
    pub name: String,
    /// Parameters sorted by name.
    pub parameters: Vec<Parameter>,
    /// Positive preconditions, sorted.
    pub preconditions: Vec<LiftedAtom>,
    /// Atoms that must be false before it, sorted: what an extra object that would only say "in
    /// this region of some object" says without naming it (module `existential`).
    pub negative_preconditions: Vec<LiftedAtom>,
    /// Add effects, sorted.
    pub add: Vec<LiftedAtom>,
    /// Delete effects (the change plus the pair's other relations on the same objects), sorted.
    pub delete: Vec<LiftedAtom>,
    /// Every observed transition it was induced from, in (demonstration, step) order of the input.
    pub transitions: Vec<TransitionRef>,
    /// How many distinct grounded transitions those are (identical repeats count once).
    pub distinct_transitions: usize,
}

impl Action {
    /// Pairs of same-typed parameters, which the domain requires to differ: `(not (= ?a ?b))`.
    pub fn distinct_parameter_pairs(&self) -> Vec<(String, String)> {
        let mut pairs = Vec::new();
        for (index, first) in self.parameters.iter().enumerate() {
            for second in &self.parameters[index + 1..] {
                if first.type_name == second.type_name {
                    pairs.push((first.name.clone(), second.name.clone()));
                }
            }
        }
        pairs
    }
}

/// One demonstration, abstracted.
pub(crate) struct AbstractDemonstration<'a> {
    pub id: &'a str,
    pub participants: &'a [Participant],
    pub states: Vec<BTreeSet<Fact>>,
}

type ClusterKey = (Vec<LiftedAtom>, Vec<LiftedAtom>);

struct Cluster {
    add: Vec<LiftedAtom>,
    delete: BTreeSet<LiftedAtom>,
    preconditions: Option<BTreeSet<LiftedAtom>>,
    types: BTreeMap<String, String>,
    /// The names of the extra objects that are not robot parts.
    extras: BTreeSet<String>,
    transitions: Vec<TransitionRef>,
    grounded: BTreeSet<(Vec<String>, Vec<String>)>,
}

/// Induces the actions of a set of abstracted demonstrations.
pub(crate) fn induce(
    vocabulary: &[PairVocabulary],
    demonstrations: &[AbstractDemonstration<'_>],
) -> Vec<Action> {
    let changing = changing_symbols(demonstrations);
    let mut clusters: BTreeMap<ClusterKey, Cluster> = BTreeMap::new();
    for demonstration in demonstrations {
        let mut became_true: BTreeSet<Fact> = BTreeSet::new();
        let states = &demonstration.states;
        for (step, after) in placements::changes(vocabulary, demonstration.participants, states) {
            let (pre, post) = (&states[step], &states[after]);
            let added: BTreeSet<Fact> = post.difference(pre).copied().collect();
            let deleted: BTreeSet<Fact> = pre.difference(post).copied().collect();
            let transition = Transition {
                participants: demonstration.participants,
                pre,
                added: &added,
                deleted: &deleted,
            };
            let (key, mapping) = canonical_lifting(vocabulary, &transition);
            let (preconditions, extras) =
                preconditions(vocabulary, &transition, &mapping, &became_true, &changing);
            let cluster = clusters.entry(key.clone()).or_insert_with(|| Cluster {
                add: key.0.clone(),
                delete: exclusive_deletes(vocabulary, &transition, &mapping)
                    .into_iter()
                    .chain(key.1.clone())
                    .collect(),
                preconditions: None,
                types: BTreeMap::new(),
                extras: BTreeSet::new(),
                transitions: Vec::new(),
                grounded: BTreeSet::new(),
            });
            for (object, name) in mapping.iter().chain(&extras) {
                cluster
                    .types
                    .insert(name.clone(), demonstration.participants[*object].type_name.clone());
            }
            // A robot's parts are few whatever the task's size, and naming them keeps "with the
            // arm tucked" readable; objects are what multiply an action's groundings.
            cluster.extras.extend(
                extras
                    .iter()
                    .filter(|(object, _)| {
                        !demonstration.participants[**object].role.is_robot_part()
                    })
                    .map(|(_, name)| name.clone()),
            );
            cluster.preconditions = Some(match cluster.preconditions.take() {
                None => preconditions,
                Some(previous) => previous.intersection(&preconditions).cloned().collect(),
            });
            cluster
                .transitions
                .push(TransitionRef { demonstration: demonstration.id.to_string(), step });
            let names = |facts: &BTreeSet<Fact>| -> Vec<String> {
                facts
                    .iter()
                    .map(|fact| grounded_text(vocabulary, demonstration.participants, *fact))
                    .collect()
            };
            cluster.grounded.insert((names(pre), names(post)));
            became_true.extend(added.iter().copied());
        }
    }
    let complements = Complements::new(vocabulary);
    clusters
        .into_values()
        .enumerate()
        .map(|(index, cluster)| finish(index, cluster, &complements))
        .collect()
}

fn finish(index: usize, cluster: Cluster, complements: &Complements) -> Action {
    let mut preconditions = cluster.preconditions.unwrap_or_default();
    let mut negative = BTreeSet::new();
    let effects: Vec<&LiftedAtom> = cluster.add.iter().chain(&cluster.delete).collect();
    quantify_lone_extras(complements, &cluster.extras, &effects, &mut preconditions, &mut negative);
    let preconditions: Vec<LiftedAtom> = preconditions.into_iter().collect();
    let negative_preconditions: Vec<LiftedAtom> = negative.into_iter().collect();
    let delete: Vec<LiftedAtom> = cluster.delete.into_iter().collect();
    let used: BTreeSet<&String> = preconditions
        .iter()
        .chain(&negative_preconditions)
        .chain(&cluster.add)
        .chain(&delete)
        .flat_map(|atom| &atom.arguments)
        .collect();
    let parameters = used
        .into_iter()
        .map(|name| Parameter {
            name: name.clone(),
            type_name: cluster
                .types
                .get(name)
                .cloned()
                .expect("every lifted name was given a type when its object was named"),
        })
        .collect();
    Action {
        name: format!("a{}", index + 1),
        parameters,
        preconditions,
        negative_preconditions,
        add: cluster.add,
        delete,
        transitions: cluster.transitions,
        distinct_transitions: cluster.grounded.len(),
    }
}

struct Transition<'a> {
    participants: &'a [Participant],
    pre: &'a BTreeSet<Fact>,
    added: &'a BTreeSet<Fact>,
    deleted: &'a BTreeSet<Fact>,
}

/// Symbols that change somewhere in some demonstration.
fn changing_symbols(demonstrations: &[AbstractDemonstration<'_>]) -> BTreeSet<Symbol> {
    let mut changing = BTreeSet::new();
    for demonstration in demonstrations {
        for window in demonstration.states.windows(2) {
            changing.extend(window[0].symmetric_difference(&window[1]).map(|fact| fact.symbol()));
        }
    }
    changing
}

fn grounded_text(
    vocabulary: &[PairVocabulary],
    participants: &[Participant],
    fact: Fact,
) -> String {
    let mut text = symbol_name(vocabulary, fact.symbol());
    for argument in fact.arguments() {
        text.push(' ');
        text.push_str(&participants[argument].name);
    }
    text
}

fn lift(
    vocabulary: &[PairVocabulary],
    fact: Fact,
    mapping: &BTreeMap<usize, String>,
) -> Option<LiftedAtom> {
    let arguments = fact
        .arguments()
        .iter()
        .map(|object| mapping.get(object).cloned())
        .collect::<Option<_>>()?;
    Some(LiftedAtom { predicate: symbol_name(vocabulary, fact.symbol()), arguments })
}

fn lift_all(
    vocabulary: &[PairVocabulary],
    facts: &BTreeSet<Fact>,
    mapping: &BTreeMap<usize, String>,
) -> Vec<LiftedAtom> {
    let mut lifted: Vec<LiftedAtom> =
        facts.iter().filter_map(|fact| lift(vocabulary, *fact, mapping)).collect();
    lifted.sort();
    lifted
}

/// The cluster key and the renaming of the changed objects that gives the smallest key.
fn canonical_lifting(
    vocabulary: &[PairVocabulary],
    transition: &Transition<'_>,
) -> (ClusterKey, BTreeMap<usize, String>) {
    let participants = transition.participants;
    let mut by_type: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    let changed: BTreeSet<usize> = transition
        .added
        .iter()
        .chain(transition.deleted)
        .flat_map(|fact| fact.arguments())
        .collect();
    for object in changed {
        by_type.entry(participants[object].type_name.as_str()).or_default().push(object);
    }
    for objects in by_type.values_mut() {
        objects.sort_by(|a, b| participants[*a].name.cmp(&participants[*b].name));
    }
    let renamings: usize = by_type.values().map(|objects| factorial(objects.len())).product();
    let groups: Vec<(&str, Vec<usize>)> = by_type.into_iter().collect();
    let mut orders: Vec<Vec<usize>> = groups.iter().map(|(_, objects)| objects.clone()).collect();
    let mut best: Option<(ClusterKey, BTreeMap<usize, String>)> = None;
    loop {
        let mapping = naming(&groups, &orders);
        let key = (
            lift_all(vocabulary, transition.added, &mapping),
            lift_all(vocabulary, transition.deleted, &mapping),
        );
        if best.as_ref().is_none_or(|(best_key, _)| key < *best_key) {
            best = Some((key, mapping));
        }
        if renamings > MAX_CANONICAL_RENAMINGS || !next_orders(&groups, &mut orders, participants) {
            break;
        }
    }
    best.expect("the loop body runs at least once")
}

fn naming(groups: &[(&str, Vec<usize>)], orders: &[Vec<usize>]) -> BTreeMap<usize, String> {
    let mut mapping = BTreeMap::new();
    for ((type_name, _), order) in groups.iter().zip(orders) {
        for (position, object) in order.iter().enumerate() {
            mapping.insert(*object, format!("?{type_name}_p{}", position + 1));
        }
    }
    mapping
}

/// Advances to the next combination of per-type orders (an odometer of lexicographic permutations).
fn next_orders(
    groups: &[(&str, Vec<usize>)],
    orders: &mut [Vec<usize>],
    participants: &[Participant],
) -> bool {
    for (group, order) in groups.iter().zip(orders.iter_mut()).rev() {
        let rank = |object: &usize| participants[*object].name.clone();
        if next_permutation(order, &rank) {
            return true;
        }
        order.clone_from(&group.1);
    }
    false
}

fn next_permutation<K: Ord>(order: &mut [usize], rank: &impl Fn(&usize) -> K) -> bool {
    let Some(pivot) = (1..order.len()).rev().find(|&i| rank(&order[i - 1]) < rank(&order[i]))
    else {
        return false;
    };
    let successor = (pivot..order.len())
        .rev()
        .find(|&j| rank(&order[j]) > rank(&order[pivot - 1]))
        .expect("the element after the pivot is larger, so a successor exists");
    order.swap(pivot - 1, successor);
    order[pivot..].reverse();
    true
}

fn factorial(n: usize) -> usize {
    (1..=n).fold(1usize, |product, k| product.saturating_mul(k))
}

/// The pair's other relations on the objects of every added relation (mutual exclusion).
fn exclusive_deletes(
    vocabulary: &[PairVocabulary],
    transition: &Transition<'_>,
    mapping: &BTreeMap<usize, String>,
) -> Vec<LiftedAtom> {
    let mut deletes = Vec::new();
    for fact in transition.added {
        if let Fact::Relation { pair, region, primary, secondary } = *fact {
            for other in 0..=vocabulary[pair].region_count() {
                if other != region {
                    let exclusive = Fact::Relation { pair, region: other, primary, secondary };
                    deletes.extend(lift(vocabulary, exclusive, mapping));
                }
            }
        }
    }
    deletes
}

/// The lifted precondition of one transition (reference §8.4 steps 1–3 and 5, and the paper's pruning),
/// with the naming of its extra objects.
fn preconditions(
    vocabulary: &[PairVocabulary],
    transition: &Transition<'_>,
    changed: &BTreeMap<usize, String>,
    became_true: &BTreeSet<Fact>,
    changing: &BTreeSet<Symbol>,
) -> (BTreeSet<LiftedAtom>, BTreeMap<usize, String>) {
    let extras = extra_parameters(vocabulary, transition, changed);
    let mut names = changed.clone();
    names.extend(extras.iter().map(|(object, name)| (*object, name.clone())));
    let parameters = Parameters { changed, extras: &extras, names: &names };
    let mut result = BTreeSet::new();
    // Step 1: what the action deletes must hold before it.
    result.extend(transition.deleted.iter().filter_map(|fact| lift(vocabulary, *fact, &names)));
    // Step 3 with pruning: every other true fact among the parameters.
    for fact in transition.pre.difference(transition.deleted) {
        if keeps(transition, &parameters, fact, became_true, changing) {
            result.extend(lift(vocabulary, *fact, &names));
        }
    }
    (result, extras)
}

/// Step 2: unchanged true relations that link a changed object to a static body or robot part,
/// or that put something in a region of a changed robot part, bring their other object in as an
/// extra parameter, named `?<type>_extra_p<k>` in the order of type, the relations that link it
/// and name.
fn extra_parameters(
    vocabulary: &[PairVocabulary],
    transition: &Transition<'_>,
    changed: &BTreeMap<usize, String>,
) -> BTreeMap<usize, String> {
    let participants = transition.participants;
    let is_changed = |object: usize| changed.contains_key(&object);
    let mut links: BTreeMap<usize, Vec<LiftedAtom>> = BTreeMap::new();
    for fact in transition.pre.difference(transition.deleted) {
        let Fact::Relation { pair, region, primary, secondary } = *fact else { continue };
        for (inside, other) in [(primary, secondary), (secondary, primary)] {
            if !is_changed(inside) || is_changed(other) {
                continue;
            }
            // A static body comes in only through a region it shares with a changed object:
            // "the glass is on no marker but this one" names, through the `_0` relation, every
            // other marker of the demonstration, which are its history, not the action's.
            let static_or_robot_link =
                transition.is_robot(other) || (!transition.is_movable(other) && region != 0);
            let robot_region = region != 0 && transition.is_robot(inside);
            if static_or_robot_link || robot_region {
                let mut placeholder = changed.clone();
                placeholder.insert(other, "?".to_string());
                let link = LiftedAtom {
                    predicate: symbol_name(vocabulary, Symbol::Relation { pair, region }),
                    arguments: [primary, secondary]
                        .iter()
                        .map(|o| placeholder[o].clone())
                        .collect(),
                };
                links.entry(other).or_default().push(link);
            }
        }
    }
    let mut extras_in_order: Vec<(String, Vec<LiftedAtom>, String, usize)> = links
        .into_iter()
        .map(|(object, mut signature)| {
            signature.sort();
            (
                participants[object].type_name.clone(),
                signature,
                participants[object].name.clone(),
                object,
            )
        })
        .collect();
    extras_in_order.sort();
    let mut extras = BTreeMap::new();
    let mut per_type: BTreeMap<String, usize> = BTreeMap::new();
    for (type_name, _, _, object) in extras_in_order {
        let count = per_type.entry(type_name.clone()).or_default();
        *count += 1;
        extras.insert(object, format!("?{type_name}_extra_p{count}"));
    }
    extras
}

/// An action's parameters: the objects it changes, the extras, and every parameter's name.
struct Parameters<'a> {
    changed: &'a BTreeMap<usize, String>,
    extras: &'a BTreeMap<usize, String>,
    names: &'a BTreeMap<usize, String>,
}

/// Step 3's pruning: whether a fact true before the action, and not deleted by it, is one of its
/// preconditions.
fn keeps(
    transition: &Transition<'_>,
    parameters: &Parameters<'_>,
    fact: &Fact,
    became_true: &BTreeSet<Fact>,
    changing: &BTreeSet<Symbol>,
) -> bool {
    let is_changed = |object: usize| parameters.changed.contains_key(&object);
    match *fact {
        Fact::Relation { region, primary, secondary, .. } => {
            let named = |object: usize| parameters.names.contains_key(&object);
            if !named(primary) || !named(secondary) {
                return false;
            }
            let touches_changed = is_changed(primary) || is_changed(secondary);
            let non_robot_extra = [primary, secondary]
                .iter()
                .any(|o| parameters.extras.contains_key(o) && !transition.is_robot(*o));
            let spurious_static = !touches_changed && !changing.contains(&fact.symbol());
            let unexplained_none = region == 0 && non_robot_extra && !became_true.contains(fact);
            !spurious_static && !unexplained_none
        }
        // A robot part the action moves keeps its clear atoms of every pair: "the gripper is
        // at no can's grasp" matters to any motion of the gripper (a tuck from a grasp pose
        // leaves the grasp), and it held at every demonstrated instance or the intersection
        // drops it. An object's clear atom stays only where the action puts something into
        // that very region of it: that its other regions were empty is the demonstrations'
        // history (the two blocks a third is laid across had nothing under them), which a
        // larger task does not repeat.
        Fact::Clear { pair, region, object } => {
            is_changed(object)
                && (transition.is_robot(object)
                    || transition.fills_region_of(pair, region, object)
                    || transition.grasp_changes(object))
        }
        // That the object is in a region of no robot part (held by another gripper, say)
        // matters to any change of its relations of the pair. Of an object's regions, as with
        // clear atoms, only the one the action puts it into: that it was in the pair's other
        // regions of none is history (the legs a lintel is laid across stood on the table),
        // which a larger task does not repeat.
        Fact::Nowhere { pair, region, object } => {
            is_changed(object)
                && if transition.robot_pair(pair) {
                    transition.changes_as_secondary(pair, object)
                } else {
                    transition.enters_region(pair, region, object)
                }
        }
    }
}

impl Transition<'_> {
    fn is_robot(&self, object: usize) -> bool {
        self.participants[object].role.is_robot_part()
    }

    fn is_movable(&self, object: usize) -> bool {
        self.participants[object].role == Role::Object { movable: true }
    }

    /// The facts the transition adds or deletes.
    fn changes(&self) -> impl Iterator<Item = &Fact> {
        self.added.iter().chain(self.deleted)
    }

    /// Whether it changes a relation of the pair with the object as its secondary.
    fn changes_as_secondary(&self, pair: usize, object: usize) -> bool {
        self.changes().any(|fact| {
            matches!(*fact, Fact::Relation { pair: p, secondary, .. } if p == pair && secondary == object)
        })
    }

    /// Whether the pair's primary is a robot part.
    fn robot_pair(&self, pair: usize) -> bool {
        self.pre.iter().any(|fact| {
            matches!(*fact, Fact::Relation { pair: p, primary, .. } if p == pair && self.is_robot(primary))
        })
    }

    /// Whether it puts the object into that very region of another.
    fn enters_region(&self, pair: usize, region: usize, object: usize) -> bool {
        self.added.iter().any(|fact| {
            matches!(*fact, Fact::Relation { pair: p, region: r, secondary, .. }
                if p == pair && r == region && secondary == object)
        })
    }

    /// Whether it puts something into that very region of the object.
    fn fills_region_of(&self, pair: usize, region: usize, object: usize) -> bool {
        self.added.iter().any(|fact| {
            matches!(*fact, Fact::Relation { pair: p, region: r, primary, .. }
                if p == pair && r == region && primary == object)
        })
    }

    /// Whether it changes how a robot part relates to the object: it comes to take it, takes
    /// it, lets go of it or leaves it.
    fn grasp_changes(&self, object: usize) -> bool {
        self.changes().any(|fact| {
            matches!(*fact, Fact::Relation { primary, secondary, .. }
                if secondary == object && self.is_robot(primary))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abstraction::tests::participants;
    use crate::config::TypePair;

    fn vocabulary() -> Vec<PairVocabulary> {
        vec![
            PairVocabulary {
                pair: TypePair::new("gripper", "can"),
                region_flags: vec![0, 1],
                clear: vec![true; 2],
                nowhere: vec![false; 2],
            },
            PairVocabulary {
                pair: TypePair::new("surface", "can"),
                region_flags: vec![0],
                clear: vec![false],
                nowhere: vec![false],
            },
        ]
    }

    fn with_surface() -> Vec<Participant> {
        let mut all = participants();
        all.push(Participant {
            name: "box".into(),
            type_name: "surface".into(),
            role: Role::Object { movable: false },
        });
        all
    }

    fn gripper_can(region: usize, can: usize) -> Fact {
        Fact::Relation { pair: 0, region, primary: 0, secondary: can }
    }

    fn surface_can(region: usize, can: usize) -> Fact {
        Fact::Relation { pair: 1, region, primary: 3, secondary: can }
    }

    fn clear(region: usize) -> Fact {
        Fact::Clear { pair: 0, region, object: 0 }
    }

    fn strings(atoms: &[LiftedAtom]) -> Vec<String> {
        atoms.iter().map(ToString::to_string).collect()
    }

    /// Gripper approaches c1 (g = 0 region 1), grasps it (region 2), carries it into the box; c2 stays away.
    fn pick_demo(first_can: usize, other_can: usize) -> Vec<BTreeSet<Fact>> {
        let state = |g_c: usize, in_box: usize| -> BTreeSet<Fact> {
            let mut facts = BTreeSet::from([
                gripper_can(g_c, first_can),
                gripper_can(0, other_can),
                surface_can(in_box, first_can),
                surface_can(0, other_can),
            ]);
            for region in 1..=2 {
                if g_c != region {
                    facts.insert(clear(region));
                }
            }
            facts
        };
        vec![state(0, 0), state(0, 0), state(1, 0), state(2, 0), state(2, 1), state(0, 1)]
    }

    #[test]
    fn transitions_cluster_by_lifted_change_and_effects_exclude_the_pair() {
        let participants = with_surface();
        let demos = [
            AbstractDemonstration {
                id: "one",
                participants: &participants,
                states: pick_demo(1, 2),
            },
            AbstractDemonstration {
                id: "two",
                participants: &participants,
                states: pick_demo(2, 1),
            },
        ];
        let actions = induce(&vocabulary(), &demos);
        // approach, grasp, place, release-and-retreat: the two demos (different cans) share every action.
        assert_eq!(actions.len(), 4);
        assert!(actions.iter().all(|a| a.transitions.len() == 2 && a.distinct_transitions == 2));
        let grasp = actions
            .iter()
            .find(|a| strings(&a.add).contains(&"(gripper_can_2 ?gripper_p1 ?can_p1)".to_string()))
            .expect("a grasp action");
        assert_eq!(
            strings(&grasp.delete),
            [
                "(clear_gripper_can_2 ?gripper_p1)",
                "(gripper_can_0 ?gripper_p1 ?can_p1)",
                "(gripper_can_1 ?gripper_p1 ?can_p1)"
            ]
        );
        assert_eq!(
            strings(&grasp.preconditions),
            ["(clear_gripper_can_2 ?gripper_p1)", "(gripper_can_1 ?gripper_p1 ?can_p1)"]
        );
        let place = actions
            .iter()
            .find(|a| strings(&a.add) == ["(surface_can_1 ?surface_p1 ?can_p1)"])
            .expect("a place action");
        // The gripper holding the can is an extra (a robot part linked to the changed can).
        assert!(
            strings(&place.preconditions)
                .contains(&"(gripper_can_2 ?gripper_extra_p1 ?can_p1)".to_string())
        );
        assert_eq!(
            place.parameters.iter().map(|p| p.name.as_str()).collect::<Vec<_>>(),
            ["?can_p1", "?gripper_extra_p1", "?surface_p1"]
        );
    }

    #[test]
    fn nowhere_atoms_are_kept_only_where_the_action_puts_the_object_into_that_region() {
        let participants = with_surface();
        let mut vocabulary = vocabulary();
        // A second surface region (beside the box, say) that no demonstration uses.
        vocabulary[1].region_flags = vec![0, 0];
        vocabulary[1].nowhere = vec![true; 2];
        // The can is in region 1 of no surface exactly when it is not in the box, and always in region 2 of none.
        let with_nowhere = |states: Vec<BTreeSet<Fact>>| -> Vec<BTreeSet<Fact>> {
            states
                .into_iter()
                .map(|mut facts| {
                    for can in [1, 2] {
                        if !facts.contains(&surface_can(1, can)) {
                            facts.insert(Fact::Nowhere { pair: 1, region: 1, object: can });
                        }
                        facts.insert(Fact::Nowhere { pair: 1, region: 2, object: can });
                    }
                    facts
                })
                .collect()
        };
        let demos = [AbstractDemonstration {
            id: "one",
            participants: &participants,
            states: with_nowhere(pick_demo(1, 2)),
        }];
        let actions = induce(&vocabulary, &demos);
        let place = actions
            .iter()
            .find(|a| strings(&a.add) == ["(surface_can_1 ?surface_p1 ?can_p1)"])
            .expect("a place action");
        assert!(strings(&place.preconditions).contains(&"(nowhere_surface_can_1 ?can_p1)".into()));
        assert!(strings(&place.delete).contains(&"(nowhere_surface_can_1 ?can_p1)".into()));
        // That the can was beside no surface is the demonstration's history, not the place's business.
        assert!(!strings(&place.preconditions).contains(&"(nowhere_surface_can_2 ?can_p1)".into()));
        // Approaching changes only the gripper–can pair: the can's nowhere atom is not its business.
        let approach = actions
            .iter()
            .find(|a| strings(&a.add).contains(&"(gripper_can_1 ?gripper_p1 ?can_p1)".to_string()))
            .expect("an approach action");
        assert!(!strings(&approach.preconditions).iter().any(|p| p.starts_with("(nowhere_")));
    }

    #[test]
    fn an_objects_clear_atom_is_kept_only_for_the_region_the_action_fills() {
        let participants = with_surface();
        let mut vocabulary = vocabulary();
        // The box has two places; the demonstration fills the first and the second stays empty throughout,
        // as the two blocks a third is laid across had nothing under them.
        vocabulary[1] = PairVocabulary {
            pair: TypePair::new("surface", "can"),
            region_flags: vec![0, 0],
            clear: vec![true; 2],
            nowhere: vec![false; 2],
        };
        let surface_clear = |region: usize| Fact::Clear { pair: 1, region, object: 3 };
        let states = pick_demo(1, 2)
            .into_iter()
            .map(|mut facts| {
                if !facts.contains(&surface_can(1, 1)) {
                    facts.insert(surface_clear(1));
                }
                facts.insert(surface_clear(2));
                facts
            })
            .collect();
        let demos = [AbstractDemonstration { id: "one", participants: &participants, states }];
        let actions = induce(&vocabulary, &demos);
        let place = actions
            .iter()
            .find(|a| strings(&a.add) == ["(surface_can_1 ?surface_p1 ?can_p1)"])
            .expect("a place action");
        let preconditions = strings(&place.preconditions);
        assert!(
            preconditions.contains(&"(clear_surface_can_1 ?surface_p1)".into()),
            "{preconditions:?}"
        );
        assert!(
            !preconditions.contains(&"(clear_surface_can_2 ?surface_p1)".into()),
            "{preconditions:?}"
        );
    }

    #[test]
    fn none_relation_to_a_static_extra_needs_an_earlier_change() {
        let participants = with_surface();
        let demos = [AbstractDemonstration {
            id: "one",
            participants: &participants,
            states: pick_demo(1, 2),
        }];
        let actions = induce(&vocabulary(), &demos);
        let approach = actions
            .iter()
            .find(|a| strings(&a.add).contains(&"(gripper_can_1 ?gripper_p1 ?can_p1)".to_string()))
            .expect("an approach action");
        // surface_can_0(box, can) held from the start and never became true, so it is not required.
        assert!(!strings(&approach.preconditions).iter().any(|p| p.starts_with("(surface_can_0")));
        let retreat = actions
            .iter()
            .find(|a| a.add.iter().any(|x| x.predicate == "gripper_can_0"))
            .expect("retreat");
        // surface_can_1 on the box extra is kept: it is a non-none relation.
        assert!(
            strings(&retreat.preconditions)
                .contains(&"(surface_can_1 ?surface_extra_p1 ?can_p1)".to_string())
        );
    }

    #[test]
    fn canonical_lifting_ignores_object_names() {
        // Two cans swap roles; the lifted key must not depend on which name sorts first.
        let participants = with_surface();
        let can_can =
            |a: usize, b: usize| Fact::Relation { pair: 0, region: 1, primary: a, secondary: b };
        let added_one = BTreeSet::from([can_can(0, 1), gripper_can(2, 2)]);
        let added_two = BTreeSet::from([can_can(0, 2), gripper_can(2, 1)]);
        let empty = BTreeSet::new();
        let key = |added: &BTreeSet<Fact>| {
            let transition =
                Transition { participants: &participants, pre: &empty, added, deleted: &empty };
            canonical_lifting(&vocabulary(), &transition).0
        };
        assert_eq!(key(&added_one), key(&added_two));
    }

    #[test]
    fn permutations_are_enumerated_in_order() {
        let mut order = vec![0, 1, 2];
        let mut seen = vec![order.clone()];
        while next_permutation(&mut order, &|x: &usize| *x) {
            seen.push(order.clone());
        }
        assert_eq!(seen.len(), 6);
        assert_eq!(seen[5], vec![2, 1, 0]);
    }
}
