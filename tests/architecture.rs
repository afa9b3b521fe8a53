//! The layering of `src/`, checked on the import graph the source states.
//!
//! Every `crate::…` and `super::…` path outside comments is resolved to the module file that
//! defines it. Nine rules hold:
//! - the layers import downward only: `engine` imports neither `harness` nor `studies`, and
//!   `harness` does not import `studies`;
//! - a layer does not skip the layers between it and a lower one it is listed with in
//!   [`REACHED_THROUGH_THE_LAYERS_BETWEEN`]: neither `studies` nor `commands` imports anything
//!   under `engine`; they take what they need of it from the harness's public face
//!   (`harness::problem`, `harness::files::error`, …);
//! - the components (a layer's direct children: `engine::fem`, `harness::run`, …) form no cycle;
//! - the harness's parts (its components) are ordered, [`HARNESS_PARTS`], and import downward
//!   only: every module of the harness lives in one of them, and none imports a part above its
//!   own;
//! - the files of one directory form no cycle among themselves (a `mod.rs`, which declares its
//!   children, is a component's root and is left to the rule above);
//! - in `commands/`, no file imports the dispatcher (`mod.rs`) and no subcommand's file imports
//!   another's: they share only [`SHARED_COMMAND_PARTS`];
//! - no `studies/` or `commands/` file branches on the geometry (`Problem::Bar`, `Problem::Box`,
//!   `Observed::Bar`, `Observed::Box`): the harness's problem and reference parts do;
//! - no module of the library reads the process's arguments (`std::env::args`, `args_os`):
//!   `main.rs` reads them once and hands the commands their typed command and its line;
//! - no report section reads another's output: only the render step ([`RENDER_STEP`]) reads a
//!   reports directory's data (`REPORT_DATA`), and no module names a previous reports directory
//!   to read from (`kept_from`);
//! - no report section does a command's work: no `studies/` module stages an output directory or
//!   fails as a command ([`COMMAND_PLUMBING`]).
//!
//! Every path names its layer: the crate root declares the four layers and re-exports nothing.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

const LAYERS: [&str; 4] = ["engine", "harness", "studies", "commands"];

/// The parts of the harness, bottom to top: a part imports only the parts before it. The
/// engine's vocabulary and the files first, then a run, the studies of runs, the verdict words
/// decided on them, the references they measure runs against, their rendering,
/// and the two witnesses that use all of these, another code's runs and GetFEM's demo.
const HARNESS_PARTS: [&str; 9] = [
    "problem",
    "files",
    "run",
    "study",
    "vocabulary",
    "reference",
    "render",
    "external",
    "getfem",
];

/// Pairs (layer, lower layer): the layer imports nothing under the lower layer directly, only
/// what the layers between re-export or wrap. One line per pair.
const REACHED_THROUGH_THE_LAYERS_BETWEEN: &[(&str, &str)] =
    &[("studies", "engine"), ("commands", "engine")];

/// A module path such as `["engine", "fem", "bar1d"]`.
type ModPath = Vec<String>;

fn module_files(dir: &Path, prefix: &ModPath, out: &mut BTreeMap<ModPath, String>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .expect("src/ is readable")
        .map(|e| e.expect("a directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            let mut p = prefix.clone();
            p.push(name);
            module_files(&path, &p, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let mut p = prefix.clone();
            if name != "mod" {
                p.push(name);
            }
            if p.len() == 1 && (p[0] == "lib" || p[0] == "main") {
                continue;
            }
            out.insert(p, std::fs::read_to_string(&path).expect("a source file"));
        }
    }
}

/// The source without comments (line comments, doc comments and block comments).
fn code_of(source: &str) -> String {
    let mut code = String::with_capacity(source.len());
    let mut depth = 0usize;
    for line in source.lines() {
        let mut rest = line;
        loop {
            if depth > 0 {
                match rest.find("*/") {
                    Some(i) => {
                        depth -= 1;
                        rest = &rest[i + 2..];
                    }
                    None => break,
                }
            } else {
                let line_comment = rest.find("//");
                let block = rest.find("/*");
                match (line_comment, block) {
                    (Some(l), b) if b.is_none_or(|b| l < b) => {
                        code.push_str(&rest[..l]);
                        break;
                    }
                    (_, Some(b)) => {
                        code.push_str(&rest[..b]);
                        depth += 1;
                        rest = &rest[b + 2..];
                    }
                    _ => {
                        code.push_str(rest);
                        break;
                    }
                }
            }
        }
        code.push('\n');
    }
    code
}

/// Expands the use tree starting at `text` (after `crate::` or `super::`) into full paths.
fn use_tree(text: &str, prefix: &ModPath, out: &mut Vec<ModPath>) -> usize {
    let bytes = text.as_bytes();
    let mut i = 0;
    let mut path = prefix.clone();
    loop {
        while i < bytes.len() && bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        if i < bytes.len() && bytes[i] == b'{' {
            i += 1;
            loop {
                while i < bytes.len() && (bytes[i].is_ascii_whitespace() || bytes[i] == b',') {
                    i += 1;
                }
                if i >= bytes.len() || bytes[i] == b'}' {
                    return i + 1;
                }
                i += use_tree(&text[i..], &path, out);
            }
        }
        let start = i;
        while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
            i += 1;
        }
        if start == i {
            out.push(path);
            return i;
        }
        path.push(text[start..i].to_string());
        if text[i..].starts_with("::") {
            i += 2;
        } else {
            out.push(path);
            return i;
        }
    }
}

/// The longest module of `modules` that is a prefix of `path`.
fn resolve(path: &ModPath, modules: &BTreeMap<ModPath, String>) -> Option<ModPath> {
    (1..=path.len())
        .rev()
        .map(|n| path[..n].to_vec())
        .find(|p| modules.contains_key(p))
}

/// The modules each module refers to, by `crate::` and `super::` paths.
fn import_graph(modules: &BTreeMap<ModPath, String>) -> BTreeMap<ModPath, BTreeSet<ModPath>> {
    let mut graph = BTreeMap::new();
    for (module, source) in modules {
        let code = code_of(source);
        let mut paths = Vec::new();
        for (at, _) in code.match_indices("crate::") {
            use_tree(&code[at + "crate::".len()..], &Vec::new(), &mut paths);
        }
        let parent = module[..module.len() - 1].to_vec();
        for (at, _) in code.match_indices("super::") {
            if at > 0 && code.as_bytes()[at - 1] == b':' {
                continue;
            }
            use_tree(&code[at + "super::".len()..], &parent, &mut paths);
        }
        let targets: BTreeSet<ModPath> = paths
            .iter()
            .filter_map(|p| resolve(p, modules))
            .filter(|t| t != module)
            .collect();
        graph.insert(module.clone(), targets);
    }
    graph
}

/// A cycle of `graph`, if it has one.
fn find_cycle<N: Ord + Clone>(graph: &BTreeMap<N, BTreeSet<N>>) -> Option<Vec<N>> {
    fn visit<N: Ord + Clone>(
        node: &N,
        graph: &BTreeMap<N, BTreeSet<N>>,
        state: &mut BTreeMap<N, bool>,
        stack: &mut Vec<N>,
    ) -> Option<Vec<N>> {
        match state.get(node) {
            Some(true) => return None,
            Some(false) => {
                let start = stack.iter().position(|n| n == node).unwrap();
                let mut cycle = stack[start..].to_vec();
                cycle.push(node.clone());
                return Some(cycle);
            }
            None => {}
        }
        state.insert(node.clone(), false);
        stack.push(node.clone());
        for next in graph.get(node).into_iter().flatten() {
            if let Some(c) = visit(next, graph, state, stack) {
                return Some(c);
            }
        }
        stack.pop();
        state.insert(node.clone(), true);
        None
    }
    let mut state = BTreeMap::new();
    graph
        .keys()
        .find_map(|n| visit(n, graph, &mut state, &mut Vec::new()))
}

fn modules() -> BTreeMap<ModPath, String> {
    let mut modules = BTreeMap::new();
    module_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &Vec::new(),
        &mut modules,
    );
    modules
}

fn show(path: &[String]) -> String {
    path.join("::")
}

#[test]
fn every_library_module_lives_in_a_layer() {
    for module in modules().keys() {
        assert!(
            LAYERS.contains(&module[0].as_str()),
            "src/{} is outside engine/, harness/ and studies/",
            module.join("/")
        );
    }
}

#[test]
fn every_crate_path_names_its_layer() {
    let modules = modules();
    let mut unresolved = Vec::new();
    for (module, source) in &modules {
        let code = code_of(source);
        let mut paths = Vec::new();
        for (at, _) in code.match_indices("crate::") {
            use_tree(&code[at + "crate::".len()..], &Vec::new(), &mut paths);
        }
        unresolved.extend(
            paths
                .iter()
                .filter(|p| resolve(p, &modules).is_none())
                .map(|p| format!("{}: crate::{}", show(module), show(p))),
        );
    }
    assert!(
        unresolved.is_empty(),
        "paths that name no module of a layer:\n{}",
        unresolved.join("\n")
    );
}

#[test]
fn layers_import_downward_only() {
    let modules = modules();
    let rank = |m: &ModPath| LAYERS.iter().position(|l| *l == m[0]).unwrap();
    let upward: Vec<String> = import_graph(&modules)
        .into_iter()
        .flat_map(|(from, targets)| {
            let above: Vec<ModPath> = targets
                .into_iter()
                .filter(|to| rank(to) > rank(&from))
                .collect();
            above
                .into_iter()
                .map(move |to| format!("{} imports {}", show(&from), show(&to)))
        })
        .collect();
    assert!(
        upward.is_empty(),
        "imports of a layer above:\n{}",
        upward.join("\n")
    );
}

#[test]
fn no_layer_skips_the_layers_between() {
    let modules = modules();
    let rank = |layer: &str| LAYERS.iter().position(|l| *l == layer).unwrap();
    let skipping: Vec<String> = import_graph(&modules)
        .into_iter()
        .flat_map(|(from, targets)| {
            let skipped: Vec<ModPath> = targets
                .into_iter()
                .filter(|to| {
                    REACHED_THROUGH_THE_LAYERS_BETWEEN.contains(&(from[0].as_str(), to[0].as_str()))
                })
                .collect();
            skipped.into_iter().map(move |to| {
                let between = &LAYERS[rank(&to[0]) + 1..rank(&from[0])];
                format!(
                    "{} imports {} (reach {} through {})",
                    show(&from),
                    show(&to),
                    to[0],
                    between.join(" or ")
                )
            })
        })
        .collect();
    assert!(
        skipping.is_empty(),
        "imports that skip a layer:\n{}",
        skipping.join("\n")
    );
}

#[test]
fn components_form_no_cycle() {
    let modules = modules();
    let component = |m: &ModPath| m[..m.len().min(2)].to_vec();
    let mut graph: BTreeMap<ModPath, BTreeSet<ModPath>> = BTreeMap::new();
    for (from, targets) in import_graph(&modules) {
        let c = component(&from);
        let entry = graph.entry(c.clone()).or_default();
        entry.extend(targets.iter().map(component).filter(|t| *t != c));
    }
    if let Some(cycle) = find_cycle(&graph) {
        let names: Vec<String> = cycle.iter().map(|c| show(c)).collect();
        panic!("module cycle: {}", names.join(" -> "));
    }
}

/// The rank in [`HARNESS_PARTS`] of the part `module` lives in; `None` outside the harness's
/// parts (another layer, the harness's `mod.rs`, a module of no part).
fn harness_part(module: &ModPath) -> Option<usize> {
    match module.as_slice() {
        [layer, part, ..] if layer == "harness" => HARNESS_PARTS.iter().position(|p| p == part),
        _ => None,
    }
}

/// The imports of a harness part by a module of a part below it.
fn harness_imports_upward(modules: &BTreeMap<ModPath, String>) -> Vec<String> {
    import_graph(modules)
        .into_iter()
        .flat_map(|(from, targets)| {
            targets
                .into_iter()
                .filter(|to| match (harness_part(&from), harness_part(to)) {
                    (Some(own), Some(imported)) => imported > own,
                    _ => false,
                })
                .map(|to| format!("{} imports {}", show(&from), show(&to)))
                .collect::<Vec<_>>()
        })
        .collect()
}

#[test]
fn every_harness_module_lives_in_a_part() {
    let outside: Vec<String> = modules()
        .into_keys()
        .filter(|m| m[0] == "harness" && m.len() > 1 && harness_part(m).is_none())
        .map(|m| show(&m))
        .collect();
    assert!(
        outside.is_empty(),
        "harness modules in none of the parts {}: {outside:?}",
        HARNESS_PARTS.join(", ")
    );
}

#[test]
fn harness_parts_import_downward_only() {
    let upward = harness_imports_upward(&modules());
    assert!(
        upward.is_empty(),
        "harness modules importing a part above their own (bottom to top: {}):\n{}",
        HARNESS_PARTS.join(", "),
        upward.join("\n")
    );
}

#[test]
fn the_part_rule_sees_an_upward_import() {
    let mut modules = modules();
    let norms = vec![
        "harness".to_string(),
        "run".to_string(),
        "norms".to_string(),
    ];
    let upward_and_downward = "\nuse crate::harness::study::rates::RateFit;\n\
                               use crate::harness::files::error::Error;\n";
    modules
        .get_mut(&norms)
        .expect("harness/run/norms.rs")
        .push_str(upward_and_downward);
    assert_eq!(
        harness_imports_upward(&modules),
        ["harness::run::norms imports harness::study::rates"]
    );
}

#[test]
fn sibling_files_form_no_cycle() {
    let modules = modules();
    let roots: BTreeSet<ModPath> = modules
        .keys()
        .filter(|m| {
            modules
                .keys()
                .any(|c| c.len() > m.len() && c.starts_with(m))
        })
        .cloned()
        .collect();
    let graph: BTreeMap<ModPath, BTreeSet<ModPath>> = import_graph(&modules)
        .into_iter()
        .filter(|(from, _)| !roots.contains(from))
        .map(|(from, targets)| {
            let siblings = targets
                .into_iter()
                .filter(|t| !roots.contains(t) && t[..t.len() - 1] == from[..from.len() - 1])
                .collect();
            (from, siblings)
        })
        .collect();
    if let Some(cycle) = find_cycle(&graph) {
        let names: Vec<String> = cycle.iter().map(|c| show(c)).collect();
        panic!("file cycle: {}", names.join(" -> "));
    }
}

#[test]
fn the_checker_sees_imports_through_groups_and_super() {
    let mut paths = Vec::new();
    let prefix = vec!["engine".to_string()];
    use_tree(
        "{fem::{Bar1d, box_mesh::BoxMesh}, model};",
        &prefix,
        &mut paths,
    );
    let shown: Vec<String> = paths.iter().map(|p| show(p)).collect();
    assert_eq!(
        shown,
        [
            "engine::fem::Bar1d",
            "engine::fem::box_mesh::BoxMesh",
            "engine::model"
        ]
    );
    let code = code_of("use a; // crate::harness\n/* crate::studies */ use b;");
    assert!(!code.contains("crate::"), "{code}");
    let mut graph = BTreeMap::new();
    graph.insert(1, BTreeSet::from([2]));
    graph.insert(2, BTreeSet::from([1]));
    assert_eq!(find_cycle(&graph), Some(vec![1, 2, 1]));
}

/// The parts of `commands/` that every subcommand may use: how a command fails, its resource
/// limits, the shared options and parsers, and sharding. Every other file is one subcommand's.
const SHARED_COMMAND_PARTS: [&str; 5] =
    ["command_error", "failure", "limits", "options", "sharding"];

/// The imports inside `commands/` that break its shape: a file importing the dispatcher
/// (`commands/mod.rs`), a subcommand importing another subcommand, or a shared part importing a
/// subcommand.
fn command_imports_out_of_shape(modules: &BTreeMap<ModPath, String>) -> Vec<String> {
    let is_commands = |m: &ModPath| m.first().is_some_and(|l| l == "commands");
    let shared = |m: &ModPath| m.len() >= 2 && SHARED_COMMAND_PARTS.contains(&m[1].as_str());
    let subcommand = |m: &ModPath| m.len() >= 2 && !shared(m);
    import_graph(modules)
        .into_iter()
        .filter(|(from, _)| is_commands(from) && from.len() >= 2)
        .flat_map(|(from, targets)| {
            targets
                .into_iter()
                .filter(|to| is_commands(to) && to[..2.min(to.len())] != from[..2])
                .filter(|to| to.len() == 1 || subcommand(to))
                .map(|to| format!("{} imports {}", show(&from), show(&to)))
                .collect::<Vec<_>>()
        })
        .collect()
}

#[test]
fn subcommand_files_import_only_the_shared_parts() {
    let out_of_shape = command_imports_out_of_shape(&modules());
    assert!(
        out_of_shape.is_empty(),
        "commands/ files importing the dispatcher or another subcommand (only {} are shared):\n{}",
        SHARED_COMMAND_PARTS.join(", "),
        out_of_shape.join("\n")
    );
}

#[test]
fn the_command_rule_sees_a_subcommand_importing_another() {
    let mut modules = modules();
    let verify = vec!["commands".to_string(), "verify".to_string()];
    let source = modules.get_mut(&verify).expect("commands/verify.rs");
    source.push_str("\nuse super::study::StudyArgs;\nuse super::Failure;\n");
    let found = command_imports_out_of_shape(&modules);
    assert_eq!(
        found,
        [
            "commands::verify imports commands",
            "commands::verify imports commands::study"
        ]
    );
}

/// The geometry's variants: a bar's or a box's problem, or what a run of either observed.
const GEOMETRY_BRANCHES: [&str; 4] = [
    "Problem::Bar",
    "Problem::Box",
    "Observed::Bar",
    "Observed::Box",
];

/// The `studies/` and `commands/` files that branch on the geometry ([`GEOMETRY_BRANCHES`]):
/// what a report section or a command does is the same for a bar and a box, the difference is
/// below them, in the problem and the reference parts of the harness (a scene's run and study,
/// the reference a scene declares).
fn layers_branching_on_the_geometry(modules: &BTreeMap<ModPath, String>) -> Vec<String> {
    modules
        .iter()
        .filter(|(m, _)| m[0] == "commands" || m[0] == "studies")
        .filter(|(_, source)| {
            let code = code_of(source);
            GEOMETRY_BRANCHES.iter().any(|branch| code.contains(branch))
        })
        .map(|(m, _)| show(m))
        .collect()
}

#[test]
fn studies_and_commands_do_not_branch_on_the_geometry() {
    let branching = layers_branching_on_the_geometry(&modules());
    assert!(
        branching.is_empty(),
        "studies/ and commands/ files branching on the geometry (the harness's SceneRun, \
         SceneStudy and DeclaredReference, and Scene::bar_problem / box_problem / load_bar, \
         take it): {branching:?}"
    );
}

#[test]
fn the_geometry_rule_sees_a_branch() {
    let mut modules = modules();
    let run = vec!["commands".to_string(), "run".to_string()];
    modules
        .get_mut(&run)
        .expect("commands/run.rs")
        .push_str("\nfn f(p: Problem) { if let Problem::Box(_) = p {} }\n");
    let gravity = vec!["studies".to_string(), "gravity".to_string()];
    modules
        .get_mut(&gravity)
        .expect("studies/gravity.rs")
        .push_str("\nfn g(o: Observed) { if let Observed::Bar(_) = o {} }\n");
    assert_eq!(
        layers_branching_on_the_geometry(&modules),
        ["commands::run", "studies::gravity"]
    );
}

/// The library's modules that read the process's arguments (`env::args`, `env::args_os`): none
/// may, the commands below `main.rs` least of all.
fn modules_reading_the_arguments(modules: &BTreeMap<ModPath, String>) -> Vec<String> {
    modules
        .iter()
        .filter(|(_, source)| code_of(source).contains("env::args"))
        .map(|(m, _)| show(m))
        .collect()
}

#[test]
fn no_module_reads_the_process_arguments() {
    let reading = modules_reading_the_arguments(&modules());
    assert!(
        reading.is_empty(),
        "modules reading the process's arguments (main.rs reads them once into a CommandLine \
         and a typed command, passed down): {reading:?}"
    );
}

#[test]
fn the_argument_rule_sees_a_read() {
    let mut modules = modules();
    let progress = vec![
        "harness".to_string(),
        "study".to_string(),
        "progress".to_string(),
    ];
    modules
        .get_mut(&progress)
        .expect("harness/study/progress.rs")
        .push_str(
            "\n// std::env::args in a comment\nfn f() -> usize { std::env::args().count() }\n",
        );
    assert_eq!(
        modules_reading_the_arguments(&modules),
        ["harness::study::progress"]
    );
}

/// The render step (`signorini figures`): the modules that build a reports directory's
/// cross-section pages, figures and index from the data files its commands wrote there.
const RENDER_STEP: [&str; 3] = [
    "studies::render",
    "studies::reports_index",
    "studies::figures::from_reports",
];

/// The modules that read their own section's data back from a reports directory: the 2D/3D
/// study judged again from its `elastic-<d>d.json` (`signorini rejudge`).
const READ_THEIR_OWN_DATA: [&str; 1] = ["studies::elastic_study::rejudge"];

/// The modules that read a reports directory's data outside the render step, or name a previous
/// reports directory to read from (`kept_from`). A read of a reports directory's data names
/// `REPORT_DATA` (the kind of file `read_json` is given, its size limit and its name in the
/// messages); only the render step reads them, so that no section reads another's output and a
/// page gathering several sections is built once, from the data, whatever order the commands
/// ran in. A module that reads its own section's data back ([`READ_THEIR_OWN_DATA`]) may too.
fn sections_reading_report_data(modules: &BTreeMap<ModPath, String>) -> Vec<String> {
    let definition = ["harness", "files", "input"];
    modules
        .iter()
        .filter(|(m, _)| m.as_slice() != definition)
        .filter(|(m, _)| {
            let name = show(m);
            !RENDER_STEP.contains(&name.as_str()) && !READ_THEIR_OWN_DATA.contains(&name.as_str())
        })
        .filter(|(_, source)| {
            let code = code_of(source);
            code.contains("REPORT_DATA") || code.contains("kept_from")
        })
        .map(|(m, _)| show(m))
        .collect()
}

#[test]
fn only_the_render_step_reads_the_reports_data() {
    let reading = sections_reading_report_data(&modules());
    assert!(
        reading.is_empty(),
        "modules reading a reports directory's data outside the render step ({RENDER_STEP:?}): \
         {reading:?}; a section writes its own data and pages, and a page gathering several \
         sections' data is built by studies::render"
    );
}

#[test]
fn the_render_step_rule_sees_a_read_and_a_kept_directory() {
    let mut modules = modules();
    let report = vec!["studies".to_string(), "report".to_string()];
    modules
        .get_mut(&report)
        .expect("studies/report.rs")
        .push_str("\nfn f(p: &Path) -> Study { read_json(p, REPORT_DATA).unwrap() }\n");
    let study_run = vec![
        "commands".to_string(),
        "study".to_string(),
        "study_run".to_string(),
    ];
    modules
        .get_mut(&study_run)
        .expect("commands/study/study_run.rs")
        .push_str("\n// REPORT_DATA in a comment\nfn g(kept_from: &Path) {}\n");
    let rejudge = vec![
        "studies".to_string(),
        "elastic_study".to_string(),
        "rejudge".to_string(),
    ];
    assert!(modules[&rejudge].contains("REPORT_DATA"));
    assert_eq!(
        sections_reading_report_data(&modules),
        ["commands::study::study_run", "studies::report"]
    );
}

/// What only a command's back-end does: stage its `--out` directory (`StagedDir`) and fail as a
/// command (`CommandError`, the exit code's input).
const COMMAND_PLUMBING: [&str; 2] = ["StagedDir", "CommandError"];

/// The `studies/` modules doing a command's work ([`COMMAND_PLUMBING`]): a report section is a
/// function from data to pages and data files, written where it is told; staging and exit codes
/// are the command's (`commands/`).
fn sections_doing_command_work(modules: &BTreeMap<ModPath, String>) -> Vec<String> {
    modules
        .iter()
        .filter(|(m, _)| m[0] == "studies")
        .filter(|(_, source)| {
            let code = code_of(source);
            COMMAND_PLUMBING.iter().any(|name| code.contains(name))
        })
        .map(|(m, _)| show(m))
        .collect()
}

#[test]
fn report_sections_leave_staging_and_exit_codes_to_the_commands() {
    let doing = sections_doing_command_work(&modules());
    assert!(
        doing.is_empty(),
        "studies/ modules staging an output directory or failing as a command (the command \
         back-ends in commands/ do): {doing:?}"
    );
}

#[test]
fn the_section_rule_sees_a_staged_directory_and_a_command_error() {
    let mut modules = modules();
    let league = vec!["studies".to_string(), "league".to_string()];
    modules
        .get_mut(&league)
        .expect("studies/league.rs")
        .push_str(
            "\n// CommandError in a comment\nfn f(d: &Path) { StagedDir::begin(\"--out\", d); }\n",
        );
    let gravity = vec!["studies".to_string(), "gravity".to_string()];
    modules
        .get_mut(&gravity)
        .expect("studies/gravity.rs")
        .push_str("\nfn g() -> Result<(), CommandError> { Ok(()) }\n");
    assert_eq!(
        sections_doing_command_work(&modules),
        ["studies::gravity", "studies::league"]
    );
}
