//! A validated mission: every field checked, coordinates inside the world.

pub use super::schema::Geodetic;
use super::schema::{Autopilot, FenceSpec, Landing, RadioSpec, RelaySpec, ZenohSpec};
use crate::world::{Separation, VerticalReach, Voxel, VoxelGrid};
use serde::{Deserialize, Serialize};

/// A mission that passed validation; the planner may trust every field.
#[derive(Debug, Clone, PartialEq)]
pub struct Mission {
    /// The mission's name, never blank; it labels logs, recordings and plan files.
    pub name: String,
    /// Free text from the file, carried along for people.
    pub description: Option<String>,
    /// The voxel world with its obstacles blocked (`0..dimensions`): each obstacle
    /// down to layer 0 unless it is overhead (see [`super::schema::ObstacleSpec`]).
    pub world: VoxelGrid,
    /// Where the drones fly, pad to pad: the world, the pad layer below it (`z = -1`,
    /// its centres at the pads' hover height) reaching sideways over every pad, in the
    /// world's own coordinates, blocked under every obstacle that stands on the
    /// ground. The planner and everything after it work in this grid.
    pub airspace: VoxelGrid,
    /// Whether formation and stage legs may pass through the pad layer
    /// (`world.formations_use_pad_layer`); takeoff and landing always cross it.
    pub formations_use_pad_layer: bool,
    /// Kinematic and safety limits every trajectory keeps.
    pub limits: Limits,
    /// Where the mission's ENU origin is on Earth, if the mission says.
    pub geo_origin: Option<Geodetic>,
    /// How the vehicles are driven over MAVLink.
    pub link: LinkSettings,
    /// At least one group; every drone has its own pad and can reach a goal of its
    /// group.
    pub groups: Vec<Group>,
    /// Formations flown after the groups' goals, in order.
    pub stages: Vec<Stage>,
    /// Where the drones land at the end.
    pub landing: Landing,
    /// The geofence every autopilot is given at pre-flight (see `fly::fence`).
    pub fence: FenceSpec,
}

/// One formation after the groups' first one.
#[derive(Debug, Clone, PartialEq)]
pub struct Stage {
    /// Unique among the stages, never blank.
    pub name: String,
    /// Seconds the swarm holds the formation once every drone has reached it.
    pub hold_s: f64,
    /// Per group, in mission order: its goals in this stage (at least one per drone),
    /// or `None` when the stage does not name the group (it holds where it is).
    pub goals: Vec<Option<Vec<Voxel>>>,
}

/// How a drone's pad was chosen, for the pad table operators place drones by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PadSource {
    /// Written in the mission file.
    Given,
    /// The cell below the drone's start (the default when no other pad takes it).
    BelowStart,
    /// Chosen by swarmctl: the nearest cell no other pad takes.
    Assigned,
}

impl std::fmt::Display for PadSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            PadSource::Given => "given",
            PadSource::BelowStart => "below start",
            PadSource::Assigned => "assigned",
        })
    }
}

impl Mission {
    /// The limits trajectories are scheduled and flown with: the mission's, with the
    /// speed lowered by the headroom the vehicles overshoot by
    /// (`link.speed_headroom`, by default [`super::Autopilot::speed_overshoot`]), so
    /// the *measured* speed keeps the mission's limit. Checks measure against
    /// `limits` itself.
    pub fn commanded_limits(&self) -> Limits {
        Limits {
            max_speed_mps: self.limits.max_speed_mps / (1.0 + self.link.speed_headroom),
            ..self.limits
        }
    }

    /// All drones, group by group, in file order.
    pub fn drones(&self) -> impl Iterator<Item = (&Group, &Drone)> {
        self.groups
            .iter()
            .flat_map(|g| g.drones.iter().map(move |d| (g, d)))
    }

    /// How many drones fly, over all groups.
    pub fn drone_count(&self) -> usize {
        self.groups.iter().map(|g| g.drones.len()).sum()
    }

    /// The pad layer's hover height above the ground, metres.
    pub fn pad_height_m(&self) -> f64 {
        self.airspace
            .pad_layer_z_m()
            .unwrap_or(self.world.origin_m()[2] - self.world.voxel_size_m())
    }

    /// Where a drone stands on its pad, ENU metres (on the ground, z = 0).
    pub fn pad_ground_m(&self, drone: &Drone) -> [f64; 3] {
        let c = self.airspace.center_m(drone.pad_voxel());
        [c.x, c.y, 0.0]
    }
}

/// Kinematic and safety limits every trajectory keeps.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Limits {
    /// Top speed of every drone, m/s; positive.
    pub max_speed_mps: f64,
    /// Top acceleration of every drone, m/s²; positive.
    pub max_accel_mps2: f64,
    /// How fast any drone's acceleration may change, m/s³; positive. Every
    /// commanded motion is an S-curve within it (see [`crate::profile`]); when the
    /// mission does not say, [`DEFAULT_MAX_JERK_MPS3`].
    pub max_jerk_mps3: f64,
    /// Drones never come closer than this, metres (centre to centre); positive.
    /// With [`Limits::vertical_separation_m`] it is the ellipsoid's horizontal
    /// radius: drones side by side keep it.
    pub safety_distance_m: f64,
    /// The ellipsoid's vertical radius, metres, when the mission separates drones by
    /// an ellipsoid (`limits.separation`); `None` for a sphere of
    /// `safety_distance_m`. See [`crate::world::Separation`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertical_separation_m: Option<f64>,
    /// How far every vehicle is trusted to stay from its setpoint, metres; zero or
    /// more. The schedule keeps setpoints [`Limits::setpoint_separation_m`] apart, so
    /// vehicles within this of their setpoints keep `safety_distance_m`; the executor
    /// holds a drone's setpoint while the drone is further than this from it.
    ///
    /// Validation demands `safety_distance_m + 2 × tracking_error_m` fit between
    /// neighbouring cell centres (the voxel size, and the gap from the pad layer to
    /// layer 0) with a centimetre to spare on each side. When the mission does not
    /// say, it is [`DEFAULT_TRACKING_ERROR_M`] or the room the geometry leaves,
    /// whichever is less — for PX4 and ArduPilot
    /// alike: both hold about that at 1 m/s with velocity feed-forward.
    pub tracking_error_m: f64,
}

/// The jerk limit of a mission that does not say, m/s³. Half ArduCopter's own
/// default for the jerk its position controller shapes targets with
/// (`PSC_JERK_XY`, 5 m/s³; PX4's `MPC_JERK_AUTO` is 4): measured on real
/// ArduCopter SITL at 1 m/s and 2 m/s² with the acceleration lead, 2.5 m/s³ keeps
/// the top speed within 4 % of the limit and the p95 tracking error at 0.07 m, where
/// 5 m/s³ reaches 5 % and 0.11 m. It costs about 0.4 s per rest-to-rest run.
pub const DEFAULT_MAX_JERK_MPS3: f64 = 2.5;

/// The tracking error a mission trusts its vehicles to keep when it does not say,
/// metres (less when the geometry leaves less room).
pub const DEFAULT_TRACKING_ERROR_M: f64 = 0.30;

impl Limits {
    /// The speed, acceleration and jerk limits every commanded motion keeps.
    pub fn kinematics(&self) -> crate::profile::Kinematics {
        crate::profile::Kinematics {
            max_speed_mps: self.max_speed_mps,
            max_accel_mps2: self.max_accel_mps2,
            max_jerk_mps3: self.max_jerk_mps3,
        }
    }

    /// How far apart the schedule keeps setpoints: the safety distance plus the
    /// tracking error of both drones (for an ellipsoid, its horizontal radius plus
    /// both drones' tracking error).
    pub fn setpoint_separation_m(&self) -> f64 {
        self.safety_distance_m + 2.0 * self.tracking_error_m
    }

    /// The separation vehicles keep: a sphere of the safety distance, or the
    /// mission's ellipsoid.
    pub fn separation(&self) -> Separation {
        Separation {
            horizontal_m: self.safety_distance_m,
            vertical_m: self.vertical_separation_m.unwrap_or(self.safety_distance_m),
        }
    }

    /// The separation the schedule keeps between *setpoints*: each radius grown by
    /// both drones' tracking error. Vehicles within the tracking error of their
    /// setpoints are then at least [`Limits::separation`] apart: setpoints outside
    /// the grown ellipsoid's bounding cylinder (`ρ ≥ H + 2e` or `|dz| ≥ V + 2e`)
    /// leave the vehicles `ρ ≥ H` or `|dz| ≥ V` apart, and either puts them outside
    /// the ellipsoid.
    pub fn setpoint_separation(&self) -> Separation {
        let grow_m = 2.0 * self.tracking_error_m;
        let s = self.separation();
        Separation {
            horizontal_m: s.horizontal_m + grow_m,
            vertical_m: s.vertical_m + grow_m,
        }
    }

    /// Whether drones are separated by an ellipsoid rather than a sphere.
    pub fn is_ellipsoid(&self) -> bool {
        self.vertical_separation_m.is_some()
    }

    /// The vertical reach the planner and the schedule keep in `airspace`:
    /// [`VerticalReach::NONE`] for a sphere.
    pub fn vertical_reach(&self, airspace: &VoxelGrid) -> VerticalReach {
        if self.is_ellipsoid() {
            VerticalReach::new(airspace, self.setpoint_separation())
        } else {
            VerticalReach::NONE
        }
    }
}

/// How the vehicles are driven over MAVLink.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinkSettings {
    /// The firmware every vehicle runs; decides offboard (PX4) or guided (ArduPilot).
    pub autopilot: Autopilot,
    /// Setpoints streamed to each vehicle per second, Hz (2.5 to 100): autopilots
    /// leave offboard control when setpoints stop coming.
    pub setpoint_rate_hz: f64,
    /// A vehicle silent for this long has lost its link (its dependants hold),
    /// seconds; positive.
    pub link_timeout_s: f64,
    /// A vehicle silent for this long is given up for the flight (LOST, the rest
    /// replanned around it), seconds; at least `link_timeout_s`.
    pub lost_after_s: f64,
    /// How far above a commanded speed the vehicles go, as a fraction (0 to 1):
    /// the mission's or the autopilot's ([`Autopilot::speed_overshoot`]).
    pub speed_headroom: f64,
    /// Where the MAVLink 2 signing key is; `None` flies unsigned.
    pub signing: Option<KeySource>,
    /// Relays carrying the vehicles' links over Zenoh, each drone in exactly one;
    /// empty when the controller reaches every vehicle itself.
    pub relays: Vec<RelaySpec>,
    /// Where the controller meets the relays; `None`: the default.
    pub zenoh: Option<ZenohSpec>,
    /// Shared telemetry radios, each drone on at most one; a drone on none has
    /// a link of its own (Wi-Fi, loopback) that the budget does not limit.
    pub radios: Vec<RadioSpec>,
}

/// Where a signing key is read from when a flight starts (see `link::signing`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub enum KeySource {
    /// A file with 64 hex digits (a path relative to the mission file once loaded).
    File(std::path::PathBuf),
    /// An environment variable with 64 hex digits.
    Env(String),
}

/// Interchangeable drones sharing one set of goals.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// Unique within the mission.
    pub name: String,
    /// At least one drone.
    pub drones: Vec<Drone>,
    /// At least one; any drone of the group may take any of them. Drones beyond
    /// the goals are spares (see [`Group::formation_targets`]).
    pub goals: Vec<Voxel>,
    /// Pad-layer cells of pads whose drones left the group in flight (a replan's
    /// lost or retired drones): with `group_pads` landing any drone of the group
    /// may land there too. Empty in a mission as written.
    pub free_pads: Vec<Voxel>,
}

impl Group {
    /// The voxels the group's spares hold while it flies a formation of `goals`
    /// goals: one per drone beyond the goals — the starts of the group's last
    /// drones in file order, or the pad-layer cells above their pads for a group
    /// without starts. Which drones end there is the planner's choice, like every
    /// assignment within a group; on a loss a replan sends a spare to the lost
    /// drone's goal.
    pub fn spare_holds(&self, goals: usize) -> Vec<Voxel> {
        let spares = self.drones.len().saturating_sub(goals);
        self.drones[self.drones.len() - spares..]
            .iter()
            .map(|d| d.start.unwrap_or_else(|| d.pad_voxel()))
            .collect()
    }

    /// Where the group's drones may end a formation of `goals`: the goals, and a
    /// holding voxel per spare ([`Group::spare_holds`]). As many as drones (or
    /// more), so every goal is taken whenever the group has a drone for it.
    pub fn formation_targets(&self, goals: &[Voxel]) -> Vec<Voxel> {
        let mut targets = goals.to_vec();
        targets.extend(self.spare_holds(goals.len()));
        targets
    }

    /// Every drone has a start (validation allows all or none within a group).
    pub fn has_starts(&self) -> bool {
        self.drones.iter().all(|d| d.start.is_some())
    }
}

impl Drone {
    /// The pad-layer cell above the drone's pad: where it hovers after takeoff.
    pub fn pad_voxel(&self) -> Voxel {
        Voxel::new(self.pad[0], self.pad[1], -1)
    }
}

/// One drone of a validated mission.
#[derive(Debug, Clone, PartialEq)]
pub struct Drone {
    /// Unique within the mission; letters, digits, '-', '_' and '.' only, so it can
    /// be written in command-line flags and file names unquoted.
    pub id: String,
    /// A free voxel no other drone starts in, flown to before the first formation;
    /// `None` flies from the pad straight to the formation.
    pub start: Option<Voxel>,
    /// The ground cell `[x, y]` the drone stands on; no two drones share one.
    pub pad: [i32; 2],
    /// How the pad was chosen.
    pub pad_source: PadSource,
    /// MAVLink address, e.g. `udpout:127.0.0.1:14541`; `None` means the bundled
    /// simulator.
    pub endpoint: Option<String>,
    /// MAVLink system id, 1 to 254 and unique; `None` means the drone's 1-based
    /// position among all the mission's drones.
    pub system_id: Option<u8>,
}
