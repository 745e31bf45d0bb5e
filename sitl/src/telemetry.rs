//! Telemetry: which messages stream at which rate (changed by
//! MAV_CMD_SET_MESSAGE_INTERVAL) and how each message is built from the state.

use crate::config::Flavour;
use crate::dynamics::GRAVITY_MPS2;
use crate::mode::FlightMode;
use crate::vehicle::Vehicle;
use mavlink::dialects::common::*;
use rand::Rng;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Message ids the vehicle can produce.
pub mod id {
    /// HEARTBEAT.
    pub const HEARTBEAT: u32 = 0;
    /// SYS_STATUS.
    pub const SYS_STATUS: u32 = 1;
    /// SYSTEM_TIME.
    pub const SYSTEM_TIME: u32 = 2;
    /// ATTITUDE.
    pub const ATTITUDE: u32 = 30;
    /// LOCAL_POSITION_NED.
    pub const LOCAL_POSITION_NED: u32 = 32;
    /// GLOBAL_POSITION_INT.
    pub const GLOBAL_POSITION_INT: u32 = 33;
    /// BATTERY_STATUS.
    pub const BATTERY_STATUS: u32 = 147;
    /// AUTOPILOT_VERSION (on request only).
    pub const AUTOPILOT_VERSION: u32 = 148;
    /// HOME_POSITION.
    pub const HOME_POSITION: u32 = 242;
    /// EXTENDED_SYS_STATE.
    pub const EXTENDED_SYS_STATE: u32 = 245;
}

/// Noise amplitude on reported positions, metres (uniform ±).
const POSITION_NOISE_M: f32 = 0.005;
/// Noise amplitude on reported velocities, m/s (uniform ±).
const VELOCITY_NOISE_MPS: f32 = 0.005;

/// One periodic message.
#[derive(Debug, Clone, PartialEq)]
struct Stream {
    message_id: u32,
    default_period_s: f64,
    /// Current period; `None` when disabled by an interval of -1.
    period_s: Option<f64>,
    next_due_s: f64,
}

/// The periodic-message schedule of one vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct Streams {
    entries: Vec<Stream>,
}

impl Streams {
    /// Default schedule: heartbeat, status and home at 1 Hz or slower,
    /// landed state at 5 Hz, position and attitude at `telemetry_rate_hz`.
    /// Each stream starts at a seed-dependent phase so a swarm does not send
    /// in bursts on the same tick.
    pub fn new(seed: u64, telemetry_rate_hz: f64) -> Self {
        let fast_s = 1.0 / telemetry_rate_hz;
        let defaults = [
            (id::HEARTBEAT, 1.0),
            (id::SYS_STATUS, 1.0),
            (id::SYSTEM_TIME, 1.0),
            (id::ATTITUDE, fast_s),
            (id::LOCAL_POSITION_NED, fast_s),
            (id::GLOBAL_POSITION_INT, fast_s),
            (id::BATTERY_STATUS, 1.0),
            (id::HOME_POSITION, 2.0),
            (id::EXTENDED_SYS_STATE, 0.2),
        ];
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed_57a7);
        let entries = defaults
            .into_iter()
            .map(|(message_id, period_s)| Stream {
                message_id,
                default_period_s: period_s,
                period_s: Some(period_s),
                // The first heartbeat goes out at once so peers discover us quickly.
                next_due_s: if message_id == id::HEARTBEAT {
                    0.0
                } else {
                    rng.random::<f64>() * period_s
                },
            })
            .collect();
        Self { entries }
    }

    /// Applies MAV_CMD_SET_MESSAGE_INTERVAL: `interval_us` -1 disables, 0
    /// restores the default, > 0 sets the period. False if `message_id` is not streamable.
    pub fn set_interval(&mut self, message_id: u32, interval_us: f32) -> bool {
        let Some(stream) = self.entries.iter_mut().find(|s| s.message_id == message_id) else {
            return false;
        };
        stream.period_s = if interval_us == -1.0 {
            None
        } else if interval_us == 0.0 || !interval_us.is_finite() {
            Some(stream.default_period_s)
        } else if interval_us > 0.0 {
            // Faster than 1 kHz makes no sense for a 100 Hz simulation.
            Some((f64::from(interval_us) / 1e6).max(1e-3))
        } else {
            return false;
        };
        true
    }

    /// Current period of a stream in seconds (`None` if disabled or unknown).
    pub fn period_s(&self, message_id: u32) -> Option<f64> {
        self.entries
            .iter()
            .find(|s| s.message_id == message_id)
            .and_then(|s| s.period_s)
    }

    /// Ids of the streams due at `now_s`, advancing their schedule.
    fn take_due(&mut self, now_s: f64, due: &mut Vec<u32>) {
        for s in &mut self.entries {
            let Some(period_s) = s.period_s else { continue };
            if now_s + 1e-9 >= s.next_due_s {
                due.push(s.message_id);
                s.next_due_s += period_s;
                if s.next_due_s < now_s {
                    s.next_due_s = now_s + period_s; // fell behind: do not burst
                }
            }
        }
    }
}

impl Vehicle {
    /// Queues every periodic message that is due now.
    pub fn queue_due_telemetry(&mut self) {
        let mut due = Vec::new();
        self.streams.take_due(self.time_s, &mut due);
        for message_id in due {
            if let Some(message) = self.build_message(message_id) {
                self.outbox.push(message);
            }
        }
    }

    fn time_boot_ms(&self) -> u32 {
        (self.time_s * 1000.0) as u32
    }

    /// Builds a message by id; `None` for ids this vehicle cannot produce.
    pub fn build_message(&mut self, message_id: u32) -> Option<MavMessage> {
        Some(match message_id {
            id::HEARTBEAT => self.heartbeat(),
            id::SYS_STATUS => self.sys_status(),
            id::SYSTEM_TIME => MavMessage::SYSTEM_TIME(SYSTEM_TIME_DATA {
                time_unix_usec: std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0, |d| d.as_micros() as u64),
                time_boot_ms: self.time_boot_ms(),
            }),
            id::ATTITUDE => self.attitude(),
            id::LOCAL_POSITION_NED => {
                let (p, v) = self.noisy_state();
                MavMessage::LOCAL_POSITION_NED(LOCAL_POSITION_NED_DATA {
                    time_boot_ms: self.time_boot_ms(),
                    x: p[0],
                    y: p[1],
                    z: p[2],
                    vx: v[0],
                    vy: v[1],
                    vz: v[2],
                })
            }
            id::GLOBAL_POSITION_INT => self.global_position(),
            id::BATTERY_STATUS => self.battery_status(),
            id::AUTOPILOT_VERSION => self.autopilot_version(),
            id::HOME_POSITION => self.home_position(),
            id::EXTENDED_SYS_STATE => MavMessage::EXTENDED_SYS_STATE(EXTENDED_SYS_STATE_DATA {
                vtol_state: MavVtolState::MAV_VTOL_STATE_UNDEFINED,
                landed_state: self.landed_state(),
            }),
            _ => return None,
        })
    }

    /// Position and velocity with deterministic sensor noise.
    fn noisy_state(&mut self) -> ([f32; 3], [f32; 3]) {
        let p = self.body.position_ned_m;
        let v = self.body.velocity_ned_mps;
        let noise = &mut self.noise;
        let p = p.map(|c| c + noise.random_range(-POSITION_NOISE_M..=POSITION_NOISE_M));
        let v = v.map(|c| c + noise.random_range(-VELOCITY_NOISE_MPS..=VELOCITY_NOISE_MPS));
        (p, v)
    }

    /// MAV_LANDED_STATE as EXTENDED_SYS_STATE reports it.
    pub fn landed_state(&self) -> MavLandedState {
        if self.landed() && (!self.armed || self.takeoff_height_m.is_none()) {
            MavLandedState::MAV_LANDED_STATE_ON_GROUND
        } else if self.takeoff_height_m.is_some() {
            MavLandedState::MAV_LANDED_STATE_TAKEOFF
        } else if matches!(self.mode, FlightMode::Land)
            || (self.mode == FlightMode::ReturnToLaunch && self.airborne())
        {
            MavLandedState::MAV_LANDED_STATE_LANDING
        } else {
            MavLandedState::MAV_LANDED_STATE_IN_AIR
        }
    }

    fn heartbeat(&self) -> MavMessage {
        let mut base_mode = MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
            | MavModeFlag::MAV_MODE_FLAG_STABILIZE_ENABLED;
        if self.armed {
            base_mode |= MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED;
        }
        if !matches!(self.mode, FlightMode::Manual) {
            base_mode |=
                MavModeFlag::MAV_MODE_FLAG_GUIDED_ENABLED | MavModeFlag::MAV_MODE_FLAG_AUTO_ENABLED;
        }
        let system_status = if self.battery_critical && self.armed {
            MavState::MAV_STATE_CRITICAL
        } else if self.armed {
            MavState::MAV_STATE_ACTIVE
        } else {
            MavState::MAV_STATE_STANDBY
        };
        MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            custom_mode: self.custom_mode(),
            mavtype: MavType::MAV_TYPE_QUADROTOR,
            autopilot: match self.flavour {
                Flavour::Px4 => MavAutopilot::MAV_AUTOPILOT_PX4,
                Flavour::ArduPilot => MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA,
            },
            base_mode,
            system_status,
            mavlink_version: 3,
        })
    }

    fn battery_voltage_mv(&self) -> u16 {
        // A 4S LiPo: 14.0 V empty, 16.8 V full.
        (14_000.0 + 2_800.0 * self.battery_pct / 100.0) as u16
    }

    fn battery_current_ca(&self) -> i16 {
        if self.armed { 1_500 } else { 50 }
    }

    fn sys_status(&self) -> MavMessage {
        let sensors = MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_GYRO
            | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_ACCEL
            | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_MAG
            | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_ABSOLUTE_PRESSURE
            | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_GPS
            | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_ANGULAR_RATE_CONTROL
            | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_ATTITUDE_STABILIZATION
            | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_YAW_POSITION
            | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_Z_ALTITUDE_CONTROL
            | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_XY_POSITION_CONTROL
            | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_MOTOR_OUTPUTS
            | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_BATTERY
            | MavSysStatusSensor::MAV_SYS_STATUS_PREARM_CHECK;
        let mut health = sensors;
        if self.config.faults.refuse_arm {
            health.remove(MavSysStatusSensor::MAV_SYS_STATUS_PREARM_CHECK);
        }
        if self.battery_critical {
            health.remove(MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_BATTERY);
        }
        MavMessage::SYS_STATUS(SYS_STATUS_DATA {
            onboard_control_sensors_present: sensors,
            onboard_control_sensors_enabled: sensors,
            onboard_control_sensors_health: health,
            load: 200,
            voltage_battery: self.battery_voltage_mv(),
            current_battery: self.battery_current_ca(),
            drop_rate_comm: 0,
            errors_comm: 0,
            errors_count1: 0,
            errors_count2: 0,
            errors_count3: 0,
            errors_count4: 0,
            battery_remaining: self.battery_pct.round() as i8,
            onboard_control_sensors_present_extended: MavSysStatusSensorExtended::empty(),
            onboard_control_sensors_enabled_extended: MavSysStatusSensorExtended::empty(),
            onboard_control_sensors_health_extended: MavSysStatusSensorExtended::empty(),
        })
    }

    fn battery_status(&self) -> MavMessage {
        let mut voltages = [u16::MAX; 10];
        voltages[0] = self.battery_voltage_mv();
        let charge_state = if self.battery_critical {
            MavBatteryChargeState::MAV_BATTERY_CHARGE_STATE_CRITICAL
        } else if self.battery_low || self.battery_pct <= crate::vehicle::LOW_BATTERY_PCT {
            MavBatteryChargeState::MAV_BATTERY_CHARGE_STATE_LOW
        } else {
            MavBatteryChargeState::MAV_BATTERY_CHARGE_STATE_OK
        };
        MavMessage::BATTERY_STATUS(BATTERY_STATUS_DATA {
            current_consumed: -1,
            energy_consumed: -1,
            temperature: i16::MAX,
            voltages,
            current_battery: self.battery_current_ca(),
            id: 0,
            battery_function: MavBatteryFunction::MAV_BATTERY_FUNCTION_ALL,
            mavtype: MavBatteryType::MAV_BATTERY_TYPE_LIPO,
            battery_remaining: self.battery_pct.round() as i8,
            time_remaining: 0,
            charge_state,
            voltages_ext: [0; 4],
            mode: MavBatteryMode::MAV_BATTERY_MODE_UNKNOWN,
            fault_bitmask: MavBatteryFault::empty(),
        })
    }

    fn attitude(&self) -> MavMessage {
        let a = self.body.accel_ned_mps2;
        let yaw = self.body.yaw_rad;
        let (sin_yaw, cos_yaw) = yaw.sin_cos();
        let forward = a[0] * cos_yaw + a[1] * sin_yaw;
        let right = -a[0] * sin_yaw + a[1] * cos_yaw;
        MavMessage::ATTITUDE(ATTITUDE_DATA {
            time_boot_ms: self.time_boot_ms(),
            roll: (right / GRAVITY_MPS2).atan(),
            pitch: -(forward / GRAVITY_MPS2).atan(),
            yaw,
            rollspeed: 0.0,
            pitchspeed: 0.0,
            yawspeed: 0.0,
        })
    }

    fn global_position(&mut self) -> MavMessage {
        let (p, v) = self.noisy_state();
        let from_home: [f64; 3] =
            std::array::from_fn(|i| f64::from(p[i] - self.initial_position_ned_m[i]));
        let geo = self.home.offset_ned(from_home);
        let cms = |mps: f32| (mps * 100.0).clamp(f32::from(i16::MIN), f32::from(i16::MAX)) as i16;
        let heading_cdeg = (self.body.yaw_rad.to_degrees().rem_euclid(360.0) * 100.0) as u16;
        MavMessage::GLOBAL_POSITION_INT(GLOBAL_POSITION_INT_DATA {
            time_boot_ms: self.time_boot_ms(),
            lat: geo.lat_e7(),
            lon: geo.lon_e7(),
            alt: (geo.alt_amsl_m * 1000.0) as i32,
            relative_alt: (-from_home[2] * 1000.0) as i32,
            vx: cms(v[0]),
            vy: cms(v[1]),
            vz: cms(v[2]),
            hdg: heading_cdeg.min(35_999),
        })
    }

    fn home_position(&self) -> MavMessage {
        let p = self.initial_position_ned_m;
        MavMessage::HOME_POSITION(HOME_POSITION_DATA {
            latitude: self.home.lat_e7(),
            longitude: self.home.lon_e7(),
            altitude: (self.home.alt_amsl_m * 1000.0) as i32,
            x: p[0],
            y: p[1],
            z: p[2],
            q: [1.0, 0.0, 0.0, 0.0],
            approach_x: 0.0,
            approach_y: 0.0,
            approach_z: 0.0,
            time_usec: (self.time_s * 1e6) as u64,
        })
    }

    fn autopilot_version(&self) -> MavMessage {
        let common = MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MAVLINK2
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_COMMAND_INT
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_SET_POSITION_TARGET_LOCAL_NED
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_SET_POSITION_TARGET_GLOBAL_INT;
        let (capabilities, flight_sw_version) = match self.flavour {
            // Version words are major << 24 | minor << 16 | patch << 8 | 255 (release).
            Flavour::Px4 => (
                common | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_BYTEWISE,
                0x010F_00FF,
            ),
            Flavour::ArduPilot => (
                common | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_C_CAST,
                0x0405_00FF,
            ),
        };
        MavMessage::AUTOPILOT_VERSION(AUTOPILOT_VERSION_DATA {
            capabilities,
            uid: u64::from(self.system_id),
            flight_sw_version,
            middleware_sw_version: 0,
            os_sw_version: 0,
            board_version: 0,
            vendor_id: 0,
            product_id: 0,
            flight_custom_version: *b"swarmctl",
            middleware_custom_version: [0; 8],
            os_custom_version: [0; 8],
            uid2: [0; 18],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intervals_disable_restore_and_reject_unknown() {
        let mut s = Streams::new(1, 20.0);
        assert_eq!(s.period_s(id::LOCAL_POSITION_NED), Some(0.05));
        assert!(s.set_interval(id::LOCAL_POSITION_NED, 100_000.0));
        assert_eq!(s.period_s(id::LOCAL_POSITION_NED), Some(0.1));
        assert!(s.set_interval(id::LOCAL_POSITION_NED, -1.0));
        assert_eq!(s.period_s(id::LOCAL_POSITION_NED), None);
        assert!(s.set_interval(id::LOCAL_POSITION_NED, 0.0));
        assert_eq!(s.period_s(id::LOCAL_POSITION_NED), Some(0.05));
        assert!(!s.set_interval(12345, 1000.0));
    }

    #[test]
    fn due_streams_follow_their_rates() {
        let mut s = Streams::new(7, 20.0);
        let mut counts = std::collections::HashMap::new();
        let mut due = Vec::new();
        for step in 0..1000 {
            due.clear();
            s.take_due(f64::from(step) * 0.01, &mut due);
            for id in &due {
                *counts.entry(*id).or_insert(0) += 1;
            }
        }
        // 10 s of simulated time.
        assert!(
            (199..=201).contains(&counts[&id::LOCAL_POSITION_NED]),
            "{counts:?}"
        );
        assert!((10..=11).contains(&counts[&id::HEARTBEAT]), "{counts:?}");
        assert!((5..=6).contains(&counts[&id::HOME_POSITION]), "{counts:?}");
    }
}
