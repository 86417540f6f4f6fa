//! The `.lamp` front end: `lamp_lang::check` on arbitrary text through an in-memory loader.
//!
//! The input is the spec, optionally followed by a NUL byte and the text of `scene.lamp`, a scene
//! file the spec may read with `scene "scene.lamp"`. The spec lives in `domains/fuzz/`, so the
//! bundled robots are at `../robots/*.urdf` as in the bundled specs; the loader holds them with
//! their real contents, plus a small mesh, one demonstration file and one plugin library, and
//! answers "missing" for every other path. Nothing touches the disk.

use std::path::{Path, PathBuf};

use lamp_lang::{CheckOutcome, MemoryLoader};

use crate::{check_diagnostic, two_texts};

/// The folder the fuzzed spec is in.
const SPEC_DIR: &str = "domains/fuzz";

/// The bundled robots, where `../robots/NAME.urdf` from [`SPEC_DIR`] finds them.
const ROBOTS: &[(&str, &str)] = &[
    ("domains/robots/fetch.urdf", include_str!("../../../domains/robots/fetch.urdf")),
    (
        "domains/robots/magnetic_gripper.urdf",
        include_str!("../../../domains/robots/magnetic_gripper.urdf"),
    ),
    (
        "domains/robots/two_finger_gripper.urdf",
        include_str!("../../../domains/robots/two_finger_gripper.urdf"),
    ),
    ("domains/robots/yumi.urdf", include_str!("../../../domains/robots/yumi.urdf")),
];

/// Other files a spec may name, relative to [`SPEC_DIR`], with small fixed contents.
const OTHER_FILES: &[(&str, &str)] = &[
    ("meshes/part.stl", "solid part\nendsolid part\n"),
    ("demos/demo_000.mcap", ""),
    ("plugins/libplanner.so", ""),
];

/// Checks the spec of `data` (see the module documentation for the layout).
///
/// # Panics
/// When the checker panics, returns a spec together with diagnostics (or neither), or reports a
/// diagnostic whose label lies outside its file.
pub fn check(data: &[u8]) {
    let outcome = check_outcome(data);
    assert_eq!(
        outcome.spec.is_some(),
        outcome.diagnostics.is_empty(),
        "a spec comes back exactly when there is no diagnostic: {:?}",
        outcome.diagnostics
    );
    for (index, diagnostic) in outcome.diagnostics.iter().enumerate() {
        let text = outcome.sources.text(diagnostic.file);
        let name = outcome.sources.name(diagnostic.file);
        check_diagnostic(&diagnostic.with_source(&outcome.sources), text, name, index);
    }
}

/// The checker's outcome for the spec (and scene file) of `data`.
fn check_outcome(data: &[u8]) -> CheckOutcome {
    let (spec, scene) = two_texts(data);
    let dir = Path::new(SPEC_DIR);
    let spec_path = dir.join("spec.lamp");
    let mut files: Vec<(PathBuf, String)> = ROBOTS
        .iter()
        .map(|(path, text)| (PathBuf::from(path), text.to_string()))
        .chain(OTHER_FILES.iter().map(|(path, text)| (dir.join(path), text.to_string())))
        .collect();
    files.push((spec_path.clone(), spec));
    if let Some(scene) = scene {
        files.push((dir.join("scene.lamp"), scene));
    }
    lamp_lang::check(&spec_path, &MemoryLoader::new(files))
}

#[cfg(test)]
mod tests {
    use super::*;

    const PACKING: &str = include_str!("../../../domains/packing/packing.lamp");

    #[test]
    fn a_bundled_spec_checks_with_the_fuzz_loader() {
        // The bundled specs name `../robots/*.urdf`: the loader must have them where they
        // resolve, or the fuzzer would spend its time on "missing file" diagnostics.
        let outcome = check_outcome(PACKING.as_bytes());
        assert!(outcome.diagnostics.is_empty(), "{:?}", outcome.diagnostics);
        check(PACKING.as_bytes());
    }

    #[test]
    fn a_scene_file_follows_the_nul() {
        // The first inline scene moved to the scene file after the NUL.
        let start = PACKING.find("  scene {").expect("packing has an inline scene");
        let end = start + PACKING[start..].find("\n  }\n").expect("the scene block ends") + 5;
        let body = &PACKING[start + "  scene {".len()..end - 5];
        let spec = format!("{}  scene \"scene.lamp\"\n{}", &PACKING[..start], &PACKING[end..]);
        let outcome = check_outcome(format!("{spec}\0{body}\n").as_bytes());
        assert!(outcome.diagnostics.is_empty(), "{:?}", outcome.diagnostics);
        // Without the scene file the same spec names a missing file.
        let outcome = check_outcome(spec.as_bytes());
        let codes: Vec<String> = outcome.diagnostics.iter().map(|d| d.code()).collect();
        assert_eq!(codes, ["lamp::check::missing_file"]);
    }
}
