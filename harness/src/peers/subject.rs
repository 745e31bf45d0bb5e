//! swarmctl itself, run exactly as a user runs it: `swarmctl plan SCEN
//! --deadline S --stats FILE` (with `--one-group` for the unlabeled problem), a
//! whole process like every peer.
//!
//! The comparable figures are the formation leg's: an imported instance's
//! formation leg is the instance itself, planned on the map's own cells, while
//! the takeoff and landing legs through pads around it are swarmctl's own (issue
//! 20). The process time includes them, and scheduling and checking the flight,
//! which no peer does.

use super::instance::GridInstance;
use super::{Answer, PeerRun, Problem, run_solver};
use crate::HarnessError;
use std::path::Path;
use std::process::Command;
use std::time::Duration;

/// The leg of an imported instance that is the instance.
const FORMATION_LEG: &str = "formation";

/// Runs the `swarmctl` binary at `binary` on `instance` as `problem`, with
/// `limit` as its deadline.
pub fn run(
    binary: &Path,
    problem: Problem,
    instance: &GridInstance,
    limit: Duration,
    work_dir: &Path,
) -> Result<PeerRun, HarnessError> {
    let stem = format!("{}.{}", instance.stem(), problem.name());
    let stats = work_dir.join(format!("{stem}.swarmctl.json"));
    let mut command = Command::new(binary);
    command
        .arg("plan")
        .arg(&instance.scen_path)
        .args(["--deadline", &format!("{:.3}", limit.as_secs_f64())])
        .arg("--stats")
        .arg(&stats);
    if problem == Problem::OneGroup {
        command.arg("--one-group");
    }
    // Its deadline is a promise within 10 %; more is a finding, not a hang.
    let log = work_dir.join(format!("{stem}.swarmctl.log"));
    let bound = (limit * 2 + Duration::from_secs(5), log.as_path());
    run_solver("swarmctl", &mut command, bound, &stats, parse)
}

/// The formation leg of `swarmctl plan --stats`: its first plan (time and
/// makespan; a leg the exact search answered first has none, and its time is
/// the leg's), its final makespan and the bound proven for it.
fn parse(text: &str) -> Option<Answer> {
    let stats: serde_json::Value = serde_json::from_str(text).ok()?;
    let leg = stats
        .get("legs")?
        .as_array()?
        .iter()
        .find(|leg| leg.get("name").and_then(|n| n.as_str()) == Some(FORMATION_LEG))?;
    let whole = |key: &str| leg.get(key).and_then(serde_json::Value::as_u64);
    let seconds = |key: &str| leg.get(key).and_then(serde_json::Value::as_f64);
    let makespan_steps = whole("makespan_steps")?;
    let proven = whole("proven_bound_steps")?;
    let (first_solution_s, first_makespan_steps) = match whole("first_plan_steps") {
        Some(steps) => (seconds("first_plan_time_s")?, steps),
        None => (seconds("time_s")?, makespan_steps),
    };
    Some(Answer {
        first_solution_s,
        first_makespan_steps,
        makespan_steps,
        lower_bound_steps: Some(proven),
        optimal: makespan_steps == proven,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_formation_legs_first_plan_and_final_plan_are_read() {
        let text = r#"{"initial_lower_bound_steps": 60, "legs": [
            {"name": "takeoff", "makespan_steps": 5, "lower_bound_steps": 5, "proven_bound_steps": 5, "first_plan_time_s": 0.0, "ct_nodes_expanded": 1, "time_s": 0.01},
            {"name": "formation", "makespan_steps": 44, "lower_bound_steps": 41, "proven_bound_steps": 42, "first_plan_steps": 47, "first_plan_time_s": 0.25, "ct_nodes_expanded": 3, "time_s": 4.5}]}"#;
        let answer = parse(text).expect("a formation leg");
        assert_eq!(answer.first_makespan_steps, 47);
        assert_eq!(answer.makespan_steps, 44);
        assert_eq!(answer.lower_bound_steps, Some(42));
        assert!(!answer.optimal);
        assert!((answer.first_solution_s - 0.25).abs() < 1e-9);
    }

    #[test]
    fn a_leg_the_exact_search_answered_first_counts_its_whole_time() {
        let text = r#"{"legs": [{"name": "formation", "makespan_steps": 12, "lower_bound_steps": 12, "proven_bound_steps": 12, "first_plan_time_s": 0.0, "time_s": 0.4}]}"#;
        let answer = parse(text).expect("a formation leg");
        assert_eq!(answer.first_makespan_steps, 12);
        assert!(answer.optimal);
        assert!((answer.first_solution_s - 0.4).abs() < 1e-9);
    }

    #[test]
    fn figures_without_a_formation_leg_are_no_answer() {
        assert_eq!(parse(r#"{"legs": []}"#), None);
        assert_eq!(parse("not json"), None);
    }
}
