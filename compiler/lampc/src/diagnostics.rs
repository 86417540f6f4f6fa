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

/// A build warning about a goal, pointed at where the goal is written.
#[derive(Debug)]
struct LocatedWarning<'a> {
    warning: &'a lamp_build::GoalWarning,
    source: miette::NamedSource<String>,
    at: miette::SourceSpan,
}

impl std::fmt::Display for LocatedWarning<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.warning.fmt(f)
    }
}

impl std::error::Error for LocatedWarning<'_> {}

impl miette::Diagnostic for LocatedWarning<'_> {
    fn code<'b>(&'b self) -> Option<Box<dyn std::fmt::Display + 'b>> {
        self.warning.code()
    }

    fn severity(&self) -> Option<miette::Severity> {
        self.warning.severity()
    }

    fn help<'b>(&'b self) -> Option<Box<dyn std::fmt::Display + 'b>> {
        self.warning.help()
    }

    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        Some(&self.source)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = miette::LabeledSpan> + '_>> {
        let label = miette::LabeledSpan::new_with_span(Some("this goal".to_string()), self.at);
        Some(Box::new(std::iter::once(label)))
    }
}

/// Renders a build warning about a goal, at the goal in the spec when it is known there.
pub(crate) fn render_goal_warning(
    warning: &lamp_build::GoalWarning,
    places: &lamp_lang::GoalPlaces,
    sources: &lamp_lang::SourceMap,
    colour: bool,
) -> String {
    let (problem, object) = warning.at_goal();
    match places.at_goal(problem, object) {
        Some(span) => {
            let located = LocatedWarning {
                warning,
                source: sources.named_source(span.file),
                at: span.source_span(),
            };
            render_error(&located, colour)
        }
        None => render_error(warning, colour),
    }
}
