//! The FF heuristic: a relaxed plan extracted from h_add best supporters (unit action costs), and
//! the preferred operators it suggests.
//!
//! The delete relaxation ignores delete effects and negative conditions. Costs are propagated with
//! a Dijkstra-style exploration (a heap ordered by (cost, fact id)); a fact's best supporter is the
//! first operator to reach it at its final cost, operators considered in id order. The relaxed plan
//! is the set of best supporters needed for the goal; h_FF is its size. Preferred operators are the
//! relaxed plan's operators applicable in the evaluated state. A goal fact unreachable in the
//! relaxation proves a dead end.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::state::State;
use crate::task::{FactId, GroundTask, OperatorId};

const UNREACHED: u32 = u32::MAX;
const NO_SUPPORTER: OperatorId = OperatorId::MAX;

/// The value of the heuristic in one state.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Estimate {
    /// No plan exists from this state (its relaxation cannot reach the goal).
    DeadEnd,
    /// Relaxed plan length (at least 1 when the state is not a goal state) and preferred operators
    /// in increasing id order.
    Value { distance: u32, preferred: Vec<OperatorId> },
}

/// Reusable scratch space for FF evaluations on one task.
#[derive(Debug)]
pub struct FfHeuristic {
    precondition_of: Vec<Vec<OperatorId>>,
    precondition_count: Vec<u32>,
    no_precondition: Vec<OperatorId>,
    fact_cost: Vec<u32>,
    supporter: Vec<OperatorId>,
    unsatisfied: Vec<u32>,
    operator_cost: Vec<u32>,
    marked_fact: Vec<bool>,
    marked_operator: Vec<bool>,
    heap: BinaryHeap<Reverse<(u32, FactId)>>,
}

impl FfHeuristic {
    /// Precomputes the operator indices of `task`.
    #[must_use]
    pub fn new(task: &GroundTask) -> Self {
        let mut precondition_of = vec![Vec::new(); task.facts.len()];
        let mut no_precondition = Vec::new();
        for (id, operator) in (0_u32..).zip(&task.operators) {
            for &fact in &operator.precondition {
                precondition_of[fact as usize].push(id);
            }
            if operator.precondition.is_empty() {
                no_precondition.push(id);
            }
        }
        let operators = task.operators.len();
        Self {
            precondition_of,
            precondition_count: task
                .operators
                .iter()
                .map(|o| u32::try_from(o.precondition.len()).unwrap_or(u32::MAX))
                .collect(),
            no_precondition,
            fact_cost: vec![UNREACHED; task.facts.len()],
            supporter: vec![NO_SUPPORTER; task.facts.len()],
            unsatisfied: vec![0; operators],
            operator_cost: vec![0; operators],
            marked_fact: vec![false; task.facts.len()],
            marked_operator: vec![false; operators],
            heap: BinaryHeap::new(),
        }
    }

    /// Evaluates `state`.
    pub fn evaluate(&mut self, task: &GroundTask, state: &State) -> Estimate {
        if state.satisfies_goal(task) {
            return Estimate::Value { distance: 0, preferred: Vec::new() };
        }
        self.explore(task, state);
        if task.goal.iter().any(|&fact| self.fact_cost[fact as usize] == UNREACHED) {
            return Estimate::DeadEnd;
        }
        self.marked_fact.fill(false);
        self.marked_operator.fill(false);
        let mut relaxed_plan = Vec::new();
        let mut stack: Vec<FactId> = task.goal.clone();
        while let Some(fact) = stack.pop() {
            let index = fact as usize;
            if self.marked_fact[index] {
                continue;
            }
            self.marked_fact[index] = true;
            let operator = self.supporter[index];
            if operator == NO_SUPPORTER || self.marked_operator[operator as usize] {
                continue;
            }
            self.marked_operator[operator as usize] = true;
            relaxed_plan.push(operator);
            stack.extend(task.operators[operator as usize].precondition.iter().copied());
        }
        relaxed_plan.sort_unstable();
        let preferred = relaxed_plan
            .iter()
            .copied()
            .filter(|&operator| state.applicable(&task.operators[operator as usize]))
            .collect();
        // Negative goals are invisible to the relaxation; a non-goal state still needs a step.
        let distance = u32::try_from(relaxed_plan.len()).unwrap_or(u32::MAX).max(1);
        Estimate::Value { distance, preferred }
    }

    fn explore(&mut self, task: &GroundTask, state: &State) {
        self.fact_cost.fill(UNREACHED);
        self.supporter.fill(NO_SUPPORTER);
        self.unsatisfied.copy_from_slice(&self.precondition_count);
        self.operator_cost.fill(0);
        self.heap.clear();
        for fact in state.facts() {
            self.fact_cost[fact as usize] = 0;
            self.heap.push(Reverse((0, fact)));
        }
        for index in 0..self.no_precondition.len() {
            let operator = self.no_precondition[index];
            self.reach_effects(task, operator, 1);
        }
        let mut goals_left = task.goal.len();
        while let Some(Reverse((cost, fact))) = self.heap.pop() {
            if cost > self.fact_cost[fact as usize] {
                continue;
            }
            if task.goal.binary_search(&fact).is_ok() {
                goals_left -= 1;
                if goals_left == 0 {
                    break;
                }
            }
            for position in 0..self.precondition_of[fact as usize].len() {
                let operator = self.precondition_of[fact as usize][position];
                let index = operator as usize;
                self.operator_cost[index] = self.operator_cost[index].saturating_add(cost);
                self.unsatisfied[index] -= 1;
                if self.unsatisfied[index] == 0 {
                    let reached = self.operator_cost[index].saturating_add(1);
                    self.reach_effects(task, operator, reached);
                }
            }
        }
    }

    fn reach_effects(&mut self, task: &GroundTask, operator: OperatorId, cost: u32) {
        for &fact in &task.operators[operator as usize].add {
            let index = fact as usize;
            if cost < self.fact_cost[index] {
                self.fact_cost[index] = cost;
                self.supporter[index] = operator;
                self.heap.push(Reverse((cost, fact)));
            }
        }
    }
}
