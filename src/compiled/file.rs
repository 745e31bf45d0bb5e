//! Reading a plan file for flight, trusting nothing in it.
//!
//! `swarmctl plan -o PLAN.json` writes a [`CompiledPlan`];
//! `swarmctl fly MISSION --plan PLAN.json` flies it. Between the two the file may
//! have been edited, truncated, corrupted, written by someone else or for other
//! limits, so [`load`] checks it before anything is started:
//!
//! 1. **It parses.** A JSON syntax error names the line and column; a field that
//!    is missing or of the wrong type is named by its path
//!    (`drones[2].path[14]: invalid length 2, expected an array of length 3`).
//! 2. **It belongs to the mission.** The same drones in the mission's order (group
//!    by group, file order within), each in its own group, every path with
//!    `makespan_steps + 1` entries.
//! 3. **It is a valid plan for the mission**, by the independent validator
//!    ([`validate_plan`]): each path starts above its drone's pad, the legs are the
//!    mission's (takeoff, formations and stages with their holds, landing) and end
//!    with every drone on a target of its leg, paths move at most one voxel per
//!    step, never enter an obstacle or leave the airspace, and no two drones meet,
//!    swap or rotate; the reported makespan and sum of costs are the true ones.
//! 4. **Its trajectories pass the independent checker.** The discrete plan is
//!    composed exactly as `swarmctl plan` composes it ([`compile_plan`]: schedule,
//!    execution graph, trajectories) and the whole flight is checked pad to pad.
//!    What `fly` flies is that checked composition.
//! 5. **It holds what its plan composes to.** Every derived field the file has
//!    (`makespan_s`, `setpoint_period_s`, `execution`, `check`, each drone's `pad`
//!    and `trajectory`) must equal the composition's, numbers to within
//!    [`SAME_WITHIN`]: a moved sample, an edited gate or a file written for other
//!    limits or by another version is refused, naming the fields that differ, so
//!    the samples a user inspected are the ones checked and flown. A file that
//!    holds only the discrete plan (no derived field at all) is composed and
//!    checked alike.
//!
//! Every error names the file.

use super::{CheckedPlan, CompileError, CompiledPlan, compile_plan};
use crate::mission::Mission;
use crate::plan::{DiscretePlan, DronePlan, validate_plan};
use crate::world::Voxel;
use serde::de::DeserializeOwned;
use serde_json::{Map, Value};
use std::path::{Path, PathBuf};

/// At most this many problems are listed in one error message.
const MAX_LISTED: usize = 20;

/// Two numbers of a derived field are the same when they differ by at most this,
/// relative to the larger (or absolutely, below 1): JSON's decimal round trip
/// may move a float by an ulp, an edit or another schedule moves it by far more.
pub const SAME_WITHIN: f64 = 1e-9;

/// Fields `swarmctl plan -o` derives from the discrete plan, at the top level.
const DERIVED: [&str; 4] = ["makespan_s", "setpoint_period_s", "execution", "check"];

/// Fields it derives for each drone.
const DERIVED_PER_DRONE: [&str; 2] = ["pad", "trajectory"];

/// Why a plan file cannot be flown. Every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum PlanFileError {
    // The underlying errors are part of the message and deliberately not
    // `#[source]`s: `{:#}` would print them twice.
    /// The file could not be read.
    #[error("cannot read plan file {}: {error}", .path.display())]
    Read {
        /// The plan file.
        path: PathBuf,
        /// What the operating system said.
        error: std::io::Error,
    },
    /// The file is not JSON; the error names line and column.
    #[error("plan file {} is not valid JSON: {error}", .path.display())]
    Syntax {
        /// The plan file.
        path: PathBuf,
        /// The parser's error, with line and column.
        error: serde_json::Error,
    },
    /// A field is missing or of the wrong type.
    #[error("plan file {}: {field}: {reason}", .path.display())]
    Field {
        /// The plan file.
        path: PathBuf,
        /// Where in the file, e.g. `drones[2].path[14]`.
        field: String,
        /// What is wrong there.
        reason: String,
    },
    /// The file parses but is not a valid plan for the mission.
    #[error(
        "plan file {} is not a valid plan for mission {mission:?}{}:\n  {}",
        .path.display(),
        written_for_note(.mission, .written_for),
        list(.problems)
    )]
    Invalid {
        /// The plan file.
        path: PathBuf,
        /// The mission it was checked against.
        mission: String,
        /// The mission the file says it was written for, if it says.
        written_for: Option<String>,
        /// Everything found wrong, one sentence each.
        problems: Vec<String>,
    },
    /// The plan is valid, but composed for flight it fails the independent
    /// checker (or cannot be scheduled).
    #[error("plan file {} cannot be flown: {error}", .path.display())]
    Unsafe {
        /// The plan file.
        path: PathBuf,
        /// Why: the schedule's error, or the checker's violations.
        error: CompileError,
    },
    /// The file's derived fields are not what its discrete plan composes to for
    /// this mission: edited, or written for other limits or by another version.
    #[error(
        "plan file {} does not hold what its plan composes to for mission {mission:?} (edited, or written for other limits or by another version of swarmctl; plan again with `swarmctl plan -o`):\n  {}",
        .path.display(),
        list(.differences)
    )]
    Stale {
        /// The plan file.
        path: PathBuf,
        /// The mission it was composed for.
        mission: String,
        /// Each field that differs: where, the file's value and the composition's.
        differences: Vec<String>,
    },
}

impl PlanFileError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            PlanFileError::Read { path, .. }
            | PlanFileError::Syntax { path, .. }
            | PlanFileError::Field { path, .. }
            | PlanFileError::Invalid { path, .. }
            | PlanFileError::Unsafe { path, .. }
            | PlanFileError::Stale { path, .. } => path,
        }
    }
}

fn written_for_note(mission: &str, written_for: &Option<String>) -> String {
    match written_for {
        Some(name) if name != mission => format!(" (it was written for mission {name:?})"),
        _ => String::new(),
    }
}

fn list(problems: &[String]) -> String {
    let mut text = problems
        .iter()
        .take(MAX_LISTED)
        .cloned()
        .collect::<Vec<_>>()
        .join("\n  ");
    if problems.len() > MAX_LISTED {
        text.push_str(&format!("\n  … and {} more", problems.len() - MAX_LISTED));
    }
    text
}

/// Reads the plan file at `path` and returns its checked composition if, and
/// only if, it is a valid plan for `mission` that passes the checker and holds
/// what it composes to (see the module documentation).
pub fn load(path: &Path, mission: &Mission) -> Result<CheckedPlan, PlanFileError> {
    let bytes = std::fs::read(path).map_err(|error| PlanFileError::Read {
        path: path.to_path_buf(),
        error,
    })?;
    from_bytes(&bytes, path, mission)
}

/// [`load`] for bytes already read; `path` only names them in errors.
pub fn from_bytes(
    bytes: &[u8],
    path: &Path,
    mission: &Mission,
) -> Result<CheckedPlan, PlanFileError> {
    let value: Value = serde_json::from_slice(bytes).map_err(|error| PlanFileError::Syntax {
        path: path.to_path_buf(),
        error,
    })?;
    let (written_for, plan) = parse(&value).map_err(|(field, reason)| PlanFileError::Field {
        path: path.to_path_buf(),
        field,
        reason,
    })?;
    let invalid = |problems| PlanFileError::Invalid {
        path: path.to_path_buf(),
        mission: mission.name.clone(),
        written_for: written_for.clone(),
        problems,
    };
    let problems = misfits(mission, &plan);
    if !problems.is_empty() {
        return Err(invalid(problems));
    }
    if let Err(violations) = validate_plan(mission, &plan) {
        return Err(invalid(violations.iter().map(|v| v.to_string()).collect()));
    }
    let lower_bound_steps = match value.get("lower_bound_steps") {
        None | Some(Value::Null) => 0,
        Some(v) => {
            typed(v, "lower_bound_steps").map_err(|(field, reason)| PlanFileError::Field {
                path: path.to_path_buf(),
                field,
                reason,
            })?
        }
    };
    let checked =
        compile_plan(mission, &plan, lower_bound_steps).map_err(|error| PlanFileError::Unsafe {
            path: path.to_path_buf(),
            error,
        })?;
    let differences = stale_fields(&value, checked.compiled());
    if !differences.is_empty() {
        return Err(PlanFileError::Stale {
            path: path.to_path_buf(),
            mission: mission.name.clone(),
            differences,
        });
    }
    Ok(checked)
}

/// Where the file's derived fields differ from `composed`'s, one line each (at
/// most [`MAX_LISTED`] and a last line saying there are more); none for a file
/// without any derived field.
fn stale_fields(file: &Value, composed: &CompiledPlan) -> Vec<String> {
    let file_drones: &[Value] = file
        .get("drones")
        .and_then(Value::as_array)
        .map_or(&[], Vec::as_slice);
    let has_any = |v: &Value, keys: &[&str]| keys.iter().any(|k| v.get(k).is_some());
    if !has_any(file, &DERIVED) && !file_drones.iter().any(|d| has_any(d, &DERIVED_PER_DRONE)) {
        return Vec::new();
    }
    let ours = match serde_json::to_value(composed) {
        Ok(v) => v,
        Err(e) => return vec![format!("the composed plan cannot be compared: {e}")],
    };
    let mut out = Differences::default();
    for key in DERIVED {
        out.compare(file.get(key), ours.get(key), key);
    }
    let our_drones = ours
        .get("drones")
        .and_then(Value::as_array)
        .map_or(&[][..], Vec::as_slice);
    for (i, (f, o)) in file_drones.iter().zip(our_drones).enumerate() {
        for key in DERIVED_PER_DRONE {
            out.compare(f.get(key), o.get(key), &format!("drones[{i}].{key}"));
        }
    }
    out.into_lines()
}

/// Differences found so far, capped.
#[derive(Default)]
struct Differences {
    lines: Vec<String>,
    more: bool,
}

impl Differences {
    fn push(&mut self, line: String) {
        // One line is kept for saying that there are more.
        if self.lines.len() + 1 < MAX_LISTED {
            self.lines.push(line);
        } else {
            self.more = true;
        }
    }

    /// Compares the file's value at `at` with the composition's. Recursion follows
    /// the composition's own shape, so a hostile file cannot make it deep.
    fn compare(&mut self, file: Option<&Value>, ours: Option<&Value>, at: &str) {
        if self.more {
            return;
        }
        match (file, ours) {
            (None, None) => {}
            (None, Some(_)) => self.push(format!(
                "{at}: missing, while the file holds other derived fields"
            )),
            (Some(_), None) => self.push(format!("{at}: the composition has no such field")),
            (Some(Value::Number(a)), Some(Value::Number(b))) => {
                if !same_number(a.as_f64(), b.as_f64()) {
                    self.push(format!("{at}: {a} in the file, {b} composed from its plan"));
                }
            }
            (Some(Value::Array(a)), Some(Value::Array(b))) => {
                if a.len() != b.len() {
                    self.push(format!(
                        "{at}: {} entries in the file, {} composed from its plan",
                        a.len(),
                        b.len()
                    ));
                    return;
                }
                for (k, (x, y)) in a.iter().zip(b).enumerate() {
                    self.compare(Some(x), Some(y), &format!("{at}[{k}]"));
                }
            }
            (Some(Value::Object(a)), Some(Value::Object(b))) => {
                let keys: std::collections::BTreeSet<&String> = a.keys().chain(b.keys()).collect();
                for key in keys {
                    self.compare(a.get(key), b.get(key), &format!("{at}.{key}"));
                }
            }
            (Some(a), Some(b)) if a == b => {}
            (Some(a), Some(b)) => self.push(format!(
                "{at}: {} in the file, {} composed from its plan",
                short(a),
                short(b)
            )),
        }
    }

    fn into_lines(mut self) -> Vec<String> {
        if self.more {
            self.lines
                .push("… further differences not listed".to_string());
        }
        self.lines
    }
}

fn same_number(a: Option<f64>, b: Option<f64>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => (a - b).abs() <= SAME_WITHIN * a.abs().max(b.abs()).max(1.0),
        _ => false,
    }
}

/// A value in a message: scalars as written, lists and objects by kind.
fn short(value: &Value) -> String {
    match value {
        Value::Array(_) | Value::Object(_) => kind(value).to_string(),
        scalar => scalar.to_string(),
    }
}

/// A problem at a place in the file: (field path, reason).
type FieldError = (String, String);

fn parse(value: &Value) -> Result<(Option<String>, DiscretePlan), FieldError> {
    let top = value.as_object().ok_or_else(|| {
        (
            "top level".to_string(),
            format!(
                "expected an object with makespan_steps, sum_of_costs_steps, legs and drones, found {}",
                kind(value)
            ),
        )
    })?;
    let written_for = match top.get("mission") {
        None | Some(Value::Null) => None,
        Some(v) => Some(typed::<String>(v, "mission")?),
    };
    let makespan_steps = typed(required(top, "makespan_steps", "")?, "makespan_steps")?;
    let sum_of_costs_steps = typed(
        required(top, "sum_of_costs_steps", "")?,
        "sum_of_costs_steps",
    )?;
    let drones = required(top, "drones", "")?
        .as_array()
        .ok_or_else(|| ("drones".to_string(), "expected a list".to_string()))?
        .iter()
        .enumerate()
        .map(|(i, d)| drone(d, &format!("drones[{i}]")))
        .collect::<Result<_, _>>()?;
    let legs = typed(required(top, "legs", "")?, "legs")?;
    Ok((
        written_for,
        DiscretePlan {
            makespan_steps,
            sum_of_costs_steps,
            drones,
            legs,
        },
    ))
}

fn drone(value: &Value, at: &str) -> Result<DronePlan, FieldError> {
    let fields = value.as_object().ok_or_else(|| {
        (
            at.to_string(),
            format!(
                "expected an object with id, group, goal and path, found {}",
                kind(value)
            ),
        )
    })?;
    let field = |name: &str| format!("{at}.{name}");
    let path = required(fields, "path", at)?
        .as_array()
        .ok_or_else(|| (field("path"), "expected a list of [x, y, z] voxels".into()))?
        .iter()
        .enumerate()
        .map(|(step, v)| typed::<Voxel>(v, &format!("{at}.path[{step}]")))
        .collect::<Result<_, _>>()?;
    Ok(DronePlan {
        id: typed(required(fields, "id", at)?, &field("id"))?,
        group: typed(required(fields, "group", at)?, &field("group"))?,
        goal: typed(required(fields, "goal", at)?, &field("goal"))?,
        path,
    })
}

fn required<'v>(
    object: &'v Map<String, Value>,
    name: &str,
    at: &str,
) -> Result<&'v Value, FieldError> {
    object.get(name).ok_or_else(|| {
        let place = if at.is_empty() { "top level" } else { at };
        (place.to_string(), format!("missing field `{name}`"))
    })
}

fn typed<T: DeserializeOwned>(value: &Value, at: &str) -> Result<T, FieldError> {
    T::deserialize(value).map_err(|e| (at.to_string(), e.to_string()))
}

fn kind(value: &Value) -> &'static str {
    match value {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "a list",
        Value::Object(_) => "an object",
    }
}

/// Does the plan name the mission's drones, in the mission's order and groups, with
/// paths of the common length? (Checked before the validator, whose work grows
/// with the claimed makespan: a hostile `makespan_steps` must not make it spin.)
fn misfits(mission: &Mission, plan: &DiscretePlan) -> Vec<String> {
    let mut problems = Vec::new();
    let expected: Vec<(&str, &str)> = mission
        .drones()
        .map(|(g, d)| (d.id.as_str(), g.name.as_str()))
        .collect();
    if plan.drones.len() != expected.len() {
        problems.push(format!(
            "the plan has {} drones, the mission {}",
            plan.drones.len(),
            expected.len()
        ));
    }
    for (i, (d, &(id, group))) in plan.drones.iter().zip(&expected).enumerate() {
        if d.id != id {
            problems.push(format!(
                "drone #{i} of the plan is {:?}, but the mission's drone #{i} is {id:?}",
                d.id
            ));
        } else if d.group != group {
            problems.push(format!(
                "drone {id:?} is listed in group {:?} but belongs to {group:?}",
                d.group
            ));
        }
    }
    let expected_len = u64::from(plan.makespan_steps) + 1;
    for d in &plan.drones {
        if d.path.len() as u64 != expected_len {
            problems.push(format!(
                "drone {:?}: path has {} entries, expected makespan_steps + 1 = {expected_len}",
                d.id,
                d.path.len()
            ));
        }
    }
    problems
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mission;

    const MISSION: &str = r#"
name: tiny
world:
  dimensions: [3, 3, 1]
  voxel_size_m: 1.0
  origin_m: [0.0, 0.0, 1.5]
  obstacles: [[1, 1, 0]]
limits: { max_speed_mps: 1.0, max_accel_mps2: 2.0, safety_distance_m: 0.25 }
groups:
  - name: a
    drones: [{ id: a1, start: [0, 0, 0] }]
    goals: [[2, 0, 0]]
  - name: b
    drones: [{ id: b1, start: [0, 2, 0] }]
    goals: [[2, 2, 0]]
"#;

    fn tiny() -> Mission {
        mission::from_yaml(MISSION, Path::new("tiny.yaml")).expect("mission")
    }

    /// The planner's plan for the tiny mission, as a plan file holds it.
    fn valid() -> Value {
        let solution =
            crate::plan::solve(&tiny(), &crate::plan::PlanOptions::default()).expect("plans");
        let mut v = serde_json::to_value(&solution.plan).expect("serialises");
        v["mission"] = serde_json::json!("tiny");
        v
    }

    /// The whole file `swarmctl plan -o` writes for the tiny mission.
    fn full() -> Value {
        let solution =
            crate::plan::solve(&tiny(), &crate::plan::PlanOptions::default()).expect("plans");
        let compiled = super::super::compile(&tiny(), &solution).expect("compiles");
        serde_json::to_value(&compiled).expect("serialises")
    }

    fn load_value(value: &Value) -> Result<DiscretePlan, PlanFileError> {
        from_bytes(
            serde_json::to_string(value).unwrap().as_bytes(),
            Path::new("p.json"),
            &tiny(),
        )
        .map(|checked| checked.discrete())
    }

    fn message(value: &Value) -> String {
        load_value(value).expect_err("refused").to_string()
    }

    #[test]
    fn accepts_a_valid_plan() {
        let plan = load_value(&valid()).expect("valid");
        // Up from the pad, two along, down to a pad of its group: its own.
        assert_eq!(plan.legs.len(), 3);
        assert_eq!(plan.drones[1].path[0], Voxel::new(0, 2, -1));
        assert_eq!(
            plan.drones[1].path[plan.legs[1].end_step as usize],
            Voxel::new(2, 2, 0)
        );
    }

    #[test]
    fn the_whole_file_is_accepted_and_flies_what_it_holds() {
        let v = full();
        let checked = from_bytes(
            serde_json::to_string(&v).unwrap().as_bytes(),
            Path::new("p.json"),
            &tiny(),
        )
        .expect("the file plan -o wrote");
        assert!(checked.figures().passed());
        let samples = v["drones"][0]["trajectory"].as_array().unwrap();
        let ours = &checked.compiled().drones[0].trajectory;
        assert_eq!(samples.len(), ours.len());
        assert!((samples[5][1].as_f64().unwrap() - ours[5][1]).abs() < 1e-9);
    }

    #[test]
    fn a_moved_sample_is_refused_naming_it() {
        let mut v = full();
        let x = v["drones"][0]["trajectory"][10][1].as_f64().unwrap();
        v["drones"][0]["trajectory"][10][1] = serde_json::json!(x + 0.3);
        let e = message(&v);
        assert!(e.contains("does not hold what its plan composes to"), "{e}");
        assert!(e.contains("drones[0].trajectory[10][1]"), "{e}");
    }

    #[test]
    fn an_edited_gate_or_a_missing_derived_field_is_refused() {
        let mut v = full();
        let reach_s = &mut v["execution"]["drones"][1]["events"][1]["reach_s"];
        *reach_s = serde_json::json!(reach_s.as_f64().unwrap() + 5.0);
        let e = message(&v);
        assert!(e.contains("execution.drones[1].events[1].reach_s"), "{e}");

        let mut v = full();
        v["drones"][1].as_object_mut().unwrap().remove("trajectory");
        let e = message(&v);
        assert!(e.contains("drones[1].trajectory: missing"), "{e}");
    }

    #[test]
    fn a_file_for_other_limits_is_refused() {
        // Written for 1 m/s, flown with a mission that now allows 0.5 m/s: the
        // samples are not what the mission's schedule gives.
        let v = full();
        let slower = mission::from_yaml(
            &MISSION.replace("max_speed_mps: 1.0", "max_speed_mps: 0.5"),
            Path::new("tiny.yaml"),
        )
        .expect("mission");
        let e = from_bytes(
            serde_json::to_string(&v).unwrap().as_bytes(),
            Path::new("p.json"),
            &slower,
        )
        .expect_err("stale")
        .to_string();
        assert!(e.contains("makespan_s"), "{e}");
    }

    #[test]
    fn legs_must_be_the_missions() {
        let mut v = valid();
        v["legs"].as_array_mut().unwrap().remove(1);
        assert!(
            message(&v).contains("the plan's legs do not match"),
            "{}",
            message(&v)
        );
        let mut v = valid();
        v.as_object_mut().unwrap().remove("legs");
        assert!(message(&v).contains("missing field `legs`"));
    }

    #[test]
    fn syntax_errors_name_file_line_and_column() {
        let e = from_bytes(b"{\n  \"drones\": [,]\n}", Path::new("p.json"), &tiny())
            .unwrap_err()
            .to_string();
        assert!(e.contains("p.json") && e.contains("line 2"), "{e}");
    }

    #[test]
    fn field_errors_name_the_field() {
        let mut v = valid();
        v["drones"][1]["path"][1] = serde_json::json!([1, 2]);
        let e = message(&v);
        assert!(
            e.contains("p.json: drones[1].path[1]: invalid length 2"),
            "{e}"
        );

        let mut v = valid();
        v["drones"][0].as_object_mut().unwrap().remove("goal");
        assert!(message(&v).contains("drones[0]: missing field `goal`"));

        let mut v = valid();
        v["makespan_steps"] = serde_json::json!(-1);
        assert!(message(&v).contains("makespan_steps: invalid value"));

        assert!(message(&serde_json::json!([1])).contains("top level: expected an object"));
    }

    #[test]
    fn a_path_through_an_obstacle_is_refused() {
        let mut v = valid();
        v["drones"][0]["path"][2] = serde_json::json!([1, 1, 0]);
        let e = message(&v);
        assert!(e.contains("inside an obstacle"), "{e}");
    }

    #[test]
    fn swapped_drones_and_foreign_goals_are_refused() {
        let mut v = valid();
        let drones = v["drones"].as_array_mut().unwrap();
        drones.swap(0, 1);
        assert!(message(&v).contains("drone #0 of the plan is \"b1\""));

        // a1 stops one step short of its formation goal.
        let mut v = valid();
        let end = v["legs"][1]["end_step"].as_u64().unwrap() as usize;
        let before = v["drones"][0]["path"][end - 1].clone();
        v["drones"][0]["path"][end] = before;
        let e = message(&v);
        assert!(e.contains("not a target of group \"a\""), "{e}");
    }

    #[test]
    fn a_huge_makespan_is_refused_quickly() {
        let mut v = valid();
        v["makespan_steps"] = serde_json::json!(u32::MAX);
        let e = message(&v);
        assert!(
            e.contains("expected makespan_steps + 1 = 4294967296"),
            "{e}"
        );
    }

    #[test]
    fn another_missions_plan_says_so() {
        let mut v = valid();
        v["mission"] = serde_json::json!("other");
        v["drones"][0]["id"] = serde_json::json!("x1");
        let e = message(&v);
        assert!(e.contains("written for mission \"other\""), "{e}");
    }

    #[test]
    fn long_lists_of_problems_are_cut() {
        let problems: Vec<String> = (0..50).map(|i| format!("p{i}")).collect();
        let text = list(&problems);
        assert!(text.contains("p19") && !text.contains("p20") && text.contains("30 more"));
    }

    #[test]
    fn a_missing_file_is_named() {
        let e = load(Path::new("/nonexistent/plan.json"), &tiny()).unwrap_err();
        assert!(e.to_string().contains("/nonexistent/plan.json"));
        assert_eq!(e.path(), Path::new("/nonexistent/plan.json"));
    }
}
