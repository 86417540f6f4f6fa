//! Architecture rules checked on every `cargo test`: the code map in `docs/ARCHITECTURE.md` is
//! the law, and this test is its enforcement.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

use lamp_tests::workspace_root;

/// External crates that may appear in exactly the listed workspace crates.
const CONFINED_DEPENDENCIES: &[(&str, &[&str])] = &[
    ("pest", &["lamp-lang", "lamp-pddl"]),
    ("pest_derive", &["lamp-lang", "lamp-pddl"]),
    ("parry3d-f64", &["lamp-geometry"]),
    ("mcap", &["lamp-trajectory"]),
    ("urdf-rs", &["lamp-robot"]),
    ("libloading", &["lamp-plugin-host"]),
];

struct Manifest {
    name: String,
    dir: PathBuf,
    table: toml::Table,
}

fn read_toml(path: &Path) -> toml::Table {
    let text = fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.parse::<toml::Table>().unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn workspace_manifests() -> Vec<Manifest> {
    let root = workspace_root();
    let workspace = read_toml(&root.join("Cargo.toml"));
    let members =
        workspace["workspace"]["members"].as_array().expect("workspace.members is a list");
    members
        .iter()
        .map(|member| {
            let dir = root.join(member.as_str().expect("member paths are strings"));
            let table = read_toml(&dir.join("Cargo.toml"));
            let name = table["package"]["name"].as_str().expect("package.name").to_string();
            Manifest { name, dir, table }
        })
        .collect()
}

fn dependency_names(manifest: &Manifest, section: &str) -> BTreeSet<String> {
    manifest
        .table
        .get(section)
        .and_then(|deps| deps.as_table())
        .map(|deps| deps.keys().cloned().collect())
        .unwrap_or_default()
}

/// The "Dependency rules" table of `docs/ARCHITECTURE.md`: crate → internal crates it may use.
fn documented_dependency_rules() -> BTreeMap<String, BTreeSet<String>> {
    let text = fs::read_to_string(workspace_root().join("docs/ARCHITECTURE.md"))
        .expect("docs/ARCHITECTURE.md exists");
    let section =
        text.split("## Dependency rules").nth(1).expect("a `## Dependency rules` section");
    let mut rules = BTreeMap::new();
    for line in section.lines().take_while(|line| !line.starts_with("## ")) {
        let cells: Vec<&str> = line.trim().trim_matches('|').split('|').map(str::trim).collect();
        if cells.len() != 2 || cells[0] == "crate" || cells[0].starts_with("---") {
            continue;
        }
        let allowed = cells[1]
            .split(',')
            .map(str::trim)
            .filter(|name| !name.is_empty() && *name != "—" && *name != "everything above")
            .map(str::to_string)
            .collect();
        rules.insert(cells[0].to_string(), allowed);
    }
    rules
}

#[test]
fn internal_dependencies_follow_the_code_map() {
    let manifests = workspace_manifests();
    let internal: BTreeSet<String> = manifests.iter().map(|m| m.name.clone()).collect();
    let rules = documented_dependency_rules();
    let mut violations = Vec::new();
    for manifest in &manifests {
        if manifest.name == "lamp-tests" || manifest.name == "lampc" {
            continue; // the binary and the workspace tests may use everything
        }
        let Some(allowed) = rules.get(&manifest.name) else {
            violations.push(format!(
                "{} is missing from the table in docs/ARCHITECTURE.md",
                manifest.name
            ));
            continue;
        };
        for dependency in dependency_names(manifest, "dependencies") {
            if internal.contains(&dependency) && !allowed.contains(&dependency) {
                violations.push(format!(
                    "{} depends on {dependency}, which docs/ARCHITECTURE.md does not allow",
                    manifest.name
                ));
            }
        }
    }
    assert!(violations.is_empty(), "{}", violations.join("\n"));
}

#[test]
fn sensitive_dependencies_stay_in_their_crate() {
    let mut violations = Vec::new();
    for manifest in workspace_manifests() {
        let used: BTreeSet<String> = ["dependencies", "dev-dependencies", "build-dependencies"]
            .iter()
            .flat_map(|section| dependency_names(&manifest, section))
            .collect();
        for (dependency, owners) in CONFINED_DEPENDENCIES {
            if used.contains(*dependency) && !owners.contains(&manifest.name.as_str()) {
                violations
                    .push(format!("{} uses {dependency}, confined to {owners:?}", manifest.name));
            }
        }
    }
    assert!(violations.is_empty(), "{}", violations.join("\n"));
}

#[test]
fn every_workspace_dependency_says_why_it_is_there() {
    let text = fs::read_to_string(workspace_root().join("Cargo.toml")).expect("root Cargo.toml");
    let section = text
        .split("[workspace.dependencies]")
        .nth(1)
        .and_then(|rest| rest.split("\n[").next())
        .expect("a [workspace.dependencies] section");
    let mut previous = "";
    let mut unexplained = Vec::new();
    for line in section.lines().map(str::trim) {
        let is_entry = !line.is_empty() && !line.starts_with('#');
        let is_internal = line.starts_with("lamp-");
        if is_entry && !is_internal && !previous.starts_with('#') {
            unexplained.push(line.to_string());
        }
        previous = line;
    }
    assert!(
        unexplained.is_empty(),
        "dependencies without a comment line above:\n{}",
        unexplained.join("\n")
    );
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|ext| ext == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn every_source_module_starts_with_its_documentation() {
    let mut undocumented = Vec::new();
    for manifest in workspace_manifests() {
        let mut files = Vec::new();
        rust_files(&manifest.dir.join("src"), &mut files);
        for file in files {
            let text = fs::read_to_string(&file).expect("readable source");
            if !text.trim_start().starts_with("//!") {
                undocumented.push(file.display().to_string());
            }
        }
    }
    assert!(undocumented.is_empty(), "modules without a `//!` doc:\n{}", undocumented.join("\n"));
}

#[test]
fn no_test_is_ignored_or_expected_to_panic() {
    let mut offenders = Vec::new();
    for manifest in workspace_manifests() {
        let mut files = Vec::new();
        rust_files(&manifest.dir, &mut files);
        for file in files {
            let text = fs::read_to_string(&file).expect("readable source");
            let should_panic = ["#[should", "_panic"].concat();
            let ignore = ["#[", "ignore]"].concat();
            if text.contains(&should_panic) || text.contains(&ignore) {
                offenders.push(file.display().to_string());
            }
        }
    }
    assert!(offenders.is_empty(), "ignored or should-panic tests:\n{}", offenders.join("\n"));
}
