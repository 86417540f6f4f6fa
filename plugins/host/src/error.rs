//! Why a plugin could not be loaded or created.

use std::path::PathBuf;

use lamp_plugin_api::PluginError;
use thiserror::Error;

use crate::plugin_info::PluginKind;

/// A refusal to load or create a plugin.
#[derive(Debug, Error, miette::Diagnostic)]
pub enum LoadError {
    /// The dynamic loader could not open the file.
    #[error("cannot load the plugin library {path}: {message}")]
    #[diagnostic(
        code(lamp::plugin::load),
        help("check that the file exists and is a shared library built for this platform")
    )]
    Load {
        /// The library's path.
        path: PathBuf,
        /// The loader's message.
        message: String,
    },

    /// The library does not export the entry symbol.
    #[error("{path} is not a lamp plugin: it does not export `{symbol}`")]
    #[diagnostic(
        code(lamp::plugin::missing_symbol),
        help("a plugin library exports its entry with `lamp_plugin_sdk::export_plugin!`")
    )]
    MissingSymbol {
        /// The library's path.
        path: PathBuf,
        /// The symbol looked for.
        symbol: &'static str,
    },

    /// The plugin was built for another ABI version.
    #[error(
        "{origin} was built for plugin ABI v{plugin_major}.{plugin_minor}; this host speaks v{host_major}.{host_minor}"
    )]
    #[diagnostic(
        code(lamp::plugin::abi_mismatch),
        help("rebuild the plugin against lamp-plugin-sdk ABI v{host_major}")
    )]
    AbiMismatch {
        /// Where the plugin came from.
        origin: String,
        /// The plugin's ABI major.
        plugin_major: u32,
        /// The plugin's ABI minor.
        plugin_minor: u32,
        /// The host's ABI major.
        host_major: u32,
        /// The host's ABI minor.
        host_minor: u32,
    },

    /// A table of the plugin is smaller than its declared ABI version requires.
    #[error(
        "{origin} declares a {table} of {declared} bytes; ABI v{host_major} needs at least {required}"
    )]
    #[diagnostic(
        code(lamp::plugin::abi_mismatch),
        help("rebuild the plugin against lamp-plugin-sdk ABI v{host_major}")
    )]
    TableTooSmall {
        /// Where the plugin came from.
        origin: String,
        /// Which table.
        table: &'static str,
        /// Its declared size.
        declared: usize,
        /// The least size accepted.
        required: usize,
        /// The host's ABI major.
        host_major: u32,
    },

    /// The descriptor or a required function is missing or malformed.
    #[error("{origin} has an invalid descriptor: {problem}")]
    #[diagnostic(
        code(lamp::plugin::invalid_descriptor),
        help("a plugin library exports its entry with `lamp_plugin_sdk::export_plugin!`")
    )]
    InvalidDescriptor {
        /// Where the plugin came from.
        origin: String,
        /// What is wrong.
        problem: String,
    },

    /// The plugin is of another kind than the one asked for.
    #[error("plugin `{name}` is a {found}, not a {expected}")]
    #[diagnostic(
        code(lamp::plugin::wrong_kind),
        help("select this plugin where a {found} is expected, or choose a {expected} plugin")
    )]
    WrongKind {
        /// The plugin's name.
        name: String,
        /// The kind asked for.
        expected: PluginKind,
        /// The plugin's kind.
        found: PluginKind,
    },

    /// The plugin refused to create an instance.
    #[error("plugin `{name}` could not be created")]
    #[diagnostic(code(lamp::plugin::create))]
    Create {
        /// The plugin's name.
        name: String,
        /// The plugin's reason.
        #[source]
        #[diagnostic_source]
        source: PluginError,
    },

    /// The plugin panicked while creating an instance.
    #[error("plugin `{name}` panicked while being created: {message}")]
    #[diagnostic(
        code(lamp::plugin::panicked),
        help("this is a bug in the plugin; report it to the plugin's authors with this message")
    )]
    Panicked {
        /// The plugin's name.
        name: String,
        /// The panic message.
        message: String,
    },
}
