//! Loading the bundled specs from disk for the demonstrators' tests and benches.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use lamp_spec::Spec;
use lamp_world::SpecWorld;

struct Disk;

impl lamp_lang::Loader for Disk {
    fn read_to_string(&self, path: &Path) -> Result<String, String> {
        std::fs::read_to_string(path).map_err(|error| error.to_string())
    }
    fn exists(&self, path: &Path) -> bool {
        path.is_file()
    }
    fn glob(&self, _pattern: &Path) -> Vec<PathBuf> {
        Vec::new()
    }
}

/// The checked spec of a bundled domain and its loaded world.
pub fn domain(name: &str) -> (Spec, SpecWorld) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(name);
    let path = dir.join(format!("{name}.lamp"));
    let outcome = lamp_lang::check(&path, &Disk);
    let spec = outcome.spec.unwrap_or_else(|| panic!("{name}: {:?}", outcome.diagnostics));
    let world = SpecWorld::load(&dir, &spec).unwrap_or_else(|error| panic!("{name}: {error}"));
    (spec, world)
}
