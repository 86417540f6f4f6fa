//! Records the source commit lampc is built from (`LAMP_SOURCE_COMMIT`), which `lampc eval`
//! writes into every row so that figures gathered over many commits say which code made them.
//! Outside a git checkout (a source archive) the commit is `unknown`.

use std::path::{Path, PathBuf};
use std::process::Command;

/// What `git ARGS` prints in this crate's folder, trimmed; `None` without git or a checkout.
fn git(args: &[&str]) -> Option<String> {
    let output =
        Command::new("git").args(args).current_dir(env!("CARGO_MANIFEST_DIR")).output().ok()?;
    let text = String::from_utf8(output.stdout).ok()?;
    (output.status.success() && !text.trim().is_empty()).then(|| text.trim().to_string())
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let commit = git(&["rev-parse", "HEAD"]).unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=LAMP_SOURCE_COMMIT={commit}");
    // HEAD changes on a checkout, its log on every commit, packed-refs when refs are packed;
    // only files that exist are watched, since a missing one would rerun this on every build.
    for name in ["HEAD", "logs/HEAD", "packed-refs"] {
        let Some(path) = git(&["rev-parse", "--git-path", name]) else { continue };
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(PathBuf::from(path));
        if path.exists() {
            println!("cargo:rerun-if-changed={}", path.display());
        }
    }
}
