//! Telemetry: how each message is built from the vehicle's state. Which
//! messages are due when is the schedule in [`crate::streams`].

use crate::dynamics::GRAVITY_MPS2;
use crate::mode::FlightMode;
use crate::streams::id;
use crate::vehicle::{LOW_BATTERY_PCT, Vehicle};
use mavlink::dialects::common::*;
use rand::Rng;

/// Noise amplitude on reported positions, metres (uniform ±).
const POSITION_NOISE_M: f32 = 0.005;
/// Noise amplitude on reported velocities, m/s (uniform ±).
const VELOCITY_NOISE_MPS: f32 = 0.005;

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
                let o = self.local_origin_ned_m;
                let p = [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
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
            id::GPS_GLOBAL_ORIGIN => self.gps_global_origin(),
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
            autopilot: self.flavour.imitation().heartbeat_autopilot(),
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
        } else if self.battery_low || self.battery_pct <= LOW_BATTERY_PCT {
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

    /// The geodetic point where the local frame is zero.
    fn gps_global_origin(&self) -> MavMessage {
        let (o, p) = (self.local_origin_ned_m, self.initial_position_ned_m);
        let origin = self
            .home
            .offset_ned(std::array::from_fn(|i| f64::from(o[i] - p[i])));
        MavMessage::GPS_GLOBAL_ORIGIN(GPS_GLOBAL_ORIGIN_DATA {
            latitude: origin.lat_e7(),
            longitude: origin.lon_e7(),
            altitude: (origin.alt_amsl_m * 1000.0) as i32,
            time_usec: (self.time_s * 1e6) as u64,
        })
    }

    fn home_position(&self) -> MavMessage {
        let (h, o) = (self.initial_position_ned_m, self.local_origin_ned_m);
        let p = [h[0] - o[0], h[1] - o[1], h[2] - o[2]];
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
        let (own, flight_sw_version) = self.flavour.imitation().version();
        let capabilities = common | own;
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
