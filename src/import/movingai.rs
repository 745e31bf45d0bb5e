//! MovingAI grid maps (`.map`) and scenarios (`.scen`), the standard MAPF benchmarks.
//!
//! A map is `type octile`, `height H`, `width W`, `map`, then H rows where `.` and `G`
//! are free and `@`, `O`, `T`, `S`, `W` are blocked; x is the column and y the row.
//! Coordinates are kept as in the files, so results can be compared with other solvers.

use super::build::{mission_file, world_spec};
use super::error::ImportError;
use crate::mission::MissionFile;
use crate::mission::schema::{DroneSpec, GroupSpec, ObstacleSpec};
use std::path::Path;

/// A parsed grid map: its size and blocked cells `[x, y]`.
#[derive(Debug, Clone, PartialEq)]
pub struct GridMap {
    /// Columns (x runs from 0 to `width - 1`).
    pub width: usize,
    /// Rows (y runs from 0 to `height - 1`, row 0 first in the file).
    pub height: usize,
    /// The blocked cells `[x, y]`, row by row.
    pub blocked: Vec<[usize; 2]>,
}

/// One scenario row: a start and a goal on a named map.
#[derive(Debug, Clone, PartialEq)]
pub struct ScenarioRow {
    /// The map file's name, looked up next to the scenario.
    pub map: String,
    /// The agent's start `[x, y]`.
    pub start: [usize; 2],
    /// The agent's goal `[x, y]`.
    pub goal: [usize; 2],
}

/// Parses a `.map` file.
///
/// ```
/// let map = swarmctl::import::parse_map("type octile\nheight 2\nwidth 3\nmap\n.@.\n...\n", "m.map".as_ref()).unwrap();
/// assert_eq!(map.blocked, vec![[1, 0]]);
/// ```
pub fn parse_map(text: &str, file: &Path) -> Result<GridMap, ImportError> {
    let mut lines = text.lines().enumerate();
    let mut height = None;
    let mut width = None;
    for (n, line) in lines.by_ref() {
        let mut words = line.split_whitespace();
        match (words.next(), words.next()) {
            (Some("type"), _) => {}
            (Some("height"), Some(v)) => height = v.parse::<usize>().ok(),
            (Some("width"), Some(v)) => width = v.parse::<usize>().ok(),
            (Some("map"), None) => break,
            _ => {
                return Err(ImportError::format(
                    file,
                    Some(n + 1),
                    format!("unexpected header line {line:?}"),
                ));
            }
        }
    }
    let (Some(height), Some(width)) = (height, width) else {
        return Err(ImportError::format(
            file,
            None,
            "header lacks a valid `height` or `width`",
        ));
    };
    let mut blocked = Vec::new();
    let mut rows = 0;
    for (n, line) in lines {
        let line = line.trim_end_matches('\r');
        if line.is_empty() {
            continue;
        }
        if rows == height {
            return Err(ImportError::format(
                file,
                Some(n + 1),
                format!("more than {height} rows"),
            ));
        }
        if line.len() != width {
            return Err(ImportError::format(
                file,
                Some(n + 1),
                format!("row has {} cells, expected {width}", line.len()),
            ));
        }
        for (x, ch) in line.chars().enumerate() {
            match ch {
                '.' | 'G' => {}
                '@' | 'O' | 'T' | 'S' | 'W' => blocked.push([x, rows]),
                other => {
                    return Err(ImportError::format(
                        file,
                        Some(n + 1),
                        format!("unknown cell {other:?}"),
                    ));
                }
            }
        }
        rows += 1;
    }
    if rows != height {
        return Err(ImportError::format(
            file,
            None,
            format!("{rows} rows, expected {height}"),
        ));
    }
    Ok(GridMap {
        width,
        height,
        blocked,
    })
}

/// Parses a `.scen` file (`version 1`, then tab-separated rows).
pub fn parse_scen(text: &str, file: &Path) -> Result<Vec<ScenarioRow>, ImportError> {
    let mut rows = Vec::new();
    for (n, line) in text.lines().enumerate() {
        if line.trim().is_empty() || line.starts_with("version") {
            continue;
        }
        let fields: Vec<&str> = line.split('\t').collect();
        let number = |i: usize| fields.get(i).and_then(|f| f.trim().parse::<usize>().ok());
        match (fields.get(1), number(4), number(5), number(6), number(7)) {
            (Some(map), Some(sx), Some(sy), Some(gx), Some(gy)) => rows.push(ScenarioRow {
                map: map.trim().to_string(),
                start: [sx, sy],
                goal: [gx, gy],
            }),
            _ => {
                return Err(ImportError::format(
                    file,
                    Some(n + 1),
                    "expected bucket, map, width, height, start x, start y, goal x, goal y, length",
                ));
            }
        }
    }
    Ok(rows)
}

/// The first `agents` rows of a scenario on its map (found next to the scenario), each
/// agent its own group: plain MAPF.
pub(crate) fn load_scenario(
    path: &Path,
    text: &str,
    agents: Option<usize>,
) -> Result<MissionFile, ImportError> {
    let rows = parse_scen(text, path)?;
    let count = agents.unwrap_or(rows.len());
    if count == 0 || count > rows.len() {
        return Err(ImportError::format(
            path,
            None,
            format!("asked for {count} agents; the scenario has {}", rows.len()),
        ));
    }
    let map_path = path.parent().unwrap_or(Path::new(".")).join(&rows[0].map);
    let map_text = std::fs::read_to_string(&map_path).map_err(|source| ImportError::Read {
        file: map_path.clone(),
        named_by: Some(path.to_path_buf()),
        source,
    })?;
    let map = parse_map(&map_text, &map_path)?;
    let to_voxel = |[x, y]: [usize; 2]| [x as i64, y as i64, 0];
    let obstacles = map
        .blocked
        .iter()
        .map(|&c| ObstacleSpec::Cell(to_voxel(c)))
        .collect();
    let groups = rows[..count]
        .iter()
        .enumerate()
        .map(|(i, row)| GroupSpec {
            name: format!("agent{i}"),
            drones: vec![DroneSpec {
                id: format!("a{i}"),
                start: Some(to_voxel(row.start)),
                pad: None,
                endpoint: None,
                system_id: None,
            }],
            goals: vec![to_voxel(row.goal)],
        })
        .collect();
    let stem = path
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let dims = [map.width as i64, map.height as i64, 1];
    Ok(mission_file(
        format!("{stem}-{count}"),
        path,
        world_spec(dims, obstacles),
        groups,
    ))
}
