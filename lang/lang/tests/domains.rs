//! Every bundled domain spec checks cleanly; its typed spec is pinned by a snapshot.

mod common;

use std::path::{Path, PathBuf};

/// The disk, for the bundled specs (the front end itself never touches it).
struct Disk;

impl lamp_lang::Loader for Disk {
    fn read_to_string(&self, path: &Path) -> Result<String, String> {
        std::fs::read_to_string(path).map_err(|e| e.to_string())
    }
    fn file_kind(&self, path: &Path) -> lamp_lang::FileKind {
        match path.is_file() {
            true => lamp_lang::FileKind::File,
            false => lamp_lang::FileKind::Missing,
        }
    }
    /// Recorded demonstrations are generated, never bundled: a `files` pattern stands for the
    /// files it would match.
    fn glob(&self, pattern: &Path) -> Vec<PathBuf> {
        vec![pattern.to_path_buf()]
    }
    /// Robot files are read by `lamp-robot`, which this crate does not know: the workspace's
    /// domain tests check the names (`lamp-test-support` loads them).
    fn robot_names(
        &self,
        _path: &Path,
        _kind: lamp_spec::RobotKind,
    ) -> Result<Option<lamp_spec::RobotNames>, String> {
        Ok(None)
    }
}

fn check_domain(name: &str) {
    let root = common::domains_dir();
    let spec_path = root.join(name).join(format!("{name}.lamp"));
    let text = std::fs::read_to_string(&spec_path).expect("the bundled spec exists");
    let outcome = lamp_lang::check_source(&format!("{name}.lamp"), &text, &root.join(name), &Disk);
    let rendered = common::render(&outcome);
    let spec = outcome.spec.unwrap_or_else(|| panic!("{name} does not check:\n{rendered}"));
    assert_eq!(spec.domain, name);
    assert!(!spec.problems.is_empty(), "{name} has a problem to solve");
    insta::assert_debug_snapshot!(format!("domain_{name}"), spec);
}

#[test]
fn packing_checks() {
    check_domain("packing");
}

#[test]
fn cafe_checks() {
    check_domain("cafe");
}

#[test]
fn keva_checks() {
    check_domain("keva");
}

#[test]
fn jenga_checks() {
    check_domain("jenga");
}

#[test]
fn dinner_checks() {
    check_domain("dinner");
}

#[test]
fn cubes_checks() {
    check_domain("cubes");
}
