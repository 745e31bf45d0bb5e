//! ARCHITECTURE.md stays true to the code: every file of the library is named in
//! the row of its module's table, so a file added without a word on what it is
//! for fails here, naming it.

use crate::support::repo_root;
use std::path::Path;

/// The library's `.rs` files, relative to `src/`, `/`-separated.
fn library_files(dir: &Path, prefix: &str, out: &mut Vec<String>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .expect("src/ is readable")
        .map(|e| e.expect("a directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if path.is_dir() {
            library_files(&path, &format!("{prefix}{name}/"), out);
        } else if let Some(stem) = name.strip_suffix(".rs") {
            out.push(format!("{prefix}{stem}"));
        }
    }
}

/// The name a file goes by in the table: its stem, or its folder's for `mod.rs`.
fn doc_name(file: &str) -> Option<&str> {
    let parts: Vec<&str> = file.split('/').collect();
    match parts.as_slice() {
        ["lib"] => None,
        [.., folder, "mod"] => Some(folder),
        [.., stem] => Some(stem),
        [] => None,
    }
}

/// Whether `row` names `name` in backticks: `` `name` ``, `` `name/` ``,
/// `` `name.rs` ``, or as the last part of a backticked path (`` `a/name` ``).
fn names(row: &str, name: &str) -> bool {
    row.split('`')
        .skip(1)
        .step_by(2)
        .flat_map(|quoted| quoted.split(['/', ' ', ',', ':', '(', ')']))
        .any(|word| word == name || word.strip_suffix(".rs") == Some(name))
}

#[test]
fn every_library_file_is_named_in_its_modules_row() {
    let root = repo_root();
    let doc = std::fs::read_to_string(root.join("ARCHITECTURE.md")).expect("ARCHITECTURE.md");
    let mut files = Vec::new();
    library_files(&root.join("src"), "", &mut files);
    let mut missing = Vec::new();
    for file in &files {
        let Some(name) = doc_name(file) else { continue };
        let top = file.split('/').next().unwrap_or(file);
        let row = doc.lines().find(|l| {
            l.starts_with(&format!("| `{top}/`")) || l.starts_with(&format!("| `{top}`"))
        });
        match row {
            None => missing.push(format!("src/{file}.rs: no row for module `{top}`")),
            Some(row) if !names(row, name) => {
                missing.push(format!(
                    "src/{file}.rs: `{name}` not named in the `{top}` row"
                ));
            }
            Some(_) => {}
        }
    }
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md's module table leaves out {} file(s):\n  {}",
        missing.len(),
        missing.join("\n  ")
    );
}

#[test]
fn a_file_is_named_by_its_stem_or_its_folder() {
    assert_eq!(doc_name("fly/drone/mod"), Some("drone"));
    assert_eq!(doc_name("fly/drone/settle"), Some("settle"));
    assert_eq!(doc_name("generate"), Some("generate"));
    assert_eq!(doc_name("lib"), None);
    assert!(names("| `fly/` | `drone/settle.rs` and `gate` |", "settle"));
    assert!(names("| `fly/` | `drone/settle.rs` and `gate` |", "gate"));
    assert!(!names("| `fly/` | settle and `gate` |", "settle"));
}
