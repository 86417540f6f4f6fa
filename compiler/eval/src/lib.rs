//! lamp-eval: the evaluation protocol behind `lampc eval` as values.
//!
//! A pool of demonstrations ([`PoolDemo`]: a name, whether it was cut short, how many objects it
//! shows) gives, per demonstration count and run, a subset drawn with a seeded generator and
//! stratified so that the fraction of cut demonstrations matches the pool's ([`draw_subset`]).
//! Each solve of a test problem with a model learned from a subset becomes a [`Row`]; the rows and
//! the evaluation's [`EvalInfo`] become the outputs: `eval.json` ([`EvalDocument`]), `eval.csv`
//! ([`csv`]), `report.md` ([`report`]) and two plots ([`success_plot`],
//! [`sample_efficiency_plot`]), through the aggregates of [`stats`].
//!
//! Pure: values in, text out, byte-identical for the same input. Learning, solving, files and
//! processes are `lampc`'s. The protocol and every column are described in `docs/evaluation.md`.

pub mod csv;
pub mod error;
pub mod plot;
pub mod report;
pub mod row;
pub mod stats;
pub mod subset;

pub use csv::{CSV_COLUMNS, csv};
pub use error::EvalError;
pub use plot::{sample_efficiency_plot, success_plot};
pub use report::report;
pub use report::{EFFICIENCY_PLOT_FILE, SUCCESS_PLOT_FILE};
pub use row::{
    EVAL_FORMAT, EVAL_VERSION, EvalDocument, EvalInfo, MACHINE_COLUMNS, Outcome, PoolInfo,
    ProblemInfo, Row, SettingsInfo, SolveResult,
};
pub use stats::{
    CountSummary, Generalization, efficiency, generalization, mean_and_std, success_table,
};
pub use subset::{PoolDemo, draw_subset, parse_counts, subset_seed};
