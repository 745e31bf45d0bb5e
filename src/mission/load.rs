//! Reading mission files from disk or text.

use super::error::{MissionError, Problem};
use super::schema::MissionFile;
use super::types::{KeySource, Mission};
use super::validate::validate;
use std::path::Path;

/// Reads, parses and validates the mission at `path`.
///
/// Every error names the file and the field; YAML errors also carry line and column.
pub fn load(path: &Path) -> Result<Mission, MissionError> {
    let text = std::fs::read_to_string(path).map_err(|source| MissionError::Read {
        file: path.to_path_buf(),
        source,
    })?;
    from_yaml(&text, path)
}

/// Parses and validates mission YAML; `file` is only used in messages.
///
/// ```
/// use swarmctl::mission;
/// let yaml = "
/// name: hop
/// world: { dimensions: [2, 1, 1], voxel_size_m: 1.0, origin_m: [0.0, 0.0, 1.5] }
/// limits: { max_speed_mps: 1.0, max_accel_mps2: 1.0, safety_distance_m: 0.2 }
/// groups:
///   - { name: solo, drones: [{ id: a, start: [0, 0, 0] }], goals: [[1, 0, 0]] }
/// ";
/// let m = mission::from_yaml(yaml, "hop.yaml".as_ref()).unwrap();
/// assert_eq!(m.drone_count(), 1);
/// let bad = yaml.replace("[1, 0, 0]", "[2, 0, 0]");
/// let err = mission::from_yaml(&bad, "hop.yaml".as_ref()).unwrap_err();
/// assert!(err.to_string().contains("groups[0].goals[0]: [2, 0, 0] is outside the world"));
/// ```
pub fn from_yaml(text: &str, file: &Path) -> Result<Mission, MissionError> {
    let parsed = parse_yaml(text).map_err(|problem| MissionError::Invalid {
        file: file.to_path_buf(),
        problems: vec![problem],
    })?;
    let mut mission = validate(&parsed).map_err(|problems| MissionError::Invalid {
        file: file.to_path_buf(),
        problems,
    })?;
    // A key file is named relative to the mission, so the mission can move with it.
    if let Some(KeySource::File(key_file)) = &mut mission.link.signing
        && key_file.is_relative()
        && let Some(dir) = file.parent()
    {
        *key_file = dir.join(&*key_file);
    }
    Ok(mission)
}

/// Parses the YAML into the file schema without validating it.
pub fn parse_yaml(text: &str) -> Result<MissionFile, Problem> {
    if let Some(problem) = super::shape::problem(text) {
        return Err(problem);
    }
    yaml_serde::from_str(text).map_err(|e| yaml_problem(&e))
}

/// Splits the YAML parser's "path: message at line L column C" into its parts.
fn yaml_problem(error: &yaml_serde::Error) -> Problem {
    let line_column = error.location().map(|l| (l.line(), l.column()));
    let message = strip_locations(&error.to_string());
    let (path, message) = match message.split_once(": ") {
        Some((path, rest)) if looks_like_field_path(path) => (path.to_string(), rest.to_string()),
        _ => (String::new(), message),
    };
    Problem {
        path,
        message,
        line_column,
    }
}

fn looks_like_field_path(s: &str) -> bool {
    !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '[' | ']'))
}

/// Removes " at line L column C" wherever the YAML parser put it; the location is kept apart.
fn strip_locations(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(at) = rest.find(" at line ") {
        out.push_str(&rest[..at]);
        let tail = &rest[at + " at line ".len()..];
        let after_line = tail.trim_start_matches(|c: char| c.is_ascii_digit());
        rest = match after_line.strip_prefix(" column ") {
            Some(col) => col.trim_start_matches(|c: char| c.is_ascii_digit()),
            None => {
                out.push_str(" at line ");
                tail
            }
        };
    }
    out.push_str(rest);
    out
}
