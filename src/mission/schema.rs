//! The mission file as written by users (YAML), before validation.
//!
//! Every struct denies unknown fields so a typo (`strat:` for `start:`) is an error,
//! never a silently ignored setting. Coordinates are signed here so that a negative
//! coordinate is reported as "outside the world" rather than as a type error.

pub use super::autopilot::Autopilot;
pub use super::fence::{FenceAction, FenceSpec};
use serde::{Deserialize, Serialize};

/// A voxel coordinate as written in a file, `[x, y, z]`.
pub type RawVoxel = [i64; 3];

/// A whole mission file: what [`super::parse_yaml`] reads and [`super::to_yaml`]
/// writes; [`super::validate`] turns it into a [`super::Mission`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MissionFile {
    /// A short name; it labels logs, recordings and plan files.
    pub name: String,
    /// Free text for people reading the file; swarmctl only carries it along.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// The voxel world the drones fly in.
    pub world: WorldSpec,
    /// Kinematic and safety limits shared by every drone.
    pub limits: LimitsSpec,
    /// How the vehicles are driven over MAVLink; optional, with defaults.
    #[serde(default)]
    pub link: LinkSpec,
    /// The drones, in groups of interchangeable ones that share their goals.
    pub groups: Vec<GroupSpec>,
    /// Formations flown after the groups' `goals` (the first formation), in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stages: Vec<StageSpec>,
    /// Where the drones land once the last formation is flown; `group_pads` by default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub landing: Option<Landing>,
    /// The geofence set on every autopilot at pre-flight; on by default.
    #[serde(default, skip_serializing_if = "FenceSpec::is_default")]
    pub fence: FenceSpec,
}

/// One formation after the first: every group named takes its `goals`, the others
/// hold where they are.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StageSpec {
    /// Names the stage in messages, plan files and recordings; unique and not blank.
    pub name: String,
    /// Seconds every drone holds this formation once the whole swarm has reached it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hold_s: Option<f64>,
    /// Per group name, at least one free voxel per drone of that group; none used twice
    /// within the stage.
    pub goals: std::collections::BTreeMap<String, Vec<RawVoxel>>,
}

/// Where drones land at the end of the flight.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Landing {
    /// Each drone lands on a free pad of its own group's pads (the planner chooses).
    #[default]
    GroupPads,
    /// Each drone lands on the pad it took off from.
    OwnPad,
    /// Each drone descends straight down from its last goal (no two last goals may
    /// share a column, and every such column must be free).
    BelowGoal,
}

impl std::fmt::Display for Landing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Landing::GroupPads => "group_pads",
            Landing::OwnPad => "own_pad",
            Landing::BelowGoal => "below_goal",
        })
    }
}

/// The world as written: a box of equal cubic voxels placed in the ENU frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldSpec {
    /// Voxels along x (east), y (north), z (up); each 1 to 4096 once validated.
    pub dimensions: [i64; 3],
    /// Edge length of one voxel, metres: the distance of one plan step.
    pub voxel_size_m: f64,
    /// ENU position of the centre of voxel [0, 0, 0], metres; z is the height of
    /// layer 0 above the ground the pads stand on. The pad layer sits below layer 0.
    /// By default `[0, 0, voxel_size_m + 0.5]` (see [`WorldSpec::origin_or_default_m`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub origin_m: Option<[f64; 3]>,
    /// Height of the pad layer above the ground, metres: where drones hover over
    /// their pads after takeoff and before touchdown. By default one voxel below
    /// layer 0 when that leaves at least 0.5 m above ground, else half of layer 0's
    /// height. It must be above 0 and at least the safety distance below layer 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pad_height_m: Option<f64>,
    /// Where the mission's ENU origin is on Earth (WGS84, altitude AMSL of the
    /// ground the pads stand on). With it, swarmctl places every vehicle's own local
    /// frame from the vehicle's GPS origin and refuses a vehicle that stands on the
    /// wrong pad; without it, each vehicle is taken to stand on its pad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geo_origin: Option<Geodetic>,
    /// Voxels no drone may enter; none by default. An obstacle stands on the
    /// ground: it also blocks every voxel below it down to, and including, the pad
    /// layer, unless it is a box written with `overhead: true`.
    #[serde(default)]
    pub obstacles: Vec<ObstacleSpec>,
    /// Whether formation and stage legs may pass through the pad layer's free cells
    /// (true by default: it is airspace like any other). False keeps them in the
    /// world's own voxels, so a formation leg is exactly the instance the world
    /// describes (imported community instances set it); takeoff and landing still
    /// cross the pad layer.
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub formations_use_pad_layer: bool,
}

/// Layer 0 stands this far above the pad layer's default hover height when the
/// mission does not place the world: the pad layer one voxel below layer 0, half a
/// metre off the ground.
pub const DEFAULT_PAD_HOVER_M: f64 = 0.5;

impl WorldSpec {
    /// `origin_m` as written, or by default `[0, 0, voxel_size_m + 0.5]`: layer 0
    /// one voxel above a pad layer that hovers [`DEFAULT_PAD_HOVER_M`] off the
    /// ground, which leaves the pad layer a whole voxel of room below layer 0 for
    /// any safety distance that fits the voxel size.
    pub fn origin_or_default_m(&self) -> [f64; 3] {
        self.origin_m
            .unwrap_or([0.0, 0.0, self.voxel_size_m + DEFAULT_PAD_HOVER_M])
    }
}

fn yes() -> bool {
    true
}

fn is_true(value: &bool) -> bool {
    *value
}

fn is_false(value: &bool) -> bool {
    !*value
}

/// One blocked voxel, or an inclusive box of them.
///
/// Obstacles stand on the ground (walls, buildings, trees): each blocks its voxels
/// and every voxel below them, the pad layer included, so no drone passes under
/// it. A box written with `overhead: true` blocks only its own voxels (a bridge, a
/// gate's lintel, a canopy). An obstacle may also lie in the pad layer (`z = -1`),
/// there anywhere in the launch area beside the world (see the README's world model).
///
/// Deserialised by hand rather than `#[serde(untagged)]`, which would hide the index
/// of the bad entry and the reason it was rejected.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum ObstacleSpec {
    /// One blocked voxel, written `[x, y, z]`.
    Cell(RawVoxel),
    /// Every voxel of an inclusive box, written `{ min: [x, y, z], max: [x, y, z] }`.
    Box(BoxSpec),
}

impl<'de> Deserialize<'de> for ObstacleSpec {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ObstacleVisitor;
        impl<'de> serde::de::Visitor<'de> for ObstacleVisitor {
            type Value = ObstacleSpec;

            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a voxel [x, y, z] or a box { min: [x, y, z], max: [x, y, z] }")
            }

            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                seq: A,
            ) -> Result<Self::Value, A::Error> {
                RawVoxel::deserialize(serde::de::value::SeqAccessDeserializer::new(seq))
                    .map(ObstacleSpec::Cell)
            }

            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<Self::Value, A::Error> {
                BoxSpec::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    .map(ObstacleSpec::Box)
            }
        }
        deserializer.deserialize_any(ObstacleVisitor)
    }
}

impl ObstacleSpec {
    /// The obstacles that block exactly the voxels `blocked` and nothing below them
    /// that is free: a voxel with obstacles all the way down to layer 0 stands on
    /// the ground (and so also blocks the pad layer under it), any other is written
    /// `overhead`. How a generated or imported world is written so that the mission
    /// means the world it came from.
    ///
    /// ```
    /// use swarmctl::mission::schema::ObstacleSpec;
    /// // A post on the ground, and a voxel floating two layers up.
    /// let specs = ObstacleSpec::exactly(&[[0, 0, 0], [1, 0, 2]]);
    /// assert_eq!(specs[0], ObstacleSpec::Cell([0, 0, 0]));
    /// assert!(matches!(&specs[1], ObstacleSpec::Box(b) if b.overhead));
    /// ```
    pub fn exactly(blocked: &[RawVoxel]) -> Vec<ObstacleSpec> {
        let set: std::collections::HashSet<RawVoxel> = blocked.iter().copied().collect();
        blocked
            .iter()
            .map(|&[x, y, z]| {
                if (0..z).all(|below| set.contains(&[x, y, below])) {
                    ObstacleSpec::Cell([x, y, z])
                } else {
                    ObstacleSpec::Box(BoxSpec {
                        min: [x, y, z],
                        max: [x, y, z],
                        overhead: true,
                    })
                }
            })
            .collect()
    }
}

/// A point on Earth: WGS84 latitude and longitude, altitude above mean sea level.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Geodetic {
    /// Latitude, degrees north (−90 to 90).
    pub lat_deg: f64,
    /// Longitude, degrees east (−180 to 180).
    pub lon_deg: f64,
    /// Altitude above mean sea level, metres.
    pub alt_m: f64,
}

/// An inclusive box of voxels: walls and floors in one line instead of hundreds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    /// The corner with the smallest coordinates, itself blocked.
    pub min: RawVoxel,
    /// The corner with the largest coordinates, itself blocked; nowhere below `min`.
    pub max: RawVoxel,
    /// True for an obstacle that leaves the space below it free (a bridge, a lintel,
    /// a canopy); by default an obstacle stands on the ground.
    #[serde(default, skip_serializing_if = "is_false")]
    pub overhead: bool,
}

/// Kinematic and safety limits as written; every one must be positive.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LimitsSpec {
    /// Top speed of every drone, m/s; the schedule and trajectories keep to it.
    pub max_speed_mps: f64,
    /// Top acceleration of every drone, m/s²; the trajectories keep to it.
    pub max_accel_mps2: f64,
    /// How fast the acceleration may change, m/s³; the trajectories keep to it.
    /// By default 2.5 m/s³ (see [`super::types::DEFAULT_MAX_JERK_MPS3`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_jerk_mps3: Option<f64>,
    /// Drones never come closer than this, metres (centre to centre): a sphere.
    /// Give this or `separation`, not both.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub safety_distance_m: Option<f64>,
    /// An ellipsoid instead of a sphere: drones keep `horizontal_m` beside one
    /// another and `vertical_m` above and below (downwash). Give this or
    /// `safety_distance_m`, not both.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub separation: Option<SeparationSpec>,
    /// How far every vehicle is trusted to stay from its setpoint, metres: the
    /// schedule keeps setpoints `safety_distance_m + 2 × tracking_error_m` apart and
    /// the executor holds back a drone that strays further. By default all the room
    /// the geometry leaves, at most 0.30 m (see [`super::types::Limits`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tracking_error_m: Option<f64>,
}

/// An ellipsoidal separation as written (`limits.separation`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeparationSpec {
    /// Radius beside a drone, metres; positive and at most the voxel size (with
    /// the tracking error).
    pub horizontal_m: f64,
    /// Radius above and below a drone, metres; positive, at most
    /// [`super::MAX_VERTICAL_LAYERS`] voxel sizes.
    pub vertical_m: f64,
}

impl LimitsSpec {
    /// The horizontal separation as written: the sphere's radius or the
    /// ellipsoid's horizontal one (0 when neither is given, which validation reports).
    pub fn horizontal_separation_m(&self) -> f64 {
        match (self.safety_distance_m, self.separation) {
            (Some(d), _) => d,
            (None, Some(e)) => e.horizontal_m,
            (None, None) => 0.0,
        }
    }
}

/// How the vehicles are driven over MAVLink; every field has a default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinkSpec {
    /// The firmware every vehicle runs; PX4 by default.
    #[serde(default)]
    pub autopilot: Autopilot,
    /// Setpoints streamed to each vehicle per second, Hz (default 20; at most 100,
    /// at least the autopilot's [`Autopilot::min_setpoint_rate_hz`]: PX4 5,
    /// ArduPilot 10): autopilots leave offboard control when setpoints stop coming.
    #[serde(default = "default_setpoint_rate_hz")]
    pub setpoint_rate_hz: f64,
    /// A vehicle silent for this long has lost its link, seconds (default 3): it
    /// is reported, and the drones that depend on it hold at their gates.
    #[serde(default = "default_link_timeout_s")]
    pub link_timeout_s: f64,
    /// A vehicle silent for this long is given up for the flight, seconds (default
    /// 10, at least `link_timeout_s`): reported LOST, left to its failsafe, and the
    /// rest of the swarm replanned around where it was last seen.
    #[serde(default = "default_lost_after_s")]
    pub lost_after_s: f64,
    /// How far above a commanded speed the vehicles go, as a fraction (0 to 1):
    /// trajectories are flown at the speed limit divided by `1 + headroom`, so the
    /// measured speed keeps the limit. Default: the autopilot's
    /// ([`Autopilot::speed_overshoot`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed_headroom: Option<f64>,
    /// MAVLink 2 signing: where the swarm's secret key is kept (never the key).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub signing: Option<SigningSpec>,
    /// Relays that carry the vehicles' links over Zenoh (`swarmctl relay`), each
    /// with the drones it serves; none: the controller reaches every vehicle itself.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub relays: Vec<RelaySpec>,
    /// Where the controller meets the relays over Zenoh (default: it listens on
    /// `tcp/127.0.0.1:7447`, where relays connect by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub zenoh: Option<ZenohSpec>,
    /// The telemetry radios that carry the vehicles' links, each with the drones
    /// it serves and what it can carry; the link budget (`swarmctl check`) must
    /// fit each. None: every drone has a link of its own with room to spare
    /// (Wi-Fi, loopback), and the budget is only reported.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub radios: Vec<RadioSpec>,
}

/// One shared telemetry radio (e.g. a SiK radio at its air rate): every drone
/// it serves sends and receives over it, both directions sharing its capacity.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RadioSpec {
    /// Unique among the radios; names it in the budget and its refusals.
    pub name: String,
    /// The drone ids it carries; a drone is on at most one radio.
    pub drones: Vec<String>,
    /// What it carries both ways together, kbit/s (a SiK radio: its air rate,
    /// 64 by default); the budget keeps 10 % of it for the radio's own framing
    /// and for bursts (commands, parameter reads).
    pub capacity_kbps: f64,
}

/// One relay: a process owning the MAVLink links of some drones, reached over Zenoh.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RelaySpec {
    /// Unique among the relays; `swarmctl relay MISSION --name NAME` serves its drones.
    pub name: String,
    /// The drone ids it serves; every drone is served by exactly one relay.
    pub drones: Vec<String>,
}

/// Zenoh endpoints (`tcp/HOST:PORT`).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ZenohSpec {
    /// Where the controller accepts Zenoh sessions.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub listen: Vec<String>,
    /// Routers (`zenohd`) or relays the controller connects to.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub connect: Vec<String>,
}

/// Where a mission's MAVLink 2 signing key comes from: exactly one of the two.
/// The key itself never appears in a mission file, a log or a message.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SigningSpec {
    /// A file holding the 32-byte key as 64 hex digits; relative paths are
    /// relative to the mission file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub key_file: Option<std::path::PathBuf>,
    /// An environment variable holding the key as 64 hex digits.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub key_env: Option<String>,
}

impl Default for LinkSpec {
    fn default() -> Self {
        Self {
            autopilot: Autopilot::default(),
            setpoint_rate_hz: default_setpoint_rate_hz(),
            link_timeout_s: default_link_timeout_s(),
            lost_after_s: default_lost_after_s(),
            speed_headroom: None,
            signing: None,
            relays: Vec::new(),
            zenoh: None,
            radios: Vec::new(),
        }
    }
}

fn default_setpoint_rate_hz() -> f64 {
    20.0
}

fn default_link_timeout_s() -> f64 {
    3.0
}

fn default_lost_after_s() -> f64 {
    10.0
}

/// Interchangeable drones and the goals they share: the planner decides which drone
/// takes which goal.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroupSpec {
    /// Unique within the mission; names the group in messages and recordings.
    pub name: String,
    /// At least one drone.
    pub drones: Vec<DroneSpec>,
    /// At least one free voxel per drone (extra ones are spare slots); any drone of
    /// the group may take any of them. The group's first formation.
    pub goals: Vec<RawVoxel>,
}

/// One drone as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DroneSpec {
    /// Unique within the mission; letters, digits, '-', '_' and '.', so it can be
    /// written in command-line flags and file names unquoted.
    pub id: String,
    /// The free voxel the drone takes off to before the first formation; no two drones
    /// share one. Without it the drone flies from its pad straight to the formation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<RawVoxel>,
    /// The ground cell `[x, y]` the drone stands on, in the world's voxel x/y
    /// coordinates (outside `0..dimensions` for a launch area beside the world).
    /// By default the cell below its start, or the nearest cell no other pad takes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pad: Option<[i64; 2]>,
    /// MAVLink address, e.g. `udpout:127.0.0.1:14541`; none means the bundled simulator.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub endpoint: Option<String>,
    /// MAVLink system id of the vehicle, 1 to 254 and unique; by default the drone's
    /// 1-based position among all the mission's drones. Messages from any other
    /// system id are ignored.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub system_id: Option<i64>,
}
