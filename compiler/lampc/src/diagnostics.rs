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

/// A build diagnostic (a goal warning, a structure finding), pointed at where the spec writes
/// what it is about.
#[derive(Debug)]
struct Located<'a> {
    inner: &'a dyn miette::Diagnostic,
    source: miette::NamedSource<String>,
    labels: Vec<miette::LabeledSpan>,
}

impl std::fmt::Display for Located<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        std::fmt::Display::fmt(self.inner, f)
    }
}

impl std::error::Error for Located<'_> {}

impl miette::Diagnostic for Located<'_> {
    fn code<'b>(&'b self) -> Option<Box<dyn std::fmt::Display + 'b>> {
        self.inner.code()
    }

    fn severity(&self) -> Option<miette::Severity> {
        self.inner.severity()
    }

    fn help<'b>(&'b self) -> Option<Box<dyn std::fmt::Display + 'b>> {
        self.inner.help()
    }

    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        Some(&self.source)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = miette::LabeledSpan> + '_>> {
        Some(Box::new(self.labels.iter().cloned()))
    }
}

/// `diagnostic` rendered with labels at `spans` (label, span), those in the file of the first;
/// without spans, as it is.
fn render_located(
    diagnostic: &dyn miette::Diagnostic,
    spans: &[(&str, lamp_lang::Span)],
    sources: &lamp_lang::SourceMap,
    colour: bool,
) -> String {
    let Some((_, first)) = spans.first() else { return render_error(diagnostic, colour) };
    let labels = spans
        .iter()
        .filter(|(_, span)| span.file == first.file)
        .map(|(label, span)| {
            miette::LabeledSpan::new_with_span(Some(label.to_string()), span.source_span())
        })
        .collect();
    let located = Located { inner: diagnostic, source: sources.named_source(first.file), labels };
    render_error(&located, colour)
}

/// Renders a build warning about a goal, at the goal in the spec when it is known there.
pub(crate) fn render_goal_warning(
    warning: &lamp_build::GoalWarning,
    places: &lamp_lang::GoalPlaces,
    sources: &lamp_lang::SourceMap,
    colour: bool,
) -> String {
    let spans: Vec<_> = match warning.place() {
        lamp_build::GoalPlace::AtGoal { problem, object } => {
            places.at_goal(problem, object).map(|span| ("this goal", span)).into_iter().collect()
        }
        lamp_build::GoalPlace::StructureObject { problem, structure, object } => [
            places.structure_object(structure, object).map(|span| ("placed here", span)),
            places.structure_goal(problem).map(|span| ("in this goal", span)),
        ]
        .into_iter()
        .flatten()
        .collect(),
    };
    render_located(warning, &spans, sources, colour)
}

/// Renders a grab-distance warning at the robot's `grab distance`, where it is known.
pub(crate) fn render_grab_warning(
    warning: &lamp_build::GrabDistanceWarning,
    places: &lamp_lang::GoalPlaces,
    sources: &lamp_lang::SourceMap,
    colour: bool,
) -> String {
    let spans: Vec<_> = places
        .grab_distance(&warning.robot)
        .map(|span| ("a grab succeeds only in this range", span))
        .into_iter()
        .collect();
    render_located(warning, &spans, sources, colour)
}

/// Renders a frame that no bag of a source records at the mapping's `object` line, `place`,
/// where it is known.
pub(crate) fn render_frame_in_no_bag(
    error: &lamp_build::Ros2Error,
    place: Option<lamp_lang::Span>,
    sources: &lamp_lang::SourceMap,
    colour: bool,
) -> String {
    let spans: Vec<_> = place.map(|span| ("no bag records this frame", span)).into_iter().collect();
    render_located(error, &spans, sources, colour)
}

/// Renders a structure finding at the object's line in the structure and at the problem's
/// structure goal, where they are known.
pub(crate) fn render_structure_issue(
    issue: &lamp_build::StructureIssue,
    places: &lamp_lang::GoalPlaces,
    sources: &lamp_lang::SourceMap,
    colour: bool,
) -> String {
    let (structure, object) = issue.structure_object();
    let object_label = format!("`{object}` is placed here");
    let mut spans = Vec::new();
    if let Some(span) = places.structure_object(structure, object) {
        spans.push((object_label.as_str(), span));
    }
    if let Some(span) = places.structure_goal(issue.problem()) {
        spans.push(("in this goal", span));
    }
    render_located(issue, &spans, sources, colour)
}

/// Renders an initial-scene finding at the lines that place its objects or robots in the
/// problem's scene, or at its `at` goals, where they are known.
pub(crate) fn render_scene_issue(
    issue: &lamp_build::SceneIssue,
    places: &lamp_lang::GoalPlaces,
    sources: &lamp_lang::SourceMap,
    colour: bool,
) -> String {
    let problem = issue.problem();
    let located: Vec<(String, lamp_lang::Span)> = issue
        .places()
        .into_iter()
        .filter_map(|place| match place {
            lamp_build::IssuePlace::Scene(name) => places
                .scene_placement(problem, name)
                .map(|span| (format!("`{name}` is placed here"), span)),
            lamp_build::IssuePlace::AtGoal(name) => {
                places.at_goal(problem, name).map(|span| (format!("the goal of `{name}`"), span))
            }
        })
        .collect();
    let spans: Vec<(&str, lamp_lang::Span)> =
        located.iter().map(|(label, span)| (label.as_str(), *span)).collect();
    render_located(issue, &spans, sources, colour)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPEC: &str = "domain d
type table { static world  box size (1, 1, 0.05) m at (0, 0, -0.025) m }
type block { movable  box size (0.06, 0.04, 0.03) m }
structure stack {
  block b1 at (0, 0, 0.016) m
  block b2 at (0, 0, 0.067) m
}
problem p {
  scene {
    table t1 at (0, 0, 0) m
    block b1 at (0.2, 0, 0.016) m
    block b2 at (0.3, 0, 0.016) m
  }
  goal {
    structure stack at t1
  }
}
";

    #[test]
    fn a_structure_finding_points_at_the_object_and_at_the_goal() {
        let loader = lamp_lang::MemoryLoader::new([("spec.lamp", SPEC)]);
        let outcome = lamp_lang::check_source("spec.lamp", SPEC, std::path::Path::new(""), &loader);
        let issue = lamp_build::StructureIssue::Unsupported {
            problem: "p".into(),
            structure: "stack".into(),
            object: "b2".into(),
            reason: "`b2` would drop 20.0 mm onto `b1`, more than the 5 mm a release may settle"
                .into(),
        };
        let rendered = render_structure_issue(&issue, &outcome.places, &outcome.sources, false);
        for expected in [
            "lamp::build::structure_unsupported",
            "structure `stack` does not stand: `b2` would drop 20.0 mm onto `b1`",
            "  block b2 at (0, 0, 0.067) m",
            "`b2` is placed here",
            "    structure stack at t1",
            "in this goal",
            "help: Every object must rest 1 mm above the table",
        ] {
            assert!(rendered.contains(expected), "`{expected}` in:\n{rendered}");
        }
        // A finding of a problem the spec does not locate is still rendered, without source.
        let elsewhere = lamp_build::StructureIssue::Contact {
            problem: "q".into(),
            structure: "tower".into(),
            object: "b1".into(),
            other: "b2".into(),
        };
        let rendered = render_structure_issue(&elsewhere, &outcome.places, &outcome.sources, false);
        assert!(rendered.contains("lamp::build::structure_contact"), "{rendered}");
        assert!(!rendered.contains("placed here"), "{rendered}");
    }

    #[test]
    fn a_scene_finding_points_at_the_scene_lines_and_at_the_goals() {
        let spec = SPEC.replace("domain d\n", "domain d\nseed 1\ntype place { marker }\n").replace(
            "    structure stack at t1\n",
            "    at b1 (0.5, 0, 0.016) m within 0.01 m 10 deg\n    at b2 (0.5, 0, 0.016) m within 0.01 m 10 deg\n",
        );
        let loader = lamp_lang::MemoryLoader::new([("spec.lamp", spec.as_str())]);
        let outcome =
            lamp_lang::check_source("spec.lamp", &spec, std::path::Path::new(""), &loader);
        assert!(outcome.spec.is_some(), "{:?}", outcome.diagnostics);
        let render = |issue: &lamp_build::SceneIssue| {
            render_scene_issue(issue, &outcome.places, &outcome.sources, false)
        };
        let contact = lamp_build::SceneIssue::Contact {
            problem: "p".into(),
            first: "t1".into(),
            second: "b2".into(),
        };
        let rendered = render(&contact);
        for expected in [
            "    table t1 at (0, 0, 0) m",
            "`t1` is placed here",
            "    block b2 at (0.3, 0, 0.016) m",
            "`b2` is placed here",
        ] {
            assert!(rendered.contains(expected), "`{expected}` in:\n{rendered}");
        }
        let overlap = lamp_build::SceneIssue::TargetsOverlap {
            problem: "p".into(),
            first: "b1".into(),
            second: "b2".into(),
        };
        let rendered = render(&overlap);
        for expected in [
            "    at b1 (0.5, 0, 0.016) m within 0.01 m 10 deg",
            "the goal of `b1`",
            "the goal of `b2`",
        ] {
            assert!(rendered.contains(expected), "`{expected}` in:\n{rendered}");
        }
        assert!(!rendered.contains("is placed here"), "{rendered}");
    }
}
