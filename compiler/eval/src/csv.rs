//! `eval.csv`: one line per row, the columns of `eval.json`'s rows in the same order.

use std::fmt::Write as _;

use crate::row::Row;

/// The header line's columns.
pub const CSV_COLUMNS: [&str; 23] = [
    "demos",
    "run",
    "problem",
    "objects",
    "subset",
    "commit",
    "model",
    "solved",
    "outcome",
    "reason",
    "stopped_by",
    "relaxed",
    "plan_length",
    "plans_tried",
    "candidates",
    "replans",
    "motion_calls",
    "seconds_planning",
    "seconds_refining",
    "seconds_validating",
    "seconds_solving",
    "peak_memory_bytes",
    "seconds_learning",
];

/// A field, quoted (RFC 4180) when it holds a comma, a quote or a line break.
fn field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

fn count(value: Option<usize>) -> String {
    value.map_or_else(String::new, |value| value.to_string())
}

/// Seconds to the millisecond; an empty field when not measured.
fn seconds(value: Option<f64>) -> String {
    value.map_or_else(String::new, |value| format!("{value:.3}"))
}

/// The CSV text of `rows`: a header line, then one line per row; empty fields for values not
/// measured; relaxed goal atoms separated by `; `.
pub fn csv(rows: &[Row]) -> String {
    let mut out = CSV_COLUMNS.join(",");
    out.push('\n');
    for row in rows {
        let result = &row.result;
        let fields = [
            row.demos.to_string(),
            row.run.to_string(),
            field(&row.problem),
            row.objects.to_string(),
            field(&row.subset),
            field(row.commit.as_deref().unwrap_or_default()),
            field(row.model.as_deref().unwrap_or_default()),
            row.solved.to_string(),
            result.outcome.name().to_string(),
            field(&result.reason),
            field(result.stopped_by.as_deref().unwrap_or_default()),
            field(&result.relaxed.join("; ")),
            count(result.plan_length),
            count(result.plans_tried),
            count(result.candidates),
            count(result.replans),
            count(result.motion_calls),
            seconds(result.seconds_planning),
            seconds(result.seconds_refining),
            seconds(result.seconds_validating),
            seconds(result.seconds_solving),
            result.peak_memory_bytes.map_or_else(String::new, |bytes| bytes.to_string()),
            seconds(row.seconds_learning),
        ];
        let _ = writeln!(out, "{}", fields.join(","));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::row::tests::rows;

    #[test]
    fn one_line_per_row_with_quoted_fields_and_empty_unmeasured_values() {
        let mut rows = rows();
        rows[6].result.reason = "no plan could be refined (3 plans, \"deepest\" step 2)".into();
        rows[6].result.stopped_by = Some("in_the_way".into());
        let text = csv(&rows);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 1 + rows.len());
        assert_eq!(
            lines[1],
            "40,1,pack2,2,fnv1a64:a,,,true,solved,,,,10,1,20,0,12,0.100,2.500,0.200,3.000,50000000,1.000"
        );
        assert!(lines[6].contains(",false,relaxed_goal,"), "{}", lines[6]);
        assert!(lines[6].contains(",(surface_can_1 box1 can4),"), "{}", lines[6]);
        assert_eq!(
            lines[7],
            "20,2,pack2,2,fnv1a64:d,,,false,refinement_budget,\"no plan could be refined (3 plans, \"\"deepest\"\" step 2)\",in_the_way,,,,,,,,,,,,0.500"
        );
    }
}
