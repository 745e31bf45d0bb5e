//! The load benchmark's generated mission.

use crate::HarnessError;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use swarmctl::mission::schema::{LimitsSpec, LinkSpec, SeparationSpec, WorldSpec};
use swarmctl::mission::{FenceSpec, MissionFile};

/// Drones per group (within a group any drone may take any goal).
const DRONES_PER_GROUP: usize = 20;
/// Layers of the world above the lowest one.
const LAYERS: u32 = 3;
/// The most drones a load mission has: one process flies at most 254 (MAVLink
/// system ids 1–254); through relays, 254 per relay.
const MAX_VEHICLES: usize = 5000;

/// A seeded random mission for `vehicles` drones on a square world just large
/// enough for two free columns per drone, four layers high, no obstacles: starts
/// on distinct x,y columns in the lowest layer, goals on distinct columns at random
/// heights, groups of up to 20. The lowest layer is 1 m above the ground. Drones
/// keep a 0.25 m sphere, or with `vertical_separation_m` an ellipsoid 0.25 m
/// across and that high.
pub fn load_mission(
    vehicles: usize,
    seed: u64,
    vertical_separation_m: Option<f64>,
) -> Result<MissionFile, HarnessError> {
    if !(1..=MAX_VEHICLES).contains(&vehicles) {
        return Err(HarnessError::LoadVehicles { vehicles });
    }
    let side = ((2 * vehicles) as f64).sqrt().ceil().max(2.0) as u32;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut columns: Vec<[i64; 2]> = (0..side)
        .flat_map(|x| (0..side).map(move |y| [i64::from(x), i64::from(y)]))
        .collect();
    columns.shuffle(&mut rng);
    let starts: Vec<[i64; 3]> = columns[..vehicles]
        .iter()
        .map(|&[x, y]| [x, y, 0])
        .collect();
    columns.shuffle(&mut rng);
    let heights: Vec<i64> = (0..vehicles)
        .map(|_| rng.random_range(0..=i64::from(LAYERS)))
        .collect();
    let goals: Vec<[i64; 3]> = columns[..vehicles]
        .iter()
        .zip(&heights)
        .map(|(&[x, y], &z)| [x, y, z])
        .collect();
    let groups = vehicles.div_ceil(DRONES_PER_GROUP);
    let group_specs = swarmctl::generate::split_into_groups(groups, &starts, &goals);
    Ok(MissionFile {
        name: format!("load-{vehicles}-s{seed}"),
        description: Some(format!(
            "Load benchmark (swarmctl bench load --vehicles {vehicles} --seed {seed}): \
             {side}x{side}x{} voxels, starts and goals on distinct columns.",
            LAYERS + 1
        )),
        world: WorldSpec {
            dimensions: [i64::from(side), i64::from(side), i64::from(LAYERS + 1)],
            voxel_size_m: 1.0,
            origin_m: Some([0.0, 0.0, 1.0]),
            pad_height_m: None,
            geo_origin: None,
            obstacles: Vec::new(),
            formations_use_pad_layer: true,
        },
        limits: LimitsSpec {
            max_speed_mps: 1.0,
            max_accel_mps2: 2.0,
            max_jerk_mps3: None,
            safety_distance_m: vertical_separation_m.is_none().then_some(0.25),
            separation: vertical_separation_m.map(|vertical_m| SeparationSpec {
                horizontal_m: 0.25,
                vertical_m,
            }),
            tracking_error_m: None,
        },
        link: LinkSpec::default(),
        groups: group_specs,
        stages: Vec::new(),
        landing: None,
        fence: FenceSpec::default(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn load_missions_keep_starts_and_goals_on_distinct_columns() {
        for (vehicles, seed) in [(1, 1), (50, 1), (200, 1), (200, 7), (254, 3), (1000, 1)] {
            let file = load_mission(vehicles, seed, None).unwrap();
            let mission = swarmctl::mission::validate(&file).unwrap();
            assert_eq!(mission.drone_count(), vehicles);
            let starts: Vec<[i64; 3]> = file
                .groups
                .iter()
                .flat_map(|g| g.drones.iter().filter_map(|d| d.start))
                .collect();
            let goals: Vec<[i64; 3]> = file.groups.iter().flat_map(|g| g.goals.clone()).collect();
            for list in [&starts, &goals] {
                let columns: std::collections::HashSet<[i64; 2]> =
                    list.iter().map(|v| [v[0], v[1]]).collect();
                assert_eq!(columns.len(), vehicles);
            }
            assert!(starts.iter().all(|s| s[2] == 0));
        }
        assert_eq!(
            load_mission(40, 2, None).unwrap(),
            load_mission(40, 2, None).unwrap()
        );
        assert!(load_mission(0, 1, None).is_err() && load_mission(5001, 1, None).is_err());
    }

    #[test]
    fn the_bundled_load_mission_is_what_the_benchmark_generates() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../missions/load-200.yaml");
        let text = std::fs::read_to_string(path).unwrap();
        let file: MissionFile = swarmctl::mission::parse_yaml(&text).unwrap();
        assert_eq!(file, load_mission(200, 1, None).unwrap());
    }
}
