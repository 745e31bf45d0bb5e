//! A reader that goes away early ends the command quietly (issue 29): `swarmctl plan
//! missions/paper-scale.yaml | head -1` used to panic ("failed printing to stdout:
//! Broken pipe") and exit 101.

use std::io::Read;
use std::os::unix::process::ExitStatusExt;
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// Runs `swarmctl ARGS` with its stdout a pipe whose reader has already gone, so its
/// first write finds the pipe closed (as the writes after `head -1` has read its line
/// do). Returns how it ended and what it wrote to stderr; kills it after two minutes.
fn into_closed_pipe(args: &[&str]) -> (ExitStatus, String) {
    let (reader, writer) = std::io::pipe().expect("a pipe");
    drop(reader);
    let mut child = Command::new(env!("CARGO_BIN_EXE_swarmctl"))
        .args(args)
        .current_dir(crate::support::repo_root())
        .stdin(Stdio::null())
        .stdout(writer)
        .stderr(Stdio::piped())
        .spawn()
        .expect("swarmctl starts");
    let mut stderr_pipe = child.stderr.take().expect("stderr is piped");
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = stderr_pipe.read_to_string(&mut text);
        text
    });
    let deadline = Instant::now() + Duration::from_secs(120);
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("swarmctl {args:?} did not end within two minutes of its reader leaving");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    (status, reader.join().expect("stderr reader"))
}

#[test]
fn plan_and_check_end_quietly_when_the_reader_has_gone() {
    for args in [
        &["plan", "missions/paper-scale.yaml"][..],
        &["check", "missions/paper-scale.yaml"][..],
        &["template"][..],
    ] {
        let (status, stderr) = into_closed_pipe(args);
        assert_ne!(status.code(), Some(101), "{args:?} panicked:\n{stderr}");
        assert!(
            !stderr.contains("panicked") && !stderr.contains("Broken pipe"),
            "{args:?}:\n{stderr}"
        );
        // Ended by SIGPIPE at its first write, as `cat` or `grep` would be.
        assert_eq!(
            status.signal(),
            Some(libc::SIGPIPE),
            "{args:?}: {status}\n{stderr}"
        );
    }
}
