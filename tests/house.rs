//! The house rules of `src/`, checked in plain `cargo test` so that CI fails on the change that
//! breaks one, not a review later: no cycle between top-level modules (last time one was
//! removed, it came back with the next feature), and no file over [`MAX_LINES`] lines; and
//! the same limit for the JavaScript and TypeScript sources.
//!
//! - **No cycle between top-level modules.** A top-level module is an item directly under
//!   `src/` (`src/foo.rs` or `src/foo/` is module `foo`; `lib.rs` is the root, not a module).
//!   Module `foo` depends on `bar` when non-test code anywhere in `foo` names a path
//!   `crate::bar…` (also inside `use crate::{…, bar::{…}}` groups), a name the root re-exports
//!   from `bar` (`crate::Mesh` is `mesh`'s), or `bar` through `super::` paths that climb out
//!   of `foo`. A cycle is printed as module names, with the file and line of each edge in it;
//!   the fix is to move what both sides need down into the lower module.
//! - **No file over [`MAX_LINES`] lines of non-test code.** Every line of the file counts,
//!   comments and blank lines included, except test code. The fix is to split the file by
//!   idea, each new module named after its idea.
//! - **No script over [`MAX_LINES`] lines.** Every `.ts`, `.mjs` and `.js` file under
//!   [`SCRIPT_DIRS`] (the package's `js/`, the demo's `www/src/`, `benches/`, `scripts/`,
//!   `tests/fuzz/`), all of its lines counted: no test code is set apart there. What a build
//!   or an install wrote is skipped (folders named `node_modules`, `pkg`, `dist…`). The fix
//!   is the same: split by idea (`benches/` names its helper modules with a leading `_`).
//!
//! Test code counts for neither rule: an item gated by `#[cfg(test)]` (the inline
//! `mod tests { … }` up to its matching brace, a test-only helper) and a file that is itself a
//! test module (`tests.rs` declared by `#[cfg(test)] mod tests;`, and any file below it). Tests
//! may reach into another module to build their fixtures; the library may not.
//!
//! The sources are read as text, with std only: comments, strings and character literals are
//! blanked first (keeping the lines), so a path in a doc comment or a brace in a string
//! counts for nothing, and the rest is split into tokens. Native only: it reads `src/` (and
//! the scripts' folders).
#![cfg(not(target_arch = "wasm32"))]

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fs;
use std::path::Path;

/// The most lines of non-test code a file under `src/` may have, and the most lines a script
/// may have.
const MAX_LINES: usize = 600;

/// The folders, from the repository's root, whose scripts (`.ts`, `.mjs`, `.js`) are held to
/// [`MAX_LINES`].
const SCRIPT_DIRS: [&str; 5] = ["js", "www/src", "benches", "scripts", "tests/fuzz"];

#[test]
fn no_cycle_between_top_level_modules() {
    let house = House::of(&read_sources());
    let cycles = house.cycles();
    assert!(
        cycles.is_empty(),
        "cycles between top-level modules of src/ (move what both sides need into the lower one):\n{}",
        house.describe(&cycles)
    );
}

#[test]
fn no_file_over_the_limit() {
    let over: Vec<String> = House::of(&read_sources())
        .over_limit()
        .into_iter()
        .map(|(path, lines)| format!("  src/{path}: {lines} lines"))
        .collect();
    assert!(
        over.is_empty(),
        "files over {MAX_LINES} lines of non-test code (split them by idea):\n{}",
        over.join("\n")
    );
}

#[test]
fn no_script_over_the_limit() {
    let scripts = read_scripts();
    assert!(
        ["js/index.ts", "www/src/main.ts", "scripts/build-gl.mjs"]
            .iter()
            .all(|p| scripts.iter().any(|s| s.path == *p)),
        "the scripts' folders were not read (found {} scripts)",
        scripts.len()
    );
    let over: Vec<String> = scripts_over_limit(&scripts)
        .into_iter()
        .map(|(path, lines)| format!("  {path}: {lines} lines"))
        .collect();
    assert!(
        over.is_empty(),
        "scripts over {MAX_LINES} lines (split them by idea; benches/ names helper modules _like-this.mjs):\n{}",
        over.join("\n")
    );
}

/// The checker itself finds what it is for, on sources made up for the purpose.
#[test]
fn the_checker_finds_cycles_and_long_files() {
    let files = [
        ("lib.rs", "mod a;\nmod b;\nmod c;\nmod d;\npub use c::Gamma;\n"),
        // Paths in a brace group; a path in a comment or a string is no edge.
        (
            "a.rs",
            "//! crate::c::Gamma\nuse crate::{b::Beta, d::{self, Delta}};\n\
             const S: &str = \"crate::c { \"; // crate::c\n",
        ),
        // `crate::Gamma` is c's through the root. The test module's paths to d are no edge:
        // the brace in its character literal does not end it before the second.
        (
            "b.rs",
            "use crate::Gamma;\npub fn f() {\n    crate::a::g()\n}\n#[cfg(test)]\nmod tests {\n    \
             use crate::d::Delta;\n    const C: char = '}';\n    use crate::d::Delta;\n}\n",
        ),
        ("c.rs", "pub struct Gamma;\n"),
        // `super::super` climbs out of d, a single `super` does not.
        ("d/mod.rs", "mod e;\n#[cfg(test)]\nmod tests;\npub struct Sibling;\n"),
        ("d/e.rs", "use super::super::c::Gamma;\nuse super::Sibling;\n"),
        // A test module's file: no edge (it would close a -> d -> a), no line count.
        ("d/tests.rs", "use crate::a::A;\n"),
        ("long.rs", &format!("{}#[cfg(test)]\nmod tests {{\n{}}}\n", "//\n".repeat(601), "\n".repeat(900))),
        ("short.rs", &format!("{}#[cfg(test)]\nmod tests {{\n{}}}\n", "//\n".repeat(600), "\n".repeat(900))),
    ];
    let sources: Vec<Source> =
        files.iter().map(|(path, text)| Source { path: path.to_string(), text: text.to_string() }).collect();
    let house = House::of(&sources);

    let edges: Vec<(&str, &str)> = house.edges.keys().map(|(a, b)| (a.as_str(), b.as_str())).collect();
    assert_eq!(edges, [("a", "b"), ("a", "d"), ("b", "a"), ("b", "c"), ("d", "c")]);
    assert_eq!(house.cycles(), [vec!["a".to_string(), "b".to_string()]]);
    assert!(house.describe(&house.cycles()).contains("a -> b -> a"));

    let lines: BTreeMap<&str, usize> = house.lines.iter().map(|(p, n)| (p.as_str(), *n)).collect();
    assert_eq!(lines["b.rs"], 4);
    assert!(!lines.contains_key("d/tests.rs"));
    assert_eq!(house.over_limit(), [("long.rs".to_string(), 601)]);
}

/// The script checker finds long scripts, counting every line (comments and blank lines
/// too), and leaves alone other files and what builds and installs wrote.
#[test]
fn the_checker_finds_long_scripts() {
    let code = "x();\n";
    let files = [
        ("js/long.ts", code.repeat(601)),
        ("js/gl/short.ts", code.repeat(600)),
        // Comments and blank lines count; so does a last line with no newline.
        ("benches/_comments.mjs", format!("{}{}", "// a comment\n\n".repeat(300), "last();")),
        ("www/src/flags.d.ts", code.repeat(700)),
        ("tests/fuzz/short.mjs", code.repeat(10)),
        // Not scripts: another language, and what a build or an install wrote.
        ("benches/libigl/arap.py", code.repeat(700)),
        ("www/dist-test/worker.js", code.repeat(700)),
        ("js/node_modules/esbuild/lib/main.js", code.repeat(700)),
        ("scripts/pkg/bunraku.js", code.repeat(700)),
    ];
    let sources: Vec<Source> =
        files.iter().map(|(path, text)| Source { path: path.to_string(), text: text.clone() }).collect();
    assert_eq!(
        scripts_over_limit(&sources),
        [
            ("js/long.ts".to_string(), 601),
            ("benches/_comments.mjs".to_string(), 601),
            ("www/src/flags.d.ts".to_string(), 700)
        ]
    );
    assert!(is_script("scripts/build-gl.mjs") && is_script("js/gl/view.ts"));
    assert!(!is_script("www/dist/main.js") && !is_script("benches/common/mod.rs"));
}

/// A source file: its path below `src/` with `/` separators (`meshing/shape.rs`), and its text
/// (or, for a script, its path from the repository's root: `www/src/main.ts`).
struct Source {
    path: String,
    text: String,
}

/// The files under `dir` (sorted, `prefix` before their paths) that `keep` accepts, not
/// entering generated folders (see [`is_generated_dir`]).
fn walk(dir: &Path, prefix: &str, keep: &dyn Fn(&str) -> bool, out: &mut Vec<Source>) {
    let mut entries: Vec<_> = fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for entry in entries {
        let name = entry.file_name().unwrap().to_str().unwrap();
        let path = format!("{prefix}{name}");
        if entry.is_dir() {
            if !is_generated_dir(name) {
                walk(&entry, &format!("{path}/"), keep, out);
            }
        } else if keep(&path) {
            out.push(Source { path, text: fs::read_to_string(&entry).unwrap() });
        }
    }
}

/// Every `.rs` file under `src/`.
fn read_sources() -> Vec<Source> {
    let mut out = Vec::new();
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    walk(&src, "", &|path: &str| path.ends_with(".rs"), &mut out);
    assert!(out.iter().any(|s| s.path == "lib.rs"), "no src/lib.rs");
    out
}

/// Every script (see [`is_script`]) under [`SCRIPT_DIRS`], generated folders not entered.
fn read_scripts() -> Vec<Source> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    for dir in SCRIPT_DIRS {
        if root.join(dir).is_dir() {
            walk(&root.join(dir), &format!("{dir}/"), &is_script, &mut out);
        }
    }
    out
}

/// A folder that a build or an install writes (`node_modules`, `pkg`, `dist`, `dist-test`…),
/// whose files are no one's source.
fn is_generated_dir(name: &str) -> bool {
    name == "node_modules" || name == "pkg" || name.starts_with("dist")
}

/// Whether `path` (from the repository's root, `/` separators) is a script held to
/// [`MAX_LINES`]: a `.ts` (`.d.ts` too), `.mjs` or `.js` file outside generated folders.
fn is_script(path: &str) -> bool {
    let (dirs, name) = path.rsplit_once('/').unwrap_or(("", path));
    [".ts", ".mjs", ".js"].iter().any(|ext| name.ends_with(ext)) && !dirs.split('/').any(is_generated_dir)
}

/// The scripts over [`MAX_LINES`] lines, every line counted, with their counts, in order.
fn scripts_over_limit(scripts: &[Source]) -> Vec<(String, usize)> {
    scripts
        .iter()
        .filter(|s| is_script(&s.path))
        .map(|s| (s.path.clone(), s.text.lines().count()))
        .filter(|&(_, n)| n > MAX_LINES)
        .collect()
}

/// What the rules look at in `src/`.
struct House {
    /// Each dependency between top-level modules, with where it was first seen
    /// (`src/meshing/shape.rs:12`).
    edges: BTreeMap<(String, String), String>,
    /// Each file's lines of non-test code (test modules' files are not listed).
    lines: Vec<(String, usize)>,
}

impl House {
    fn of(sources: &[Source]) -> House {
        let files: Vec<(&Source, Scan)> = sources.iter().map(|s| (s, Scan::of(&s.text))).collect();
        let test_files = test_files(&files);
        let modules: BTreeSet<String> =
            sources.iter().filter_map(|s| top_level_module(&s.path)).map(str::to_string).collect();
        let root_exports = files
            .iter()
            .find(|(s, _)| s.path == "lib.rs")
            .map(|(_, scan)| root_exports(&scan.code(), &modules))
            .unwrap_or_default();

        let mut edges = BTreeMap::new();
        let mut lines = Vec::new();
        for (source, scan) in &files {
            if test_files.iter().any(|t| is_test_file(&source.path, t)) {
                continue;
            }
            lines.push((source.path.clone(), scan.lines - scan.test_lines()));
            let Some(from) = top_level_module(&source.path) else { continue };
            for (name, line) in scan.dependencies(module_depth(&source.path)) {
                let to = if modules.contains(name) {
                    Some(name)
                } else {
                    root_exports.get(name).map(|s| s.as_str())
                };
                if let Some(to) = to.filter(|&to| to != from) {
                    edges
                        .entry((from.to_string(), to.to_string()))
                        .or_insert_with(|| format!("src/{}:{line}", source.path));
                }
            }
        }
        House { edges, lines }
    }

    /// The files over [`MAX_LINES`] lines of non-test code, with their counts.
    fn over_limit(&self) -> Vec<(String, usize)> {
        self.lines.iter().filter(|(_, n)| *n > MAX_LINES).cloned().collect()
    }

    /// One cycle per group of modules that depend on each other (a strongly connected
    /// component of two or more), the shortest through the group's first module, in order:
    /// `[a, b, c]` is `a -> b -> c -> a`.
    fn cycles(&self) -> Vec<Vec<String>> {
        let mut next: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
        for (a, b) in self.edges.keys() {
            next.entry(a).or_default().push(b);
        }
        let reach = |from: &str| -> BTreeSet<&str> {
            let mut seen = BTreeSet::new();
            let mut stack = vec![from];
            while let Some(m) = stack.pop() {
                for &n in next.get(m).into_iter().flatten() {
                    if seen.insert(n) {
                        stack.push(n);
                    }
                }
            }
            seen
        };
        let reaches: BTreeMap<&str, BTreeSet<&str>> = next.keys().map(|&m| (m, reach(m))).collect();
        let mut done = BTreeSet::new();
        let mut cycles = Vec::new();
        for (&start, from_start) in &reaches {
            if done.contains(start) || !from_start.contains(start) {
                continue;
            }
            let group: BTreeSet<&str> = from_start
                .iter()
                .copied()
                .filter(|m| reaches.get(m).is_some_and(|r| r.contains(start)))
                .collect();
            done.extend(group.iter().copied());
            // Breadth-first from `start` inside the group, back to `start`.
            let mut parent: BTreeMap<&str, &str> = BTreeMap::new();
            let mut queue = VecDeque::from([start]);
            'search: while let Some(m) = queue.pop_front() {
                for &n in &next[m] {
                    if n == start {
                        parent.insert(start, m);
                        break 'search;
                    }
                    if group.contains(n) && !parent.contains_key(n) {
                        parent.insert(n, m);
                        queue.push_back(n);
                    }
                }
            }
            let mut cycle = vec![start.to_string()];
            let mut m = parent[start];
            while m != start {
                cycle.push(m.to_string());
                m = parent[m];
            }
            cycle[1..].reverse();
            cycles.push(cycle);
        }
        cycles
    }

    /// The cycles as `a -> b -> a`, then every edge between the modules of each cycle's group
    /// with where it comes from.
    fn describe(&self, cycles: &[Vec<String>]) -> String {
        let mut out = String::new();
        for cycle in cycles {
            out += &format!("  {} -> {}\n", cycle.join(" -> "), cycle[0]);
        }
        out += "edges among them (the first place each is seen):\n";
        let members: BTreeSet<&String> = cycles.iter().flatten().collect();
        for ((a, b), place) in &self.edges {
            if members.contains(a) && members.contains(b) {
                out += &format!("  {a} -> {b}  ({place})\n");
            }
        }
        out
    }
}

/// A token of Rust source: an identifier or keyword (numbers too), `::`, or one other
/// character; with its line, from 1.
struct Token {
    text: String,
    line: usize,
}

/// One file, scanned.
struct Scan {
    tokens: Vec<Token>,
    /// The token ranges (inclusive) of items gated by `#[cfg(test)]`.
    tests: Vec<(usize, usize)>,
    /// The names of the test modules the file declares without a body (`#[cfg(test)] mod tests;`).
    test_modules: Vec<String>,
    /// Whether the whole file is test code (`#![cfg(test)]`).
    test_file: bool,
    /// How many lines the file has.
    lines: usize,
}

impl Scan {
    fn of(text: &str) -> Scan {
        let tokens = tokens(&blank_comments_and_literals(text));
        let at = |i: usize, texts: &[&str]| {
            texts.iter().enumerate().all(|(k, t)| tokens.get(i + k).is_some_and(|tok| tok.text == *t))
        };
        let mut tests = Vec::new();
        let mut test_modules = Vec::new();
        let mut i = 0;
        while i < tokens.len() {
            if at(i, &["#", "[", "cfg", "(", "test", ")", "]"]) {
                let end = item_end(&tokens, i + 7);
                if at(end - 2, &["mod"]) && at(end, &[";"]) {
                    test_modules.push(tokens[end - 1].text.clone());
                }
                tests.push((i, end));
                i = end;
            }
            i += 1;
        }
        let test_file = (0..tokens.len()).any(|i| at(i, &["#", "!", "[", "cfg", "(", "test", ")", "]"]));
        Scan { tokens, tests, test_modules, test_file, lines: text.lines().count() }
    }

    /// The tokens outside test code.
    fn code(&self) -> Vec<&Token> {
        let mut tests = self.tests.iter().peekable();
        let mut out = Vec::new();
        let mut i = 0;
        while i < self.tokens.len() {
            match tests.peek() {
                Some(&&(start, end)) if start == i => {
                    tests.next();
                    i = end + 1;
                }
                _ => {
                    out.push(&self.tokens[i]);
                    i += 1;
                }
            }
        }
        out
    }

    /// How many lines test items span.
    fn test_lines(&self) -> usize {
        let lines: BTreeSet<usize> = self
            .tests
            .iter()
            .flat_map(|&(start, end)| self.tokens[start].line..=self.tokens[end].line)
            .collect();
        lines.len()
    }

    /// The first names of the paths that leave a module `depth` levels below the root, with
    /// their lines: `crate::a::…` and `crate::{a::…, b}` name `a` and `b`, so does
    /// `super::super::a` two levels below the root (in a file, or in inline modules).
    fn dependencies(&self, depth: usize) -> Vec<(&str, usize)> {
        let code = self.code();
        let text = |i: usize| code.get(i).map_or("", |t| t.text.as_str());
        let mut out = Vec::new();
        let mut braces = 0;
        let mut inline_modules = Vec::new(); // the brace depth each was opened at
        for i in 0..code.len() {
            let starts_path = i == 0 || !matches!(text(i - 1), "::" | "$");
            match text(i) {
                "{" => braces += 1,
                "}" => {
                    braces -= 1;
                    if inline_modules.last() == Some(&braces) {
                        inline_modules.pop();
                    }
                }
                "mod" if text(i + 2) == "{" => inline_modules.push(braces),
                "crate" if starts_path && text(i + 1) == "::" => out.extend(heads(&code, i + 2)),
                "super" if starts_path => {
                    let mut j = i;
                    while text(j) == "super" && text(j + 1) == "::" {
                        j += 2;
                    }
                    if (j - i) / 2 >= depth + inline_modules.len() {
                        out.extend(heads(&code, j));
                    }
                }
                _ => {}
            }
        }
        out.into_iter().map(|t| (t.text.as_str(), t.line)).collect()
    }
}

/// The first segments of the path tree at `code[i]`: `a` for `a::…`, and each member's for a
/// group `{a::…, b, c::{…}, self}` (groups nest).
fn heads<'a>(code: &[&'a Token], i: usize) -> Vec<&'a Token> {
    let Some(first) = code.get(i) else { return Vec::new() };
    if first.text != "{" {
        return if is_identifier(&first.text) { vec![first] } else { Vec::new() };
    }
    let mut out = Vec::new();
    let mut depth = 0;
    let mut member_starts = true;
    for (j, token) in code.iter().enumerate().skip(i + 1) {
        match token.text.as_str() {
            "{" => {
                if depth == 0 && member_starts {
                    out.extend(heads(code, j));
                }
                depth += 1;
            }
            "}" if depth == 0 => break,
            "}" => depth -= 1,
            "," if depth == 0 => {
                member_starts = true;
                continue;
            }
            name if depth == 0 && member_starts && is_identifier(name) && name != "self" => out.push(token),
            _ => {}
        }
        member_starts = false;
    }
    out
}

/// The index of the last token of the item that starts at `tokens[i]` (after its attributes):
/// its `;`, or the brace that closes its body (and a `;` right after it).
fn item_end(tokens: &[Token], i: usize) -> usize {
    let mut nesting = 0; // of ( ) and [ ]
    let mut j = i;
    while j < tokens.len() {
        match tokens[j].text.as_str() {
            "(" | "[" => nesting += 1,
            ")" | "]" => nesting -= 1,
            ";" if nesting == 0 => return j,
            "{" if nesting == 0 => {
                let mut braces = 0;
                while j < tokens.len() {
                    match tokens[j].text.as_str() {
                        "{" => braces += 1,
                        "}" => braces -= 1,
                        _ => {}
                    }
                    if braces == 0 {
                        break;
                    }
                    j += 1;
                }
                let closes = tokens.get(j + 1).is_some_and(|t| t.text == ";");
                return (j + usize::from(closes)).min(tokens.len() - 1);
            }
            _ => {}
        }
        j += 1;
    }
    tokens.len() - 1
}

/// The root's re-exports (`pub use mesh::{Edge, Mesh};`), by name: the module each comes from.
fn root_exports(code: &[&Token], modules: &BTreeSet<String>) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    let mut braces = 0;
    let mut i = 0;
    while i < code.len() {
        match code[i].text.as_str() {
            "{" => braces += 1,
            "}" => braces -= 1,
            "use" if braces == 0 => {
                let mut j = i + 1;
                while matches!(code.get(j + 1).map(|t| t.text.as_str()), Some("::"))
                    && matches!(code[j].text.as_str(), "crate" | "self")
                {
                    j += 2;
                }
                let module = &code[j].text;
                while j < code.len() && code[j].text != ";" {
                    let name = &code[j].text;
                    let followed_by_path = code.get(j + 1).is_some_and(|t| t.text == "::");
                    if modules.contains(module) && is_identifier(name) && !followed_by_path && name != "as" {
                        out.insert(name.clone(), module.clone());
                    }
                    j += 1;
                }
                i = j;
            }
            _ => {}
        }
        i += 1;
    }
    out
}

/// The files that are test modules' (`#[cfg(test)] mod tests;` in `foo/mod.rs` declares
/// `foo/tests.rs` or `foo/tests/mod.rs`, with all below `foo/tests/`), as module paths
/// (`foo/tests`); and the files marked `#![cfg(test)]`, as they are (`foo/bar.rs`).
fn test_files(files: &[(&Source, Scan)]) -> Vec<String> {
    let mut out = Vec::new();
    for (source, scan) in files {
        if scan.test_file {
            out.push(source.path.clone());
        }
        let dir = match source.path.as_str() {
            "lib.rs" => String::new(),
            path if path.ends_with("/mod.rs") => path.trim_end_matches("mod.rs").to_string(),
            path => format!("{}/", path.trim_end_matches(".rs")),
        };
        out.extend(scan.test_modules.iter().map(|name| format!("{dir}{name}")));
    }
    out
}

/// Whether `path` is the file `test` (`foo/bar.rs`), or the module `test`'s (`foo/tests`).
fn is_test_file(path: &str, test: &str) -> bool {
    path == test
        || path == format!("{test}.rs")
        || path.strip_prefix(test).is_some_and(|rest| rest.starts_with('/'))
}

/// The top-level module a file belongs to: `foo` for `foo.rs` and `foo/…`; none for `lib.rs`.
fn top_level_module(path: &str) -> Option<&str> {
    match path.split_once('/') {
        Some((module, _)) => Some(module),
        None => path.strip_suffix(".rs").filter(|&m| m != "lib"),
    }
}

/// How many levels below the root a file's module is: 1 for `foo.rs` and `foo/mod.rs`, 2 for
/// `foo/bar.rs`; 0 for `lib.rs`.
fn module_depth(path: &str) -> usize {
    let levels = path.split('/').count();
    if path.ends_with("/mod.rs") || path == "lib.rs" {
        levels - 1
    } else {
        levels
    }
}

fn is_identifier(text: &str) -> bool {
    text.starts_with(|c: char| c.is_alphabetic() || c == '_')
}

/// The tokens of source text whose comments and literals are blank.
fn tokens(text: &str) -> Vec<Token> {
    let mut out = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let mut chars = line.char_indices().peekable();
        while let Some((start, c)) = chars.next() {
            let mut end = start + c.len_utf8();
            if c.is_alphanumeric() || c == '_' {
                while let Some(&(k, d)) = chars.peek().filter(|(_, d)| d.is_alphanumeric() || *d == '_') {
                    end = k + d.len_utf8();
                    chars.next();
                }
            } else if c == ':' && chars.peek().is_some_and(|&(_, d)| d == ':') {
                chars.next();
                end += 1;
            } else if c.is_whitespace() {
                continue;
            }
            out.push(Token { text: line[start..end].to_string(), line: index + 1 });
        }
    }
    out
}

/// The text with every comment (line, block, doc) and the inside of every string, raw string
/// and character literal replaced by spaces, lines kept: what is left is code.
fn blank_comments_and_literals(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let blank = |out: &mut String, c: char| out.push(if c == '\n' { '\n' } else { ' ' });
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        let after_identifier = i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_');
        // A raw string: `r"…"`, `r#"…"#`, `br"…"` (not a raw identifier `r#type`).
        let raw = if !after_identifier && (c == 'r' || c == 'b' && next == Some('r')) {
            let open = if c == 'b' { i + 2 } else { i + 1 };
            let hashes = chars[open..].iter().take_while(|&&h| h == '#').count();
            (chars.get(open + hashes) == Some(&'"')).then_some((open, hashes))
        } else {
            None
        };
        if let Some((open, hashes)) = raw {
            out.extend(&chars[i..=open + hashes]);
            i = open + hashes + 1;
            let closes = |k: usize| {
                chars[k] == '"' && chars[k + 1..].iter().take(hashes).filter(|&&h| h == '#').count() == hashes
            };
            while i < chars.len() && !closes(i) {
                blank(&mut out, chars[i]);
                i += 1;
            }
            out.extend(chars[i..].iter().take(hashes + 1));
            i += hashes + 1;
        } else if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                blank(&mut out, chars[i]);
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < chars.len() {
                let pair = (chars[i], chars.get(i + 1).copied());
                if pair == ('/', Some('*')) || pair == ('*', Some('/')) {
                    depth += if pair.0 == '/' { 1 } else { -1 };
                    out += "  ";
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    blank(&mut out, chars[i]);
                    i += 1;
                }
            }
        } else if c == '"' {
            out.push('"');
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                let width = if chars[i] == '\\' { 2 } else { 1 };
                for &d in chars[i..].iter().take(width) {
                    blank(&mut out, d);
                }
                i += width;
            }
            out.push('"');
            i += 1;
        } else if c == '\'' && (next == Some('\\') || chars.get(i + 2) == Some(&'\'')) {
            // A character literal (`'x'`, `'\''`, `'\u{7b}'`), not a lifetime or label (`'a`).
            out.push('\'');
            i += 1;
            if chars[i] == '\\' {
                out += "  ";
                i += 2;
            }
            while i < chars.len() && chars[i] != '\'' {
                blank(&mut out, chars[i]);
                i += 1;
            }
            out.push('\'');
            i += 1;
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}
