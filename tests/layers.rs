//! The house, checked on the source itself: the library's modules import one way, from the
//! science's first steps to its reports, and no two of them import each other. The module graph is
//! read from the code (every `crate::…` and `super::…` path outside comments and test modules,
//! resolved to the deepest module of the tree that it names).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

mod common;
use common::rust_files;

/// The layers of the library, lowest first: a module may import its own layer and those below,
/// never one above. Within `dynamics`, the stages are layers of their own.
const LAYERS: &[&[&str]] = &[
    // The crate root's own items (Vec3, Point3, GRAVITY, the error type) are below everything.
    &["", "error", "rng", "stats", "monitor", "ground_motion"],
    &["mesh"],
    &["solid"],
    &["hull"],
    &["equilibria", "generate", "shape", "tipping"],
    &["morse_smale"],
    &["hierarchy"],
    &["planar", "basins"],
    &["analysis", "mutation"],
    &["bundled"],
    &["dynamics::size"],
    &["dynamics::engine"],
    &["dynamics::surface", "dynamics::stone"],
    &["dynamics::certificate"],
    &["dynamics::drops", "dynamics::resting"],
    &["dynamics::pushes", "dynamics::shaking"],
    &["dynamics"],
    &["study"],
    &["plot", "report"],
    // Re-exports for programs over the library; nothing inside it may import them.
    &["prelude"],
];

/// The module path of a source file (`dynamics::engine::world`; `` for lib.rs).
fn module_of(src: &Path, file: &Path) -> String {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let parts: Vec<String> = rel.iter().map(|p| p.to_string_lossy().into_owned()).collect();
    let parts: Vec<&str> =
        parts.iter().map(String::as_str).filter(|p| *p != "mod" && *p != "lib" && *p != "main").collect();
    parts.join("::")
}

/// The code of a file without comments and without its test module.
fn code_of(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap();
    text.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n")
}

/// The deepest module of `modules` that `path` (a `::` path from the crate root) names.
fn resolve(path: &[&str], modules: &BTreeSet<String>) -> Option<String> {
    (0..=path.len()).rev().map(|k| path[..k].join("::")).find(|m| modules.contains(m))
}

/// The modules that module `me` (in file `is_mod`: a `mod.rs`/`lib.rs`) refers to in `code`.
fn imports(me: &str, code: &str, modules: &BTreeSet<String>) -> BTreeSet<String> {
    let own: Vec<&str> = if me.is_empty() { vec![] } else { me.split("::").collect() };
    let ident = |c: char| c.is_alphanumeric() || c == '_' || c == ':' || c == '{' || c == ',' || c == ' ';
    let mut out = BTreeSet::new();
    for (at, word) in [("crate::", 0usize), ("super::", 1)] {
        for (i, _) in code.match_indices(at) {
            if i > 0 && code[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_' || c == ':') {
                continue; // `a::super::` or part of a longer name
            }
            let mut base: Vec<&str> = if word == 0 { vec![] } else { own[..own.len().saturating_sub(1)].to_vec() };
            let mut rest = &code[i + at.len()..];
            while let Some(r) = rest.strip_prefix("super::") {
                base.pop();
                rest = r;
            }
            let path: String = rest.chars().take_while(|&c| ident(c)).collect();
            // `a::b::{c, d::e}`: each item of a brace list, one level deep.
            let (head, list) = match path.split_once('{') {
                Some((h, l)) => (h.trim_end_matches(':').to_string(), l.split(',').map(str::trim).collect()),
                None => (path.split_whitespace().next().unwrap_or("").to_string(), vec![""]),
            };
            for item in list {
                let mut full = base.clone();
                full.extend(head.split("::").filter(|s| !s.is_empty()));
                full.extend(item.split("::").map(str::trim).filter(|s| !s.is_empty() && *s != "self"));
                if let Some(m) = resolve(&full, modules) {
                    if m != me && !me.starts_with(&format!("{m}::")) {
                        out.insert(m);
                    }
                }
            }
        }
    }
    out
}

/// The library's module graph: each module and the modules it imports.
fn graph() -> BTreeMap<String, BTreeSet<String>> {
    graph_of("src")
}

/// The module graph of the crate whose sources are in `dir` (below the repository's root).
fn graph_of(dir: &str) -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.retain(|f| !f.starts_with(src.join("cmd")) && !f.ends_with("main.rs"));
    let modules: BTreeSet<String> = files.iter().map(|f| module_of(&src, f)).collect();
    files
        .iter()
        .map(|f| {
            let me = module_of(&src, f);
            let deps = imports(&me, &code_of(&std::fs::read_to_string(f).unwrap()), &modules);
            (me, deps)
        })
        .collect()
}

/// The layer of a module: that of the deepest layer entry it lies in.
fn layer(m: &str) -> usize {
    let within = |entry: &str| entry.is_empty() || m == entry || m.starts_with(&format!("{entry}::"));
    LAYERS
        .iter()
        .enumerate()
        .filter_map(|(k, entries)| entries.iter().filter(|e| within(e)).map(|e| (e.len(), k)).max())
        .max()
        .map(|(_, k)| k)
        .unwrap()
}

/// A cycle of `graph`, if any (depth-first search for a back edge).
fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        m: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        path: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        match state.get(m) {
            Some(2) => return None,
            Some(1) => {
                let start = path.iter().position(|p| p == m).unwrap();
                let mut cycle = path[start..].to_vec();
                cycle.push(m.to_string());
                return Some(cycle);
            }
            _ => {}
        }
        state.insert(m.to_string(), 1);
        path.push(m.to_string());
        for n in graph.get(m).into_iter().flatten() {
            if let Some(c) = visit(n, graph, state, path) {
                return Some(c);
            }
        }
        path.pop();
        state.insert(m.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    graph.keys().find_map(|m| visit(m, graph, &mut state, &mut Vec::new()))
}

/// The graph with every module replaced by its folder of depth `depth` (`dynamics::engine` at 2).
fn folded(graph: &BTreeMap<String, BTreeSet<String>>, depth: usize) -> BTreeMap<String, BTreeSet<String>> {
    let fold = |m: &str| m.split("::").take(depth).collect::<Vec<_>>().join("::");
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (m, deps) in graph {
        let entry = out.entry(fold(m)).or_default();
        // A parent module's own file (mod.rs) re-exports its children: that is not an arrow.
        entry.extend(deps.iter().map(|d| fold(d)).filter(|d| *d != fold(m) && !fold(m).starts_with(&format!("{d}::"))));
    }
    out
}

#[test]
fn the_parser_sees_the_imports_it_must() {
    let g = graph();
    assert!(g.len() > 100, "only {} modules", g.len());
    let has = |a: &str, b: &str| g.get(a).is_some_and(|d| d.contains(b));
    assert!(has("dynamics::drops::batch", "dynamics::drops::launch"), "{:?}", g.get("dynamics::drops::batch"));
    assert!(has("dynamics::drops::simulate", "dynamics::drops::batch"));
    assert!(has("dynamics::engine::simulation", "dynamics::engine::impact"));
    assert!(has("analysis", "hull"));
}

#[test]
fn no_two_modules_import_each_other() {
    let g = graph();
    for depth in [1, 2, usize::MAX] {
        let g = if depth == usize::MAX { g.clone() } else { folded(&g, depth) };
        let cycle = find_cycle(&g);
        assert!(cycle.is_none(), "import cycle: {}", cycle.unwrap().join(" → "));
    }
    // The search finds a cycle where there is one.
    let mut with_cycle = g.clone();
    with_cycle.get_mut("dynamics::stone").unwrap().insert("dynamics::drops::simulate".into());
    assert!(find_cycle(&with_cycle).is_some());
}

#[test]
fn lower_layers_never_import_higher_ones() {
    let g = graph();
    let upward: Vec<String> = g
        .iter()
        .flat_map(|(m, deps)| deps.iter().filter(|d| layer(d) > layer(m)).map(move |d| format!("{m} → {d}")))
        .collect();
    assert!(upward.is_empty(), "arrows that point up the layers:\n{}", upward.join("\n"));
    // The check sees an arrow up where there is one.
    assert!(layer("mesh") < layer("analysis") && layer("dynamics::engine::world") < layer("dynamics::drops::batch"));
}

#[test]
fn dynamics_has_at_most_six_files_at_its_top() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/dynamics");
    let files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert!(files.contains(&"mod.rs".to_string()), "{files:?}");
    assert!(files.len() <= 6, "{} files at the top of src/dynamics: {files:?}", files.len());
}

#[test]
fn the_python_package_has_no_import_cycle() {
    let g = graph_of("python/src");
    let has = |a: &str, b: &str| g.get(a).is_some_and(|d| d.contains(b));
    assert!(has("drops", "stone") && has("stone", "mesh_input"), "{g:?}");
    let cycle = find_cycle(&g);
    assert!(cycle.is_none(), "import cycle in the Python package: {}", cycle.unwrap().join(" → "));
}
