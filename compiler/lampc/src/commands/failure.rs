//! How a subcommand ends, one type for all of them: done, or stopped with the reason and what it
//! left on disk. Subcommands return it; `main` alone renders a stop and chooses the exit code.

use miette::Diagnostic;

/// What a subcommand that did its job reports with its exit code.
pub(crate) enum Finished {
    /// All of it.
    Done,
    /// A result short of what was asked, written all the same (a solve to a relaxed goal).
    Partial,
}

/// Why a subcommand stopped.
pub(crate) enum Failure {
    /// Said already, where it happened: the spec's diagnostics, findings rendered with their
    /// places in the spec, the summary of an interrupted evaluation.
    Said,
    /// A diagnostic to render.
    Report(Box<dyn Diagnostic + Send + Sync>),
    /// A message to print as it is.
    Message(String),
}

impl<E: Diagnostic + Send + Sync + 'static> From<E> for Failure {
    fn from(error: E) -> Self {
        Failure::Report(Box::new(error))
    }
}

/// A subcommand that stopped short: why, what followed from it, and what it left behind.
pub(crate) struct Stopped {
    pub(crate) failure: Failure,
    /// Lines said after the failure (the time limit that ran out).
    pub(crate) notes: Vec<String>,
    /// What the command left on disk ("no model was written"), said in its last line.
    pub(crate) left: Option<String>,
    /// Stopped by Ctrl-C or SIGTERM rather than by a failure.
    pub(crate) interrupted: bool,
}

impl<F: Into<Failure>> From<F> for Stopped {
    fn from(failure: F) -> Self {
        Stopped { failure: failure.into(), notes: Vec::new(), left: None, interrupted: false }
    }
}

/// The exit code after Ctrl-C or SIGTERM, as shells report a process ended by SIGINT.
pub(crate) const EXIT_INTERRUPTED: u8 = 130;

impl Stopped {
    /// A stop whose reason has been said already.
    pub(crate) fn said() -> Self {
        Stopped::from(Failure::Said)
    }

    /// The same stop, saying in its last line what `command` left on disk.
    pub(crate) fn leaving(self, left: impl Into<String>) -> Self {
        Stopped { left: Some(left.into()), ..self }
    }

    pub(crate) fn exit_code(&self) -> u8 {
        if self.interrupted { EXIT_INTERRUPTED } else { crate::EXIT_DIAGNOSTICS }
    }

    /// Prints the stop of `command` to standard error, as [`Stopped::render`] writes it.
    pub(crate) fn print(&self, command: &str, colour: bool) {
        eprint!("{}", self.render(command, colour));
    }

    /// The stop of `command` as the user reads it: the failure (unless said already), the notes,
    /// then one last line, "lampc COMMAND: failed; LEFT", unless there is nothing to add to what
    /// was said.
    pub(crate) fn render(&self, command: &str, colour: bool) -> String {
        let mut text = match &self.failure {
            Failure::Said => String::new(),
            Failure::Report(report) => crate::diagnostics::render_error(report.as_ref(), colour),
            Failure::Message(message) => format!("{}\n", message.trim_end()),
        };
        for note in &self.notes {
            text.push_str(&format!("lampc {command}: {note}\n"));
        }
        let how = if self.interrupted { "interrupted" } else { "failed" };
        match (&self.failure, &self.left) {
            (Failure::Said, None) => {}
            (_, None) => text.push_str(&format!("lampc {command}: {how}\n")),
            (_, Some(left)) => text.push_str(&format!("lampc {command}: {how}; {left}\n")),
        }
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, thiserror::Error, miette::Diagnostic)]
    #[error("the model is stale")]
    #[diagnostic(code(lamp::test::stale), help("build again"))]
    struct Stale;

    #[test]
    fn a_stop_already_said_adds_only_what_it_left() {
        assert_eq!(Stopped::said().render("check", false), "");
        let left = Stopped::said().leaving("no model was written");
        assert_eq!(left.render("build", false), "lampc build: failed; no model was written\n");
    }

    #[test]
    fn a_report_is_rendered_once_with_its_code_then_the_notes_and_the_last_line() {
        let stopped = Stopped {
            notes: vec!["the time limit of 2 s (`--timeout`) ran out".to_string()],
            ..Stopped::from(Stale).leaving("no solution files were written")
        };
        let text = stopped.render("solve", false);
        assert_eq!(text.matches("the model is stale").count(), 1, "{text}");
        assert!(text.contains("lamp::test::stale") && text.contains("build again"), "{text}");
        assert!(
            text.ends_with(
                "lampc solve: the time limit of 2 s (`--timeout`) ran out\n\
                 lampc solve: failed; no solution files were written\n"
            ),
            "{text}"
        );
        assert_eq!(stopped.exit_code(), crate::EXIT_DIAGNOSTICS);
    }

    #[test]
    fn an_interrupted_stop_says_so_and_exits_as_after_sigint() {
        let stopped = Stopped {
            interrupted: true,
            ..Stopped::from(Failure::Message("stopped at step 3".to_string()))
        };
        assert_eq!(stopped.render("solve", false), "stopped at step 3\nlampc solve: interrupted\n");
        assert_eq!(stopped.exit_code(), EXIT_INTERRUPTED);
    }
}
