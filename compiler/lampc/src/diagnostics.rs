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
