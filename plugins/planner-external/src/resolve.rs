//! Finding the planner to run: the configured command, else a driver on `PATH`, else the driver
//! shipped inside a pip package.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::error::ExternalError;
use crate::options::{COMMAND_OPTION, CommandLine, ExternalOptions, KSTAR_COMMAND_OPTION};

/// Which planner family a call needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Engine {
    /// Fast Downward's lazy greedy search: one plan.
    FastDownward,
    /// K*: the top-k plans.
    KStar,
}

impl Engine {
    /// The engine's name, for messages.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Engine::FastDownward => "Fast Downward",
            Engine::KStar => "K*",
        }
    }
}

/// Fast Downward's driver under the names its own build and distributions install.
const DRIVER_NAMES: [&str; 2] = ["fast-downward", "fast-downward.py"];

/// The driver script inside the `up-fast-downward` wheel; the package has no `-m` entry point.
/// The package is located, not imported: importing it needs `unified-planning`, which the driver
/// does not.
const UP_FAST_DOWNWARD_DRIVER: &str = "import importlib.util, os\n\
     spec = importlib.util.find_spec('up_fast_downward')\n\
     print(os.path.join(spec.submodule_search_locations[0], 'downward', 'fast-downward.py'))";

/// The `downward` build inside the `kstar-planner` wheel, which its driver needs as `--build`.
const KSTAR_BUILD: &str = "import importlib.util, os\n\
     spec = importlib.util.find_spec('kstar_planner')\n\
     print(os.path.join(spec.submodule_search_locations[0], 'builds', 'release', 'bin'))";

/// The command that runs `engine`, in the documented order.
///
/// # Errors
/// [`ExternalError::NotInstalled`] naming everything that was tried.
pub fn resolve(engine: Engine, options: &ExternalOptions) -> Result<CommandLine, ExternalError> {
    match engine {
        Engine::FastDownward => {
            if let Some(command) = &options.command {
                return Ok(command.clone());
            }
            if let Some(path) = DRIVER_NAMES.iter().find_map(|name| find_on_path(name)) {
                return Ok(CommandLine::program(path.to_string_lossy()));
            }
            if let Some(driver) = python_path(&options.python, UP_FAST_DOWNWARD_DRIVER) {
                return Ok(CommandLine {
                    program: options.python.clone(),
                    arguments: vec![driver.to_string_lossy().into_owned()],
                });
            }
            Err(ExternalError::NotInstalled {
                purpose: "one plan".to_string(),
                tried: format!(
                    "option `{COMMAND_OPTION}`, `fast-downward` and `fast-downward.py` on PATH, \
                     and the pip package up-fast-downward for `{}`",
                    options.python
                ),
            })
        }
        Engine::KStar => {
            if let Some(command) = &options.kstar_command {
                return Ok(command.clone());
            }
            if let Some(build) = python_path(&options.python, KSTAR_BUILD) {
                return Ok(CommandLine {
                    program: options.python.clone(),
                    arguments: vec![
                        "-B".to_string(),
                        "-m".to_string(),
                        "kstar_planner.driver.main".to_string(),
                        "--build".to_string(),
                        build.to_string_lossy().into_owned(),
                    ],
                });
            }
            Err(ExternalError::NotInstalled {
                purpose: "more than one plan".to_string(),
                tried: format!(
                    "option `{KSTAR_COMMAND_OPTION}` and the pip package kstar-planner for `{}`",
                    options.python
                ),
            })
        }
    }
}

/// The first executable file called `name` in the folders of `PATH`.
fn find_on_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path).map(|folder| folder.join(name)).find(|file| is_executable(file))
}

#[cfg(unix)]
fn is_executable(file: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(file)
        .is_ok_and(|meta| meta.is_file() && meta.permissions().mode() & 0o111 != 0)
}

#[cfg(not(unix))]
fn is_executable(file: &Path) -> bool {
    file.is_file()
}

/// Runs `script` with `python` and returns the path it prints, when the interpreter, the package
/// and the printed path all exist.
fn python_path(python: &str, script: &str) -> Option<PathBuf> {
    let output = Command::new(python)
        .args(["-c", script])
        .stdin(Stdio::null())
        .stderr(Stdio::null())
        .output()
        .ok()?;
    if !output.status.success() {
        return None;
    }
    let path = PathBuf::from(String::from_utf8(output.stdout).ok()?.trim());
    path.exists().then_some(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_configured_command_wins_without_looking_further() {
        let options = ExternalOptions {
            command: Some(CommandLine::program("/nowhere/fd")),
            kstar_command: Some(CommandLine::program("/nowhere/kstar")),
            ..ExternalOptions::default()
        };
        let fast_downward = resolve(Engine::FastDownward, &options).expect("configured");
        assert_eq!(fast_downward.program, "/nowhere/fd");
        assert_eq!(resolve(Engine::KStar, &options).expect("configured").program, "/nowhere/kstar");
    }

    #[test]
    fn nothing_found_names_what_was_tried() {
        let options = ExternalOptions {
            python: "/nowhere/python3".to_string(),
            ..ExternalOptions::default()
        };
        // `fast-downward` may be on this machine's PATH; K* is only found through Python.
        let error = resolve(Engine::KStar, &options).expect_err("no interpreter, no K*");
        assert!(matches!(error, ExternalError::NotInstalled { .. }), "{error:?}");
        let message = error.to_string();
        assert!(message.contains("kstar-planner") && message.contains("/nowhere/python3"));
    }
}
