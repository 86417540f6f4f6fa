//! Why a subcommand stopped, one type for all of them: the spec's errors (rendered already while
//! checking), a diagnostic to render, or a message to print as it is.

use miette::Diagnostic;

pub(crate) enum Failure {
    /// The spec has errors, already rendered.
    Spec,
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

impl Failure {
    /// The report, when it is an `E`: for a command whose last words depend on the error.
    pub(crate) fn report_of<E: std::error::Error + 'static>(&self) -> Option<&E> {
        match self {
            Failure::Report(report) => {
                let error: &(dyn std::error::Error + 'static) = report.as_ref();
                error.downcast_ref::<E>()
            }
            Failure::Spec | Failure::Message(_) => None,
        }
    }

    /// Prints the failure: a report rendered, a message as it is, nothing for the spec's errors.
    pub(crate) fn print(&self, colour: bool) {
        match self {
            Failure::Spec => {}
            Failure::Report(report) => {
                eprint!("{}", crate::diagnostics::render_error(report.as_ref(), colour));
            }
            Failure::Message(message) => eprintln!("{}", message.trim_end()),
        }
    }
}
