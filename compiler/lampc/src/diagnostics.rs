//! Rendering diagnostics for people: miette's graphical report with the source attached.

use std::collections::BTreeMap;

use miette::{GraphicalReportHandler, GraphicalTheme};

/// Diagnostics of one code rendered in full; the rest of that code are counted in one line.
/// Thousands of diagnostics of one kind are one mistake repeated (a generated spec, a pasted
/// block): twenty show it, and the output stays readable and its size bounded.
pub(crate) const SHOWN_PER_CODE: usize = 20;

/// Renders the diagnostics of a check, in order, each followed by a blank line: the first
/// [`SHOWN_PER_CODE`] of each code, then one line per code counting the ones not shown.
pub(crate) fn render_all(outcome: &lamp_lang::CheckOutcome, colour: bool, width: usize) -> String {
    let theme = if colour { GraphicalTheme::unicode() } else { GraphicalTheme::unicode_nocolor() };
    let handler = GraphicalReportHandler::new_themed(theme).with_width(width);
    let mut out = String::new();
    let mut per_code: BTreeMap<String, usize> = BTreeMap::new();
    for diagnostic in &outcome.diagnostics {
        let seen = per_code.entry(diagnostic.code()).or_default();
        *seen += 1;
        if *seen > SHOWN_PER_CODE {
            continue;
        }
        let with_source = diagnostic.with_source(&outcome.sources);
        if handler.render_report(&mut out, &with_source).is_err() {
            out.push_str(&format!("error: {}\n", diagnostic.error));
        }
        out.push('\n');
    }
    for (code, seen) in per_code {
        match seen.saturating_sub(SHOWN_PER_CODE) {
            0 => {}
            1 => out.push_str(&format!("… and 1 more `{code}` error\n")),
            hidden => out.push_str(&format!("… and {hidden} more `{code}` errors\n")),
        }
    }
    out
}

/// Renders one library error (a build, demonstration or render failure) with its code and help.
pub(crate) fn render_error(error: &dyn miette::Diagnostic, colour: bool) -> String {
    let theme = if colour { GraphicalTheme::unicode() } else { GraphicalTheme::unicode_nocolor() };
    let handler = GraphicalReportHandler::new_themed(theme).with_width(crate::terminal_width());
    let mut out = String::new();
    if handler.render_report(&mut out, error).is_err() {
        out = format!("error: {error}\n");
    }
    out.push('\n');
    out
}
