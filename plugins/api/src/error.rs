//! Errors a plugin call can end with, and errors of the host's services.

use thiserror::Error;

/// Why a host service could not answer.
#[derive(Clone, Debug, PartialEq, Eq, Error, miette::Diagnostic)]
pub enum HostError {
    /// The host offers no such service in this context (for example, no world while planning).
    #[error("the host does not offer `{service}` here")]
    #[diagnostic(code(lamp::plugin::host_unsupported))]
    Unsupported {
        /// The service's name, as in [`crate::HostServices`].
        service: String,
    },
    /// The service failed, for example for an unknown robot or link.
    #[error("{message}")]
    #[diagnostic(code(lamp::plugin::host_failed))]
    Failed {
        /// What went wrong, for the user.
        message: String,
    },
}

impl HostError {
    /// A [`HostError::Unsupported`] for `service`.
    #[must_use]
    pub fn unsupported(service: &str) -> Self {
        Self::Unsupported { service: service.to_string() }
    }

    /// A [`HostError::Failed`] with `message`.
    #[must_use]
    pub fn failed(message: impl Into<String>) -> Self {
        Self::Failed { message: message.into() }
    }
}

/// Why a plugin call produced no answer. An answer that says "no plan" or "no path" is not an
/// error: it is a status in the response.
#[derive(Clone, Debug, PartialEq, Eq, Error, miette::Diagnostic)]
pub enum PluginError {
    /// The request could not be understood (a malformed document, an unsupported wire version).
    #[error("the plugin could not understand the request: {message}")]
    #[diagnostic(code(lamp::plugin::invalid_request))]
    InvalidRequest {
        /// What was wrong with it.
        message: String,
    },
    /// A host service the plugin relies on failed.
    #[error("a host service failed: {0}")]
    #[diagnostic(code(lamp::plugin::host_service))]
    Host(#[from] HostError),
    /// The plugin stopped because the host asked it to.
    #[error("the plugin stopped because the run was cancelled")]
    #[diagnostic(code(lamp::plugin::cancelled))]
    Cancelled,
    /// The plugin panicked; the panic was caught at the plugin boundary.
    #[error("the plugin panicked: {message}")]
    #[diagnostic(
        code(lamp::plugin::panicked),
        help("this is a bug in the plugin; report it to the plugin's authors with this message")
    )]
    Panicked {
        /// The panic message.
        message: String,
    },
    /// The plugin failed for a reason of its own.
    #[error("the plugin failed: {message}")]
    #[diagnostic(code(lamp::plugin::failed))]
    Failed {
        /// What went wrong.
        message: String,
    },
}

impl PluginError {
    /// A [`PluginError::Failed`] with `message`.
    #[must_use]
    pub fn failed(message: impl Into<String>) -> Self {
        Self::Failed { message: message.into() }
    }

    /// A [`PluginError::InvalidRequest`] with `message`.
    #[must_use]
    pub fn invalid_request(message: impl Into<String>) -> Self {
        Self::InvalidRequest { message: message.into() }
    }
}
