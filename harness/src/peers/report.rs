//! The side-by-side table: one row per map, agent count, problem and solver,
//! medians over the seeds, each solver's times also as a ratio to swarmctl's
//! on the same instances.

use super::{InstanceRuns, PeerRun, Problem};
use crate::median;
use std::collections::BTreeMap;
use std::fmt;

/// Every instance's runs; `Display` prints the table.
#[derive(Debug, Clone, PartialEq)]
pub struct PeersReport {
    /// In the order they ran.
    pub instances: Vec<InstanceRuns>,
}

/// The rows of one solver on one map, agent count and problem, over the seeds.
struct Row<'a> {
    map: &'a str,
    agents: usize,
    problem: Problem,
    solver: &'static str,
    /// Each seed's run with swarmctl's run on the same instance.
    runs: Vec<(&'a PeerRun, &'a PeerRun)>,
}

impl PeersReport {
    /// Rows in run order: per instance family, swarmctl first, then its peers.
    fn rows(&self) -> Vec<Row<'_>> {
        let mut rows: Vec<Row<'_>> = Vec::new();
        let mut index: BTreeMap<(&str, usize, Problem, &str), usize> = BTreeMap::new();
        for instance in &self.instances {
            let Some(ours) = instance.runs.first() else {
                continue;
            };
            for run in &instance.runs {
                let key = (
                    instance.map.as_str(),
                    instance.agents,
                    instance.problem,
                    run.solver,
                );
                let at = *index.entry(key).or_insert_with(|| {
                    rows.push(Row {
                        map: &instance.map,
                        agents: instance.agents,
                        problem: instance.problem,
                        solver: run.solver,
                        runs: Vec::new(),
                    });
                    rows.len() - 1
                });
                rows[at].runs.push((run, ours));
            }
        }
        rows
    }
}

impl fmt::Display for PeersReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "| map | agents | problem | solver | solved | first solution | its makespan | final makespan | lower bound | process | peak memory | first solution ÷ swarmctl's | process ÷ swarmctl's |"
        )?;
        writeln!(f, "|---|---|---|---|---|---|---|---|---|---|---|---|---|")?;
        for row in self.rows() {
            write_row(f, &row)?;
        }
        Ok(())
    }
}

/// One row: medians over the seeds the solver answered (and, for the ratios,
/// over the seeds both it and swarmctl answered).
fn write_row(f: &mut fmt::Formatter<'_>, row: &Row<'_>) -> fmt::Result {
    let answered: Vec<_> = row
        .runs
        .iter()
        .filter_map(|(run, ours)| run.answer.map(|a| (a, run, ours)))
        .collect();
    let optimal = answered.iter().filter(|(a, ..)| a.optimal).count();
    let solved = format!(
        "{}/{}{}",
        answered.len(),
        row.runs.len(),
        if optimal > 0 {
            format!(" ({optimal} optimal)")
        } else {
            String::new()
        }
    );
    let med = |values: Vec<f64>| median(&values);
    let first = med(answered.iter().map(|(a, ..)| a.first_solution_s).collect());
    let first_steps = med(answered
        .iter()
        .map(|(a, ..)| a.first_makespan_steps as f64)
        .collect());
    let steps = med(answered
        .iter()
        .map(|(a, ..)| a.makespan_steps as f64)
        .collect());
    let bound = med(answered
        .iter()
        .filter_map(|(a, ..)| a.lower_bound_steps.map(|b| b as f64))
        .collect());
    let process = med(row.runs.iter().map(|(run, _)| run.process.wall_s).collect());
    let memory = med(row
        .runs
        .iter()
        .filter_map(|(run, _)| {
            run.process
                .peak_rss_bytes
                .map(|b| b as f64 / f64::from(1 << 20))
        })
        .collect());
    let both: Vec<_> = answered
        .iter()
        .filter_map(|(a, run, ours)| ours.answer.map(|o| (a, run, o, ours)))
        .collect();
    let first_ratio = med(both
        .iter()
        .map(|(a, _, o, _)| a.first_solution_s / o.first_solution_s)
        .collect());
    let process_ratio = med(both
        .iter()
        .map(|(_, run, _, ours)| run.process.wall_s / ours.process.wall_s)
        .collect());
    writeln!(
        f,
        "| {} | {} | {} | {} | {solved} | {} | {} | {} | {} | {} | {} | {} | {} |",
        row.map,
        row.agents,
        row.problem.name(),
        row.solver,
        figure(first, " s", 3),
        figure(first_steps, "", 0),
        figure(steps, "", 0),
        figure(bound, "", 0),
        figure(process, " s", 2),
        figure(memory, " MiB", 0),
        ratio(row.solver, first_ratio),
        ratio(row.solver, process_ratio),
    )
}

/// `value` with `decimals` and `unit`, or `–` where there is none.
fn figure(value: f64, unit: &str, decimals: usize) -> String {
    if value.is_finite() {
        format!("{value:.decimals$}{unit}")
    } else {
        "–".to_string()
    }
}

/// A ratio to swarmctl's figure; swarmctl's own row has none.
fn ratio(solver: &str, value: f64) -> String {
    if solver == "swarmctl" || !value.is_finite() {
        "–".to_string()
    } else {
        format!("{value:.2}×")
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Answer, ChildRun, Exit};
    use super::*;

    fn run(solver: &'static str, wall_s: f64, answer: Option<(f64, u64)>) -> PeerRun {
        PeerRun {
            solver,
            process: ChildRun {
                wall_s,
                peak_rss_bytes: Some(64 << 20),
                exit: Exit::Code(0),
            },
            answer: answer.map(|(first_solution_s, makespan_steps)| Answer {
                first_solution_s,
                first_makespan_steps: makespan_steps,
                makespan_steps,
                lower_bound_steps: Some(40),
                optimal: false,
            }),
        }
    }

    #[test]
    fn rows_give_medians_over_seeds_and_ratios_to_swarmctl() {
        let instance = |seed, ours: PeerRun, theirs: PeerRun| InstanceRuns {
            map: "random-64-64-20.map".into(),
            agents: 1000,
            seed,
            problem: Problem::PerAgent,
            runs: vec![ours, theirs],
        };
        let report = PeersReport {
            instances: vec![
                instance(
                    1,
                    run("swarmctl", 2.0, Some((0.5, 50))),
                    run("LaCAM3", 3.0, Some((1.0, 60))),
                ),
                instance(
                    2,
                    run("swarmctl", 4.0, Some((1.0, 52))),
                    run("LaCAM3", 4.0, Some((3.0, 62))),
                ),
                instance(
                    3,
                    run("swarmctl", 3.0, Some((0.5, 51))),
                    run("LaCAM3", 61.0, None),
                ),
            ],
        };
        let table = report.to_string();
        let lines: Vec<&str> = table.lines().collect();
        assert_eq!(lines.len(), 4, "{table}");
        assert!(lines[2].starts_with("| random-64-64-20.map | 1000 | per-agent | swarmctl | 3/3 | 0.500 s | 51 | 51 | 40 | 3.00 s | 64 MiB | – | – |"), "{}", lines[2]);
        // LaCAM3 answered seeds 1 and 2: first solutions 2× and 3× swarmctl's,
        // processes 1.5× and 1×; its process median counts the timed-out seed.
        assert!(lines[3].starts_with("| random-64-64-20.map | 1000 | per-agent | LaCAM3 | 2/3 | 2.000 s | 61 | 61 | 40 | 4.00 s | 64 MiB | 2.50× | 1.25× |"), "{}", lines[3]);
    }
}
