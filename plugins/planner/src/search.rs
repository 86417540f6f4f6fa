//! Lazy greedy best-first search with FF and preferred operators, over states paired with a
//! position in a trie of forbidden plans.
//!
//! The search follows Fast Downward's `lazy_greedy([hff], preferred=[hff])`: successors are queued
//! with their parent's heuristic value and evaluated only when popped; there are two queues, one
//! with every successor and one with the successors reached by preferred operators, taken in
//! alternation (the queue taken fewer times goes next; ties go to the full queue), and every time
//! the search reaches a new lowest heuristic value the preferred queue gains [`PREFERRED_BOOST`]
//! turns. Within a queue, entries with equal value leave in insertion order (FIFO), and successors
//! are inserted in operator-id order, so the search is fully deterministic.
//!
//! A node is a dead end without evaluating FF when a goal literal is lost for good
//! ([`LostGoals`]), which is much cheaper and proves the same.
//!
//! The trie holds plans that must not be returned again (for top-k). A search node is a state and
//! either a trie node (the path so far equals a forbidden plan's prefix) or the trie node where the
//! path left the trie. A path may not revisit a state, so every plan returned is loop-free, and a
//! goal state ends the search only where the path is not exactly a forbidden plan. With an empty
//! trie this is plain greedy best-first search with duplicate detection.

use std::cmp::Reverse;
use std::collections::{BTreeMap, BinaryHeap, HashSet};
use std::time::Instant;

use crate::Budget;
use crate::heuristic::{Estimate, FfHeuristic};
use crate::lost_goals::LostGoals;
use crate::state::{State, StateId, StateRegistry};
use crate::successors::Successors;
use crate::task::{GroundTask, OperatorId};

/// Turns the preferred queue gains each time the search makes heuristic progress (as in Fast
/// Downward's alternation open list).
pub const PREFERRED_BOOST: i64 = 1000;

/// How often (in evaluations) the wall-clock limit and the stop request are checked.
const CLOCK_CHECK_INTERVAL: u64 = 256;

/// Counters of one or more searches.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Statistics {
    /// Search nodes evaluated (each costs one heuristic computation unless cached).
    pub expanded: u64,
    /// Queue entries created.
    pub generated: u64,
    /// Evaluated nodes recognised as dead ends.
    pub dead_ends: u64,
    /// Distinct states seen.
    pub states: u64,
}

/// How one search ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SearchEnd {
    /// A plan, as operator ids.
    Found(Vec<OperatorId>),
    /// Every reachable search node was expanded without reaching an allowed goal.
    Exhausted,
    /// The budget ran out.
    OutOfBudget,
}

type TrieId = u32;

#[derive(Debug)]
struct TrieNode {
    parent: Option<TrieId>,
    state: StateId,
    children: BTreeMap<OperatorId, TrieId>,
    /// A forbidden plan ends here.
    terminal: bool,
}

/// Where a search node stands relative to the trie of forbidden plans.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Place {
    /// The path so far is exactly the prefix ending at this trie node.
    OnTrie(TrieId),
    /// The path left the trie after this trie node.
    Left(TrieId),
}

#[derive(Debug)]
struct Node {
    state: StateId,
    place: Place,
    parent: Option<(u32, OperatorId)>,
}

/// State registry, heuristic cache and forbidden-plan trie shared by successive searches.
#[derive(Debug)]
pub struct SearchSpace<'a> {
    task: &'a GroundTask,
    registry: StateRegistry,
    heuristic: FfHeuristic,
    lost_goals: LostGoals,
    successors: Successors,
    estimates: Vec<Option<Estimate>>,
    trie: Vec<TrieNode>,
    initial: StateId,
    statistics: Statistics,
    started: Instant,
}

impl<'a> SearchSpace<'a> {
    /// A space for `task` with an empty trie.
    #[must_use]
    pub fn new(task: &'a GroundTask) -> Self {
        let mut registry = StateRegistry::default();
        let initial = registry.insert(State::from_facts(task.fact_count(), &task.initial));
        Self {
            task,
            registry,
            heuristic: FfHeuristic::new(task),
            lost_goals: LostGoals::new(task),
            successors: Successors::new(task),
            estimates: Vec::new(),
            trie: vec![TrieNode {
                parent: None,
                state: initial,
                children: BTreeMap::new(),
                terminal: false,
            }],
            initial,
            statistics: Statistics::default(),
            started: Instant::now(),
        }
    }

    /// Counters accumulated over every search in this space.
    #[must_use]
    pub fn statistics(&self) -> Statistics {
        Statistics { states: self.registry.len() as u64, ..self.statistics }
    }

    /// Forbids `plan` (assumed applicable from the initial state) in later searches.
    pub fn forbid(&mut self, plan: &[OperatorId]) {
        let mut node: TrieId = 0;
        let mut state = self.registry.get(self.initial).clone();
        for &operator in plan {
            state = state.apply(&self.task.operators[operator as usize]);
            node = match self.trie[node as usize].children.get(&operator) {
                Some(&child) => child,
                None => {
                    let child = TrieId::try_from(self.trie.len()).unwrap_or(TrieId::MAX);
                    let state_id = self.registry.insert(state.clone());
                    self.trie.push(TrieNode {
                        parent: Some(node),
                        state: state_id,
                        children: BTreeMap::new(),
                        terminal: false,
                    });
                    self.trie[node as usize].children.insert(operator, child);
                    child
                }
            };
        }
        self.trie[node as usize].terminal = true;
    }

    fn estimate(&mut self, state: StateId) -> Estimate {
        let index = state as usize;
        if self.estimates.len() <= index {
            self.estimates.resize(index + 1, None);
        }
        if let Some(estimate) = &self.estimates[index] {
            return estimate.clone();
        }
        let current = self.registry.get(state);
        let estimate = if self.lost_goals.any_lost(current) {
            Estimate::DeadEnd
        } else {
            self.heuristic.evaluate(self.task, current)
        };
        self.estimates[index] = Some(estimate.clone());
        estimate
    }

    /// Whether `state` lies on the trie path from the root to `node`.
    fn on_prefix(&self, node: TrieId, state: StateId) -> bool {
        let mut current = Some(node);
        while let Some(id) = current {
            let trie_node = &self.trie[id as usize];
            if trie_node.state == state {
                return true;
            }
            current = trie_node.parent;
        }
        false
    }

    /// Where the path stands after applying `operator` at `place` to reach `state`, or `None` when
    /// the step would revisit a state of the path's trie prefix.
    fn step(&self, place: Place, operator: OperatorId, state: StateId) -> Option<Place> {
        match place {
            Place::OnTrie(node) => match self.trie[node as usize].children.get(&operator) {
                Some(&child) => Some(Place::OnTrie(child)),
                None => (!self.on_prefix(node, state)).then_some(Place::Left(node)),
            },
            Place::Left(node) => (!self.on_prefix(node, state)).then_some(place),
        }
    }

    fn goal_allowed(&self, place: Place) -> bool {
        match place {
            Place::OnTrie(node) => !self.trie[node as usize].terminal,
            Place::Left(_) => true,
        }
    }

    fn budget_exhausted(&self, budget: &Budget, stop: &dyn Fn() -> bool) -> bool {
        if budget.max_expansions.is_some_and(|limit| self.statistics.expanded >= limit) {
            return true;
        }
        self.statistics.expanded.is_multiple_of(CLOCK_CHECK_INTERVAL)
            && (budget.time_limit.is_some_and(|limit| self.started.elapsed() >= limit) || stop())
    }

    /// Runs one lazy GBFS from the initial state. The budget counts over every search in this space.
    pub fn search(&mut self, budget: &Budget) -> SearchEnd {
        self.search_until(budget, &|| false)
    }

    /// [`search`](Self::search) that also ends, as out of budget, once `stop` says so (polled
    /// with the clock, every few hundred evaluations): a cancelled run.
    pub fn search_until(&mut self, budget: &Budget, stop: &dyn Fn() -> bool) -> SearchEnd {
        let mut nodes: Vec<Node> = Vec::new();
        let mut closed: HashSet<(StateId, Place)> = HashSet::new();
        let mut queues = Queues::default();
        let mut best = u32::MAX;
        let mut pending = Some(Node { state: self.initial, place: Place::OnTrie(0), parent: None });
        loop {
            if let Some(node) = pending.take() {
                if self.budget_exhausted(budget, stop) {
                    return SearchEnd::OutOfBudget;
                }
                if closed.insert((node.state, node.place)) {
                    let id = u32::try_from(nodes.len()).expect("fewer than 2^32 search nodes");
                    let (state, place) = (node.state, node.place);
                    nodes.push(node);
                    self.statistics.expanded += 1;
                    if self.registry.get(state).satisfies_goal(self.task)
                        && self.goal_allowed(place)
                    {
                        return SearchEnd::Found(extract(&nodes, id));
                    }
                    self.expand(id, state, &mut queues, &mut best);
                }
            }
            let Some((parent, operator)) = queues.pop() else {
                return SearchEnd::Exhausted;
            };
            let parent_node = &nodes[parent as usize];
            let successor =
                self.registry.get(parent_node.state).apply(&self.task.operators[operator as usize]);
            let parent_place = parent_node.place;
            let state = self.registry.insert(successor);
            if let Some(place) = self.step(parent_place, operator, state) {
                pending = Some(Node { state, place, parent: Some((parent, operator)) });
            }
        }
    }

    /// Evaluates node `id` and queues its successors (lazily, with the node's own value).
    fn expand(&mut self, id: u32, state: StateId, queues: &mut Queues, best: &mut u32) {
        match self.estimate(state) {
            Estimate::DeadEnd => self.statistics.dead_ends += 1,
            Estimate::Value { distance, preferred } => {
                if distance < *best {
                    *best = distance;
                    queues.boost_preferred();
                }
                let current = self.registry.get(state);
                for operator in self.successors.applicable(self.task, current) {
                    let is_preferred = preferred.binary_search(&operator).is_ok();
                    queues.push(distance, id, operator, is_preferred);
                    self.statistics.generated += 1;
                }
            }
        }
    }
}

/// A queued successor: (parent's heuristic value, insertion number, parent node, operator). The
/// insertion number makes equal values leave first-in first-out.
type Entry = Reverse<(u32, u64, u32, OperatorId)>;

/// The two alternating queues: index 0 holds every successor, index 1 the preferred ones.
#[derive(Default)]
struct Queues {
    heaps: [BinaryHeap<Entry>; 2],
    turns: [i64; 2],
    inserted: u64,
}

impl Queues {
    fn push(&mut self, value: u32, parent: u32, operator: OperatorId, preferred: bool) {
        self.heaps[0].push(Reverse((value, self.inserted, parent, operator)));
        self.inserted += 1;
        if preferred {
            self.heaps[1].push(Reverse((value, self.inserted, parent, operator)));
            self.inserted += 1;
        }
    }

    fn boost_preferred(&mut self) {
        self.turns[1] -= PREFERRED_BOOST;
    }

    /// Takes from the queue with fewer turns (the full queue on ties), skipping empty ones.
    fn pop(&mut self) -> Option<(u32, OperatorId)> {
        let order = if self.turns[1] < self.turns[0] { [1, 0] } else { [0, 1] };
        let choice = order.into_iter().find(|&index| !self.heaps[index].is_empty())?;
        self.turns[choice] += 1;
        self.heaps[choice].pop().map(|Reverse((_, _, parent, operator))| (parent, operator))
    }
}

fn extract(nodes: &[Node], mut id: u32) -> Vec<OperatorId> {
    let mut plan = Vec::new();
    while let Some((parent, operator)) = nodes[id as usize].parent {
        plan.push(operator);
        id = parent;
    }
    plan.reverse();
    plan
}
