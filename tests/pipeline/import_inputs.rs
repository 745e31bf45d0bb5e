//! Instances other planners accept, and the mistakes users make feeding them in:
//! each is read, or refused with a message about what the user wrote.

use std::error::Error;
use swarmctl::import::{self, ImportError};
use swarmctl::plan::{self, PlanOptions};

fn libmrp(agents: &str) -> Result<swarmctl::mission::MissionFile, ImportError> {
    let yaml = format!("map: {{ dimensions: [5, 3], obstacles: [] }}\nagents:\n{agents}");
    import::parse_libmrp(&yaml, "instance.yaml".as_ref())
}

/// The whole chain as `{:#}` prints it, to count how often a reason appears.
fn chain(e: &ImportError) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        text.push_str(&format!(": {s}"));
        source = s.source();
    }
    text
}

#[test]
fn a_team_with_spare_potential_goals_is_planned() {
    let file = libmrp(
        "  - { name: a, start: [0, 0], potentialGoals: [[4, 0], [4, 1], [4, 2]] }\n  - { name: b, start: [0, 1], potentialGoals: [[4, 0], [4, 1], [4, 2]] }\n",
    )
    .unwrap();
    assert_eq!(file.groups.len(), 1);
    assert_eq!(file.groups[0].goals.len(), 3);
    let mission = swarmctl::mission::validate(&file).unwrap();
    let solution = plan::solve(&mission, &PlanOptions::default()).unwrap();
    assert!(plan::validate_plan(&mission, &solution.plan).is_ok());
}

#[test]
fn overlapping_different_goal_sets_are_refused_naming_the_agents() {
    let e = libmrp(
        "  - { name: a, start: [0, 0], potentialGoals: [[4, 0], [4, 1]] }\n  - { name: b, start: [0, 1], potentialGoals: [[4, 1], [4, 2]] }\n",
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("agents \"a\" and \"b\""), "{e}");
    assert!(e.contains("overlap at [4, 1]"), "{e}");
    assert!(e.contains("potentialGoals"), "{e}");
    assert!(!e.contains("group"), "no groups the user never wrote: {e}");
}

#[test]
fn plain_agents_sharing_a_goal_are_named_not_merged() {
    let e = libmrp(
        "  - { name: a, start: [0, 0], goal: [3, 2] }\n  - { name: b, start: [0, 1], goal: [3, 2] }\n",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("agents \"a\" and \"b\" share goal [3, 2]"),
        "{e}"
    );
}

#[test]
fn a_map_given_as_the_instance_says_to_pass_the_scenario() {
    let map = crate::support::repo_path("tests/data/movingai/random-32-32-10.map");
    let e = import::load_any(&map, None).unwrap_err().to_string();
    assert!(e.contains("is a MovingAI map"), "{e}");
    assert!(e.contains(".scen"), "{e}");
    assert!(e.len() < 400, "the map is not printed: {e}");
}

#[test]
fn a_missing_file_gives_the_reason_once() {
    let e = import::load_any("no/such/instance.yaml".as_ref(), None).unwrap_err();
    let text = chain(&e);
    assert!(
        text.starts_with("no/such/instance.yaml: cannot read"),
        "{text}"
    );
    assert_eq!(text.matches("os error 2").count(), 1, "{text}");
}

#[test]
fn a_scenario_whose_map_is_missing_names_both() {
    let dir = tempfile::tempdir().unwrap();
    let scen = dir.path().join("lonely.scen");
    std::fs::write(
        &scen,
        "version 1\n3\tnowhere.map\t32\t32\t1\t1\t2\t2\t1.4\n",
    )
    .unwrap();
    let e = import::load_any(&scen, None).unwrap_err().to_string();
    assert!(e.contains("nowhere.map: cannot read"), "{e}");
    assert!(e.contains("lonely.scen"), "{e}");
}
