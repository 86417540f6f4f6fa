//! Loading the bundled specs from disk for the world's tests.

#![allow(dead_code, clippy::unwrap_used)]

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
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains").join(name);
    let path = dir.join(format!("{name}.lamp"));
    let outcome = lamp_lang::check(&path, &Disk);
    let spec = outcome.spec.unwrap_or_else(|| panic!("{name}: {:?}", outcome.diagnostics));
    let world = SpecWorld::load(&dir, &spec).unwrap();
    (spec, world)
}

/// A pose from a translation and roll, pitch, yaw (radians).
pub fn pose(x: f64, y: f64, z: f64, roll: f64, pitch: f64, yaw: f64) -> lamp_geometry::Pose {
    lamp_geometry::Pose::from_parts(
        nalgebra::Translation3::new(x, y, z),
        nalgebra::UnitQuaternion::from_euler_angles(roll, pitch, yaw),
    )
}
