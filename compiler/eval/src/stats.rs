//! Aggregates of the rows: the solved fraction per run with its mean and sample standard
//! deviation per demonstration count, the success table per problem, and the generalization
//! factor.

use crate::row::{EvalInfo, Outcome, Row};

/// The mean and the sample standard deviation (divisor n − 1) of `values`: `None` for no values;
/// the deviation is `None` for a single value, where it is undefined.
pub fn mean_and_std(values: &[f64]) -> Option<(f64, Option<f64>)> {
    if values.is_empty() {
        return None;
    }
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    if values.len() < 2 {
        return Some((mean, None));
    }
    let squares: f64 = values.iter().map(|value| (value - mean).powi(2)).sum();
    Some((mean, Some((squares / (n - 1.0)).sqrt())))
}

/// One demonstration count: how each run did, and their mean and spread.
#[derive(Clone, Debug, PartialEq)]
pub struct CountSummary {
    pub count: usize,
    /// Per run that has rows, in run order: (run, problems solved, problems evaluated).
    pub runs: Vec<(usize, usize, usize)>,
    /// The solved fraction per run, in the same order.
    pub fractions: Vec<f64>,
    /// Mean and sample standard deviation of the fractions (`None` without runs; the deviation
    /// `None` with one run).
    pub mean: Option<f64>,
    pub std: Option<f64>,
    /// The most objects in a test problem solved by any run of this count.
    pub largest_solved: Option<usize>,
    /// How many rows ended with each outcome, in [`Outcome::ALL`] order.
    pub outcomes: Vec<(Outcome, usize)>,
}

/// The sample-efficiency summary: one entry per count of `info`, in the order given.
pub fn efficiency(info: &EvalInfo, rows: &[Row]) -> Vec<CountSummary> {
    info.counts
        .iter()
        .map(|&count| {
            let of_count: Vec<&Row> = rows.iter().filter(|row| row.demos == count).collect();
            let mut runs = Vec::new();
            for run in 1..=info.runs {
                let of_run: Vec<&&Row> = of_count.iter().filter(|row| row.run == run).collect();
                if !of_run.is_empty() {
                    let solved = of_run.iter().filter(|row| row.solved).count();
                    runs.push((run, solved, of_run.len()));
                }
            }
            let fractions: Vec<f64> =
                runs.iter().map(|&(_, solved, total)| solved as f64 / total as f64).collect();
            let (mean, std) = match mean_and_std(&fractions) {
                Some((mean, std)) => (Some(mean), std),
                None => (None, None),
            };
            let largest_solved =
                of_count.iter().filter(|row| row.solved).map(|row| row.objects).max();
            let outcomes = Outcome::ALL
                .iter()
                .map(|&outcome| {
                    (outcome, of_count.iter().filter(|row| row.result.outcome == outcome).count())
                })
                .collect();
            CountSummary { count, runs, fractions, mean, std, largest_solved, outcomes }
        })
        .collect()
}

/// One line of the success table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProblemSuccess {
    pub problem: String,
    pub objects: usize,
    /// Per count (in the evaluation's order): the runs that solved the problem, and those that
    /// tried.
    pub cells: Vec<(usize, usize)>,
}

/// The success table: one line per problem, in the evaluation's order.
pub fn success_table(info: &EvalInfo, rows: &[Row]) -> Vec<ProblemSuccess> {
    info.problems
        .iter()
        .map(|problem| {
            let cells = info
                .counts
                .iter()
                .map(|&count| {
                    let tried =
                        rows.iter().filter(|row| row.demos == count && row.problem == problem.name);
                    let (solved, total) =
                        tried.fold((0, 0), |(s, t), row| (s + usize::from(row.solved), t + 1));
                    (solved, total)
                })
                .collect();
            ProblemSuccess { problem: problem.name.clone(), objects: problem.objects, cells }
        })
        .collect()
}

/// The generalization factor: the most objects in a solved test problem ÷ the most objects in a
/// training demonstration.
#[derive(Clone, Debug, PartialEq)]
pub struct Generalization {
    /// The most objects any demonstration of the pool shows.
    pub training_objects: usize,
    /// The most objects in a solved test problem, and the first such problem in spec order.
    pub test_objects: Option<usize>,
    pub problem: Option<String>,
    /// `test_objects / training_objects`; `None` when nothing was solved or no demonstration
    /// shows an object.
    pub factor: Option<f64>,
}

/// The generalization factor of the rows, over every count and run.
pub fn generalization(info: &EvalInfo, rows: &[Row]) -> Generalization {
    let training_objects = info.pool.max_objects;
    let test_objects = rows.iter().filter(|row| row.solved).map(|row| row.objects).max();
    let problem = test_objects.and_then(|most| {
        info.problems
            .iter()
            .find(|problem| {
                problem.objects == most
                    && rows.iter().any(|row| row.solved && row.problem == problem.name)
            })
            .map(|problem| problem.name.clone())
    });
    let factor = test_objects
        .filter(|_| training_objects > 0)
        .map(|most| most as f64 / training_objects as f64);
    Generalization { training_objects, test_objects, problem, factor }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::row::tests::{info, rows};

    #[test]
    fn mean_and_sample_standard_deviation_match_known_answers() {
        assert_eq!(mean_and_std(&[]), None);
        assert_eq!(mean_and_std(&[0.5]), Some((0.5, None)));
        // 2, 4, 4, 4, 5, 5, 7, 9: mean 5, squared deviations sum to 32, sample variance 32 / 7.
        let (mean, std) = mean_and_std(&[2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0]).expect("values");
        assert!((mean - 5.0).abs() < 1e-12);
        assert!((std.expect("two or more") - (32.0_f64 / 7.0).sqrt()).abs() < 1e-12);
        let (_, zero) = mean_and_std(&[1.0, 1.0]).expect("values");
        assert_eq!(zero, Some(0.0));
    }

    #[test]
    fn efficiency_has_one_fraction_per_run_and_counts_relaxed_goals_as_failures() {
        let summaries = efficiency(&info(), &rows());
        assert_eq!(summaries.len(), 2);
        assert_eq!(summaries[0].count, 40);
        assert_eq!(summaries[0].fractions, vec![1.0, 1.0]);
        assert_eq!((summaries[0].mean, summaries[0].std), (Some(1.0), Some(0.0)));
        assert_eq!(summaries[0].largest_solved, Some(4));
        let twenty = &summaries[1];
        assert_eq!(twenty.runs, vec![(1, 1, 2), (2, 0, 2)]);
        assert_eq!(twenty.fractions, vec![0.5, 0.0]);
        assert_eq!(twenty.mean, Some(0.25));
        let std = twenty.std.expect("two runs");
        assert!((std - 0.125_f64.sqrt()).abs() < 1e-12, "{std}");
        assert_eq!(twenty.largest_solved, Some(2));
        let count = |outcome| twenty.outcomes.iter().find(|(o, _)| *o == outcome).map(|o| o.1);
        assert_eq!(count(Outcome::RelaxedGoal), Some(1));
        assert_eq!(count(Outcome::Solved), Some(1));
    }

    #[test]
    fn the_success_table_counts_runs_per_problem_and_count() {
        let table = success_table(&info(), &rows());
        let line = |problem: &str, objects, cells: &[(usize, usize)]| ProblemSuccess {
            problem: problem.into(),
            objects,
            cells: cells.to_vec(),
        };
        assert_eq!(
            table,
            [line("pack2", 2, &[(2, 2), (1, 2)]), line("pack4", 4, &[(2, 2), (0, 2)])]
        );
    }

    #[test]
    fn the_generalization_factor_divides_solved_objects_by_demonstrated_ones() {
        let g = generalization(&info(), &rows());
        assert_eq!((g.training_objects, g.test_objects), (1, Some(4)));
        assert_eq!(g.problem.as_deref(), Some("pack4"));
        assert_eq!(g.factor, Some(4.0));
        // Only the 20-demonstration rows: pack4 was relaxed, so the largest solved task is pack2.
        let few: Vec<Row> = rows().into_iter().filter(|row| row.demos == 20).collect();
        let g = generalization(&info(), &few);
        assert_eq!((g.test_objects, g.factor), (Some(2), Some(2.0)));
        // Nothing solved: no factor.
        let none: Vec<Row> = few.into_iter().filter(|row| !row.solved).collect();
        assert_eq!(generalization(&info(), &none).factor, None);
        // Two objects in the largest demonstration halve the factor.
        let mut wide = info();
        wide.pool.max_objects = 2;
        assert_eq!(generalization(&wide, &rows()).factor, Some(2.0));
    }
}
