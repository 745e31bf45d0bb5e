//! MovingAI 3D voxel maps (`.3dmap`) and scenarios (`.3dscen`).
//!
//! A map is a line `voxel W H D`, then one `x y z` line per blocked voxel. A scenario
//! is `version 1`, the map's file name, then `sx sy sz gx gy gz length ratio` per
//! line. The benchmark's own paths are 26-connected; swarmctl flies 6-connected
//! moves, so its optimal lengths are not comparable with the file's.

use super::build::{mission_file, world_spec};
use super::error::ImportError;
use crate::mission::MissionFile;
use crate::mission::schema::{DroneSpec, GroupSpec, ObstacleSpec};
use std::path::Path;

/// Parses a `.3dmap`: dimensions and blocked voxels.
///
/// ```
/// let (dims, blocked) = swarmctl::import::parse_3dmap("voxel 2 2 2\n1 1 1\n", "m.3dmap".as_ref()).unwrap();
/// assert_eq!((dims, blocked), ([2, 2, 2], vec![[1, 1, 1]]));
/// ```
pub fn parse_3dmap(text: &str, file: &Path) -> Result<([i64; 3], Vec<[i64; 3]>), ImportError> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let dims = match lines.next() {
        Some((_, header)) => {
            let words: Vec<&str> = header.split_whitespace().collect();
            match words.as_slice() {
                ["voxel", w, h, d] => triple(&[w, h, d]),
                _ => None,
            }
        }
        None => None,
    }
    .ok_or_else(|| ImportError::format(file, Some(1), "expected a first line `voxel W H D`"))?;
    let mut blocked = Vec::new();
    for (n, line) in lines {
        let words: Vec<&str> = line.split_whitespace().collect();
        let voxel = triple(&words).ok_or_else(|| {
            ImportError::format(file, Some(n + 1), format!("expected `x y z`, got {line:?}"))
        })?;
        blocked.push(voxel);
    }
    Ok((dims, blocked))
}

/// A `.3dscen`'s map file name and its `(start, goal)` voxel pairs.
pub type Scenario3d = (String, Vec<([i64; 3], [i64; 3])>);

/// Parses a `.3dscen`.
pub fn parse_3dscen(text: &str, file: &Path) -> Result<Scenario3d, ImportError> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    match lines.next() {
        Some((_, l)) if l.trim().starts_with("version") => {}
        _ => return Err(ImportError::format(file, Some(1), "expected `version 1`")),
    }
    let map = lines
        .next()
        .map(|(_, l)| l.trim().to_string())
        .ok_or_else(|| ImportError::format(file, Some(2), "expected the map's file name"))?;
    let mut pairs = Vec::new();
    for (n, line) in lines {
        let words: Vec<&str> = line.split_whitespace().collect();
        match (
            words.get(0..3).and_then(triple),
            words.get(3..6).and_then(triple),
        ) {
            (Some(start), Some(goal)) => pairs.push((start, goal)),
            _ => {
                return Err(ImportError::format(
                    file,
                    Some(n + 1),
                    "expected `sx sy sz gx gy gz length ratio`",
                ));
            }
        }
    }
    Ok((map, pairs))
}

fn triple(words: &[&str]) -> Option<[i64; 3]> {
    match words {
        [x, y, z] => Some([x.parse().ok()?, y.parse().ok()?, z.parse().ok()?]),
        _ => None,
    }
}

/// The first `agents` pairs of a 3D scenario, each agent its own group.
pub(crate) fn load_scenario(
    path: &Path,
    text: &str,
    agents: Option<usize>,
) -> Result<MissionFile, ImportError> {
    let (map_name, pairs) = parse_3dscen(text, path)?;
    let count = agents.unwrap_or(pairs.len());
    if count == 0 || count > pairs.len() {
        return Err(ImportError::format(
            path,
            None,
            format!("asked for {count} agents; the scenario has {}", pairs.len()),
        ));
    }
    let map_path = path.parent().unwrap_or(Path::new(".")).join(&map_name);
    let map_text = std::fs::read_to_string(&map_path).map_err(|source| ImportError::Read {
        file: map_path.clone(),
        named_by: Some(path.to_path_buf()),
        source,
    })?;
    let (dims, blocked) = parse_3dmap(&map_text, &map_path)?;
    let groups = pairs[..count]
        .iter()
        .enumerate()
        .map(|(i, &(start, goal))| GroupSpec {
            name: format!("agent{i}"),
            drones: vec![DroneSpec {
                id: format!("a{i}"),
                start: Some(start),
                pad: None,
                endpoint: None,
                system_id: None,
            }],
            goals: vec![goal],
        })
        .collect();
    let obstacles = ObstacleSpec::exactly(&blocked);
    let stem = path
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    Ok(mission_file(
        format!("{stem}-{count}"),
        path,
        world_spec(dims, obstacles),
        groups,
    ))
}
