//! Packed states (one bit per fact) and the registry that numbers them.

use std::collections::HashMap;

use crate::task::{FactId, GroundTask, Operator};

/// Index of a state in a [`StateRegistry`].
pub type StateId = u32;

const BITS: usize = 64;

/// A set of true facts, one bit each.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct State {
    words: Box<[u64]>,
}

impl State {
    /// The state in which exactly `facts` hold.
    #[must_use]
    pub fn from_facts(fact_count: usize, facts: &[FactId]) -> Self {
        let mut words = vec![0_u64; fact_count.div_ceil(BITS)].into_boxed_slice();
        for &fact in facts {
            let fact = fact as usize;
            words[fact / BITS] |= 1 << (fact % BITS);
        }
        Self { words }
    }

    /// Whether `fact` holds.
    #[must_use]
    pub fn holds(&self, fact: FactId) -> bool {
        let fact = fact as usize;
        self.words.get(fact / BITS).is_some_and(|word| word & (1 << (fact % BITS)) != 0)
    }

    fn set(&mut self, fact: FactId, value: bool) {
        let fact = fact as usize;
        if let Some(word) = self.words.get_mut(fact / BITS) {
            if value {
                *word |= 1 << (fact % BITS);
            } else {
                *word &= !(1 << (fact % BITS));
            }
        }
    }

    /// Whether `operator` is applicable here.
    #[must_use]
    pub fn applicable(&self, operator: &Operator) -> bool {
        operator.precondition.iter().all(|&fact| self.holds(fact))
            && !operator.negative_precondition.iter().any(|&fact| self.holds(fact))
    }

    /// The state after `operator` (deletes first, then adds, as PDDL prescribes).
    #[must_use]
    pub fn apply(&self, operator: &Operator) -> Self {
        let mut next = self.clone();
        for &fact in &operator.delete {
            next.set(fact, false);
        }
        for &fact in &operator.add {
            next.set(fact, true);
        }
        next
    }

    /// Whether the goal of `task` holds.
    #[must_use]
    pub fn satisfies_goal(&self, task: &GroundTask) -> bool {
        task.goal.iter().all(|&fact| self.holds(fact))
            && !task.negative_goal.iter().any(|&fact| self.holds(fact))
    }

    /// The true facts in increasing order.
    #[must_use]
    pub fn facts(&self) -> Vec<FactId> {
        let mut facts = Vec::new();
        for (index, &word) in self.words.iter().enumerate() {
            let mut remaining = word;
            while remaining != 0 {
                let bit = remaining.trailing_zeros() as usize;
                facts.push(u32::try_from(index * BITS + bit).unwrap_or(u32::MAX));
                remaining &= remaining - 1;
            }
        }
        facts
    }
}

/// Numbers distinct states in order of first registration. The map is used for lookups only, so
/// its iteration order never reaches an output.
#[derive(Debug, Default)]
pub struct StateRegistry {
    states: Vec<State>,
    ids: HashMap<State, StateId>,
}

impl StateRegistry {
    /// The id of `state`, registering it if new.
    pub fn insert(&mut self, state: State) -> StateId {
        if let Some(&id) = self.ids.get(&state) {
            return id;
        }
        let id =
            StateId::try_from(self.states.len()).expect("fewer than 2^32 states are registered");
        self.states.push(state.clone());
        self.ids.insert(state, id);
        id
    }

    /// The state with `id`.
    ///
    /// # Panics
    /// If `id` was not returned by this registry.
    #[must_use]
    pub fn get(&self, id: StateId) -> &State {
        &self.states[id as usize]
    }

    /// Number of registered states.
    #[must_use]
    pub fn len(&self) -> usize {
        self.states.len()
    }

    /// Whether no state is registered.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.states.is_empty()
    }
}
