//! Hostile and broken plan files: `swarmctl::compiled::file` never panics,
//! never spins, names the file in every error, refuses every plan that does not
//! fit its mission, and accepts the plan `swarmctl plan` wrote.

use proptest::prelude::*;
use serde_json::{Value, json};
use std::path::Path;
use std::sync::LazyLock;
use std::time::{Duration, Instant};
use swarmctl::compiled::{self, PlanFileError};
use swarmctl::mission::{self, Mission};
use swarmctl::plan;

const FILE: &str = "fuzzed-plan.json";

/// A mission and the plan file `swarmctl plan -o` writes for it.
struct Fixture {
    mission: Mission,
    /// The whole compiled plan file.
    full: Value,
    /// The same file with only the discrete plan (small, so byte mutations hit it).
    discrete: Value,
}

fn fixture(file: &str) -> Fixture {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
    let mission = mission::load(&path).expect("example mission loads");
    let solution = plan::solve(&mission, &plan::PlanOptions::default()).expect("solves");
    let compiled = swarmctl::compiled::compile(&mission, &solution).expect("compiles");
    let full = serde_json::to_value(&compiled).expect("serialises");
    let discrete = serde_json::to_value(compiled.discrete()).expect("serialises");
    Fixture {
        mission,
        full,
        discrete,
    }
}

/// Two drones, one per group: plain MAPF through a corridor with a pocket.
static CORRIDOR: LazyLock<Fixture> = LazyLock::new(|| fixture("missions/swap-corridor.yaml"));
/// Two groups of four: goals are interchangeable within a group.
static FORMATION: LazyLock<Fixture> = LazyLock::new(|| fixture("missions/formation-change.yaml"));

fn load(bytes: &[u8], mission: &Mission) -> Result<plan::DiscretePlan, PlanFileError> {
    let start = Instant::now();
    let result = compiled::file::from_bytes(bytes, Path::new(FILE), mission)
        .map(|checked| checked.discrete());
    assert!(
        start.elapsed() < Duration::from_secs(5),
        "loading took {:?}",
        start.elapsed()
    );
    if let Err(e) = &result {
        let message = e.to_string();
        assert!(
            message.contains(FILE),
            "error does not name the file: {message}"
        );
        assert_eq!(e.path(), Path::new(FILE));
    }
    result
}

fn load_value(value: &Value, mission: &Mission) -> Result<plan::DiscretePlan, PlanFileError> {
    load(&serde_json::to_vec(value).expect("json"), mission)
}

/// Whatever the loader accepts is a valid plan for the mission by the validator too.
fn accepted_means_valid(result: &Result<plan::DiscretePlan, PlanFileError>, mission: &Mission) {
    if let Ok(p) = result {
        assert!(plan::validate_plan(mission, p).is_ok());
    }
}

fn refused(value: &Value, mission: &Mission, what: &str) -> String {
    match load_value(value, mission) {
        Ok(_) => panic!("{what}: the mutated plan was accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn unmutated_plans_are_accepted() {
    for f in [&*CORRIDOR, &*FORMATION] {
        let full = load_value(&f.full, &f.mission).expect("the compiled plan file");
        let discrete = load_value(&f.discrete, &f.mission).expect("the discrete plan alone");
        assert_eq!(full, discrete);
    }
}

#[test]
fn a_real_file_is_named_in_errors() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("broken-plan.json");
    std::fs::write(&path, b"{\"makespan_steps\": 3,").expect("write");
    let e = compiled::file::load(&path, &CORRIDOR.mission).expect_err("truncated");
    assert!(e.to_string().contains(&path.display().to_string()), "{e}");
    let e = compiled::file::load(&dir.path().join("missing.json"), &CORRIDOR.mission)
        .expect_err("missing");
    assert!(e.to_string().contains("missing.json"), "{e}");
}

#[test]
fn the_other_missions_plan_is_refused() {
    let e = load_value(&FORMATION.full, &CORRIDOR.mission).expect_err("wrong mission");
    let message = e.to_string();
    assert!(
        message.contains("written for mission \"formation-change\""),
        "{message}"
    );
}

#[test]
fn deep_nesting_and_huge_numbers_are_errors() {
    let deep = "[".repeat(100_000);
    assert!(load(deep.as_bytes(), &CORRIDOR.mission).is_err());
    let mut v = CORRIDOR.discrete.clone();
    v["drones"][0]["path"][1] = json!([1e300, 1, 1]);
    assert!(refused(&v, &CORRIDOR.mission, "float voxel").contains("drones[0].path[1]"));
    v["drones"][0]["path"][1] = json!([u64::MAX, 1, 1]);
    assert!(refused(&v, &CORRIDOR.mission, "huge voxel").contains("drones[0].path[1]"));
}

/// Paths of all drones, for choosing mutation targets.
fn path_len(v: &Value, drone: usize) -> usize {
    v["drones"][drone]["path"].as_array().map_or(0, Vec::len)
}

fn drone_count(v: &Value) -> usize {
    v["drones"].as_array().map_or(0, Vec::len)
}

/// A mutation of a valid plan that keeps it parseable.
#[derive(Debug, Clone)]
enum Mutation {
    /// Moves one voxel of one path by `delta` (may leave the world).
    MoveVoxel {
        drone: usize,
        step: usize,
        delta: [i64; 3],
    },
    /// Exchanges the goals of two drones (paths unchanged).
    SwapGoals { a: usize, b: usize },
    /// Removes one step of one path.
    DropStep { drone: usize, step: usize },
    /// Repeats one step of one path (the path gets one entry too many).
    RepeatStep { drone: usize, step: usize },
    /// Changes the reported makespan or sum of costs.
    Counters { makespan: i64, sum_of_costs: i64 },
    /// Exchanges two drones' entries.
    SwapDrones { a: usize, b: usize },
    /// Drops a drone.
    DropDrone { drone: usize },
    /// Renames a drone or moves it into another group's name.
    Rename { drone: usize, field: &'static str },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let index = 0usize..64;
    let delta = prop::array::uniform3(-4i64..=4);
    prop_oneof![
        (index.clone(), index.clone(), delta)
            .prop_map(|(drone, step, delta)| Mutation::MoveVoxel { drone, step, delta }),
        (index.clone(), index.clone()).prop_map(|(a, b)| Mutation::SwapGoals { a, b }),
        (index.clone(), index.clone()).prop_map(|(drone, step)| Mutation::DropStep { drone, step }),
        (index.clone(), index.clone())
            .prop_map(|(drone, step)| Mutation::RepeatStep { drone, step }),
        (-3i64..=3, -3i64..=3).prop_map(|(makespan, sum_of_costs)| Mutation::Counters {
            makespan,
            sum_of_costs
        }),
        (index.clone(), index.clone()).prop_map(|(a, b)| Mutation::SwapDrones { a, b }),
        index
            .clone()
            .prop_map(|drone| Mutation::DropDrone { drone }),
        (index, prop::sample::select(vec!["id", "group"]))
            .prop_map(|(drone, field)| Mutation::Rename { drone, field }),
    ]
}

/// Applies `m` to `v`; returns whether the result is certainly invalid (`None` when
/// the mutation changed nothing).
fn apply(v: &mut Value, m: &Mutation) -> Option<bool> {
    let n = drone_count(v);
    match *m {
        Mutation::MoveVoxel { drone, step, delta } => {
            let drone = drone % n;
            let step = step % path_len(v, drone).max(1);
            let voxel = &mut v["drones"][drone]["path"][step];
            let before: Vec<i64> = (0..3)
                .map(|a| voxel[a].as_i64().expect("coordinate"))
                .collect();
            // A negative coordinate does not parse as a voxel; keep it parseable.
            let after: Vec<i64> = (0..3).map(|a| (before[a] + delta[a]).max(0)).collect();
            if before == after {
                return None;
            }
            for (a, c) in after.iter().enumerate() {
                voxel[a] = json!(c);
            }
            let moved: i64 = (0..3).map(|a| (after[a] - before[a]).abs()).sum();
            // Certainly invalid: the path no longer starts at the drone's start, or
            // it jumps at least 2 voxels from the step before (a move of 3 or more
            // minus the at most one voxel the drone moved there).
            Some(step == 0 || moved >= 3)
        }
        Mutation::SwapGoals { a, b } => {
            let (a, b) = (a % n, b % n);
            let (ga, gb) = (
                v["drones"][a]["goal"].clone(),
                v["drones"][b]["goal"].clone(),
            );
            if ga == gb {
                return None;
            }
            v["drones"][a]["goal"] = gb;
            v["drones"][b]["goal"] = ga;
            Some(true)
        }
        Mutation::DropStep { drone, step } => {
            let drone = drone % n;
            let step = step % path_len(v, drone);
            v["drones"][drone]["path"]
                .as_array_mut()
                .unwrap()
                .remove(step);
            Some(true)
        }
        Mutation::RepeatStep { drone, step } => {
            let drone = drone % n;
            let path = v["drones"][drone]["path"].as_array_mut().unwrap();
            let step = step % path.len();
            let voxel = path[step].clone();
            path.insert(step, voxel);
            Some(true)
        }
        Mutation::Counters {
            makespan,
            sum_of_costs,
        } => {
            if makespan == 0 && sum_of_costs == 0 {
                return None;
            }
            for (field, d) in [
                ("makespan_steps", makespan),
                ("sum_of_costs_steps", sum_of_costs),
            ] {
                let c = v[field].as_i64().unwrap() + d;
                v[field] = json!(c.max(0));
            }
            // Clamping at 0 could undo the change only for a zero counter, which a
            // plan that moves anyone never has.
            Some(true)
        }
        Mutation::SwapDrones { a, b } => {
            let (a, b) = (a % n, b % n);
            if a == b {
                return None;
            }
            v["drones"].as_array_mut().unwrap().swap(a, b);
            Some(true)
        }
        Mutation::DropDrone { drone } => {
            v["drones"].as_array_mut().unwrap().remove(drone % n);
            Some(true)
        }
        Mutation::Rename { drone, field } => {
            let drone = drone % n;
            let old = v["drones"][drone][field].as_str().unwrap().to_string();
            v["drones"][drone][field] = json!(format!("{old}x"));
            Some(true)
        }
    }
}

/// Mutates a random byte range of `text`: overwrite, insert, delete or truncate.
#[derive(Debug, Clone)]
enum ByteEdit {
    Overwrite(usize, Vec<u8>),
    Insert(usize, Vec<u8>),
    Delete(usize, usize),
    Truncate(usize),
}

fn byte_edit() -> impl Strategy<Value = ByteEdit> {
    let at = any::<usize>();
    let bytes = prop::collection::vec(
        prop_oneof![
            any::<u8>(),
            prop::sample::select(b"0123456789[]{},:\"-.eE ".to_vec())
        ],
        1..6,
    );
    prop_oneof![
        (at, bytes.clone()).prop_map(|(a, b)| ByteEdit::Overwrite(a, b)),
        (at, bytes).prop_map(|(a, b)| ByteEdit::Insert(a, b)),
        (at, 1usize..8).prop_map(|(a, n)| ByteEdit::Delete(a, n)),
        at.prop_map(ByteEdit::Truncate),
    ]
}

fn edit(text: &mut Vec<u8>, e: &ByteEdit) {
    let len = text.len();
    match e {
        ByteEdit::Overwrite(at, bytes) => {
            for (i, b) in bytes.iter().enumerate() {
                if let Some(slot) = text.get_mut((at % len) + i) {
                    *slot = *b;
                }
            }
        }
        ByteEdit::Insert(at, bytes) => {
            let at = at % (len + 1);
            text.splice(at..at, bytes.iter().copied());
        }
        ByteEdit::Delete(at, n) => {
            let at = at % len;
            text.drain(at..(at + n).min(len));
        }
        ByteEdit::Truncate(at) => text.truncate(at % len),
    }
}

/// Random JSON shaped loosely like a plan, to exercise the field walker.
fn plan_like() -> impl Strategy<Value = Value> {
    let leaf = prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::Bool),
        any::<i64>().prop_map(|n| json!(n)),
        (0u32..8).prop_map(|n| json!(n)),
        any::<f64>().prop_map(|f| json!(f)),
        prop::sample::select(vec!["a", "b", "eastbound", "westbound", ""]).prop_map(|s| json!(s)),
    ];
    let key = prop::sample::select(vec![
        "makespan_steps",
        "sum_of_costs_steps",
        "drones",
        "id",
        "group",
        "goal",
        "path",
        "mission",
        "trajectory",
    ]);
    leaf.prop_recursive(5, 64, 6, move |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..6).prop_map(Value::Array),
            prop::collection::btree_map(key.clone().prop_map(String::from), inner, 0..6)
                .prop_map(|m| Value::Object(m.into_iter().collect())),
        ]
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, .. ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_are_refused(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
        let result = load(&bytes, &CORRIDOR.mission);
        accepted_means_valid(&result, &CORRIDOR.mission);
    }

    #[test]
    fn arbitrary_plan_shaped_json_never_panics(value in plan_like()) {
        let result = load_value(&value, &CORRIDOR.mission);
        accepted_means_valid(&result, &CORRIDOR.mission);
    }

    #[test]
    fn byte_mutations_of_a_valid_plan_never_panic(
        edits in prop::collection::vec(byte_edit(), 1..4),
        formation in any::<bool>(),
        whole_file in prop::bool::weighted(0.1),
    ) {
        let f = if formation { &*FORMATION } else { &*CORRIDOR };
        let source = if whole_file { &f.full } else { &f.discrete };
        let mut text = serde_json::to_vec(source).unwrap();
        for e in &edits {
            if text.is_empty() {
                break;
            }
            edit(&mut text, e);
        }
        let result = load(&text, &f.mission);
        accepted_means_valid(&result, &f.mission);
    }

    #[test]
    fn invalid_mutations_are_refused(m in mutation(), formation in any::<bool>()) {
        let f = if formation { &*FORMATION } else { &*CORRIDOR };
        let mut v = f.discrete.clone();
        let certainly_invalid = apply(&mut v, &m);
        let result = load_value(&v, &f.mission);
        accepted_means_valid(&result, &f.mission);
        match certainly_invalid {
            Some(true) => prop_assert!(result.is_err(), "accepted after {m:?}"),
            None => prop_assert!(result.is_ok(), "refused after the no-op {m:?}"),
            Some(false) => {}
        }
    }

    #[test]
    fn mutation_sequences_never_panic(
        mutations in prop::collection::vec(mutation(), 2..6),
        formation in any::<bool>(),
    ) {
        let f = if formation { &*FORMATION } else { &*CORRIDOR };
        let mut v = f.discrete.clone();
        for m in &mutations {
            if drone_count(&v) == 0 {
                break;
            }
            apply(&mut v, m);
        }
        let result = load_value(&v, &f.mission);
        accepted_means_valid(&result, &f.mission);
        if v == f.discrete {
            prop_assert!(result.is_ok());
        }
    }
}
