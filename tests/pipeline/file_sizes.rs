//! CODE_STYLE.md's size rule, held by a test so it cannot drift again: no non-test
//! source file in the workspace has more than [`MAX_LINES`] lines before its first
//! `#[cfg(test)]`. A file over it holds more than one concept; split it by concept
//! (a module directory with one file per concept), not by trimming lines.
//!
//! Test code is exempt: whatever follows a file's first `#[cfg(test)]`, files named
//! `tests.rs` or `*_tests.rs` (declared `#[cfg(test)] mod …;`), and everything under
//! a `tests/` directory.

use crate::support::repo_root;
use std::path::{Path, PathBuf};

/// CODE_STYLE.md: "no non-test source file over 500 lines".
const MAX_LINES: usize = 500;

/// The workspace's source roots: the library and each member crate's sources and
/// benchmarks.
const ROOTS: &[&str] = &[
    "src",
    "benches",
    "cli/src",
    "cli/benches",
    "harness/src",
    "relay/src",
    "sitl/src",
    "viz/src",
    "bundled/src",
];

/// Every `.rs` file below `dir`, except under `tests/` directories.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries {
        let path = entry.unwrap().path();
        if path.is_dir() {
            if path.file_name().is_some_and(|n| n != "tests") {
                rust_files(&path, out);
            }
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

fn is_test_file(path: &Path) -> bool {
    path.file_stem()
        .and_then(|s| s.to_str())
        .is_some_and(|s| s == "tests" || s.ends_with("_tests"))
}

/// Lines before the first line that starts (after indentation) with `#[cfg(test)]`.
fn non_test_lines(text: &str) -> usize {
    text.lines()
        .take_while(|line| !line.trim_start().starts_with("#[cfg(test)]"))
        .count()
}

#[test]
fn the_line_count_stops_at_the_first_test_attribute() {
    assert_eq!(non_test_lines("a\nb\n#[cfg(test)]\nmod tests {}\n"), 2);
    assert_eq!(non_test_lines("a\n    #[cfg(test)]\nb\n"), 1);
    assert_eq!(non_test_lines("a\nb\nc"), 3);
    assert!(is_test_file(Path::new("sitl/src/vehicle_tests.rs")));
    assert!(!is_test_file(Path::new("src/verify/mod.rs")));
}

#[test]
fn no_source_file_holds_more_than_one_concept_by_size() {
    let root = repo_root();
    let mut files = Vec::new();
    for dir in ROOTS {
        rust_files(&root.join(dir), &mut files);
    }
    assert!(
        files.len() > 100,
        "found only {} source files under {ROOTS:?}: is the repository root right?",
        files.len()
    );
    files.sort();
    let over: Vec<String> = files
        .iter()
        .filter(|f| !is_test_file(f))
        .filter_map(|f| {
            let n = non_test_lines(&std::fs::read_to_string(f).unwrap());
            let name = f.strip_prefix(&root).unwrap_or(f).display();
            (n > MAX_LINES).then(|| format!("{name}: {n} lines"))
        })
        .collect();
    assert!(
        over.is_empty(),
        "non-test source files over {MAX_LINES} lines (split each by concept, see CODE_STYLE.md):\n  {}",
        over.join("\n  ")
    );
}
