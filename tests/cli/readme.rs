//! The README's shell blocks, run as a newcomer types them (issue 19): every
//! ```` ```sh ```` block, line by line and block after block, in one scratch
//! directory holding a link to the repository's `missions/`, with `swarmctl` the
//! binary under test. A command that fails fails the test, so the README cannot
//! show a command that does not work.
//!
//! How lines are run:
//! - `swarmctl ARGS`, `target/release/swarmctl ARGS` and
//!   `cargo run --release -- ARGS`: the binary under test with ARGS;
//! - a line ending in `&` runs in the background; `kill %1 %2 …` stops those
//!   jobs (SIGTERM) and requires a clean exit; at the end of a block every
//!   background job must have exited by itself, successfully;
//! - `rerun FILE.rrd` (open a recording in the viewer): the Rerun CLI from `.venv`
//!   checks the file instead (`rerun rrd verify`), as no window can open here;
//! - an argument holding `<unix time>` names the newest file that matches it;
//! - not run, each for the reason given in [`not_run`]: the test command itself,
//!   building and installing, and viewers that need a display.
//!
//! Anything else is an error naming the line: a new kind of command must be
//! taught here before the README may show it.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// `<unix time>` while a command is split into words.
const PLACEHOLDER: &str = "<unix-time>";

/// No README command may take longer than this.
const COMMAND_LIMIT: Duration = Duration::from_secs(300);

fn binary() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_swarmctl"))
}

/// The shell blocks of the README, in order, each as its lines.
fn shell_blocks(readme: &str) -> Vec<Vec<String>> {
    let mut blocks = Vec::new();
    let mut current: Option<Vec<String>> = None;
    for line in readme.lines() {
        match (&mut current, line.trim_start()) {
            (None, "```sh") => current = Some(Vec::new()),
            (Some(_), "```") => blocks.extend(current.take()),
            (Some(lines), text) => lines.push(text.to_string()),
            (None, _) => {}
        }
    }
    blocks
}

/// The command without its trailing `# comment`.
fn without_comment(line: &str) -> &str {
    match line.find(" #") {
        Some(at) => line[..at].trim(),
        None if line.starts_with('#') => "",
        None => line.trim(),
    }
}

/// Why a README line is not run here, if it is not.
fn not_run(command: &str) -> Option<&'static str> {
    if command.contains("cargo test") {
        return Some("the test command: this test is part of it");
    }
    if command.starts_with("cargo build") || command.starts_with("cargo install") {
        return Some("builds or installs the binary this test already runs");
    }
    if command.starts_with("pip ")
        || command.starts_with("apt-get ")
        || command.starts_with("rustup ")
    {
        return Some("installs a tool on the user's machine");
    }
    let words: Vec<&str> = command.split_whitespace().collect();
    let to_a_viewer = words
        .windows(2)
        .any(|w| w[0] == "--connect" && !w[1].starts_with("tcp/"));
    if command.contains("--spawn") || to_a_viewer || command.starts_with("rerun --") {
        return Some(
            "needs a Rerun viewer with a display (tests/cli/viz_recordings.rs streams to a headless one)",
        );
    }
    None
}

/// A README command line as a process: the program and its arguments.
fn program(words: &[String], dir: &Path) -> (PathBuf, Vec<String>) {
    let args =
        |from: usize| -> Vec<String> { words[from..].iter().map(|w| resolve(w, dir)).collect() };
    match words.first().map(String::as_str) {
        Some("swarmctl" | "target/release/swarmctl") => (binary(), args(1)),
        Some("cargo")
            if words.get(1..4) == Some(&["run".into(), "--release".into(), "--".into()]) =>
        {
            (binary(), args(4))
        }
        Some("rerun") if words.len() == 2 => {
            let rerun = crate::support::repo_root().join(".venv/bin/rerun");
            assert!(rerun.exists(), "run `bash .ci/install-peers` first");
            let mut verify = vec!["rrd".to_string(), "verify".to_string()];
            verify.extend(args(1));
            (rerun, verify)
        }
        _ => {
            panic!("the README runs {words:?}, which tests/cli/readme.rs does not know how to run")
        }
    }
}

/// `word` with a `<unix time>` placeholder replaced by the newest file it matches.
fn resolve(word: &str, dir: &Path) -> String {
    let Some((before, after)) = word.split_once(PLACEHOLDER) else {
        return word.to_string();
    };
    let path = dir.join(before);
    let (parent, prefix) = (
        path.parent().expect("a directory"),
        path.file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
    );
    let matches: Vec<PathBuf> = std::fs::read_dir(parent)
        .unwrap_or_else(|e| panic!("{word}: cannot list {}: {e}", parent.display()))
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| {
            let name = p
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            name.starts_with(&prefix) && name.ends_with(after)
        })
        .collect();
    // The newest: the README opens the file the command before it wrote.
    let newest = matches
        .iter()
        .max_by_key(|p| std::fs::metadata(p).and_then(|m| m.modified()).ok())
        .unwrap_or_else(|| panic!("{word} matches no file in {}", parent.display()));
    newest.display().to_string()
}

/// Waits for `child` at most [`COMMAND_LIMIT`]; kills it past that.
fn wait(child: &mut Child, line: &str) -> std::process::ExitStatus {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().expect("wait") {
            return status;
        }
        if start.elapsed() > COMMAND_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("README command did not finish in {COMMAND_LIMIT:?}: {line}");
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// Background jobs of a block, stopped by the test if it fails early.
#[derive(Default)]
struct Jobs(Vec<(String, Child)>);

impl Drop for Jobs {
    fn drop(&mut self) {
        for (_, child) in &mut self.0 {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

fn run_block(lines: &[String], dir: &Path, log: &mut Vec<String>) {
    let mut jobs = Jobs::default();
    for line in lines {
        let command = without_comment(line);
        if command.is_empty() {
            continue;
        }
        if let Some(why) = not_run(command) {
            log.push(format!("not run ({why}): {command}"));
            continue;
        }
        if let Some(targets) = command.strip_prefix("kill ") {
            for target in targets.split_whitespace() {
                let n: usize = target
                    .strip_prefix('%')
                    .and_then(|n| n.parse().ok())
                    .unwrap_or_else(|| panic!("kill takes job numbers like %1: {command}"));
                let (job, child) = &mut jobs.0[n - 1];
                // SIGTERM, as `kill` sends: the process stops cleanly.
                let pid = i32::try_from(child.id()).expect("pid");
                // SAFETY: kill(2) on a child we started and have not reaped.
                unsafe { libc::kill(pid, libc::SIGTERM) };
                let status = wait(child, job);
                assert!(
                    status.success(),
                    "`{job}` stopped by `kill` exited {status}"
                );
            }
            log.push(format!("ran: {command}"));
            continue;
        }
        let (background, command) = match command.strip_suffix('&') {
            Some(rest) => (true, rest.trim()),
            None => (false, command),
        };
        // The placeholder is one argument, though it holds a space.
        let words: Vec<String> = command
            .replace("<unix time>", PLACEHOLDER)
            .split_whitespace()
            .map(str::to_string)
            .collect();
        let (program, args) = program(&words, dir);
        let mut process = Command::new(&program);
        process.args(&args).current_dir(dir).stdin(Stdio::null());
        if background {
            let child = process
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .unwrap_or_else(|e| panic!("cannot start {command}: {e}"));
            jobs.0.push((command.to_string(), child));
        } else {
            let out_path = dir.join("last-command.out");
            let out = std::fs::File::create(&out_path).expect("output file");
            let mut child = process
                .stdout(out.try_clone().expect("clone"))
                .stderr(out)
                .spawn()
                .unwrap_or_else(|e| panic!("cannot start {command}: {e}"));
            let status = wait(&mut child, command);
            let output = std::fs::read_to_string(&out_path).unwrap_or_default();
            assert!(
                status.success(),
                "README command `{command}` exited {status}:\n{output}"
            );
        }
        log.push(format!("ran: {command}"));
    }
    for (job, child) in &mut jobs.0 {
        if child.try_wait().expect("wait").is_some_and(|s| s.success()) {
            continue;
        }
        let status = wait(child, job);
        assert!(status.success(), "background `{job}` exited {status}");
    }
    jobs.0.clear();
}

/// Every shell block of the README runs as shown.
#[test]
fn the_readme_commands_work_as_shown() {
    let root = crate::support::repo_root();
    let readme = std::fs::read_to_string(root.join("README.md")).expect("README.md");
    let blocks = shell_blocks(&readme);
    assert!(
        blocks.len() >= 4,
        "expected the README's shell blocks, found {blocks:?}"
    );
    let dir = tempfile::tempdir().expect("temp dir");
    std::os::unix::fs::symlink(root.join("missions"), dir.path().join("missions"))
        .expect("link missions/");
    let mut log = Vec::new();
    for block in &blocks {
        run_block(block, dir.path(), &mut log);
    }
    // Every kind of step a newcomer takes was run, not skipped.
    let ran = log
        .iter()
        .filter(|l| l.starts_with("ran: "))
        .cloned()
        .collect::<Vec<_>>()
        .join("\n");
    for step in ["template", "check", "plan", "fly", "replay", "relay"] {
        assert!(
            ran.contains(&format!(" {step} ")),
            "no `{step}` was run:\n{}",
            log.join("\n")
        );
    }
    eprintln!("{}", log.join("\n"));
}
