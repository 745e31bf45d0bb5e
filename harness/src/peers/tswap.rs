//! tswap (Okumura & Défago, AIJ 2023; github.com/Kei18/tswap) on one group: the
//! unlabeled problem, every agent free to take any goal. Two of its solvers are
//! compared: TSWAP (suboptimal, complete, fast) and FlowNetwork (the
//! makespan-optimal max-flow method of Yu & LaValle, with tswap's pruning and
//! flow reuse).
//!
//! tswap reads an instance file of its own (`map_file=`, `agents=`, then
//! `sx,sy,gx,gy` per agent) and looks the map up in the `map/` folder it was
//! built with, so the map is copied there first.

use super::instance::GridInstance;
use super::result_file::{inner_number, number};
use super::{Answer, PeerRun, run_solver};
use crate::HarnessError;
use std::path::Path;
use std::process::Command;
use std::time::Duration;

/// Which of tswap's solvers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Solver {
    /// TSWAP: a first solution, suboptimal.
    Tswap,
    /// FlowNetwork: the makespan optimum.
    FlowNetwork,
}

impl Solver {
    /// Its name on tswap's command line and in the table.
    pub fn name(self) -> &'static str {
        match self {
            Solver::Tswap => "TSWAP",
            Solver::FlowNetwork => "FlowNetwork",
        }
    }
}

/// Runs tswap at `binary` with `solver` on `instance`, giving it `limit`; its map
/// goes into `map_dir` (the folder tswap was built to read maps from).
pub fn run(
    binary: &Path,
    map_dir: &Path,
    solver: Solver,
    instance: &GridInstance,
    limit: Duration,
    work_dir: &Path,
) -> Result<PeerRun, HarnessError> {
    place_map(instance, map_dir)?;
    let stem = format!("{}.{}", instance.stem(), solver.name());
    let input = work_dir.join(format!("{stem}.in.txt"));
    std::fs::write(&input, instance_text(instance, limit)).map_err(|source| HarnessError::Io {
        what: format!("writing {}", input.display()),
        source,
    })?;
    let result = work_dir.join(format!("{stem}.txt"));
    let mut command = Command::new(binary);
    command
        .arg("-i")
        .arg(&input)
        .args(["-s", solver.name()])
        .arg("-o")
        .arg(&result);
    let log = work_dir.join(format!("{stem}.log"));
    let bound = (limit + Duration::from_secs(1), log.as_path());
    run_solver(solver.name(), &mut command, bound, &result, |text| {
        parse(text, solver)
    })
}

/// Copies the instance's map into tswap's map folder, unless the same file is
/// there; refuses to overwrite a different map of that name.
fn place_map(instance: &GridInstance, map_dir: &Path) -> Result<(), HarnessError> {
    let io = |what: String| move |source| HarnessError::Io { what, source };
    let ours = std::fs::read(&instance.map_path)
        .map_err(io(format!("reading {}", instance.map_path.display())))?;
    let theirs = map_dir.join(&instance.map_name);
    match std::fs::read(&theirs) {
        Ok(existing) if existing == ours => {}
        Ok(_) => {
            return Err(HarnessError::PeerInstance {
                map: theirs,
                problem: format!(
                    "tswap's map folder holds another map of this name than {}",
                    instance.map_path.display()
                ),
            });
        }
        Err(_) => std::fs::write(&theirs, &ours)
            .map_err(io(format!("copying the map to {}", theirs.display())))?,
    }
    Ok(())
}

/// tswap's instance file: the map by name, the agents, a timestep cap no
/// solution on the map needs, the time limit in milliseconds, and the agents'
/// starts and goals.
fn instance_text(instance: &GridInstance, limit: Duration) -> String {
    let [width, height] = instance.size;
    let max_timestep = (10 * (width + height)).max(1000);
    let mut text = format!(
        "map_file={}\nagents={}\nseed=0\nrandom_problem=0\nmax_timestep={max_timestep}\nmax_comp_time={}\n",
        instance.map_name,
        instance.starts.len(),
        limit.as_millis()
    );
    for ([sx, sy], [gx, gy]) in instance.starts.iter().zip(&instance.goals) {
        text.push_str(&format!("{sx},{sy},{gx},{gy}\n"));
    }
    text
}

/// tswap's result file: `solved`, `makespan`, `comp_time` (ms); TSWAP's
/// `estimated_makespan` is its bottleneck assignment's, a lower bound.
fn parse(text: &str, solver: Solver) -> Option<Answer> {
    if number(text, "solved")? != 1 {
        return None;
    }
    let makespan_steps = number(text, "makespan")?;
    Some(Answer {
        first_solution_s: number(text, "comp_time")? as f64 / 1000.0,
        first_makespan_steps: makespan_steps,
        makespan_steps,
        lower_bound_steps: match solver {
            Solver::Tswap => inner_number(text, "estimated_makespan"),
            Solver::FlowNetwork => Some(makespan_steps),
        },
        optimal: solver == Solver::FlowNetwork,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The head of tswap's own example output (its README).
    const TSWAP_RESULT: &str = "instance=../instances/sample.txt\nagents=100\nmap_file=arena.map\nsolver=TSWAP\nsolved=1\nsoc=1864\nmakespan=30\ncomp_time=91\ninternal_info=\nelapsed_assignment:82\nelapsed_path_planning:9\nestimated_soc:1602\nestimated_makespan:29\nstarts=(32,21),(18,22)\n";

    #[test]
    fn tswap_gives_its_assignment_bound() {
        let answer = parse(TSWAP_RESULT, Solver::Tswap).expect("solved");
        assert_eq!(answer.makespan_steps, 30);
        assert_eq!(answer.lower_bound_steps, Some(29));
        assert!((answer.first_solution_s - 0.091).abs() < 1e-9);
        assert!(!answer.optimal);
    }

    #[test]
    fn flow_network_is_its_own_bound() {
        let text = TSWAP_RESULT.replace("solver=TSWAP", "solver=FlowNetwork");
        let answer = parse(&text, Solver::FlowNetwork).expect("solved");
        assert_eq!(answer.lower_bound_steps, Some(30));
        assert!(answer.optimal);
    }

    #[test]
    fn the_instance_lists_every_agent_in_tswaps_order() {
        let instance = GridInstance {
            map_name: "m.map".into(),
            map_path: "m.map".into(),
            scen_path: "m-2-1.scen".into(),
            size: [64, 64],
            starts: vec![[1, 2], [3, 4]],
            goals: vec![[5, 6], [7, 8]],
        };
        let text = instance_text(&instance, Duration::from_secs(30));
        assert!(text.starts_with("map_file=m.map\nagents=2\n"), "{text}");
        assert!(text.contains("random_problem=0\n"));
        assert!(text.contains("max_comp_time=30000\n"));
        assert!(text.ends_with("1,2,5,6\n3,4,7,8\n"), "{text}");
    }
}
