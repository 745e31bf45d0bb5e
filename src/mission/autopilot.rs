//! The autopilot families a mission may name (`link.autopilot`): the one
//! autopilot type of the library. What each does its own way in flight is its
//! flavour in `fly::autopilot`.

use serde::{Deserialize, Serialize};

/// Which autopilot firmware the vehicles run; decides offboard (PX4) or guided (ArduPilot).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Autopilot {
    /// PX4: position setpoints in offboard mode (the default).
    #[default]
    Px4,
    /// ArduPilot: position targets in guided mode.
    Ardupilot,
}

impl Autopilot {
    /// Every autopilot swarmctl flies (each has its flavour in `fly::autopilot`).
    pub const ALL: [Autopilot; 2] = [Autopilot::Px4, Autopilot::Ardupilot];

    /// The name mission files (`link.autopilot`) and `--autopilot` use.
    pub const fn name(self) -> &'static str {
        match self {
            Autopilot::Px4 => "px4",
            Autopilot::Ardupilot => "ardupilot",
        }
    }

    /// How far above a commanded speed this autopilot's position controller goes
    /// while following swarmctl's setpoints, as a fraction: the headroom the
    /// trajectories leave below the mission's speed limit. ArduCopter trails its
    /// setpoint by some 8 cm at speed and overshoots the commanded speed catching up
    /// at the end of every acceleration, by 4–6 % on one vehicle and up to 9 % in an
    /// 8-vehicle swarm (SITL, 1 m/s, 2 m/s², 2.5 m/s³, acceleration led by
    /// `ATC_INPUT_TC`, 2026-12-02); once flights kept their schedule (drones picking
    /// up mid-brake, issue 32) one 8-vehicle formation change in three reached
    /// 12 % (truth 1.057 m/s at 0.943 m/s commanded, 2026-12-05), so 10 %. PX4 (and
    /// the bundled simulator's PX4 flavour) apply the feed-forward directly: none.
    pub fn speed_overshoot(self) -> f64 {
        match self {
            Autopilot::Px4 => 0.0,
            Autopilot::Ardupilot => 0.10,
        }
    }
}

impl Autopilot {
    /// The lowest setpoint rate (and position-telemetry rate) a mission may fly
    /// this autopilot at, Hz: the lowest at which the formation change kept every
    /// guarantee on the real firmware (README, "Setpoint rates"). ArduCopter SITL,
    /// 1 m voxels, 2026-12-06: at 20 and 10 Hz every guarantee held (truth
    /// separation 0.947 / 0.908 m, top speed 0.98 m/s); at 5 Hz it went 1.06 m/s
    /// by telemetry against the 1 m/s limit (5 % tolerance). PX4 SIH, 3 m voxels:
    /// at 20, 10 and 5 Hz every guarantee held (5 Hz: truth separation 2.651 m,
    /// top speed 0.94 m/s, on time); below 2 Hz PX4 leaves OFFBOARD.
    pub fn min_setpoint_rate_hz(self) -> f64 {
        match self {
            Autopilot::Px4 => 5.0,
            Autopilot::Ardupilot => 10.0,
        }
    }
}

impl std::str::FromStr for Autopilot {
    type Err = String;

    /// The name mission files use (`px4`, `ardupilot`), as [`Autopilot::name`]
    /// gives it.
    fn from_str(name: &str) -> Result<Self, String> {
        Autopilot::ALL
            .into_iter()
            .find(|a| a.name() == name)
            .ok_or_else(|| {
                let known = Autopilot::ALL.map(Autopilot::name).join(", ");
                format!("unknown autopilot {name:?} (known: {known})")
            })
    }
}

impl std::fmt::Display for Autopilot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
