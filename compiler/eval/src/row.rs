//! The evaluation's values: one [`Row`] per (demonstration count, run, problem), what a solve
//! reported ([`SolveResult`]), what the evaluation was ([`EvalInfo`]), and `eval.json`
//! ([`EvalDocument`]).

use serde::{Deserialize, Serialize};

/// The `format` field of `eval.json`.
pub const EVAL_FORMAT: &str = "lamp-eval";
/// The `version` field of `eval.json`; raised when a field changes meaning or goes away.
pub const EVAL_VERSION: u32 = 1;

/// The columns whose values depend on the machine and its load (wall-clock seconds, memory):
/// everything else of a row is the same on every machine and for every job count.
pub const MACHINE_COLUMNS: [&str; 6] = [
    "seconds_learning",
    "seconds_planning",
    "seconds_refining",
    "seconds_validating",
    "seconds_solving",
    "peak_memory_bytes",
];

/// How a solve ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// A validated trajectory reaches the whole goal.
    Solved,
    /// A validated trajectory reaches only part of the goal: some goal atoms were dropped
    /// because no plan reached them. Not a success.
    RelaxedGoal,
    /// The planner found no plan (and no relaxation helped).
    NoPlan,
    /// Plans exist, but none was refined into motion within the deterministic budget.
    RefinementBudget,
    /// A time limit ran out: the per-solve `--timeout`, or the planner's own `timeout` before
    /// it found a plan.
    Timeout,
    /// Learning from the subset failed, or the build wrote no PDDL problem for this problem.
    BuildFailed,
    /// Anything else: a plugin failure, a stale problem, an invalid solution, a solver that panicked (the
    /// worker reports it as this row). A worker that dies without a row is an executor failure, never a row.
    Error,
}

impl Outcome {
    /// Every outcome, in the order reports list them.
    pub const ALL: [Outcome; 7] = [
        Outcome::Solved,
        Outcome::RelaxedGoal,
        Outcome::NoPlan,
        Outcome::RefinementBudget,
        Outcome::Timeout,
        Outcome::BuildFailed,
        Outcome::Error,
    ];

    /// The outcome's name in JSON, CSV and the report.
    pub fn name(self) -> &'static str {
        match self {
            Outcome::Solved => "solved",
            Outcome::RelaxedGoal => "relaxed_goal",
            Outcome::NoPlan => "no_plan",
            Outcome::RefinementBudget => "refinement_budget",
            Outcome::Timeout => "timeout",
            Outcome::BuildFailed => "build_failed",
            Outcome::Error => "error",
        }
    }
}

/// What one solve reported: a row without its place in the evaluation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolveResult {
    pub outcome: Outcome,
    /// Why it is not solved, in one line (empty when solved).
    pub reason: String,
    /// What kind of cause stopped the plans where most of them ended, when plans were refined
    /// and one kind stood out: `in_the_way`, `out_of_reach`, `no_path`, `not_at_rest`,
    /// `target_missed`, `effects_unmet`, `rest_broken` or `fixed_bodies` (`docs/solving.md`,
    /// "When a solve fails"). Absent from rows written before it was recorded.
    #[serde(default)]
    pub stopped_by: Option<String>,
    /// Goal atoms dropped by relaxation.
    pub relaxed: Vec<String>,
    /// Steps of the refined plan (when a trajectory was found).
    pub plan_length: Option<usize>,
    /// Symbolic plans tried, refiner candidates tried, replans and motion-planner calls (each
    /// when the solver reported it: all four on a trajectory, the first two after a refinement
    /// failure or a time limit).
    pub plans_tried: Option<usize>,
    pub candidates: Option<usize>,
    pub replans: Option<usize>,
    pub motion_calls: Option<usize>,
    /// Seconds planning, refining and validating (when a trajectory was found), and the wall
    /// time of the whole solve (spec, world, plugins and the search).
    pub seconds_planning: Option<f64>,
    pub seconds_refining: Option<f64>,
    pub seconds_validating: Option<f64>,
    pub seconds_solving: Option<f64>,
    /// The solving process's peak resident memory (Linux `VmHWM`; `None` elsewhere).
    pub peak_memory_bytes: Option<u64>,
}

impl SolveResult {
    /// A result with only an outcome and a reason (nothing was solved or measured).
    pub fn failed(outcome: Outcome, reason: impl Into<String>) -> SolveResult {
        SolveResult {
            outcome,
            reason: reason.into(),
            stopped_by: None,
            relaxed: Vec::new(),
            plan_length: None,
            plans_tried: None,
            candidates: None,
            replans: None,
            motion_calls: None,
            seconds_planning: None,
            seconds_refining: None,
            seconds_validating: None,
            seconds_solving: None,
            peak_memory_bytes: None,
        }
    }
}

/// One solve of the evaluation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// The demonstration count N and the run (1-based).
    pub demos: usize,
    pub run: usize,
    pub problem: String,
    /// Objects of the test problem: its scene's objects of a movable type.
    pub objects: usize,
    /// The digest of the demonstration subset learned from.
    pub subset: String,
    /// The source commit of the lampc that learned and solved (`unknown` when built outside a
    /// git checkout); absent from rows written before it was recorded.
    #[serde(default)]
    pub commit: Option<String>,
    /// The digest of what the solve was given: the learned domain, the sampler file and the
    /// problem's PDDL (or, when the build failed, why). Two learners that give the same model
    /// give the same digest; absent from rows written before it was recorded.
    #[serde(default)]
    pub model: Option<String>,
    /// Whether the problem was solved: the outcome is `solved`.
    pub solved: bool,
    #[serde(flatten)]
    pub result: SolveResult,
    /// Seconds learning the subset's model (shared by the subset's rows).
    pub seconds_learning: Option<f64>,
}

impl Row {
    /// A row of `result`; `solved` follows from its outcome.
    pub fn new(
        demos: usize,
        run: usize,
        problem: &str,
        objects: usize,
        subset: &str,
        result: SolveResult,
        seconds_learning: Option<f64>,
    ) -> Row {
        Row {
            demos,
            run,
            problem: problem.to_string(),
            objects,
            subset: subset.to_string(),
            commit: None,
            model: None,
            solved: result.outcome == Outcome::Solved,
            result,
            seconds_learning,
        }
    }

    /// Whether `solved` agrees with the outcome, as [`Row::new`] makes it: a row read back from a
    /// file that says otherwise was edited or damaged, and would make the figures contradict
    /// themselves.
    pub fn is_consistent(&self) -> bool {
        self.solved == (self.result.outcome == Outcome::Solved)
    }
}

/// A test problem of the evaluation.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ProblemInfo {
    pub name: String,
    /// Objects of a movable type in its scene.
    pub objects: usize,
}

/// The pool the subsets are drawn from.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PoolInfo {
    /// Demonstration files, how many were cut short, and how many this evaluation generated.
    pub demonstrations: usize,
    pub cut: usize,
    pub generated: usize,
    /// The most objects any demonstration shows.
    pub max_objects: usize,
    /// The demonstration digest of the whole pool.
    pub digest: String,
}

/// The solver's settings, as every solve of the evaluation used them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SettingsInfo {
    /// The plugins, each as its name or library path with its options.
    pub planner: String,
    pub refiner: String,
    pub motion: String,
    /// Plans asked per planner call, rounds with fresh samples, wasted candidates per plan,
    /// RRT-Connect iterations per motion call.
    pub plans: usize,
    pub rounds: usize,
    pub max_refused: usize,
    pub motion_iterations: u64,
    /// Whether unreachable goal atoms are dropped (a relaxed goal is still not a success).
    pub relax_goal: bool,
    /// The per-solve time limit in seconds (`--timeout`): results then depend on the machine.
    pub timeout: Option<f64>,
    /// The digest that keys finished rows in the journal (see `docs/evaluation.md`).
    pub key: String,
}

/// What was evaluated, and how.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EvalInfo {
    /// The spec's file name and domain.
    pub spec: String,
    pub domain: String,
    /// The seed of the subset draws, the learning and the solves.
    pub seed: u64,
    /// Demonstration counts, in the order given, and runs per count.
    pub counts: Vec<usize>,
    pub runs: usize,
    /// The selected test problems, in spec order.
    pub problems: Vec<ProblemInfo>,
    pub pool: PoolInfo,
    pub settings: SettingsInfo,
}

/// `eval.json`: the evaluation and its rows, in (count as given, run, problem in spec order) order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EvalDocument {
    pub format: String,
    pub version: u32,
    #[serde(flatten)]
    pub info: EvalInfo,
    pub rows: Vec<Row>,
}

impl EvalDocument {
    /// The document of `info` and `rows`.
    pub fn new(info: EvalInfo, rows: Vec<Row>) -> EvalDocument {
        EvalDocument { format: EVAL_FORMAT.to_string(), version: EVAL_VERSION, info, rows }
    }

    /// Pretty JSON with a final newline.
    pub fn to_json(&self) -> Result<String, serde_json::Error> {
        let mut text = serde_json::to_string_pretty(self)?;
        text.push('\n');
        Ok(text)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A small evaluation: two counts × two runs × two problems.
    pub(crate) fn info() -> EvalInfo {
        EvalInfo {
            spec: "packing.lamp".into(),
            domain: "packing".into(),
            seed: 1,
            counts: vec![40, 20],
            runs: 2,
            problems: vec![
                ProblemInfo { name: "pack2".into(), objects: 2 },
                ProblemInfo { name: "pack4".into(), objects: 4 },
            ],
            pool: PoolInfo {
                demonstrations: 40,
                cut: 20,
                generated: 0,
                max_objects: 1,
                digest: "fnv1a64:0123456789abcdef".into(),
            },
            settings: SettingsInfo {
                planner: "gbfs-ff (timeout 30)".into(),
                refiner: "gmm (draws 2000, samples 4)".into(),
                motion: "rrt-connect (resolution 0.01)".into(),
                plans: 3,
                rounds: 20,
                max_refused: 100,
                motion_iterations: 4000,
                relax_goal: true,
                timeout: None,
                key: "fnv1a64:fedcba9876543210".into(),
            },
        }
    }

    pub(crate) fn solved(plan_length: usize) -> SolveResult {
        SolveResult {
            outcome: Outcome::Solved,
            reason: String::new(),
            stopped_by: None,
            relaxed: Vec::new(),
            plan_length: Some(plan_length),
            plans_tried: Some(1),
            candidates: Some(20),
            replans: Some(0),
            motion_calls: Some(12),
            seconds_planning: Some(0.1),
            seconds_refining: Some(2.5),
            seconds_validating: Some(0.2),
            seconds_solving: Some(3.0),
            peak_memory_bytes: Some(50_000_000),
        }
    }

    /// Rows of [`info`]: with 40 demonstrations every problem is solved; with 20, run 1 solves
    /// `pack2` only (`pack4` relaxed), run 2 nothing (a refinement failure and a failed build).
    pub(crate) fn rows() -> Vec<Row> {
        let relaxed = SolveResult {
            relaxed: vec!["(surface_can_1 box1 can4)".into()],
            reason: "the goal was relaxed: dropped (surface_can_1 box1 can4)".into(),
            outcome: Outcome::RelaxedGoal,
            ..solved(15)
        };
        vec![
            Row::new(40, 1, "pack2", 2, "fnv1a64:a", solved(10), Some(1.0)),
            Row::new(40, 1, "pack4", 4, "fnv1a64:a", solved(19), Some(1.0)),
            Row::new(40, 2, "pack2", 2, "fnv1a64:b", solved(10), Some(1.0)),
            Row::new(40, 2, "pack4", 4, "fnv1a64:b", solved(19), Some(1.0)),
            Row::new(20, 1, "pack2", 2, "fnv1a64:c", solved(10), Some(0.5)),
            Row::new(20, 1, "pack4", 4, "fnv1a64:c", relaxed, Some(0.5)),
            Row::new(
                20,
                2,
                "pack2",
                2,
                "fnv1a64:d",
                SolveResult::failed(Outcome::RefinementBudget, "no plan could be refined"),
                Some(0.5),
            ),
            Row::new(
                20,
                2,
                "pack4",
                4,
                "fnv1a64:d",
                SolveResult::failed(Outcome::BuildFailed, "the problem was not written"),
                Some(0.5),
            ),
        ]
    }

    #[test]
    fn a_relaxed_goal_is_not_solved() {
        let rows = rows();
        assert!(rows[4].solved);
        assert_eq!(rows[5].result.outcome, Outcome::RelaxedGoal);
        assert!(!rows[5].solved);
    }

    /// The keys of pretty-printed JSON at `indent` spaces, in the order written, up to the line
    /// `stop` (serde_json's `Value` sorts keys, so the order is read from the text).
    pub(crate) fn keys_at(text: &str, indent: usize, stop: &str) -> Vec<String> {
        let prefix = format!("{}\"", " ".repeat(indent));
        text.lines()
            .take_while(|line| *line != stop)
            .filter_map(|line| line.strip_prefix(&prefix))
            .filter_map(|rest| rest.split_once('"').map(|(key, _)| key.to_string()))
            .collect()
    }

    #[test]
    fn eval_json_has_the_documented_fields_and_reads_back() {
        let document = EvalDocument::new(info(), rows());
        let text = document.to_json().expect("serialises");
        assert_eq!(
            keys_at(&text, 2, "never"),
            [
                "format", "version", "spec", "domain", "seed", "counts", "runs", "problems",
                "pool", "settings", "rows"
            ]
        );
        // The rows' fields, in order, are the CSV's columns.
        assert_eq!(
            keys_at(&text[text.find("\"rows\"").unwrap_or(0)..], 6, "    },"),
            crate::csv::CSV_COLUMNS.map(String::from)
        );
        let value: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
        assert_eq!(value["format"], EVAL_FORMAT);
        let row = value["rows"][5].as_object().expect("a row object");
        assert_eq!(row["outcome"], "relaxed_goal");
        assert_eq!(row["solved"], false);
        for column in MACHINE_COLUMNS {
            assert!(row.contains_key(column), "{column}");
        }
        let back: EvalDocument = serde_json::from_str(&text).expect("reads back");
        assert_eq!(back, document);
    }

    #[test]
    fn outcome_names_match_their_json() {
        for outcome in Outcome::ALL {
            let json = serde_json::to_value(outcome).expect("serialises");
            assert_eq!(json, outcome.name());
        }
    }
}
