//! Every import points down the layers (issue 39): no two top-level
//! modules of a crate may import each other, directly or round a longer
//! loop. The graph is read from the sources: every `crate::` path and every
//! `super::` path that climbs to the crate root, outside comments, tests
//! included; a name the root re-exports (`pub use m::X`) counts as an
//! import of `m`. A loop is broken by moving what both sides share below
//! both, not by adding it here.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The crates whose top-level modules are checked (folders under the
/// workspace). Not yet `crates/color`: its spectrum lookup's unit tests
/// read the CIE tables and lamp files through `cie` and `io`, which are
/// built on `spectrum`.
const CRATES: &[&str] = &[
    "crates/render",
    "crates/scene",
    "crates/image",
    "crates/vision",
    "crates/cli",
    "python",
];

#[test]
fn top_level_modules_import_each_other_in_no_loop() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut found = Vec::new();
    for name in CRATES {
        let src = root.join(name).join("src");
        let graph = Graph::read(&src);
        assert!(
            graph.modules.len() > 3,
            "{}: no modules read",
            src.display()
        );
        for cycle in graph.cycles() {
            found.push(format!("{name}: {}", graph.describe(&cycle)));
        }
    }
    assert!(found.is_empty(), "imports in a loop:\n{}", found.join("\n"));
}

/// The check itself: a made-up crate with a loop through three modules
/// is caught, and the same crate without the loop's closing import is not.
#[test]
fn a_loop_is_found() {
    let dir = std::env::temp_dir().join(format!("scotopia-layers-{}", std::process::id()));
    let src = dir.join("src");
    std::fs::create_dir_all(src.join("b")).unwrap();
    let write = |path: &str, text: &str| std::fs::write(src.join(path), text).unwrap();
    write(
        "lib.rs",
        "mod a;\nmod b;\nmod c;\nmod d;\npub use d::Low;\n",
    );
    write("b/mod.rs", "mod inner;\n// use crate::a::Commented;\n");
    write("b/inner.rs", "use super::super::c::{self, X};\n");
    write("d.rs", "pub struct Low;\n");
    // c → a through a group, a → b through a root re-export's module.
    write("c.rs", "use crate::{d::Low, a::Top};\n");
    write("a.rs", "pub struct Top;\nfn f() { let _ = crate::Low; }\n");
    let graph = Graph::read(&src);
    assert!(graph.cycles().is_empty(), "{:?}", graph.edges);
    write(
        "a.rs",
        "pub struct Top;\n#[cfg(test)]\nmod tests {\n    use super::super::b;\n}\n",
    );
    let cycles = Graph::read(&src).cycles();
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(cycles, vec![vec!["a".to_string(), "b".into(), "c".into()]]);
}

/// Top-level modules and the imports between them.
struct Graph {
    modules: BTreeSet<String>,
    /// (from, to) → where: "file:line", first few.
    edges: BTreeMap<(String, String), Vec<String>>,
}

impl Graph {
    fn read(src: &Path) -> Graph {
        let mut files = Vec::new();
        rust_files(src, &mut files);
        // A file's module path: from where it lies, or from the
        // `#[path = "…"] mod name;` that includes it.
        let mut module_of: BTreeMap<PathBuf, Vec<String>> = files
            .iter()
            .map(|f| (f.clone(), module_path(src, f)))
            .collect();
        for file in &files {
            let text = read(file);
            for (i, _) in text.match_indices("#[path = \"") {
                let rest = &text[i + 10..];
                let Some(end) = rest.find('"') else { continue };
                let Some(at) = rest[end..].find("mod ") else {
                    continue;
                };
                let name: String = rest[end + at + 4..]
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                let mut path = module_of[file].clone();
                path.push(name);
                module_of.insert(file.parent().unwrap().join(&rest[..end]), path);
            }
        }
        let path_of = |f: &Path| module_of[f].clone();
        let modules: BTreeSet<String> = files
            .iter()
            .filter_map(|f| path_of(f).first().cloned())
            .collect();
        let root_file = ["lib.rs", "main.rs"]
            .iter()
            .map(|n| src.join(n))
            .find(|p| p.exists())
            .expect("a crate root");
        let reexports = reexports(&strip_comments(&read(&root_file)));
        let mut edges: BTreeMap<(String, String), Vec<String>> = BTreeMap::new();
        for file in &files {
            let path = path_of(file);
            let Some(from) = path.first() else { continue };
            let text = strip_comments(&read(file));
            let rel = file.strip_prefix(src.parent().unwrap()).unwrap_or(file);
            // Each line's module depth below the root: the file's, and one
            // more inside each inline `mod x { … }`.
            let (mut inline, mut braces, mut depths) = (Vec::new(), 0i32, Vec::new());
            for line in text.lines() {
                let item = line.trim_start();
                let item = item.strip_prefix("pub(crate) ").unwrap_or(item);
                let item = item.strip_prefix("pub ").unwrap_or(item);
                if item.starts_with("mod ") && line.contains('{') {
                    inline.push(braces);
                }
                depths.push(path.len() + inline.len());
                braces += line.matches('{').count() as i32 - line.matches('}').count() as i32;
                while inline.last().is_some_and(|&d| braces <= d) {
                    inline.pop();
                }
            }
            for (offset, first) in imports(&text, |o| depths[line_of(&text, o)]) {
                let target = match reexports.get(&first) {
                    Some(m) if !modules.contains(&first) => m.clone(),
                    _ => first,
                };
                if modules.contains(&target) && &target != from {
                    let at = edges.entry((from.clone(), target)).or_default();
                    if at.len() < 3 {
                        at.push(format!("{}:{}", rel.display(), line_of(&text, offset) + 1));
                    }
                }
            }
        }
        Graph { modules, edges }
    }

    /// Strongly connected components of more than one module, each sorted.
    fn cycles(&self) -> Vec<Vec<String>> {
        let next = |m: &String| -> Vec<&String> {
            self.edges
                .keys()
                .filter(|(a, _)| a == m)
                .map(|(_, b)| b)
                .collect()
        };
        let reach = |start: &String| -> BTreeSet<String> {
            let mut seen = BTreeSet::new();
            let mut todo = vec![start];
            while let Some(m) = todo.pop() {
                for n in next(m) {
                    if seen.insert(n.clone()) {
                        todo.push(n);
                    }
                }
            }
            seen
        };
        let reaches: BTreeMap<&String, BTreeSet<String>> =
            self.modules.iter().map(|m| (m, reach(m))).collect();
        let mut out: Vec<Vec<String>> = Vec::new();
        for m in &self.modules {
            if !reaches[m].contains(m) || out.iter().any(|c| c.contains(m)) {
                continue;
            }
            let component = self
                .modules
                .iter()
                .filter(|n| reaches[m].contains(*n) && reaches[*n].contains(m))
                .cloned()
                .collect();
            out.push(component);
        }
        out
    }

    /// The loop's modules and each import that closes it, with where.
    fn describe(&self, cycle: &[String]) -> String {
        let mut text = cycle.join(" ↔ ");
        for ((a, b), at) in &self.edges {
            if cycle.contains(a) && cycle.contains(b) {
                text += &format!("\n    {a} → {b}: {}", at.join(", "));
            }
        }
        text
    }
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// `src/a/b.rs` → [a, b]; `src/a/mod.rs` → [a]; the root → [].
fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if parts.len() == 1 && (parts[0] == "lib" || parts[0] == "main")
        || parts.last().unwrap() == "mod"
    {
        parts.pop();
    }
    parts
}

/// The text without `//` and `/* */` comments (a `//` inside a string,
/// as in a URL, is kept).
fn strip_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(i) = rest.find("/*") {
        out.push_str(&rest[..i]);
        let end = rest[i..].find("*/").map_or(rest.len(), |j| i + j + 2);
        // Keep the line count.
        out.extend(rest[i..end].chars().filter(|&c| c == '\n'));
        rest = &rest[end..];
    }
    out.push_str(rest);
    out.lines()
        .map(|line| {
            let mut quotes = 0;
            for (i, c) in line.char_indices() {
                if c == '"' {
                    quotes += 1;
                } else if quotes % 2 == 0 && line[i..].starts_with("//") {
                    return &line[..i];
                }
            }
            line
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The root's `pub use m::{X, Y}`: X → m.
fn reexports(root: &str) -> BTreeMap<String, String> {
    let flat = root.replace('\n', " ");
    let mut out = BTreeMap::new();
    for (i, _) in flat.match_indices("pub use ") {
        for path in paths(&flat[i + 8..]) {
            if let (Some(first), Some(last)) = (path.first(), path.last()) {
                if path.len() > 1 && first != "crate" && first != "self" {
                    out.insert(last.clone(), first.clone());
                }
            }
        }
    }
    out
}

fn line_of(text: &str, offset: usize) -> usize {
    text[..offset].matches('\n').count()
}

/// Where each path into another module starts, and the first name it
/// gives under the root: after `crate::`, or after as many `super::` as
/// climb from the depth at that offset to the root.
fn imports(text: &str, depth_at: impl Fn(usize) -> usize) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let word_start = |i: usize| {
        !text[..i]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':')
    };
    for (i, _) in text.match_indices("crate::") {
        if word_start(i) {
            out.extend(
                paths(&text[i + 7..])
                    .into_iter()
                    .filter_map(|p| Some((i, p.first()?.clone()))),
            );
        }
    }
    for (i, _) in text.match_indices("super::") {
        if !word_start(i) {
            continue;
        }
        let mut rest = &text[i..];
        let mut supers = 0;
        while let Some(r) = rest.strip_prefix("super::") {
            supers += 1;
            rest = r;
        }
        if supers == depth_at(i) {
            out.extend(
                paths(rest)
                    .into_iter()
                    .filter_map(|p| Some((i, p.first()?.clone()))),
            );
        }
    }
    out
}

/// The paths at the start of `text`: `a::b` is [[a, b]], `{a::b, c}` is
/// [[a, b], [c]] (nested groups flattened into their prefix).
fn paths(text: &str) -> Vec<Vec<String>> {
    let text = text.trim_start();
    if let Some(inner) = text.strip_prefix('{') {
        let mut depth = 0;
        let mut end = inner.len();
        for (i, c) in inner.char_indices() {
            match c {
                '{' => depth += 1,
                '}' if depth == 0 => {
                    end = i;
                    break;
                }
                '}' => depth -= 1,
                _ => {}
            }
        }
        let inner = &inner[..end];
        let (mut items, mut start, mut depth) = (Vec::new(), 0, 0);
        for (i, c) in inner.char_indices() {
            match c {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    items.push(&inner[start..i]);
                    start = i + 1;
                }
                _ => {}
            }
        }
        items.push(&inner[start..]);
        return items
            .into_iter()
            .filter(|item| !item.trim().is_empty())
            .flat_map(paths)
            .collect();
    }
    let mut segments = Vec::new();
    let mut rest = text;
    loop {
        let len = rest
            .find(|c: char| !(c.is_alphanumeric() || c == '_'))
            .unwrap_or(rest.len());
        if len == 0 {
            break;
        }
        segments.push(rest[..len].to_string());
        rest = &rest[len..];
        match rest.strip_prefix("::") {
            Some(r) if r.starts_with('{') => {
                return paths(r)
                    .into_iter()
                    .map(|tail| segments.iter().cloned().chain(tail).collect())
                    .collect();
            }
            Some(r) => rest = r,
            None => break,
        }
    }
    vec![segments]
}
