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
    ("rapier3d-f64", &["lamp-physics"]),
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

/// Crates that sit on top: they put the libraries together for one command, so no library may
/// depend on them (the binary, the workspace tests and the fuzz entries may).
const ORCHESTRATION_CRATES: &[&str] = &["lamp-build", "lamp-eval", "lamp-tamp", "lampc"];
/// Crates that may use the orchestration crates as normal dependencies.
const ORCHESTRATION_USERS: &[&str] = &["lampc", "lamp-tests", "lamp-fuzz-entries"];

#[test]
fn no_library_depends_on_an_orchestration_crate() {
    let mut violations = Vec::new();
    for manifest in workspace_manifests() {
        if ORCHESTRATION_USERS.contains(&manifest.name.as_str()) {
            continue;
        }
        for dependency in dependency_names(&manifest, "dependencies") {
            if ORCHESTRATION_CRATES.contains(&dependency.as_str()) {
                violations.push(format!("{} depends on {dependency}", manifest.name));
            }
        }
    }
    assert!(
        violations.is_empty(),
        "arrows up into the orchestration layer:\n{}",
        violations.join("\n")
    );
}

/// The only compiler and runtime crates a first-party plugin may link: small leaves that need
/// neither geometry, robots, files nor the learner.
const PLUGIN_LEAVES: &[&str] = &["lamp-pddl", "lamp-planner", "lamp-rrt", "lamp-abstraction"];

#[test]
fn plugins_link_only_the_plugin_contract_and_small_leaves() {
    let root = workspace_root();
    let manifests = workspace_manifests();
    let internal: BTreeSet<String> = manifests.iter().map(|m| m.name.clone()).collect();
    let plugin_crates: BTreeSet<String> = manifests
        .iter()
        .filter(|m| m.dir.starts_with(root.join("plugins")))
        .map(|m| m.name.clone())
        .collect();
    let mut violations = Vec::new();
    for manifest in manifests.iter().filter(|m| plugin_crates.contains(&m.name)) {
        for dependency in dependency_names(manifest, "dependencies") {
            let allowed =
                plugin_crates.contains(&dependency) || PLUGIN_LEAVES.contains(&dependency.as_str());
            if internal.contains(&dependency) && !allowed {
                violations.push(format!("{} depends on {dependency}", manifest.name));
            }
        }
    }
    assert!(violations.is_empty(), "plugins linking heavy crates:\n{}", violations.join("\n"));
}

/// The code of a crate's `src/` files: each cut at its tests, without comment lines (whose
/// examples are not the crate's code).
fn library_source(manifest: &Manifest) -> Vec<(PathBuf, String)> {
    let mut files = Vec::new();
    rust_files(&manifest.dir.join("src"), &mut files);
    files.sort();
    files
        .into_iter()
        .map(|file| {
            let code = code_of(&fs::read_to_string(&file).expect("readable source"));
            (file, code)
        })
        .collect()
}

/// A source file's code: cut at its tests, without comment lines.
fn code_of(text: &str) -> String {
    text.split("#[cfg(test)]")
        .next()
        .unwrap_or_default()
        .lines()
        .filter(|line| !line.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn every_plugin_reads_its_configuration_as_one_json_object() {
    let root = workspace_root();
    let mut violations = Vec::new();
    for manifest in workspace_manifests().iter().filter(|m| m.dir.starts_with(root.join("plugins")))
    {
        let source = library_source(manifest);
        let makes = source.iter().any(|(_, code)| code.contains("impl PluginFactory for"));
        let reads = source.iter().any(|(_, code)| code.contains("PluginConfig::parse("));
        if makes && !reads {
            violations.push(manifest.name.clone());
        }
    }
    assert!(
        violations.is_empty(),
        "plugins whose factory does not read lamp_plugin_api::PluginConfig:\n{}",
        violations.join("\n")
    );
}

#[test]
fn lampc_names_first_party_plugins_only_in_its_one_factory_table() {
    let manifests = workspace_manifests();
    let lampc = manifests.iter().find(|m| m.name == "lampc").expect("lampc is a member");
    let plugin_crates =
        ["lamp_planner_builtin", "lamp_planner_external", "lamp_refiner_gmm", "lamp_motion_rrt"];
    let mut violations = Vec::new();
    for (file, code) in library_source(lampc) {
        if file.ends_with("builtin_plugins.rs") {
            continue;
        }
        for name in plugin_crates.iter().filter(|name| code.contains(&format!("{name}::"))) {
            violations.push(format!("{} names {name}", file.display()));
        }
    }
    assert!(
        violations.is_empty(),
        "built-in plugins made outside compiler/lampc/src/builtin_plugins.rs:\n{}",
        violations.join("\n")
    );
}

/// The crate-internal modules a source file names (`crate::name`, `crate::{a, b}`), outside
/// comments and after its tests are cut off.
fn named_modules(text: &str) -> BTreeSet<String> {
    let code = code_of(text);
    let identifier = |rest: &str| -> String {
        rest.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect()
    };
    let mut names = BTreeSet::new();
    for (index, _) in code.match_indices("crate::") {
        let rest = &code[index + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let group = group.split('}').next().unwrap_or_default();
            for item in group.split(',') {
                names.insert(identifier(item.trim()));
            }
        } else {
            names.insert(identifier(rest));
        }
    }
    names.retain(|name| !name.is_empty());
    names
}

/// Module → the sibling modules it names, for the top-level modules of one crate's `src`.
fn module_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut files = Vec::new();
    rust_files(src, &mut files);
    for file in files {
        let relative = file.strip_prefix(src).expect("under src");
        let Some(first) = relative.components().next() else { continue };
        let module = first.as_os_str().to_string_lossy().trim_end_matches(".rs").to_string();
        if module == "lib" || module == "main" {
            continue;
        }
        let text = fs::read_to_string(&file).expect("readable source");
        let names = named_modules(&text);
        graph.entry(module.clone()).or_default().extend(names.into_iter().filter(|n| *n != module));
    }
    let modules: BTreeSet<String> = graph.keys().cloned().collect();
    for names in graph.values_mut() {
        names.retain(|name| modules.contains(name));
    }
    graph
}

/// A cycle through `start`, if there is one, as the modules along it.
fn cycle_through(graph: &BTreeMap<String, BTreeSet<String>>, start: &str) -> Option<Vec<String>> {
    let mut stack = vec![(start.to_string(), vec![start.to_string()])];
    let mut seen = BTreeSet::new();
    while let Some((module, path)) = stack.pop() {
        for next in graph.get(&module).into_iter().flatten() {
            if next == start {
                return Some(path.clone());
            }
            if seen.insert(next.clone()) {
                let mut longer = path.clone();
                longer.push(next.clone());
                stack.push((next.clone(), longer));
            }
        }
    }
    None
}

#[test]
fn no_crate_has_an_import_loop_between_its_modules() {
    let mut loops = BTreeSet::new();
    for manifest in workspace_manifests() {
        let graph = module_graph(&manifest.dir.join("src"));
        for module in graph.keys() {
            if let Some(mut cycle) = cycle_through(&graph, module) {
                // One entry per loop, however it is entered.
                let smallest = cycle.iter().enumerate().min_by_key(|(_, m)| *m).map(|(i, _)| i);
                cycle.rotate_left(smallest.unwrap_or(0));
                loops.insert(format!("{}: {}", manifest.name, cycle.join(" → ")));
            }
        }
    }
    assert!(
        loops.is_empty(),
        "modules that import each other (move what they share into a leaf module):\n{}",
        loops.into_iter().collect::<Vec<_>>().join("\n")
    );
}
