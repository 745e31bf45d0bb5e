//! The instances every solver gets: random starts and goals on a MovingAI map,
//! written as a MovingAI scenario that swarmctl and LaCAM3 read as they are, and
//! that the tswap adapter turns into its own instance file.
//!
//! Starts are distinct cells, goals are distinct cells (a goal may be another
//! agent's start, as in MovingAI's random scenarios), all in the map's largest
//! 4-connected region, so every instance is solvable and no solver is asked to
//! prove a walled-off agent impossible.

use crate::HarnessError;
use rand::SeedableRng;
use rand::seq::SliceRandom;
use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use swarmctl::import::{GridMap, parse_map};

/// One instance: a map and where its agents start and end.
#[derive(Debug, Clone, PartialEq)]
pub struct GridInstance {
    /// The map's file name (as the scenario names it).
    pub map_name: String,
    /// The map, copied into the work directory beside the scenario.
    pub map_path: PathBuf,
    /// The scenario naming it (`version 1` and one row per agent).
    pub scen_path: PathBuf,
    /// The map's width and height, cells.
    pub size: [usize; 2],
    /// Agent `k` starts at `starts[k]` (`[x, y]`, x the column).
    pub starts: Vec<[usize; 2]>,
    /// Agent `k`'s own goal (the unlabeled problem takes them as one set).
    pub goals: Vec<[usize; 2]>,
}

impl GridInstance {
    /// The scenario's file stem (`<map>-<agents>-<seed>`): names the result and
    /// log files of every solver on this instance.
    pub fn stem(&self) -> String {
        self.scen_path.file_stem().map_or_else(
            || "instance".to_string(),
            |s| s.to_string_lossy().into_owned(),
        )
    }
}

/// `agents` random starts and goals on `map_file` (seeded by `seed`), written to
/// `work_dir` as `<map>-<agents>-<seed>.scen` beside a copy of the map.
pub fn random_instance(
    map_file: &Path,
    agents: usize,
    seed: u64,
    work_dir: &Path,
) -> Result<GridInstance, HarnessError> {
    let io = |what: String| move |source| HarnessError::Io { what, source };
    let text = std::fs::read_to_string(map_file)
        .map_err(io(format!("reading the map {}", map_file.display())))?;
    let map = parse_map(&text, map_file)?;
    let region = largest_region(&map);
    if region.len() < agents {
        return Err(HarnessError::PeerInstance {
            map: map_file.to_path_buf(),
            problem: format!(
                "its largest connected region has {} free cells, fewer than the {agents} agents asked",
                region.len()
            ),
        });
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut cells = region;
    cells.shuffle(&mut rng);
    let starts = cells[..agents].to_vec();
    cells.shuffle(&mut rng);
    let goals = cells[..agents].to_vec();

    let map_name = map_file.file_name().map_or_else(
        || "map.map".to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let map_path = work_dir.join(&map_name);
    std::fs::write(&map_path, &text).map_err(io(format!("writing {}", map_path.display())))?;
    let stem = map_name.trim_end_matches(".map");
    let scen_path = work_dir.join(format!("{stem}-{agents}-{seed}.scen"));
    let scen = scenario_text(&map_name, [map.width, map.height], &starts, &goals);
    std::fs::write(&scen_path, scen).map_err(io(format!("writing {}", scen_path.display())))?;
    Ok(GridInstance {
        map_name,
        map_path,
        scen_path,
        size: [map.width, map.height],
        starts,
        goals,
    })
}

/// A MovingAI scenario: `version 1`, then `bucket map width height sx sy gx gy
/// length` per agent, tab-separated. Solvers read the lengths as hints at most;
/// 0 says none was computed.
fn scenario_text(
    map_name: &str,
    [width, height]: [usize; 2],
    starts: &[[usize; 2]],
    goals: &[[usize; 2]],
) -> String {
    let mut text = String::from("version 1\n");
    for ([sx, sy], [gx, gy]) in starts.iter().zip(goals) {
        text.push_str(&format!(
            "0\t{map_name}\t{width}\t{height}\t{sx}\t{sy}\t{gx}\t{gy}\t0\n"
        ));
    }
    text
}

/// The free cells of the map's largest 4-connected region, in row-major order.
fn largest_region(map: &GridMap) -> Vec<[usize; 2]> {
    let (width, height) = (map.width, map.height);
    let mut free = vec![true; width * height];
    for &[x, y] in &map.blocked {
        free[y * width + x] = false;
    }
    let mut region_of = vec![usize::MAX; width * height];
    let mut sizes: Vec<usize> = Vec::new();
    let mut queue = VecDeque::new();
    for seed in 0..width * height {
        if !free[seed] || region_of[seed] != usize::MAX {
            continue;
        }
        let region = sizes.len();
        sizes.push(0);
        region_of[seed] = region;
        queue.push_back(seed);
        while let Some(cell) = queue.pop_front() {
            sizes[region] += 1;
            let (x, y) = (cell % width, cell / width);
            let left = (x > 0).then(|| cell - 1);
            let right = (x + 1 < width).then(|| cell + 1);
            let up = (y > 0).then(|| cell - width);
            let down = (y + 1 < height).then(|| cell + width);
            for next in [left, right, up, down].into_iter().flatten() {
                if free[next] && region_of[next] == usize::MAX {
                    region_of[next] = region;
                    queue.push_back(next);
                }
            }
        }
    }
    let Some(largest) = (0..sizes.len()).max_by_key(|&r| sizes[r]) else {
        return Vec::new();
    };
    (0..width * height)
        .filter(|&cell| region_of[cell] == largest)
        .map(|cell| [cell % width, cell / width])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    /// Two rooms: a 3-cell one on the left, a 5-cell one on the right.
    const TWO_ROOMS: &str = "type octile\nheight 2\nwidth 5\nmap\n.@...\n.@@..\n";

    fn write_map(dir: &Path) -> PathBuf {
        let path = dir.join("rooms.map");
        std::fs::write(&path, TWO_ROOMS).expect("map");
        path
    }

    #[test]
    fn agents_start_and_end_on_distinct_cells_of_the_largest_region() {
        let dir = tempfile::tempdir().expect("temp dir");
        let map = write_map(dir.path());
        let instance = random_instance(&map, 5, 7, dir.path()).expect("instance");
        let right_room: HashSet<[usize; 2]> = [[2, 0], [3, 0], [4, 0], [3, 1], [4, 1]]
            .into_iter()
            .collect();
        for cells in [&instance.starts, &instance.goals] {
            let distinct: HashSet<_> = cells.iter().copied().collect();
            assert_eq!(distinct.len(), 5, "{cells:?}");
            assert!(distinct.is_subset(&right_room), "{cells:?}");
        }
    }

    #[test]
    fn the_scenario_reads_back_through_swarmctls_importer() {
        let dir = tempfile::tempdir().expect("temp dir");
        let map = write_map(dir.path());
        let instance = random_instance(&map, 4, 1, dir.path()).expect("instance");
        let text = std::fs::read_to_string(&instance.scen_path).expect("scen");
        let rows = swarmctl::import::parse_scen(&text, &instance.scen_path).expect("parses");
        assert_eq!(rows.len(), 4);
        for (k, row) in rows.iter().enumerate() {
            assert_eq!(row.map, "rooms.map");
            assert_eq!(row.start, instance.starts[k]);
            assert_eq!(row.goal, instance.goals[k]);
        }
        let mission = swarmctl::import::load_any(&instance.scen_path, None).expect("loads");
        assert_eq!(mission.groups.len(), 4);
    }

    #[test]
    fn the_same_seed_gives_the_same_instance_and_another_seed_another() {
        let dir = tempfile::tempdir().expect("temp dir");
        let map = write_map(dir.path());
        let a = random_instance(&map, 3, 11, dir.path()).expect("instance");
        let b = random_instance(&map, 3, 11, dir.path()).expect("instance");
        assert_eq!((&a.starts, &a.goals), (&b.starts, &b.goals));
        let others: Vec<_> = (12..20)
            .map(|seed| random_instance(&map, 3, seed, dir.path()).expect("instance"))
            .collect();
        assert!(
            others
                .iter()
                .any(|o| (&o.starts, &o.goals) != (&a.starts, &a.goals))
        );
    }

    #[test]
    fn more_agents_than_the_region_holds_is_refused_naming_the_map() {
        let dir = tempfile::tempdir().expect("temp dir");
        let map = write_map(dir.path());
        let error = random_instance(&map, 6, 1, dir.path()).expect_err("too many");
        let text = error.to_string();
        assert!(
            text.contains("rooms.map") && text.contains("5 free cells"),
            "{text}"
        );
    }
}
