//! Grounding with relaxed reachability.
//!
//! Actions are instantiated only for bindings whose positive preconditions are reachable in the
//! delete relaxation from the initial state; the reachable set is grown to a fixpoint by joining
//! each action's positive preconditions against it. Bindings respect parameter types (an object fits
//! a parameter when its type is the parameter's type or a subtype), equality constraints, and
//! negative preconditions on static predicates (which are exact: static atoms never change).
//! Atoms of static predicates are compiled away; a fluent atom that is never reachable is always
//! false, so negative conditions on it are dropped.

use std::cell::Cell;
use std::collections::{BTreeMap, HashSet};

use lamp_pddl::{Condition, Domain, Literal, Problem, Term};

use crate::PlannerError;
use crate::task::{FactId, GroundAtom, GroundTask, GroundingVerdict, Operator};

mod locks;
mod reachable;

use locks::GoalLocks;
use reachable::{ArgumentMask, Reachable, known_before, masked};

/// A ground atom over indices: the predicate index followed by the object indices.
type Key = Vec<u32>;

/// An argument of a lifted atom after name resolution.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Slot {
    Parameter(usize),
    Object(u32),
}

#[derive(Clone, Debug, PartialEq, Eq)]
struct LiftedAtom {
    predicate: u32,
    slots: Vec<Slot>,
}

#[derive(Debug)]
struct LiftedAction {
    name: String,
    /// For each parameter, the objects that fit its type, in object order.
    candidates: Vec<Vec<u32>>,
    positive: Vec<LiftedAtom>,
    /// For each positive precondition, in join order, the argument positions whose values are
    /// known when the join reaches it (constants, and parameters of the atoms before it): the
    /// key of the [`Reachable`] index it is looked up in.
    known_before: Vec<ArgumentMask>,
    negative: Vec<LiftedAtom>,
    /// `(left, right, must_be_equal)`.
    equalities: Vec<(Slot, Slot, bool)>,
    add: Vec<LiftedAtom>,
    delete: Vec<LiftedAtom>,
}

/// Names and indices shared by the whole grounding.
struct Universe {
    predicates: Vec<String>,
    is_static: Vec<bool>,
    objects: Vec<String>,
}

impl Universe {
    fn ground_atom(&self, key: &[u32]) -> GroundAtom {
        GroundAtom {
            predicate: self.predicates[key[0] as usize].clone(),
            arguments: key[1..]
                .iter()
                .map(|&object| self.objects[object as usize].clone())
                .collect(),
        }
    }
}

/// Grounds `problem` over `domain`. Both must pass `lamp_pddl`'s checks.
///
/// # Errors
/// [`PlannerError::InvalidInput`] when the model fails the checks, and
/// [`PlannerError::TooManyOperators`] when grounding would exceed `max_operators`.
pub fn ground(
    domain: &Domain,
    problem: &Problem,
    max_operators: usize,
) -> Result<GroundTask, PlannerError> {
    ground_until(domain, problem, max_operators, &|| false)
}

/// [`ground`] that gives up with [`PlannerError::Stopped`] once `stop` says so, polled every
/// [`STOP_CHECK_INTERVAL`] bindings.
///
/// # Errors
/// As [`ground`], and [`PlannerError::Stopped`].
pub fn ground_until(
    domain: &Domain,
    problem: &Problem,
    max_operators: usize,
    stop: &dyn Fn() -> bool,
) -> Result<GroundTask, PlannerError> {
    check_model(domain, problem)?;
    let poll = Poll { stop, bindings: Cell::new(0), stopped: Cell::new(false) };
    let names = Names::new(domain, problem);
    let actions = lift_actions(domain, &names);
    let initial: HashSet<Key> = problem.init.iter().map(|atom| names.key(atom)).collect();
    let goal_atoms: Vec<Key> = problem
        .goal
        .iter()
        .filter(|literal| literal.positive)
        .map(|literal| names.key(&literal.atom))
        .collect();
    let locks = GoalLocks::new(&actions, domain.predicates.len(), &goal_atoms, &initial);
    let grounding = Grounding { universe: &names.universe, initial: &initial, locks: &locks };

    let reachable = relaxed_reachability(domain, &actions, &initial, &grounding, &poll)?;
    let (facts, fact_of) = fluent_facts(&reachable, &names.universe);
    let mut operators =
        ground_operators(&actions, &reachable, &grounding, &fact_of, max_operators, &poll)?;
    // Stable sort: action position (enumeration order) then argument names.
    let position: BTreeMap<&str, usize> =
        domain.actions.iter().enumerate().map(|(i, a)| (a.name.as_str(), i)).collect();
    operators.sort_by(|a, b| {
        (position.get(a.action.as_str()), &a.arguments)
            .cmp(&(position.get(b.action.as_str()), &b.arguments))
    });

    let mut initial_facts: Vec<FactId> =
        initial.iter().filter_map(|key| fact_of.get(key).copied()).collect();
    initial_facts.sort_unstable();
    let (goal, negative_goal, verdict) = ground_goal(problem, &names, &initial, &fact_of);
    Ok(GroundTask { facts, operators, initial: initial_facts, goal, negative_goal, verdict })
}

/// Refuses a model that fails `lamp_pddl`'s checks.
fn check_model(domain: &Domain, problem: &Problem) -> Result<(), PlannerError> {
    let mut errors = lamp_pddl::check_domain(domain);
    if errors.is_empty() {
        errors = lamp_pddl::check_problem(domain, problem);
    }
    match errors.is_empty() {
        true => Ok(()),
        false => Err(PlannerError::InvalidInput(lamp_pddl::PddlErrors { errors })),
    }
}

/// Whether to go on enumerating bindings: asks `stop` every [`STOP_CHECK_INTERVAL`] of them.
struct Poll<'a> {
    stop: &'a dyn Fn() -> bool,
    bindings: Cell<u64>,
    stopped: Cell<bool>,
}

impl Poll<'_> {
    fn keep_going(&self) -> bool {
        self.bindings.set(self.bindings.get() + 1);
        if self.bindings.get().is_multiple_of(STOP_CHECK_INTERVAL) && (self.stop)() {
            self.stopped.set(true);
        }
        !self.stopped.get()
    }

    fn check(&self) -> Result<(), PlannerError> {
        match self.stopped.get() {
            true => Err(PlannerError::Stopped),
            false => Ok(()),
        }
    }
}

/// The objects (in name order: indices then sort like names, which fixes every later order) and
/// predicates of a model, by index.
struct Names<'m> {
    typed_objects: Vec<(&'m str, &'m str)>,
    object_index: BTreeMap<&'m str, u32>,
    predicate_index: BTreeMap<&'m str, u32>,
    universe: Universe,
}

impl<'m> Names<'m> {
    fn new(domain: &'m Domain, problem: &'m Problem) -> Names<'m> {
        let mut typed_objects: Vec<(&str, &str)> = domain
            .constants
            .iter()
            .chain(&problem.objects)
            .map(|o| (o.name.as_str(), o.type_name.as_str()))
            .collect();
        typed_objects.sort_unstable();
        let object_index: BTreeMap<&str, u32> =
            typed_objects.iter().zip(0_u32..).map(|((name, _), index)| (*name, index)).collect();

        let predicate_index: BTreeMap<&str, u32> = domain
            .predicates
            .iter()
            .zip(0_u32..)
            .map(|(p, index)| (p.name.as_str(), index))
            .collect();
        let mut is_static = vec![true; domain.predicates.len()];
        for action in &domain.actions {
            for atom in action.add.iter().chain(&action.delete) {
                if let Some(&index) = predicate_index.get(atom.predicate.as_str()) {
                    is_static[index as usize] = false;
                }
            }
        }
        let universe = Universe {
            predicates: domain.predicates.iter().map(|p| p.name.clone()).collect(),
            is_static,
            objects: typed_objects.iter().map(|(name, _)| (*name).to_owned()).collect(),
        };
        Names { typed_objects, object_index, predicate_index, universe }
    }

    fn predicate(&self, atom: &lamp_pddl::Atom) -> u32 {
        self.predicate_index.get(atom.predicate.as_str()).copied().unwrap_or(u32::MAX)
    }

    /// A ground atom's key.
    fn key(&self, atom: &lamp_pddl::Atom) -> Key {
        let mut key = vec![self.predicate(atom)];
        key.extend(
            atom.arguments
                .iter()
                .map(|term| self.object_index.get(term.name()).copied().unwrap_or(u32::MAX)),
        );
        key
    }

    /// An atom of an action's, its terms resolved against `parameters` and the objects.
    fn lifted(&self, atom: &lamp_pddl::Atom, parameters: &[lamp_pddl::Typed]) -> LiftedAtom {
        LiftedAtom {
            predicate: self.predicate(atom),
            slots: atom
                .arguments
                .iter()
                .map(|term| resolve(term, parameters, &self.object_index))
                .collect(),
        }
    }
}

/// The domain's actions over indices, their positive preconditions ordered for the join.
fn lift_actions(domain: &Domain, names: &Names<'_>) -> Vec<LiftedAction> {
    domain
        .actions
        .iter()
        .map(|action| {
            let mut lifted = LiftedAction {
                name: action.name.clone(),
                candidates: action
                    .parameters
                    .iter()
                    .map(|parameter| {
                        names
                            .typed_objects
                            .iter()
                            .zip(0_u32..)
                            .filter(|((_, type_name), _)| {
                                domain.is_subtype(type_name, &parameter.type_name)
                            })
                            .map(|(_, index)| index)
                            .collect()
                    })
                    .collect(),
                positive: Vec::new(),
                known_before: Vec::new(),
                negative: Vec::new(),
                equalities: Vec::new(),
                add: action.add.iter().map(|a| names.lifted(a, &action.parameters)).collect(),
                delete: action.delete.iter().map(|a| names.lifted(a, &action.parameters)).collect(),
            };
            for condition in &action.precondition {
                match condition {
                    Condition::Atom { atom, positive: true } => {
                        lifted.positive.push(names.lifted(atom, &action.parameters));
                    }
                    Condition::Atom { atom, positive: false } => {
                        lifted.negative.push(names.lifted(atom, &action.parameters));
                    }
                    Condition::Equality { left, right, positive, .. } => lifted.equalities.push((
                        resolve(left, &action.parameters, &names.object_index),
                        resolve(right, &action.parameters, &names.object_index),
                        *positive,
                    )),
                }
            }
            order_for_join(&mut lifted.positive);
            lifted.known_before = known_before(&lifted.positive);
            lifted
        })
        .collect()
}

/// Relaxed reachability to a fixpoint; the per-predicate lists keep insertion order.
fn relaxed_reachability(
    domain: &Domain,
    actions: &[LiftedAction],
    initial: &HashSet<Key>,
    grounding: &Grounding<'_>,
    poll: &Poll<'_>,
) -> Result<Reachable, PlannerError> {
    let mut reachable = Reachable::new(domain.predicates.len(), actions);
    let mut initial_sorted: Vec<Key> = initial.iter().cloned().collect();
    initial_sorted.sort_unstable();
    for key in initial_sorted {
        reachable.insert(key);
    }
    loop {
        let mut new_atoms = Vec::new();
        for (index, action) in actions.iter().enumerate() {
            enumerate(index, action, &reachable, grounding, &mut |binding| {
                for atom in &action.add {
                    let key = instantiate(atom, binding);
                    if !reachable.contains(&key) {
                        new_atoms.push(key);
                    }
                }
                poll.keep_going()
            });
        }
        poll.check()?;
        if new_atoms.is_empty() {
            return Ok(reachable);
        }
        for key in new_atoms {
            reachable.insert(key);
        }
    }
}

/// Facts: reachable fluent atoms, in (predicate name, argument names) order, and each one's id.
fn fluent_facts(
    reachable: &Reachable,
    universe: &Universe,
) -> (Vec<GroundAtom>, std::collections::HashMap<Key, FactId>) {
    let mut fact_keys: Vec<Key> =
        reachable.all.iter().filter(|key| !universe.is_static[key[0] as usize]).cloned().collect();
    let mut facts: Vec<GroundAtom> =
        fact_keys.iter().map(|key| universe.ground_atom(key)).collect();
    let mut order: Vec<usize> = (0..facts.len()).collect();
    order.sort_by(|&a, &b| facts[a].cmp(&facts[b]));
    fact_keys = order.iter().map(|&i| fact_keys[i].clone()).collect();
    facts = order.iter().map(|&i| facts[i].clone()).collect();
    let fact_of = fact_keys.into_iter().zip(0_u32..).collect();
    (facts, fact_of)
}

/// The operators of every binding reachable in the relaxation, in enumeration order.
fn ground_operators(
    actions: &[LiftedAction],
    reachable: &Reachable,
    grounding: &Grounding<'_>,
    fact_of: &std::collections::HashMap<Key, FactId>,
    max_operators: usize,
    poll: &Poll<'_>,
) -> Result<Vec<Operator>, PlannerError> {
    let universe = grounding.universe;
    let mut operators = Vec::new();
    let mut too_many = false;
    for (index, action) in actions.iter().enumerate() {
        enumerate(index, action, reachable, grounding, &mut |binding| {
            if operators.len() >= max_operators {
                too_many = true;
                return false;
            }
            let facts_of = |atoms: &[LiftedAtom]| -> Vec<FactId> {
                let mut ids: Vec<FactId> = atoms
                    .iter()
                    .filter(|atom| !universe.is_static[atom.predicate as usize])
                    .filter_map(|atom| fact_of.get(&instantiate(atom, binding)).copied())
                    .collect();
                ids.sort_unstable();
                ids.dedup();
                ids
            };
            operators.push(Operator {
                action: action.name.clone(),
                arguments: binding.iter().map(|&o| universe.objects[o as usize].clone()).collect(),
                precondition: facts_of(&action.positive),
                negative_precondition: facts_of(&action.negative),
                add: facts_of(&action.add),
                delete: facts_of(&action.delete),
            });
            poll.keep_going()
        });
        if too_many {
            return Err(PlannerError::TooManyOperators { limit: max_operators });
        }
        poll.check()?;
    }
    Ok(operators)
}

/// The goal's positive and negative facts, and whether a goal literal can never hold.
fn ground_goal(
    problem: &Problem,
    names: &Names<'_>,
    initial: &HashSet<Key>,
    fact_of: &std::collections::HashMap<Key, FactId>,
) -> (Vec<FactId>, Vec<FactId>, GroundingVerdict) {
    let mut verdict = GroundingVerdict::Open;
    let mut goal = Vec::new();
    let mut negative_goal = Vec::new();
    for literal in &problem.goal {
        let key = names.key(&literal.atom);
        let is_static = names.universe.is_static[key[0] as usize];
        let unreachable = match (literal.positive, is_static) {
            (true, true) => !initial.contains(&key),
            (false, true) => initial.contains(&key),
            (true, false) => match fact_of.get(&key) {
                Some(&fact) => {
                    goal.push(fact);
                    false
                }
                None => true,
            },
            (false, false) => {
                if let Some(&fact) = fact_of.get(&key) {
                    negative_goal.push(fact);
                }
                false
            }
        };
        if unreachable && verdict == GroundingVerdict::Open {
            verdict = GroundingVerdict::GoalUnreachable { literal: literal_text(literal) };
        }
    }
    goal.sort_unstable();
    goal.dedup();
    negative_goal.sort_unstable();
    negative_goal.dedup();
    (goal, negative_goal, verdict)
}

fn literal_text(literal: &Literal) -> String {
    let atom = lamp_pddl::atom_text(&literal.atom);
    if literal.positive { atom } else { format!("(not {atom})") }
}

fn resolve(term: &Term, parameters: &[lamp_pddl::Typed], objects: &BTreeMap<&str, u32>) -> Slot {
    match term {
        Term::Variable(name) => {
            Slot::Parameter(parameters.iter().position(|p| &p.name == name).unwrap_or(usize::MAX))
        }
        Term::Constant(name) => {
            Slot::Object(objects.get(name.as_str()).copied().unwrap_or(u32::MAX))
        }
    }
}

/// Orders positive preconditions so that each atom binds as few new parameters as possible given
/// the ones before it (ties keep the written order); joins then filter early.
fn order_for_join(atoms: &mut Vec<LiftedAtom>) {
    let mut remaining = std::mem::take(atoms);
    let mut bound: HashSet<usize> = HashSet::new();
    while !remaining.is_empty() {
        let new_parameters = |atom: &LiftedAtom| {
            let mut new: Vec<usize> = atom
                .slots
                .iter()
                .filter_map(|slot| match slot {
                    Slot::Parameter(index) if !bound.contains(index) => Some(*index),
                    _ => None,
                })
                .collect();
            new.sort_unstable();
            new.dedup();
            new.len()
        };
        let best = (0..remaining.len()).min_by_key(|&i| new_parameters(&remaining[i])).unwrap_or(0);
        let atom = remaining.remove(best);
        for slot in &atom.slots {
            if let Slot::Parameter(index) = slot {
                bound.insert(*index);
            }
        }
        atoms.push(atom);
    }
}

fn instantiate(atom: &LiftedAtom, binding: &[u32]) -> Key {
    let mut key = Vec::with_capacity(atom.slots.len() + 1);
    key.push(atom.predicate);
    key.extend(atom.slots.iter().map(|slot| slot_value(*slot, binding)));
    key
}

fn slot_value(slot: Slot, binding: &[u32]) -> u32 {
    match slot {
        Slot::Parameter(index) => binding.get(index).copied().unwrap_or(UNBOUND),
        Slot::Object(object) => object,
    }
}

const UNBOUND: u32 = u32::MAX;

/// How often (in bindings enumerated) grounding asks whether to stop: a binding takes
/// microseconds, so a stop request is seen within milliseconds.
const STOP_CHECK_INTERVAL: u64 = 1024;

/// What every binding is checked against besides reachability.
struct Grounding<'g> {
    universe: &'g Universe,
    initial: &'g HashSet<Key>,
    locks: &'g GoalLocks,
}

/// Calls `visit` with every binding of `action`'s parameters (the domain's action at `index`)
/// whose positive preconditions are in `reachable`, whose equality and static negative conditions
/// hold, and which loses no goal for good ([`GoalLocks`]). `visit` returns `false` to stop early.
fn enumerate(
    index: usize,
    action: &LiftedAction,
    reachable: &Reachable,
    grounding: &Grounding<'_>,
    visit: &mut dyn FnMut(&[u32]) -> bool,
) {
    let mut binding = vec![UNBOUND; action.candidates.len()];
    let mut join = Join { index, action, reachable, grounding, visit };
    join.join(0, &mut binding);
}

/// The enumeration of one action's bindings.
struct Join<'j, 'g> {
    index: usize,
    action: &'j LiftedAction,
    reachable: &'j Reachable,
    grounding: &'j Grounding<'g>,
    visit: &'j mut dyn FnMut(&[u32]) -> bool,
}

impl Join<'_, '_> {
    /// Whether no binding extending `binding` is to be visited.
    fn excluded(&self, binding: &[u32]) -> bool {
        !equalities_hold(self.action, binding)
            || self.grounding.locks.prunes(self.index, self.action, binding)
    }

    fn join(&mut self, depth: usize, binding: &mut Vec<u32>) -> bool {
        let action = self.action;
        if self.excluded(binding) {
            return true;
        }
        let Some(atom) = action.positive.get(depth) else {
            return self.bind_rest(0, binding);
        };
        let reachable = self.reachable;
        let mask = action.known_before.get(depth).copied().unwrap_or(0);
        let values = masked(mask, atom.slots.iter().map(|slot| slot_value(*slot, binding)));
        if let Some(positions) = reachable.lookup(atom.predicate, mask, &values) {
            for &position in positions {
                if !self.join_atom(depth, atom, &reachable.all[position], binding) {
                    return false;
                }
            }
            return true;
        }
        let Some(candidates) = reachable.by_predicate.get(atom.predicate as usize) else {
            return true;
        };
        for key in candidates {
            if !self.join_atom(depth, atom, key, binding) {
                return false;
            }
        }
        true
    }

    /// Joins `key`, an atom of the predicate of `atom` (the positive precondition at `depth`),
    /// then the preconditions after it; whether to go on.
    fn join_atom(
        &mut self,
        depth: usize,
        atom: &LiftedAtom,
        key: &[u32],
        binding: &mut Vec<u32>,
    ) -> bool {
        let action = self.action;
        let mut newly_bound = Vec::new();
        let mut consistent = true;
        for (slot, &value) in atom.slots.iter().zip(&key[1..]) {
            match *slot {
                Slot::Object(object) => consistent &= object == value,
                Slot::Parameter(index) => match binding.get(index).copied() {
                    Some(UNBOUND) => {
                        if action.candidates[index].binary_search(&value).is_ok() {
                            binding[index] = value;
                            newly_bound.push(index);
                        } else {
                            consistent = false;
                        }
                    }
                    Some(bound) => consistent &= bound == value,
                    None => consistent = false,
                },
            }
            if !consistent {
                break;
            }
        }
        let keep_going = !consistent || self.join(depth + 1, binding);
        for index in newly_bound {
            binding[index] = UNBOUND;
        }
        keep_going
    }

    /// Binds parameters that no positive precondition mentions, over their typed candidates.
    fn bind_rest(&mut self, from: usize, binding: &mut Vec<u32>) -> bool {
        let action = self.action;
        let Some(index) = (from..binding.len()).find(|&i| binding[i] == UNBOUND) else {
            let Grounding { universe, initial, .. } = self.grounding;
            let static_negatives_hold = action
                .negative
                .iter()
                .filter(|atom| universe.is_static[atom.predicate as usize])
                .all(|atom| !initial.contains(&instantiate(atom, binding)));
            return if static_negatives_hold && !self.excluded(binding) {
                (self.visit)(binding)
            } else {
                true
            };
        };
        for position in 0..action.candidates[index].len() {
            binding[index] = action.candidates[index][position];
            let keep_going = self.excluded(binding) || self.bind_rest(index + 1, binding);
            if !keep_going {
                binding[index] = UNBOUND;
                return false;
            }
        }
        binding[index] = UNBOUND;
        true
    }
}

/// Whether every equality constraint whose two sides are bound holds.
fn equalities_hold(action: &LiftedAction, binding: &[u32]) -> bool {
    action.equalities.iter().all(|&(left, right, equal)| {
        let (left, right) = (slot_value(left, binding), slot_value(right, binding));
        left == UNBOUND || right == UNBOUND || (left == right) == equal
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every action's bindings over the relaxation's atoms, in the order a join visits them,
    /// with the atoms looked up in the joins' indexes or, without them, found by scanning.
    fn bindings_in_order(domain: &str, problem: &str, indexed: bool) -> Vec<(usize, Vec<u32>)> {
        let fixture = |name: &str| {
            let path = format!("{}/tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"));
            std::fs::read_to_string(&path).unwrap_or_else(|error| panic!("{path}: {error}"))
        };
        let domain = lamp_pddl::parse_domain(&fixture(domain)).expect("domain parses");
        let problem = lamp_pddl::parse_problem(&fixture(problem), &domain).expect("parses");
        let names = Names::new(&domain, &problem);
        let actions = lift_actions(&domain, &names);
        let initial: HashSet<Key> = problem.init.iter().map(|atom| names.key(atom)).collect();
        let locks = GoalLocks::new(&actions, domain.predicates.len(), &[], &initial);
        let grounding = Grounding { universe: &names.universe, initial: &initial, locks: &locks };
        let poll = Poll { stop: &|| false, bindings: Cell::new(0), stopped: Cell::new(false) };
        let reachable = relaxed_reachability(&domain, &actions, &initial, &grounding, &poll)
            .expect("not stopped");
        let mut atoms =
            Reachable::new(domain.predicates.len(), if indexed { &actions } else { &[] });
        for key in &reachable.all {
            atoms.insert(key.clone());
        }
        let mut visited = Vec::new();
        for (index, action) in actions.iter().enumerate() {
            enumerate(index, action, &atoms, &grounding, &mut |binding| {
                visited.push((index, binding.to_vec()));
                true
            });
        }
        visited
    }

    #[test]
    fn a_join_through_the_indexes_visits_the_bindings_a_scan_visits_in_its_order() {
        for (domain, problem) in [
            ("cafe-learned-domain.pddl", "cafe-learned-18.pddl"),
            ("blocksworld-domain.pddl", "blocksworld-reverse5.pddl"),
            ("gripper-domain.pddl", "gripper-20.pddl"),
        ] {
            let scanned = bindings_in_order(domain, problem, false);
            assert!(scanned.len() > 20, "{problem}: {} bindings", scanned.len());
            assert_eq!(bindings_in_order(domain, problem, true), scanned, "{problem}");
        }
    }
}
