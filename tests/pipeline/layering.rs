//! The library's layers run one way, no module's files import each other in a
//! circle, and the checkers share no code with what they check.
//!
//! Every `src/**/*.rs` is read up to its first `#[cfg(test)]`, comments and string
//! contents blanked out, and each path that starts with `crate::`, `super::`,
//! `self::` or (in a file declaring submodules) a submodule's name becomes an edge
//! from the file to the file that defines the path's last module (through `pub use`
//! re-exports, so `super::ScheduleError` leads to `schedule/error.rs`, not to
//! `schedule/mod.rs`). A module file's own `pub use child::…` facade lines are not
//! edges. Inline `mod name { … }` blocks are read as part of their file.

use crate::support::repo_root;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fmt::Write as _;
use std::path::Path;

/// The library's top-level modules, lowest first. A module may import its own layer's
/// peers and earlier layers, never a later one.
const LAYERS: &[&[&str]] = &[
    &["world"],
    &["profile"],
    &["mission"],
    &["import", "generate"],
    &["plan"],
    &["schedule"],
    &["trajectory"],
    &["verify"],
    &["compiled"],
    &["link"],
    &["fly"],
];

/// A checker and what it checks: files under the first prefix may not import files
/// under any of the second, except those under a prefix listed third.
const CHECKERS: &[(&str, &[&str], &[&str])] = &[
    (
        "src/verify/",
        &[
            "src/plan/",
            "src/schedule/",
            "src/trajectory/",
            "src/profile",
        ],
        &[],
    ),
    (
        "src/plan/validator/",
        &["src/plan/"],
        &["src/plan/discrete_plan.rs", "src/plan/validator/"],
    ),
];

/// One path found in a source file.
#[derive(Debug, Clone)]
struct Reference {
    line: usize,
    /// As written, e.g. `super::solve::PlanError`.
    text: String,
    /// From the crate root, e.g. `["plan", "solve", "PlanError"]`.
    absolute: Vec<String>,
}

/// A source file: its path below the repository (`src/plan/rotation.rs`), module path
/// (`["plan", "rotation"]`), references and `pub use` names.
struct SourceFile {
    path: String,
    module: Vec<String>,
    references: Vec<Reference>,
    /// `pub use` names of this file's module, each to its absolute path.
    reexports: HashMap<String, Vec<String>>,
}

/// One import from a file to another.
struct Edge {
    from: String,
    to: String,
    line: usize,
    text: String,
}

#[test]
fn library_layers_run_one_way_without_cycles() {
    let root = repo_root();
    let files = read_sources(&root.join("src"));
    let edges = resolve_edges(&files);
    let mut failures = Vec::new();
    failures.extend(unlisted_modules(&files));
    failures.extend(layer_violations(&edges));
    failures.extend(cycles(&edges));
    failures.extend(checker_violations(&edges));
    assert!(
        failures.is_empty(),
        "{} layering problem(s):\n  {}",
        failures.len(),
        failures.join("\n  ")
    );
}

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|layer| layer.contains(&module))
}

/// The top-level module a file belongs to (`None` for `src/lib.rs`).
fn top_module(path: &str) -> Option<&str> {
    let rest = path.strip_prefix("src/")?;
    let first = rest.split('/').next()?;
    let name = first.strip_suffix(".rs").unwrap_or(first);
    (name != "lib").then_some(name)
}

fn unlisted_modules(files: &[SourceFile]) -> Vec<String> {
    let modules: BTreeSet<&str> = files.iter().filter_map(|f| top_module(&f.path)).collect();
    modules
        .into_iter()
        .filter(|m| layer_of(m).is_none())
        .map(|m| format!("module `{m}` is missing from LAYERS in tests/pipeline/layering.rs"))
        .collect()
}

fn layer_violations(edges: &[Edge]) -> Vec<String> {
    let mut out = Vec::new();
    for e in edges {
        let (Some(from), Some(to)) = (top_module(&e.from), top_module(&e.to)) else {
            continue;
        };
        if let (Some(a), Some(b)) = (layer_of(from), layer_of(to))
            && b > a
        {
            out.push(format!(
                "{}:{}: `{}` — {from} imports {to}, a later layer",
                e.from, e.line, e.text
            ));
        }
    }
    out
}

fn checker_violations(edges: &[Edge]) -> Vec<String> {
    let mut out = Vec::new();
    for &(checker, checked, allowed) in CHECKERS {
        for e in edges.iter().filter(|e| e.from.starts_with(checker)) {
            if checked.iter().any(|c| e.to.starts_with(c))
                && !allowed.iter().any(|a| e.to.starts_with(a))
            {
                out.push(format!(
                    "{}:{}: `{}` — the checker imports {}, which it checks",
                    e.from, e.line, e.text, e.to
                ));
            }
        }
    }
    out
}

/// Import cycles among the files of one top-level module, one line per cycle.
fn cycles(edges: &[Edge]) -> Vec<String> {
    let mut graph: BTreeMap<&str, Vec<&Edge>> = BTreeMap::new();
    for e in edges {
        if e.from != e.to
            && top_module(&e.from).is_some()
            && top_module(&e.from) == top_module(&e.to)
        {
            graph.entry(&e.from).or_default().push(e);
        }
    }
    // Depth-first search; a back edge closes a cycle through the current stack.
    let mut state: HashMap<&str, u8> = HashMap::new(); // 1 on the stack, 2 done
    let mut stack: Vec<&Edge> = Vec::new();
    let mut found = Vec::new();
    let mut seen: BTreeSet<BTreeSet<String>> = BTreeSet::new();
    let starts: Vec<&str> = graph.keys().copied().collect();
    for start in starts {
        dfs(start, &graph, &mut state, &mut stack, &mut found, &mut seen);
    }
    found
}

fn dfs<'a>(
    file: &'a str,
    graph: &BTreeMap<&'a str, Vec<&'a Edge>>,
    state: &mut HashMap<&'a str, u8>,
    stack: &mut Vec<&'a Edge>,
    found: &mut Vec<String>,
    seen: &mut BTreeSet<BTreeSet<String>>,
) {
    if state.contains_key(file) {
        return;
    }
    state.insert(file, 1);
    for &e in graph.get(file).into_iter().flatten() {
        match state.get(e.to.as_str()) {
            Some(1) => {
                let first = stack
                    .iter()
                    .position(|s| s.from == e.to)
                    .unwrap_or(stack.len());
                let cycle: Vec<&Edge> = stack[first..].iter().copied().chain([e]).collect();
                let members = cycle.iter().map(|c| c.from.clone()).collect();
                if seen.insert(members) {
                    let mut text = String::from("import cycle:");
                    for c in &cycle {
                        write!(text, " {}:{} `{}` →", c.from, c.line, c.text).unwrap();
                    }
                    write!(text, " {}", e.to).unwrap();
                    found.push(text);
                }
            }
            Some(_) => {}
            None => {
                stack.push(e);
                dfs(&e.to, graph, state, stack, found, seen);
                stack.pop();
            }
        }
    }
    state.insert(file, 2);
}

/// Every file's references, resolved to the file that defines their module.
fn resolve_edges(files: &[SourceFile]) -> Vec<Edge> {
    let by_module: HashMap<&[String], &SourceFile> =
        files.iter().map(|f| (f.module.as_slice(), f)).collect();
    let mut edges = Vec::new();
    for f in files {
        for r in &f.references {
            edges.push(Edge {
                from: f.path.clone(),
                to: resolve(&r.absolute, &by_module, 0).to_string(),
                line: r.line,
                text: r.text.clone(),
            });
        }
    }
    edges
}

/// The file defining the deepest module `path` names, following `pub use` names.
fn resolve<'a>(
    path: &[String],
    by_module: &HashMap<&[String], &'a SourceFile>,
    depth: usize,
) -> &'a str {
    let crate_root: &[String] = &[];
    let mut file = by_module[crate_root];
    let mut module: Vec<String> = Vec::new();
    for (i, segment) in path.iter().enumerate() {
        if segment == "self" {
            continue;
        }
        module.push(segment.clone());
        if let Some(child) = by_module.get(module.as_slice()) {
            file = child;
            continue;
        }
        if let Some(target) = file.reexports.get(segment)
            && depth < 8
        {
            let full: Vec<String> = target.iter().chain(&path[i + 1..]).cloned().collect();
            return resolve(&full, by_module, depth + 1);
        }
        break;
    }
    &file.path
}

fn read_sources(src: &Path) -> Vec<SourceFile> {
    let mut paths = Vec::new();
    collect_rs(src, &mut paths);
    paths.sort();
    let root = src.parent().unwrap();
    paths
        .iter()
        .map(|p| {
            let rel = p
                .strip_prefix(root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            let text = std::fs::read_to_string(p).unwrap();
            parse_file(&rel, &text)
        })
        .collect()
}

fn collect_rs(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            collect_rs(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// `src/plan/mod.rs` → `["plan"]`, `src/plan/rotation.rs` → `["plan", "rotation"]`, `src/lib.rs` → `[]`.
fn module_path(rel: &str) -> Vec<String> {
    let rest = rel
        .strip_prefix("src/")
        .unwrap()
        .strip_suffix(".rs")
        .unwrap();
    let mut parts: Vec<String> = rest.split('/').map(str::to_string).collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        parts.pop();
    }
    parts
}

fn parse_file(rel: &str, text: &str) -> SourceFile {
    let module = module_path(rel);
    let code = blank_comments_and_strings(non_test_part(text));
    let children = declared_children(&code);
    let mut references = Vec::new();
    let mut reexports = HashMap::new();
    // `pub use` statements: names of this module; only crate/super paths are edges.
    let mut facade = vec![false; code.len()];
    for (start, end) in pub_use_spans(&code) {
        let body = &code[start..end];
        let use_at = body.find("use").unwrap() + 3;
        for (segments, name) in use_tree(&body[use_at..]) {
            let absolute = absolute(&module, &segments);
            if let (Some(name), Some(absolute)) = (name, absolute) {
                reexports.insert(name, absolute);
            }
        }
        facade[start..end].iter_mut().for_each(|b| *b = true);
    }
    let bytes = code.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        let starts_word =
            i == 0 || !(is_ident(bytes[i - 1]) || bytes[i - 1] == b':' || bytes[i - 1] == b'$');
        if !starts_word || !is_ident(bytes[i]) {
            i += 1;
            continue;
        }
        let word_end = i + code[i..].bytes().take_while(|&b| is_ident(b)).count();
        let word = &code[i..word_end];
        let relative_child = children.contains(word) && !facade[i];
        if code[word_end..].starts_with("::")
            && (matches!(word, "crate" | "super" | "self") || relative_child)
        {
            let end = path_end(&code, i);
            for (segments, _) in use_tree(&code[i..end]) {
                if let Some(absolute) = absolute(&module, &segments) {
                    references.push(Reference {
                        line: code[..i].matches('\n').count() + 1,
                        text: segments.join("::").trim_end_matches("::self").to_string(),
                        absolute,
                    });
                }
            }
            i = end;
        } else {
            i = word_end;
        }
    }
    SourceFile {
        path: rel.to_string(),
        module,
        references,
        reexports,
    }
}

fn is_ident(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

/// The text before the first `#[cfg(test)]` line.
fn non_test_part(text: &str) -> &str {
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        if line.trim_start().starts_with("#[cfg(test)]") {
            return &text[..offset];
        }
        offset += line.len();
    }
    text
}

/// The source with comments and the insides of string and char literals replaced by
/// spaces (newlines kept, so byte offsets and line numbers stay).
fn blank_comments_and_strings(code: &str) -> String {
    let b = code.as_bytes();
    let mut out = b.to_vec();
    let mut i = 0;
    let blank = |out: &mut Vec<u8>, from: usize, to: usize| {
        for c in &mut out[from..to] {
            if *c != b'\n' {
                *c = b' ';
            }
        }
    };
    while i < b.len() {
        if b[i..].starts_with(b"//") {
            let end = b[i..]
                .iter()
                .position(|&c| c == b'\n')
                .map_or(b.len(), |p| i + p);
            blank(&mut out, i, end);
            i = end;
        } else if b[i..].starts_with(b"/*") {
            let (mut depth, mut j) = (1, i + 2);
            while j < b.len() && depth > 0 {
                if b[j..].starts_with(b"/*") {
                    depth += 1;
                    j += 2;
                } else if b[j..].starts_with(b"*/") {
                    depth -= 1;
                    j += 2;
                } else {
                    j += 1;
                }
            }
            blank(&mut out, i, j);
            i = j;
        } else if b[i] == b'r'
            && (i == 0 || !is_ident(b[i - 1]))
            && matches!(b.get(i + 1), Some(b'"' | b'#'))
        {
            let hashes = b[i + 1..].iter().take_while(|&&c| c == b'#').count();
            if b.get(i + 1 + hashes) != Some(&b'"') {
                i += 1;
                continue;
            }
            let close: Vec<u8> = std::iter::once(b'"')
                .chain(std::iter::repeat_n(b'#', hashes))
                .collect();
            let body = i + 2 + hashes;
            let end = (body..b.len())
                .find(|&j| b[j..].starts_with(&close))
                .unwrap_or(b.len());
            blank(&mut out, body, end);
            i = end + close.len();
        } else if b[i] == b'"' {
            let mut j = i + 1;
            while j < b.len() && b[j] != b'"' {
                j += if b[j] == b'\\' { 2 } else { 1 };
            }
            blank(&mut out, i + 1, j.min(b.len()));
            i = j + 1;
        } else if b[i] == b'\'' {
            // A char literal ('x', '\n', '"'); anything else is a lifetime.
            let len = if b.get(i + 1) == Some(&b'\\') {
                b[i + 2..].iter().position(|&c| c == b'\'').map(|p| p + 2)
            } else {
                let ch = code[i + 1..].chars().next().map_or(1, char::len_utf8);
                (b.get(i + 1 + ch) == Some(&b'\'')).then_some(ch)
            };
            match len {
                Some(len) => {
                    blank(&mut out, i + 1, i + 1 + len);
                    i += len + 2;
                }
                None => i += 1,
            }
        } else {
            i += 1;
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Names declared with `mod name;` (or `pub mod name;`).
fn declared_children(code: &str) -> BTreeSet<String> {
    code.split(';')
        .filter_map(|statement| {
            let words: Vec<&str> = statement.split_whitespace().collect();
            match words.as_slice() {
                [.., "mod", name] if is_plain_name(name) => Some((*name).to_string()),
                _ => None,
            }
        })
        .collect()
}

fn is_plain_name(s: &str) -> bool {
    !s.is_empty() && s.bytes().all(is_ident)
}

/// Byte ranges of `pub use …;` and `pub(…) use …;` statements.
fn pub_use_spans(code: &str) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut from = 0;
    while let Some(p) = code[from..].find("pub") {
        let start = from + p;
        from = start + 3;
        if start > 0 && is_ident(code.as_bytes()[start - 1]) {
            continue;
        }
        let mut rest = code[start + 3..].trim_start();
        if rest.starts_with('(') {
            rest = rest[rest.find(')').map_or(0, |c| c + 1)..].trim_start();
        }
        if rest.starts_with("use ") || rest.starts_with("use\n") {
            let end = start + code[start..].find(';').unwrap_or(code.len() - start);
            spans.push((start, end));
            from = end;
        }
    }
    spans
}

/// Where the path starting at `start` ends: after its last segment or closing brace.
fn path_end(code: &str, start: usize) -> usize {
    let b = code.as_bytes();
    let mut i = start;
    let mut depth = 0usize;
    while i < b.len() {
        match b[i] {
            b'{' => depth += 1,
            b'}' if depth > 0 => {
                depth -= 1;
                if depth == 0 {
                    return i + 1;
                }
            }
            c if depth > 0
                && (is_ident(c) || c.is_ascii_whitespace() || matches!(c, b',' | b':' | b'*')) => {}
            c if depth == 0 && (is_ident(c) || c == b':') => {}
            _ if depth == 0 => return i,
            _ => {}
        }
        i += 1;
    }
    i
}

/// Expands a use tree (`a::{b, c::{self, D as E}}`) into its paths, each with the
/// name it binds.
fn use_tree(text: &str) -> Vec<(Vec<String>, Option<String>)> {
    let mut out = Vec::new();
    expand(text.trim().trim_end_matches(';').trim(), &[], &mut out);
    out
}

fn expand(text: &str, prefix: &[String], out: &mut Vec<(Vec<String>, Option<String>)>) {
    let text = text.trim().trim_start_matches("::");
    if let Some(open) = text.find('{') {
        let head: Vec<String> = segments(&text[..open]);
        let inner = &text[open + 1..text.rfind('}').unwrap_or(text.len())];
        let base: Vec<String> = prefix.iter().cloned().chain(head).collect();
        for part in split_top_level(inner) {
            expand(part, &base, out);
        }
        return;
    }
    let (path, rename) = match text.split_once(" as ") {
        Some((p, r)) => (p, Some(r.trim().to_string())),
        None => (text, None),
    };
    let mut full: Vec<String> = prefix.to_vec();
    full.extend(segments(path));
    if full.is_empty() {
        return;
    }
    let name = rename.or_else(|| full.last().filter(|s| *s != "*" && *s != "self").cloned());
    out.push((full, name));
}

fn segments(path: &str) -> Vec<String> {
    path.split("::")
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(str::to_string)
        .collect()
}

fn split_top_level(inner: &str) -> Vec<&str> {
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0usize, 0);
    for (i, c) in inner.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth = depth.saturating_sub(1),
            ',' if depth == 0 => {
                parts.push(&inner[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&inner[start..]);
    parts.into_iter().filter(|p| !p.trim().is_empty()).collect()
}

/// A path written in `module` made absolute (`None` for paths outside the crate).
fn absolute(module: &[String], segments: &[String]) -> Option<Vec<String>> {
    let (first, rest) = segments.split_first()?;
    let mut base: Vec<String> = match first.as_str() {
        "crate" => Vec::new(),
        "self" => module.to_vec(),
        "super" => module[..module.len().checked_sub(1)?].to_vec(),
        _ => {
            let mut m = module.to_vec();
            m.push(first.clone());
            m
        }
    };
    let mut rest = rest;
    while let Some((s, tail)) = rest.split_first() {
        if s != "super" {
            break;
        }
        base.pop()?;
        rest = tail;
    }
    base.extend(rest.iter().cloned());
    Some(base)
}
