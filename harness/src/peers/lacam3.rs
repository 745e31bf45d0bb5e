//! LaCAM3 (Okumura, AAMAS-24; github.com/Kei18/lacam3) on one drone per group:
//! labeled MAPF, the problem swarmctl solves when every agent is its own group.
//!
//! Run as `main -m MAP -i SCEN -N AGENTS -t LIMIT -o RESULT --no-star`: without
//! its anytime part LaCAM3 stops at its first solution, which is what is
//! compared (time to a first solution, and that solution's makespan).

use super::instance::GridInstance;
use super::result_file::number;
use super::{Answer, PeerRun, run_solver};
use crate::HarnessError;
use std::path::Path;
use std::process::Command;
use std::time::Duration;

/// Runs LaCAM3 at `binary` on `instance`, giving it `limit`.
pub fn run(
    binary: &Path,
    instance: &GridInstance,
    limit: Duration,
    work_dir: &Path,
) -> Result<PeerRun, HarnessError> {
    let stem = instance.stem();
    let result = work_dir.join(format!("{stem}.lacam3.txt"));
    let mut command = Command::new(binary);
    command
        .arg("-m")
        .arg(&instance.map_path)
        .arg("-i")
        .arg(&instance.scen_path)
        .args(["-N", &instance.starts.len().to_string()])
        .args(["-t", &format!("{:.3}", limit.as_secs_f64())])
        .arg("-o")
        .arg(&result)
        .arg("--no-star");
    // A second beyond its own limit, for reading the map and writing the result.
    let log = work_dir.join(format!("{stem}.lacam3.log"));
    let bound = (limit + Duration::from_secs(1), log.as_path());
    run_solver("LaCAM3", &mut command, bound, &result, parse)
}

/// LaCAM3's `result.txt`: `solved`, `makespan`, `makespan_lb`, `comp_time` (ms).
fn parse(text: &str) -> Option<Answer> {
    if number(text, "solved")? != 1 {
        return None;
    }
    let makespan_steps = number(text, "makespan")?;
    Some(Answer {
        first_solution_s: number(text, "comp_time")? as f64 / 1000.0,
        first_makespan_steps: makespan_steps,
        makespan_steps,
        lower_bound_steps: number(text, "makespan_lb"),
        optimal: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_solved_result_gives_time_makespan_and_bound() {
        // The head of a real LaCAM3 result file (random-32-32-10, 400 agents).
        let text = "agents=400\nmap_file=random-32-32-10.map\nsolver=planner\nsolved=1\nsoc=12345\nsoc_lb=11000\nmakespan=57\nmakespan_lb=48\nsum_of_loss=12000\nsum_of_loss_lb=11000\ncomp_time=241\nseed=0\n";
        let answer = parse(text).expect("solved");
        assert_eq!(answer.makespan_steps, 57);
        assert_eq!(answer.lower_bound_steps, Some(48));
        assert!((answer.first_solution_s - 0.241).abs() < 1e-9);
    }

    #[test]
    fn an_unsolved_result_is_no_answer() {
        assert_eq!(parse("solved=0\nmakespan=0\ncomp_time=3000\n"), None);
        assert_eq!(parse("garbage"), None);
    }
}
