//! The import graph of a source tree, its cycles and its long files.
//!
//! The graph is built from the source text: every `use` tree and every
//! `crate::…`/`super::…` path in code (tests excluded: a file is read up to
//! its `#[cfg(test)]`), resolved to the file that defines the item. A
//! folder's `mod.rs` that only re-exports is looked through: a name it
//! re-exports with `pub use` resolves to the file that defines it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

pub const MAX_FILE_LINES: usize = 500;

/// Every `.rs` file under `dir`, by module path (`["fe", "newton"]`;
/// `mod.rs`, `lib.rs` and a binary's `main.rs` by their folder's path).
pub fn modules(root: &Path) -> BTreeMap<Vec<String>, PathBuf> {
    let mut found = BTreeMap::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let relative = path.strip_prefix(root).unwrap();
            let mut names: Vec<String> = relative
                .iter()
                .map(|c| c.to_string_lossy().trim_end_matches(".rs").to_string())
                .collect();
            // A folder's mod.rs, and the crate root (lib.rs, or a binary's
            // main.rs), by the folder's path.
            let root_file = names.len() == 1 && names[0] == "main";
            if root_file || matches!(names.last().map(String::as_str), Some("mod" | "lib")) {
                names.pop();
            }
            found.insert(names, path);
        }
    }
    found
}

/// The file's code before its tests, without comments.
pub fn code(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let before_tests = text.split("#[cfg(test)]").next().unwrap_or("");
    before_tests
        .lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The paths a `use` tree names: `a::{b, c::{d, e}}` → a::b, a::c::d, a::c::e.
pub fn expand(tree: &str) -> Vec<String> {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        let path = tree.split(" as ").next().unwrap_or("").trim();
        return vec![path.to_string()];
    };
    let prefix = &tree[..open];
    let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
    let (mut parts, mut depth, mut start) = (Vec::new(), 0, 0);
    for (i, ch) in inner.char_indices() {
        match ch {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&inner[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&inner[start..]);
    parts
        .into_iter()
        .filter(|p| !p.trim().is_empty())
        .flat_map(expand)
        .map(|p| format!("{prefix}{p}"))
        .collect()
}

/// Every path a file's code uses, with whether it is a `pub use`.
pub fn paths(code: &str) -> Vec<(String, bool)> {
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find("use ") {
        let before = &rest[..at];
        let boundary = before
            .chars()
            .last()
            .is_none_or(|c| !c.is_alphanumeric() && c != '_');
        let Some(end) = rest[at..].find(';') else {
            break;
        };
        if boundary {
            let public = before.trim_end().ends_with("pub") || before.trim_end().ends_with(')');
            let statement = &rest[at + 4..at + end];
            out.extend(expand(statement).into_iter().map(|p| (p, public)));
        }
        rest = &rest[at + end + 1..];
    }
    // Paths written out in code.
    for (i, _) in code
        .match_indices("crate::")
        .chain(code.match_indices("super::"))
    {
        let before = code[..i].chars().last();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        let path: String = code[i..]
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
            .collect();
        // `super::{a, b}` is a use tree, already expanded above.
        if code[i + path.len()..].starts_with('{') {
            continue;
        }
        out.push((path.trim_end_matches(':').to_string(), false));
    }
    out
}

/// `path` as written in the module `from`, made absolute: `self` is the
/// module itself, each `super` one level up, and a path that starts with a
/// child module's name is relative (`is_module` tells which exist).
pub fn absolute(
    from: &[String],
    path: &str,
    is_module: &dyn Fn(&[String]) -> bool,
) -> Option<Vec<String>> {
    let mut parts = path.split("::").map(str::trim).peekable();
    let first = *parts.peek()?;
    let mut child = from.to_vec();
    child.push(first.to_string());
    let mut base = match first {
        "crate" => {
            parts.next();
            vec![]
        }
        "self" | "super" => from.to_vec(),
        _ if is_module(&child) => from.to_vec(),
        _ => return None, // an external crate
    };
    while let Some(&step) = parts.peek() {
        match step {
            "self" => {}
            "super" => {
                base.pop();
            }
            _ => break,
        }
        parts.next();
    }
    base.extend(parts.map(str::to_string));
    Some(base)
}

pub type Graph = BTreeMap<Vec<String>, BTreeSet<Vec<String>>>;

/// The file-level import graph of the source tree at `root`, one cycle per
/// strongly connected group, and the files over `MAX_FILE_LINES`.
pub fn structure(root: &Path) -> (Graph, Vec<String>, Vec<String>) {
    let modules = modules(root);
    let folders: BTreeSet<Vec<String>> = modules
        .iter()
        .filter(|(m, p)| p.ends_with("mod.rs") || m.is_empty())
        .map(|(m, _)| m.clone())
        .collect();
    let mut long = Vec::new();
    for path in modules.values() {
        let lines = std::fs::read_to_string(path).unwrap().lines().count();
        if lines > MAX_FILE_LINES {
            long.push(format!("{} ({lines} lines)", path.display()));
        }
    }
    // Re-exports of each folder: name → the absolute path it stands for.
    let mut reexports: BTreeMap<Vec<String>, Vec<String>> = BTreeMap::new();
    let mut uses: BTreeMap<Vec<String>, Vec<Vec<String>>> = BTreeMap::new();
    for (module, path) in &modules {
        let is_folder = folders.contains(module);
        for (written, public) in paths(&code(path)) {
            let Some(target) = absolute(module, &written, &|m| modules.contains_key(m)) else {
                continue;
            };
            if public && is_folder {
                let mut name = module.clone();
                name.push(target.last().cloned().unwrap_or_default());
                reexports.insert(name, target);
            } else {
                uses.entry(module.clone()).or_default().push(target);
            }
        }
    }
    // The file an absolute path lands in, looking through re-exports.
    let resolve = |mut target: Vec<String>| -> Option<Vec<String>> {
        for _ in 0..8 {
            if let Some(again) = reexports.get(&target) {
                target = again.clone();
                continue;
            }
            let mut prefix = target.clone();
            while !prefix.is_empty() && !modules.contains_key(&prefix) {
                prefix.pop();
            }
            // A name re-exported by the folder the prefix stops at.
            if prefix.len() < target.len() {
                let mut name = prefix.clone();
                name.push(target[prefix.len()].clone());
                if let Some(again) = reexports.get(&name) {
                    let mut again = again.clone();
                    again.extend(target[prefix.len() + 1..].iter().cloned());
                    target = again;
                    continue;
                }
            }
            return Some(prefix);
        }
        None
    };
    let mut graph: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = BTreeMap::new();
    for (module, targets) in &uses {
        for target in targets {
            if let Some(file) = resolve(target.clone())
                && &file != module
                && !file.is_empty()
            {
                graph.entry(module.clone()).or_default().insert(file);
            }
        }
    }
    let show = |m: &Vec<String>| m.join("::");
    let cycles: Vec<String> = find_cycles(&graph)
        .iter()
        .map(|c| c.iter().map(show).collect::<Vec<_>>().join(" → "))
        .collect();
    (graph, cycles, long)
}

/// One cycle through each strongly connected group of the graph.
pub fn find_cycles(graph: &Graph) -> Vec<Vec<Vec<String>>> {
    let mut cycles = Vec::new();
    let mut done: BTreeSet<Vec<String>> = BTreeSet::new();
    for start in graph.keys() {
        if done.contains(start) {
            continue;
        }
        // Depth-first search with an explicit path.
        let mut path: Vec<(Vec<String>, Vec<Vec<String>>)> =
            vec![(start.clone(), graph[start].iter().cloned().collect())];
        let mut on_path: BTreeSet<Vec<String>> = [start.clone()].into();
        while let Some((_, next)) = path.last_mut() {
            let Some(node) = next.pop() else {
                let (node, _) = path.pop().unwrap();
                on_path.remove(&node);
                done.insert(node);
                continue;
            };
            if on_path.contains(&node) {
                let from = path.iter().position(|(n, _)| *n == node).unwrap();
                let mut cycle: Vec<Vec<String>> =
                    path[from..].iter().map(|(n, _)| n.clone()).collect();
                cycle.push(node);
                cycles.push(cycle);
                continue;
            }
            if done.contains(&node) {
                continue;
            }
            let children = graph
                .get(&node)
                .map(|t| t.iter().cloned().collect())
                .unwrap_or_default();
            on_path.insert(node.clone());
            path.push((node, children));
        }
    }
    cycles
}
