//! `report.md`: what was evaluated, the sample-efficiency table, the generalization factor, the
//! success table per problem and why solves failed, with the two plots embedded; and, apart,
//! the journal's rows that another learner made.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use crate::row::{EvalInfo, Outcome, Row};
use crate::stats::{efficiency, generalization, success_table};

/// The file names the report embeds.
pub const SUCCESS_PLOT_FILE: &str = "success.svg";
pub const EFFICIENCY_PLOT_FILE: &str = "sample_efficiency.svg";

/// A fraction as a percentage with `decimals` decimals.
pub(crate) fn percent(fraction: f64, decimals: usize) -> String {
    format!("{:.*} %", decimals, fraction * 100.0)
}

/// A factor with at most one decimal: `4×`, `2.5×`.
pub(crate) fn factor_text(factor: f64) -> String {
    let text = format!("{factor:.1}");
    format!("{}×", text.strip_suffix(".0").unwrap_or(&text))
}

/// The header of a table with a column per demonstration count after the `first` columns (the
/// first left-aligned, the others and the counts right-aligned).
fn table_header(out: &mut String, first: &[&str], counts: &[usize]) {
    out.push('|');
    for name in first {
        let _ = write!(out, " {name} |");
    }
    for count in counts {
        let _ = write!(out, " {count} |");
    }
    out.push_str("\n| --- |");
    for _ in 1..first.len() + counts.len() {
        out.push_str(" ---: |");
    }
    out.push('\n');
}

/// How many of a subset of `count` demonstrations reach their goal, as drawn from `pool`.
fn reaching_goal(count: usize, pool: &crate::PoolInfo) -> String {
    if count > pool.demonstrations {
        return "—".to_string();
    }
    (count - crate::subset::cut_places(count, pool.demonstrations, pool.cut)).to_string()
}

/// The report of `rows` (in any order); `earlier` are rows of the same solves made with another
/// model (an earlier learner's), listed apart and counted in no figure.
pub fn report(info: &EvalInfo, rows: &[Row], earlier: &[Row]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "# Evaluation of `{}`\n", info.spec);
    let counts: Vec<String> = info.counts.iter().map(usize::to_string).collect();
    let _ = writeln!(
        out,
        "Domain `{}`, seed {}: {} demonstration count(s) ({}) × {} run(s) × {} test problem(s) = {} solves, {} of them in this report.",
        info.domain,
        info.seed,
        info.counts.len(),
        counts.join(", "),
        info.runs,
        info.problems.len(),
        info.counts.len() * info.runs * info.problems.len(),
        rows.len()
    );
    let pool = &info.pool;
    let _ = writeln!(
        out,
        "Each run learns from its own subset of one pool of {} demonstrations ({} cut short, `{}`), drawn with the pool's fraction of cut demonstrations; the others reach their goal, and the paper counts those (its \"as few as 40 goal-achieving demonstrations\"): the sample efficiency table says how many of each subset do.",
        pool.demonstrations, pool.cut, pool.digest
    );
    let settings = &info.settings;
    let _ = writeln!(
        out,
        "Solves use `lampc solve`'s settings: planner {}, refiner {}, motion planner {}; {} plan(s) per call, {} rounds, at least {} wasted candidates per plan (more for long plans, `docs/solving.md`), {} RRT-Connect iterations per motion call; goal relaxation {} (a relaxed goal counts as not solved).",
        settings.planner,
        settings.refiner,
        settings.motion,
        settings.plans,
        settings.rounds,
        settings.max_refused,
        settings.motion_iterations,
        if settings.relax_goal { "on" } else { "off" }
    );
    match settings.timeout {
        Some(seconds) => {
            let _ = writeln!(
                out,
                "Each solve had a time limit of {seconds} s (`--timeout`), so these results depend on the machine and its load."
            );
        }
        None => {
            let _ = writeln!(
                out,
                "No solve had a time limit: every budget is deterministic, so the rows are the same on any machine."
            );
        }
    }

    let summaries = efficiency(info, rows);
    out.push_str("\n## Sample efficiency\n\n");
    out.push_str("The fraction of the test problems each run solved, per number of training demonstrations: mean ± sample standard deviation over the runs.\n\n");
    out.push_str(
        "| demonstrations | reaching their goal | runs | solved (mean ± std) | worst run | best run | largest solved task |\n",
    );
    out.push_str("| ---: | ---: | ---: | --- | ---: | ---: | ---: |\n");
    for summary in &summaries {
        let mean = summary.mean.map_or_else(|| "—".to_string(), |mean| percent(mean, 1));
        let std = summary.std.map_or_else(|| "—".to_string(), |std| percent(std, 1));
        let worst = summary.fractions.iter().copied().reduce(f64::min);
        let best = summary.fractions.iter().copied().reduce(f64::max);
        let show = |value: Option<f64>| value.map_or_else(|| "—".to_string(), |v| percent(v, 0));
        let largest = summary
            .largest_solved
            .map_or_else(|| "—".to_string(), |objects| format!("{objects} objects"));
        let _ = writeln!(
            out,
            "| {} | {} | {} | {mean} ± {std} | {} | {} | {largest} |",
            summary.count,
            reaching_goal(summary.count, pool),
            summary.runs.len(),
            show(worst),
            show(best)
        );
    }
    let _ = writeln!(out, "\n![Sample efficiency]({})", EFFICIENCY_PLOT_FILE);

    let g = generalization(info, rows);
    out.push_str("\n## Generalization\n\n");
    match (g.test_objects, g.factor) {
        (Some(test), Some(factor)) => {
            let _ = writeln!(
                out,
                "Most objects in a solved test task ÷ most objects in a training demonstration = {test} ÷ {} = **{}** (`{}`).",
                g.training_objects,
                factor_text(factor),
                g.problem.as_deref().unwrap_or("?")
            );
        }
        (Some(test), None) => {
            let _ = writeln!(
                out,
                "A task with {test} objects was solved, but no demonstration shows an object, so there is no factor."
            );
        }
        (None, _) => {
            out.push_str("No test task was solved, so there is no generalization factor.\n")
        }
    }
    out.push_str("The training side is read from the demonstration files (bodies of a movable type), the test side from the problems' scenes.\n");

    out.push_str("\n## Success per problem\n\n");
    out.push_str("Runs that solved each test problem, per number of training demonstrations.\n\n");
    table_header(&mut out, &["problem", "objects"], &info.counts);
    for line in success_table(info, rows) {
        let _ = write!(out, "| `{}` | {} |", line.problem, line.objects);
        for (solved, total) in line.cells {
            let _ = write!(out, " {solved}/{total} |");
        }
        out.push('\n');
    }
    let _ = writeln!(out, "\n![Success per problem]({})", SUCCESS_PLOT_FILE);

    out.push_str("\n## Outcomes\n\n");
    out.push_str("How the solves ended, per number of training demonstrations (`eval.csv` has the reason of each).\n\n");
    table_header(&mut out, &["outcome"], &info.counts);
    for outcome in Outcome::ALL {
        let cells: Vec<usize> = summaries
            .iter()
            .map(|summary| {
                summary.outcomes.iter().find(|(o, _)| *o == outcome).map_or(0, |(_, n)| *n)
            })
            .collect();
        if cells.iter().all(|&n| n == 0) {
            continue;
        }
        let _ = write!(out, "| `{}` |", outcome.name());
        for n in cells {
            let _ = write!(out, " {n} |");
        }
        out.push('\n');
    }
    stopped_table(&mut out, info, rows);
    earlier_table(&mut out, earlier);
    out
}

/// The rows another learner made, by commit and demonstration count; nothing when there are none.
fn earlier_table(out: &mut String, earlier: &[Row]) {
    if earlier.is_empty() {
        return;
    }
    out.push_str("\n## Rows from another learner\n\n");
    let _ = writeln!(
        out,
        "{} row(s) of the journal answer these solves with a model that this lampc no longer learns from their subsets: the learner has changed since. They stay in the journal and count in none of the figures above.\n",
        earlier.len()
    );
    let mut groups: BTreeMap<(&str, usize), (usize, usize)> = BTreeMap::new();
    for row in earlier {
        let commit = row.commit.as_deref().unwrap_or("not recorded");
        let (rows, solved) = groups.entry((commit, row.demos)).or_default();
        *rows += 1;
        *solved += usize::from(row.solved);
    }
    out.push_str("| commit | demonstrations | rows | solved |\n| --- | ---: | ---: | ---: |\n");
    for ((commit, demos), (rows, solved)) in groups {
        let short: String = commit.chars().take(12).collect();
        let _ = writeln!(out, "| `{short}` | {demos} | {rows} | {solved} |");
    }
}

/// The table of what stopped the failed solves that refined plans, by kind and demonstration
/// count; nothing when no row says.
fn stopped_table(out: &mut String, info: &EvalInfo, rows: &[Row]) {
    let mut kinds: Vec<&str> =
        rows.iter().filter_map(|row| row.result.stopped_by.as_deref()).collect();
    kinds.sort_unstable();
    kinds.dedup();
    if kinds.is_empty() {
        return;
    }
    out.push_str("\n## What stopped the failed solves\n\n");
    out.push_str("For the failed solves that refined plans, what kind of cause was refused most where most of their plans ended (`docs/solving.md`, \"When a solve fails\"; the reason in `eval.csv` names the step and the objects).\n\n");
    table_header(out, &["stopped by"], &info.counts);
    for kind in kinds {
        let _ = write!(out, "| `{kind}` |");
        for &count in &info.counts {
            let n = rows
                .iter()
                .filter(|row| row.demos == count && row.result.stopped_by.as_deref() == Some(kind))
                .count();
            let _ = write!(out, " {n} |");
        }
        out.push('\n');
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::row::tests::{info, rows};

    #[test]
    fn the_report_has_the_tables_the_factor_and_the_plots() {
        let text = report(&info(), &rows(), &[]);
        assert!(text.starts_with("# Evaluation of `packing.lamp`\n"), "{text}");
        assert!(
            text.contains("| 40 | 20 | 2 | 100.0 % ± 0.0 % | 100 % | 100 % | 4 objects |"),
            "{text}"
        );
        assert!(
            text.contains("| 20 | 10 | 2 | 25.0 % ± 35.4 % | 0 % | 50 % | 2 objects |"),
            "{text}"
        );
        assert!(text.contains("= 4 ÷ 1 = **4×** (`pack4`)"), "{text}");
        assert!(text.contains("| `pack4` | 4 | 2/2 | 0/2 |"), "{text}");
        assert!(text.contains("| `relaxed_goal` | 0 | 1 |"), "{text}");
        assert!(!text.contains("`timeout`"), "outcomes that never happened are left out");
        assert!(text.contains("![Sample efficiency](sample_efficiency.svg)"));
        assert!(text.contains("![Success per problem](success.svg)"));
        assert!(text.contains("No solve had a time limit"));
        assert_eq!(text, report(&info(), &rows(), &[]), "deterministic");
    }

    #[test]
    fn failed_solves_are_counted_by_what_stopped_them() {
        assert!(!report(&info(), &rows(), &[]).contains("What stopped"), "no row says");
        let mut rows = rows();
        let failed = rows.iter_mut().find(|row| row.result.outcome == Outcome::RefinementBudget);
        failed.expect("a refinement failure").result.stopped_by = Some("in_the_way".into());
        let text = report(&info(), &rows, &[]);
        assert!(text.contains("## What stopped the failed solves"), "{text}");
        assert!(text.contains("| `in_the_way` | 0 | 1 |"), "{text}");
    }

    #[test]
    fn a_time_limit_is_said_to_make_results_machine_dependent() {
        let mut info = info();
        info.settings.timeout = Some(60.0);
        let text = report(&info, &rows(), &[]);
        assert!(text.contains("a time limit of 60 s (`--timeout`)"), "{text}");
    }

    #[test]
    fn rows_of_another_learner_are_listed_apart_and_counted_in_no_figure() {
        let rows = rows();
        assert!(!report(&info(), &rows, &[]).contains("another learner"));
        let mut earlier = vec![rows[0].clone(), rows[1].clone()];
        earlier[0].commit = Some("0123456789abcdef0123".into());
        earlier[1].commit = None;
        for row in &mut earlier {
            row.solved = false;
        }
        let text = report(&info(), &rows, &earlier);
        assert!(text.contains("## Rows from another learner"), "{text}");
        assert!(text.contains("| `0123456789ab` | 40 | 1 | 0 |"), "{text}");
        assert!(text.contains("| `not recorded` | 40 | 1 | 0 |"), "{text}");
        let without = report(&info(), &rows, &[]);
        assert!(text.starts_with(&without), "the figures are those of `rows` alone");
    }

    #[test]
    fn factors_print_with_at_most_one_decimal() {
        assert_eq!(factor_text(4.0), "4×");
        assert_eq!(factor_text(2.5), "2.5×");
        assert_eq!(factor_text(18.0), "18×");
    }
}
