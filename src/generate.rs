//! Random missions in the style of the paper's experiments.

use crate::mission::schema::{
    DroneSpec, GroupSpec, LimitsSpec, LinkSpec, ObstacleSpec, StageSpec, WorldSpec,
};
use crate::mission::{FenceSpec, MissionFile};
use crate::world::{Voxel, VoxelGrid};
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

/// What to generate. [`Default`] gives the paper's setting.
#[derive(Debug, Clone, PartialEq)]
pub struct GenerateOptions {
    /// World size in voxels along x (east), y (north), z (up).
    pub dimensions: [u32; 3],
    /// Number of obstacle voxels to place.
    pub obstacles: usize,
    /// Number of drones (each gets its own goal).
    pub drones: usize,
    /// Number of groups the drones are dealt into, as evenly as possible.
    pub groups: usize,
    /// Seeds the random layout; the same options give the same mission.
    pub seed: u64,
    /// Edge length of one voxel, metres.
    pub voxel_size_m: f64,
    /// Where the drones' pads go.
    pub pads: PadLayout,
    /// Random formations flown after the first, each a `stages` entry.
    pub stages: usize,
    /// Formations on a lattice this many voxels apart, as drone shows fly them
    /// (`None`: random free voxels). See [`generate`].
    pub spacing: Option<u32>,
}

/// Where a generated mission puts its launch pads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PadLayout {
    /// No `pad` fields: each drone's pad defaults to the cell below its start (or
    /// the nearest free one where starts share a column).
    #[default]
    Default,
    /// A launch area around the world (checkerboard rings, nearest first), written
    /// as explicit `pad` fields.
    Beside,
}

impl Default for GenerateOptions {
    fn default() -> Self {
        Self {
            dimensions: [10, 10, 5],
            obstacles: 150,
            drones: 100,
            groups: 5,
            seed: 1,
            voxel_size_m: 1.0,
            pads: PadLayout::Default,
            stages: 0,
            spacing: None,
        }
    }
}

/// Why no mission could be generated.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum GenerateError {
    /// The options cannot be met at all (e.g. more drones than free voxels); the
    /// message says which.
    #[error("{0}")]
    Impossible(String),
    /// Every obstacle layout drawn (the count given) split the free space; fewer
    /// obstacles would help.
    #[error(
        "no obstacle layout with connected free space found in {0} attempts; use fewer obstacles"
    )]
    Disconnected(usize),
}

/// Attempts at drawing obstacles before giving up on connected free space.
const MAX_ATTEMPTS: usize = 10_000;

/// A random valid mission: random obstacle voxels leaving the free space connected
/// (so every drone can reach every goal), distinct free starts, distinct free goals,
/// drones split into groups as evenly as possible. The same options give the same mission.
///
/// With a `spacing`, starts and goals are free points of a lattice that many
/// voxels apart, as a show's formations are: the drones start on its lowest
/// layers, south to north (a carpet), the first formation is the lattice points
/// nearest the world's centre (a ball), and each stage a random draw of them.
///
/// ```
/// use swarmctl::generate::{generate, GenerateOptions};
/// let file = generate(&GenerateOptions { drones: 10, groups: 3, ..Default::default() }).unwrap();
/// let sizes: Vec<usize> = file.groups.iter().map(|g| g.drones.len()).collect();
/// assert_eq!(sizes, [4, 3, 3]);
/// assert!(swarmctl::mission::validate(&file).is_ok());
/// ```
pub fn generate(options: &GenerateOptions) -> Result<MissionFile, GenerateError> {
    let GenerateOptions {
        dimensions,
        obstacles,
        drones,
        groups,
        seed,
        voxel_size_m,
        pads,
        stages,
        spacing,
    } = *options;
    let total: usize = dimensions.iter().map(|&d| d as usize).product();
    if dimensions.contains(&0) {
        return Err(GenerateError::Impossible(
            "every dimension must be at least 1".into(),
        ));
    }
    if groups == 0 || drones < groups {
        return Err(GenerateError::Impossible(format!(
            "need at least one drone per group ({drones} drones, {groups} groups)"
        )));
    }
    if obstacles + drones > total {
        return Err(GenerateError::Impossible(format!(
            "{obstacles} obstacles and {drones} drones do not fit in {total} voxels"
        )));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut cells: Vec<usize> = (0..total).collect();
    let world = (0..MAX_ATTEMPTS)
        .find_map(|_| {
            cells.shuffle(&mut rng);
            let mut world = VoxelGrid::new(dimensions, voxel_size_m, [0.0; 3]);
            for &c in &cells[..obstacles] {
                let v = world.voxel(c);
                world.block(v);
            }
            let labels = world.components();
            let connected = labels.iter().all(|&l| l == 0 || l == u32::MAX);
            connected.then_some(world)
        })
        .ok_or(GenerateError::Disconnected(MAX_ATTEMPTS))?;

    let mut free = free_points(&world, spacing);
    if free.len() < drones {
        return Err(GenerateError::Impossible(format!(
            "{drones} drones do not fit on the {} free points of a lattice {} voxels apart",
            free.len(),
            spacing.unwrap_or(1)
        )));
    }
    let (starts, goals) = formations(&mut free, drones, spacing, dimensions, &mut rng);
    let to_raw = |v: Voxel| [i64::from(v.x), i64::from(v.y), i64::from(v.z)];
    let starts: Vec<[i64; 3]> = starts.into_iter().map(to_raw).collect();
    let goals: Vec<[i64; 3]> = goals.into_iter().map(to_raw).collect();
    let mut group_specs = split_into_groups(groups, &starts, &goals);
    if pads == PadLayout::Beside {
        pads_beside(&mut group_specs, dimensions);
    }
    let stage_specs = (1..=stages)
        .map(|k| random_stage(k, &group_specs, &mut free, &mut rng))
        .collect();

    let lattice = spacing.map_or_else(String::new, |s| format!("-l{s}"));
    let on = spacing.map_or_else(String::new, |s| {
        format!(", formations on a lattice {s} voxels apart")
    });
    Ok(MissionFile {
        name: format!(
            "random-{}x{}x{}-o{obstacles}-d{drones}-g{groups}-s{seed}{lattice}",
            dimensions[0], dimensions[1], dimensions[2]
        ),
        description: Some(format!(
            "Random mission (swarmctl gen --seed {seed}): {obstacles} obstacles, {drones} drones in {groups} groups{on}."
        )),
        world: WorldSpec {
            dimensions: dimensions.map(i64::from),
            voxel_size_m,
            // Lift the lowest layer one metre off the ground drones take off from
            // (higher for big voxels, so the pad layer below keeps the safety distance).
            origin_m: Some([0.0, 0.0, 1.0_f64.max(0.5 * voxel_size_m)]),
            pad_height_m: None,
            geo_origin: None,
            // Random voxels, not walls: those on layer 0 stand on the ground, the
            // rest float (written overhead), exactly as drawn.
            obstacles: ObstacleSpec::exactly(&world.obstacles().map(to_raw).collect::<Vec<_>>()),
            formations_use_pad_layer: true,
        },
        limits: LimitsSpec {
            max_speed_mps: 1.0,
            max_accel_mps2: 2.0,
            max_jerk_mps3: None,
            safety_distance_m: Some(0.25 * voxel_size_m),
            separation: None,
            tracking_error_m: None,
        },
        link: LinkSpec::default(),
        groups: group_specs,
        stages: stage_specs,
        landing: None,
        fence: FenceSpec::default(),
    })
}

/// The free voxels of `world` in cell order, only the lattice's points with a
/// `spacing`.
fn free_points(world: &VoxelGrid, spacing: Option<u32>) -> Vec<Voxel> {
    let on_lattice = |v: &Voxel| {
        spacing.is_none_or(|s| {
            let s = i32::try_from(s.max(1)).unwrap_or(i32::MAX);
            [v.x, v.y, v.z].iter().all(|&c| c.rem_euclid(s) == 0)
        })
    };
    (0..world.len())
        .filter(|&c| world.is_free_cell(c))
        .map(|c| world.voxel(c))
        .filter(on_lattice)
        .collect()
}

/// `drones` starts and as many goals among the `free` voxels: random ones, or on
/// a lattice (`spacing`, `free` holding only its points in cell order) the
/// lowest layers' for starts and those nearest the world's centre for goals.
fn formations(
    free: &mut [Voxel],
    drones: usize,
    spacing: Option<u32>,
    dimensions: [u32; 3],
    rng: &mut ChaCha8Rng,
) -> (Vec<Voxel>, Vec<Voxel>) {
    if spacing.is_none() {
        free.shuffle(rng);
        let starts = free[..drones].to_vec();
        free.shuffle(rng);
        return (starts, free[..drones].to_vec());
    }
    // The cell order is z, then y, then x: the lowest layers first.
    let starts = free[..drones].to_vec();
    let centre = dimensions.map(|d| i64::from(d) - 1);
    let from_centre = |v: &Voxel| {
        let d = [v.x, v.y, v.z].map(i64::from);
        (0..3).map(|k| (2 * d[k] - centre[k]).pow(2)).sum::<i64>()
    };
    let mut nearest = free.to_vec();
    nearest.sort_by_key(|v| (from_centre(v), v.z, v.y, v.x));
    (starts, nearest[..drones].to_vec())
}

/// Writes explicit pads in a launch area around the world: rings of growing
/// distance from its footprint, on a checkerboard (no two pads face to face, so
/// every pad keeps free cells beside it for drones to pass), nearest rings first.
fn pads_beside(groups: &mut [GroupSpec], dimensions: [u32; 3]) {
    let [dx, dy] = [i64::from(dimensions[0]), i64::from(dimensions[1])];
    let mut cells = Vec::new();
    let mut r = 1;
    let drones: usize = groups.iter().map(|g| g.drones.len()).sum();
    while cells.len() < drones {
        for y in -r..dy + r {
            for x in -r..dx + r {
                let on_ring = x == -r || y == -r || x == dx + r - 1 || y == dy + r - 1;
                if on_ring && (x + y).rem_euclid(2) == 0 {
                    cells.push([x, y]);
                }
            }
        }
        r += 1;
    }
    let all = groups.iter_mut().flat_map(|g| g.drones.iter_mut());
    for (d, cell) in all.zip(cells) {
        d.pad = Some(cell);
    }
}

/// Stage `k`: for every group as many random free voxels as it has drones, no voxel
/// twice within the stage.
fn random_stage(
    k: usize,
    groups: &[GroupSpec],
    free: &mut [Voxel],
    rng: &mut ChaCha8Rng,
) -> StageSpec {
    free.shuffle(rng);
    let mut next = free
        .iter()
        .map(|v| [i64::from(v.x), i64::from(v.y), i64::from(v.z)]);
    StageSpec {
        name: format!("stage-{k}"),
        hold_s: None,
        goals: groups
            .iter()
            .map(|g| (g.name.clone(), next.by_ref().take(g.drones.len()).collect()))
            .collect(),
    }
}

/// Colour names read better than numbers in logs and viewers.
/// Drones `i` (start `starts[i]`, goal `goals[i]`) dealt into `groups` groups of
/// near-equal size, in order, named red, green, blue, … and their drones
/// `red-1`, `red-2`, ….
pub fn split_into_groups(groups: usize, starts: &[[i64; 3]], goals: &[[i64; 3]]) -> Vec<GroupSpec> {
    let drones = starts.len();
    let mut next = 0;
    (0..groups)
        .map(|g| {
            let size = drones / groups + usize::from(g < drones % groups);
            let name = group_name(g);
            let range = next..next + size;
            next += size;
            GroupSpec {
                drones: range
                    .clone()
                    .enumerate()
                    .map(|(k, i)| DroneSpec {
                        id: format!("{name}-{}", k + 1),
                        start: Some(starts[i]),
                        pad: None,
                        endpoint: None,
                        system_id: None,
                    })
                    .collect(),
                goals: range.map(|i| goals[i]).collect(),
                name,
            }
        })
        .collect()
}

fn group_name(index: usize) -> String {
    const NAMES: [&str; 10] = [
        "red", "green", "blue", "orange", "purple", "cyan", "magenta", "yellow", "teal", "brown",
    ];
    match NAMES.get(index) {
        Some(name) => (*name).to_string(),
        None => format!("group{}", index + 1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_mission_other_seed_other_mission() {
        let a = generate(&GenerateOptions::default()).unwrap();
        let b = generate(&GenerateOptions::default()).unwrap();
        let c = generate(&GenerateOptions {
            seed: 2,
            ..Default::default()
        })
        .unwrap();
        assert_eq!(a, b);
        assert_ne!(a.world.obstacles, c.world.obstacles);
    }

    #[test]
    fn paper_setting_is_valid_for_twenty_seeds() {
        for seed in 1..=20 {
            let file = generate(&GenerateOptions {
                seed,
                ..Default::default()
            })
            .unwrap();
            let mission =
                crate::mission::validate(&file).unwrap_or_else(|p| panic!("seed {seed}: {p:?}"));
            assert_eq!(mission.drone_count(), 100);
            assert_eq!(mission.world.free_count(), 500 - 150);
        }
    }

    #[test]
    fn pads_beside_and_stages_make_valid_missions() {
        let options = GenerateOptions {
            drones: 30,
            groups: 3,
            pads: PadLayout::Beside,
            stages: 2,
            ..Default::default()
        };
        let file = generate(&options).unwrap();
        assert_eq!(file.stages.len(), 2);
        let pads: Vec<[i64; 2]> = file
            .groups
            .iter()
            .flat_map(|g| g.drones.iter().filter_map(|d| d.pad))
            .collect();
        assert_eq!(pads.len(), 30);
        let outside = |p: &[i64; 2]| !((0..10).contains(&p[0]) && (0..10).contains(&p[1]));
        assert!(pads.iter().all(outside), "{pads:?}");
        assert!(pads.iter().all(|p| (p[0] + p[1]).rem_euclid(2) == 0));
        let mission = crate::mission::validate(&file).unwrap();
        assert_eq!(mission.stages.len(), 2);
        assert!(
            mission
                .stages
                .iter()
                .all(|s| s.goals.iter().all(Option::is_some))
        );
        // Without pads or stages the generator draws exactly what it drew before.
        let plain = generate(&GenerateOptions::default()).unwrap();
        let again = generate(&GenerateOptions {
            stages: 3,
            ..Default::default()
        })
        .unwrap();
        assert_eq!(plain.groups, again.groups);
    }

    #[test]
    fn lattice_formations_are_spaced_and_valid() {
        let options = GenerateOptions {
            dimensions: [12, 12, 6],
            obstacles: 0,
            drones: 40,
            groups: 2,
            spacing: Some(2),
            stages: 1,
            ..Default::default()
        };
        let file = generate(&options).unwrap();
        let points = file
            .groups
            .iter()
            .flat_map(|g| {
                g.drones
                    .iter()
                    .filter_map(|d| d.start)
                    .chain(g.goals.iter().copied())
            })
            .chain(
                file.stages
                    .iter()
                    .flat_map(|s| s.goals.values().flatten().copied()),
            );
        for p in points {
            assert!(p.iter().all(|c| c % 2 == 0), "{p:?} is off the lattice");
        }
        // A carpet: 36 lattice points a layer, so 36 drones on layer 0 and 4 on layer 2.
        let starts: Vec<[i64; 3]> = file
            .groups
            .iter()
            .flat_map(|g| g.drones.iter().filter_map(|d| d.start))
            .collect();
        assert_eq!(starts.iter().filter(|s| s[2] == 0).count(), 36);
        // A ball: no lattice point left out is nearer the centre (5.5, 5.5, 2.5)
        // than a goal.
        let twice_from_centre =
            |p: &[i64; 3]| (2 * p[0] - 11).pow(2) + (2 * p[1] - 11).pow(2) + (2 * p[2] - 5).pow(2);
        let goals: Vec<[i64; 3]> = file
            .groups
            .iter()
            .flat_map(|g| g.goals.iter().copied())
            .collect();
        let farthest_goal = goals.iter().map(twice_from_centre).max().unwrap();
        let lattice = (0..6)
            .flat_map(|x| (0..6).flat_map(move |y| (0..3).map(move |z| [2 * x, 2 * y, 2 * z])));
        let nearest_left_out = lattice
            .filter(|p| !goals.contains(p))
            .map(|p| twice_from_centre(&p))
            .min()
            .unwrap();
        assert!(
            farthest_goal <= nearest_left_out,
            "{farthest_goal} > {nearest_left_out}"
        );
        let mission = crate::mission::validate(&file).unwrap();
        assert_eq!(mission.drone_count(), 40);
        let too_many = GenerateOptions {
            drones: 200,
            ..options
        };
        assert!(matches!(
            generate(&too_many),
            Err(GenerateError::Impossible(_))
        ));
    }

    #[test]
    fn refuses_what_cannot_fit() {
        let too_many = GenerateOptions {
            obstacles: 450,
            drones: 100,
            ..Default::default()
        };
        assert!(matches!(
            generate(&too_many),
            Err(GenerateError::Impossible(_))
        ));
    }
}
