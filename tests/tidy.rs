//! Architecture rules checked on every `cargo test`: the code map in `docs/ARCHITECTURE.md` is
//! the law, and this test is its enforcement.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

use lamp_tests::workspace_root;
use petgraph::graphmap::DiGraphMap;
use proc_macro2::{TokenStream, TokenTree};
use syn::visit::{self, Visit};

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

/// The top-level folders in the order of `docs/ARCHITECTURE.md`'s "Folders, from the bottom
/// up" line.
fn documented_folder_order() -> Vec<String> {
    let text = fs::read_to_string(workspace_root().join("docs/ARCHITECTURE.md"))
        .expect("docs/ARCHITECTURE.md exists");
    let line = text
        .lines()
        .find(|line| line.starts_with("Folders, from the bottom up:"))
        .expect("a `Folders, from the bottom up:` line");
    line.split('`')
        .skip(1)
        .step_by(2)
        .map(|folder| folder.trim_end_matches('/').to_string())
        .collect()
}

#[test]
fn folders_depend_only_on_their_own_or_the_ones_below() {
    let order = documented_folder_order();
    let root = workspace_root();
    let manifests = workspace_manifests();
    let folder_of = |dir: &Path| -> String {
        let relative = dir.strip_prefix(&root).expect("members lie in the workspace");
        relative
            .components()
            .next()
            .map_or_else(String::new, |first| first.as_os_str().to_string_lossy().into_owned())
    };
    let rank: BTreeMap<String, usize> = manifests
        .iter()
        .map(|manifest| {
            let folder = folder_of(&manifest.dir);
            let rank = order.iter().position(|known| *known == folder).unwrap_or_else(|| {
                panic!("{}'s folder `{folder}` is not in the documented order", manifest.name)
            });
            (manifest.name.clone(), rank)
        })
        .collect();
    let mut violations = Vec::new();
    for manifest in &manifests {
        for dependency in dependency_names(manifest, "dependencies") {
            let Some(&below) = rank.get(&dependency) else { continue };
            if below > rank[&manifest.name] {
                violations.push(format!(
                    "{} in {}/ depends on {dependency} in {}/, a folder above it",
                    manifest.name, order[rank[&manifest.name]], order[below]
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

/// A Rust file parsed, or the reason it is not (the tidy rules read items, not text).
fn parse_source(file: &Path) -> syn::File {
    let text = fs::read_to_string(file).expect("readable source");
    syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", file.display()))
}

/// The test attributes a file carries anywhere, its test modules included: `#[ignore]` in
/// either form, `#[should_panic]`, and both inside `#[cfg_attr(…)]`.
fn forbidden_test_attributes(file: &syn::File) -> Vec<String> {
    struct Attributes(Vec<String>);
    impl<'ast> Visit<'ast> for Attributes {
        fn visit_attribute(&mut self, attribute: &'ast syn::Attribute) {
            let names: Vec<String> = match attribute.path().get_ident() {
                Some(name) if name == "cfg_attr" => match &attribute.meta {
                    syn::Meta::List(list) => token_identifiers(list.tokens.clone()),
                    _ => Vec::new(),
                },
                Some(name) => vec![name.to_string()],
                None => Vec::new(),
            };
            for name in names {
                if name == "ignore" || name == "should_panic" {
                    self.0.push(format!("#[{name}]"));
                }
            }
        }
    }
    let mut attributes = Attributes(Vec::new());
    attributes.visit_file(file);
    attributes.0
}

/// Every identifier in a token stream, groups included.
fn token_identifiers(tokens: TokenStream) -> Vec<String> {
    let mut names = Vec::new();
    for tree in tokens {
        match tree {
            TokenTree::Ident(name) => names.push(name.to_string()),
            TokenTree::Group(group) => names.extend(token_identifiers(group.stream())),
            TokenTree::Punct(_) | TokenTree::Literal(_) => {}
        }
    }
    names
}

#[test]
fn no_test_is_ignored_or_expected_to_panic() {
    let mut offenders = Vec::new();
    for manifest in workspace_manifests() {
        let mut files = Vec::new();
        rust_files(&manifest.dir, &mut files);
        for file in files {
            let found = forbidden_test_attributes(&parse_source(&file));
            if !found.is_empty() {
                offenders.push(format!("{}: {}", file.display(), found.join(", ")));
            }
        }
    }
    assert!(offenders.is_empty(), "ignored or should-panic tests:\n{}", offenders.join("\n"));
}

#[test]
fn the_test_attribute_rule_sees_ignore_in_every_form() {
    let found = |source: &str| forbidden_test_attributes(&syn::parse_file(source).unwrap());
    let ignored = "#[cfg(test)] mod tests { #[test] #[ignore] fn a() {} }";
    assert_eq!(found(ignored), ["#[ignore]"]);
    let with_reason = "#[cfg(test)] mod tests { #[test] #[ignore = \"slow\"] fn a() {} }";
    assert_eq!(found(with_reason), ["#[ignore]"]);
    let conditional = "#[test] #[cfg_attr(miri, ignore = \"slow\")] fn a() {}";
    assert_eq!(found(conditional), ["#[ignore]"]);
    let panicking = "#[test] #[should_panic(expected = \"no\")] fn a() {}";
    assert_eq!(found(panicking), ["#[should_panic]"]);
    let in_text = "//! `#[ignore]`\nconst RULE: &str = \"#[ignore]\"; #[test] fn a() {}";
    assert!(found(in_text).is_empty());
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

/// What a source file's product code names, everything but the items under `#[cfg(test)]`
/// (a test module is skipped whole, however early it comes, and the code after it is read).
#[derive(Debug, Default)]
struct ProductCode {
    /// Every path, `::`-joined: in `use` items (groups expanded, renames by their source), in
    /// types and expressions, and in the tokens of macro calls.
    paths: BTreeSet<String>,
    /// The traits it implements, as written.
    implemented: BTreeSet<String>,
    /// The names its `use` items bring in, and the path each comes from (read of a crate root,
    /// whose names the other modules reach as `crate::Name`).
    imported: BTreeMap<String, String>,
}

impl ProductCode {
    fn of(file: &syn::File) -> ProductCode {
        let mut code = ProductCode::default();
        code.visit_file(file);
        code
    }
}

/// Whether an item is compiled for tests only (`#[cfg(test)]`).
fn is_test_only(attributes: &[syn::Attribute]) -> bool {
    attributes.iter().any(|attribute| match &attribute.meta {
        syn::Meta::List(list) => list.path.is_ident("cfg") && list.tokens.to_string() == "test",
        _ => false,
    })
}

/// A path's segments, `::`-joined, without generic arguments.
fn path_text(path: &syn::Path) -> String {
    let segments: Vec<String> = path.segments.iter().map(|s| s.ident.to_string()).collect();
    segments.join("::")
}

/// The paths of a `use` tree, groups expanded: `a::{b, c::d as e}` gives `a::b` and `a::c::d`,
/// each with the name it is known by.
fn use_paths(tree: &syn::UseTree, prefix: &str, out: &mut Vec<(String, String)>) {
    let joined = |name: &syn::Ident| {
        if prefix.is_empty() { name.to_string() } else { format!("{prefix}::{name}") }
    };
    match tree {
        syn::UseTree::Path(path) => use_paths(&path.tree, &joined(&path.ident), out),
        syn::UseTree::Name(name) => out.push((joined(&name.ident), name.ident.to_string())),
        syn::UseTree::Rename(rename) => {
            out.push((joined(&rename.ident), rename.rename.to_string()));
        }
        syn::UseTree::Glob(_) => out.push((format!("{prefix}::*"), "*".to_string())),
        syn::UseTree::Group(group) => {
            for item in &group.items {
                use_paths(item, prefix, out);
            }
        }
    }
}

/// The paths in macro tokens, which syn leaves unparsed: runs of `ident::ident…`.
fn token_paths(tokens: TokenStream, out: &mut BTreeSet<String>) {
    fn finish(current: &mut Vec<String>, out: &mut BTreeSet<String>) {
        if !current.is_empty() {
            out.insert(current.join("::"));
            current.clear();
        }
    }
    let mut current: Vec<String> = Vec::new();
    let mut colons = 0;
    for tree in tokens {
        match tree {
            TokenTree::Ident(name) => {
                if colons != 2 {
                    finish(&mut current, out);
                }
                current.push(name.to_string());
                colons = 0;
            }
            TokenTree::Punct(punct) if punct.as_char() == ':' && !current.is_empty() => {
                colons += 1;
            }
            TokenTree::Group(group) => {
                finish(&mut current, out);
                colons = 0;
                token_paths(group.stream(), out);
            }
            TokenTree::Punct(_) | TokenTree::Literal(_) => {
                finish(&mut current, out);
                colons = 0;
            }
        }
    }
    finish(&mut current, out);
}

impl<'ast> Visit<'ast> for ProductCode {
    fn visit_item(&mut self, item: &'ast syn::Item) {
        let attributes = match item {
            syn::Item::Const(item) => &item.attrs,
            syn::Item::Enum(item) => &item.attrs,
            syn::Item::Fn(item) => &item.attrs,
            syn::Item::Impl(item) => &item.attrs,
            syn::Item::Macro(item) => &item.attrs,
            syn::Item::Mod(item) => &item.attrs,
            syn::Item::Static(item) => &item.attrs,
            syn::Item::Struct(item) => &item.attrs,
            syn::Item::Trait(item) => &item.attrs,
            syn::Item::Type(item) => &item.attrs,
            syn::Item::Use(item) => &item.attrs,
            _ => return visit::visit_item(self, item),
        };
        if !is_test_only(attributes) {
            visit::visit_item(self, item);
        }
    }

    fn visit_item_use(&mut self, item: &'ast syn::ItemUse) {
        let mut paths = Vec::new();
        use_paths(&item.tree, "", &mut paths);
        for (path, name) in paths {
            self.imported.insert(name, path.clone());
            self.paths.insert(path);
        }
    }

    fn visit_item_impl(&mut self, item: &'ast syn::ItemImpl) {
        if let Some((_, path, _)) = &item.trait_ {
            self.implemented.insert(path_text(path));
        }
        visit::visit_item_impl(self, item);
    }

    fn visit_path(&mut self, path: &'ast syn::Path) {
        self.paths.insert(path_text(path));
        visit::visit_path(self, path);
    }

    fn visit_macro(&mut self, mac: &'ast syn::Macro) {
        token_paths(mac.tokens.clone(), &mut self.paths);
        visit::visit_macro(self, mac);
    }
}

/// What each of a crate's `src/` files names in its product code.
fn library_source(manifest: &Manifest) -> Vec<(PathBuf, ProductCode)> {
    let mut files = Vec::new();
    rust_files(&manifest.dir.join("src"), &mut files);
    files.sort();
    files.into_iter().map(|file| (file.clone(), ProductCode::of(&parse_source(&file)))).collect()
}

/// Whether one of `paths` ends in the segments of `suffix`.
fn names(paths: &BTreeSet<String>, suffix: &str) -> bool {
    paths.iter().any(|path| path == suffix || path.ends_with(&format!("::{suffix}")))
}

#[test]
fn every_plugin_reads_its_configuration_as_one_json_object() {
    let root = workspace_root();
    let mut violations = Vec::new();
    for manifest in workspace_manifests().iter().filter(|m| m.dir.starts_with(root.join("plugins")))
    {
        let source = library_source(manifest);
        let makes = source.iter().any(|(_, code)| names(&code.implemented, "PluginFactory"));
        let reads = source.iter().any(|(_, code)| names(&code.paths, "PluginConfig::parse"));
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
        for name in plugin_crates {
            if !code.paths.iter().any(|path| path.split("::").next() == Some(name)) {
                continue;
            }
            violations.push(format!("{} names {name}", file.display()));
        }
    }
    assert!(
        violations.is_empty(),
        "built-in plugins made outside compiler/lampc/src/builtin_plugins.rs:\n{}",
        violations.join("\n")
    );
}

/// The crate root's names that stand for an item of one of its modules (`pub use a::{B, C}` or
/// a private `use`): name → module.
fn root_reexports(root: &ProductCode) -> BTreeMap<String, String> {
    root.imported
        .iter()
        .filter_map(|(name, path)| {
            let mut segments = path.split("::").skip_while(|s| *s == "crate" || *s == "self");
            let module = segments.next()?;
            segments.next()?; // a bare `use module;` names the module itself
            Some((name.clone(), module.to_string()))
        })
        .collect()
}

/// The crate-internal modules a file's product code names: `crate::module…`, or a crate-root
/// name that the root re-exports from a module (`crate::Name`, `crate::{Name, …}`).
fn named_modules(code: &ProductCode, reexports: &BTreeMap<String, String>) -> BTreeSet<String> {
    code.paths
        .iter()
        .filter_map(|path| path.strip_prefix("crate::"))
        .filter_map(|rest| rest.split("::").next())
        .map(|first| reexports.get(first).cloned().unwrap_or_else(|| first.to_string()))
        .collect()
}

/// Module → the sibling modules it names, for the top-level modules of a crate: `root` is the
/// crate root's code, `files` each other file's top-level module and code.
fn module_graph_of(
    root: &ProductCode,
    files: &[(String, ProductCode)],
) -> BTreeMap<String, BTreeSet<String>> {
    let reexports = root_reexports(root);
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (module, code) in files {
        let names = named_modules(code, &reexports);
        graph.entry(module.clone()).or_default().extend(names.into_iter().filter(|n| n != module));
    }
    let modules: BTreeSet<String> = graph.keys().cloned().collect();
    for names in graph.values_mut() {
        names.retain(|name| modules.contains(name));
    }
    graph
}

/// Module → the sibling modules it names, for the top-level modules of one crate's `src`.
fn module_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut root = ProductCode::default();
    let mut modules = Vec::new();
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files.sort();
    for file in files {
        let relative = file.strip_prefix(src).expect("under src");
        let Some(first) = relative.components().next() else { continue };
        let module = first.as_os_str().to_string_lossy().trim_end_matches(".rs").to_string();
        let code = ProductCode::of(&parse_source(&file));
        if module == "lib" || (module == "main" && !src.join("lib.rs").exists()) {
            root = code;
        } else if module != "main" && module != "bin" {
            modules.push((module, code));
        }
    }
    module_graph_of(&root, &modules)
}

/// Every import loop of a module graph: each set of modules that reach one another (a strongly
/// connected component of two or more, or a module that names itself), sorted.
fn import_loops(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    let mut edges = DiGraphMap::<&str, ()>::new();
    for (module, names) in graph {
        edges.add_node(module);
        for name in names {
            edges.add_edge(module, name, ());
        }
    }
    let mut loops: Vec<Vec<String>> = petgraph::algo::tarjan_scc(&edges)
        .into_iter()
        .filter(|component| component.len() > 1 || edges.contains_edge(component[0], component[0]))
        .map(|component| {
            let mut modules: Vec<String> = component.into_iter().map(str::to_string).collect();
            modules.sort();
            modules
        })
        .collect();
    loops.sort();
    loops
}

#[test]
fn no_crate_has_an_import_loop_between_its_modules() {
    let mut loops = Vec::new();
    for manifest in workspace_manifests() {
        let graph = module_graph(&manifest.dir.join("src"));
        for modules in import_loops(&graph) {
            loops.push(format!("{}: {}", manifest.name, modules.join(", ")));
        }
    }
    assert!(
        loops.is_empty(),
        "modules that import each other (move what they share into a leaf module):\n{}",
        loops.join("\n")
    );
}

/// The product code of a source text, for the rules' own tests.
fn code_of(source: &str) -> ProductCode {
    ProductCode::of(&syn::parse_file(source).expect("a test source parses"))
}

#[test]
fn the_import_loop_rule_follows_crate_root_reexports() {
    let root =
        code_of("mod model; mod write; pub use model::Domain; pub use write::{write_domain};");
    let model = code_of("impl Domain { fn text(&self) -> String { crate::write_domain(self) } }");
    let write = code_of("use crate::{Domain}; pub fn write_domain(_: &Domain) -> String { 1 }");
    let graph = module_graph_of(&root, &[("model".into(), model), ("write".into(), write)]);
    assert_eq!(import_loops(&graph), [["model".to_string(), "write".to_string()]]);
}

#[test]
fn the_rules_read_the_code_after_an_early_test_module_and_skip_only_its_body() {
    let source = "
        #[cfg(test)]
        mod tests { use crate::early::Fixture; fn f() { lamp_refiner_gmm::make(); } }
        pub fn late() { crate::late::run(); assert!(crate::in_macro::check()); }
    ";
    let code = code_of(source);
    let named = named_modules(&code, &BTreeMap::new());
    assert_eq!(named, BTreeSet::from(["late".to_string(), "in_macro".to_string()]));
    assert!(!code.paths.iter().any(|path| path.starts_with("lamp_refiner_gmm")));
}

#[test]
fn the_plugin_rules_see_implementations_and_calls_not_comments() {
    let code = code_of(
        "// impl PluginFactory for Commented {}
         impl lamp_plugin_api::PluginFactory for Made {
             fn create(&self, text: &str) { let _ = PluginConfig::parse(text); }
         }",
    );
    assert!(names(&code.implemented, "PluginFactory"));
    assert!(names(&code.paths, "PluginConfig::parse"));
    assert!(!names(&code.paths, "Commented"));
}
