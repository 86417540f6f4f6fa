//! Rendering diagnostics for people: miette's graphical report with the source attached.

use miette::{GraphicalReportHandler, GraphicalTheme};

/// Renders every diagnostic of a check, in order, each followed by a blank line.
pub(crate) fn render_all(outcome: &lamp_lang::CheckOutcome, colour: bool, width: usize) -> String {
    let theme = if colour { GraphicalTheme::unicode() } else { GraphicalTheme::unicode_nocolor() };
    let handler = GraphicalReportHandler::new_themed(theme).with_width(width);
    let mut out = String::new();
    for diagnostic in &outcome.diagnostics {
        let with_source = diagnostic.with_source(&outcome.sources);
        if handler.render_report(&mut out, &with_source).is_err() {
            out.push_str(&format!("error: {}\n", diagnostic.error));
        }
        out.push('\n');
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
