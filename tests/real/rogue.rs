//! A second ground station on a vehicle's spare MAVLink port: it reads the
//! vehicle's parameters apart from swarmctl (an independent read-back of what
//! pre-flight set) and, as a rogue, flies the vehicle away to find out what its
//! own geofence does.

use mavlink::AsyncMavConnection;
use mavlink::dialects::common::*;
use std::time::{Duration, Instant};

/// A ground station of its own on one vehicle.
pub struct Rogue {
    connection: mavlink::AsyncDialectConnection<mavlink::static_dialect::StaticDialect<MavMessage>>,
    system_id: u8,
    header: mavlink::MavHeader,
}

impl Rogue {
    /// Connects to `address` (retrying for 30 s while the firmware opens it).
    pub async fn connect(address: &str, system_id: u8) -> Rogue {
        let deadline = Instant::now() + Duration::from_secs(30);
        let connection = loop {
            match mavlink::connect_async::<MavMessage>(address).await {
                Ok(c) => break c,
                Err(e) if Instant::now() > deadline => panic!("no link to {address}: {e}"),
                Err(_) => tokio::time::sleep(Duration::from_millis(500)).await,
            }
        };
        Rogue {
            connection,
            system_id,
            header: mavlink::MavHeader {
                system_id: 252,
                component_id: 190,
                sequence: 0,
            },
        }
    }

    async fn send(&self, message: &MavMessage) {
        let _ = self.connection.send(&self.header, message).await;
    }

    /// The next message from the vehicle within `within`, if any.
    async fn next(&self, within: Duration) -> Option<MavMessage> {
        match tokio::time::timeout(within, self.connection.recv()).await {
            Ok(Ok((from, m))) if from.system_id == u32::from(self.system_id) => Some(m),
            _ => None,
        }
    }

    /// Parameter `name`'s `param_value` as the vehicle answers it (asked again
    /// every second, for 10 s).
    pub async fn read_param(&self, name: &str) -> f32 {
        let deadline = Instant::now() + Duration::from_secs(10);
        while Instant::now() < deadline {
            self.send(&MavMessage::PARAM_REQUEST_READ(PARAM_REQUEST_READ_DATA {
                param_index: -1,
                target_system: self.system_id,
                target_component: 1,
                param_id: name.into(),
            }))
            .await;
            let asked = Instant::now();
            while asked.elapsed() < Duration::from_secs(1) {
                if let Some(MavMessage::PARAM_VALUE(v)) =
                    self.next(Duration::from_millis(200)).await
                    && v.param_id.to_str().ok() == Some(name)
                {
                    return v.param_value;
                }
            }
        }
        panic!("{name}: no PARAM_VALUE within 10 s");
    }

    /// Sends a COMMAND_LONG and waits up to 3 s for its acknowledgement.
    pub async fn command(&self, command: MavCmd, params: [f32; 7]) -> Option<MavResult> {
        self.send(&MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            target_system: self.system_id,
            target_component: 1,
            command,
            confirmation: 0,
            param1: params[0],
            param2: params[1],
            param3: params[2],
            param4: params[3],
            param5: params[4],
            param6: params[5],
            param7: params[6],
        }))
        .await;
        let deadline = Instant::now() + Duration::from_secs(3);
        while Instant::now() < deadline {
            if let Some(MavMessage::COMMAND_ACK(a)) = self.next(Duration::from_millis(200)).await
                && a.command == command
            {
                return Some(a.result);
            }
        }
        None
    }

    /// Switches to custom main mode `mode` (MAV_CMD_DO_SET_MODE) and returns the
    /// acknowledgement.
    pub async fn set_mode(&self, mode: f32) -> Option<MavResult> {
        self.command(
            MavCmd::MAV_CMD_DO_SET_MODE,
            [1.0, mode, 0.0, 0.0, 0.0, 0.0, 0.0],
        )
        .await
    }

    /// Arms the vehicle and returns the acknowledgement.
    pub async fn arm(&self) -> Option<MavResult> {
        self.command(
            MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        )
        .await
    }

    /// Streams a velocity target `velocity_ned_mps` (local NED) at 20 Hz for `for_`.
    pub async fn stream_velocity(&self, velocity_ned_mps: [f32; 3], for_: Duration) {
        // Velocity only: position, acceleration and yaw ignored.
        self.stream(0b1101_1100_0111, [0.0; 3], velocity_ned_mps, for_)
            .await;
    }

    /// Streams a position target `position_ned_m` (local NED) at 20 Hz for `for_`.
    pub async fn stream_position(&self, position_ned_m: [f32; 3], for_: Duration) {
        // Position only: velocity, acceleration and yaw ignored.
        self.stream(0b1101_1111_1000, position_ned_m, [0.0; 3], for_)
            .await;
    }

    async fn stream(
        &self,
        type_mask: u16,
        position_ned_m: [f32; 3],
        velocity_ned_mps: [f32; 3],
        for_: Duration,
    ) {
        let until = Instant::now() + for_;
        while Instant::now() < until {
            self.send(&MavMessage::SET_POSITION_TARGET_LOCAL_NED(
                SET_POSITION_TARGET_LOCAL_NED_DATA {
                    time_boot_ms: 0,
                    target_system: self.system_id,
                    target_component: 1,
                    coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
                    type_mask: PositionTargetTypemask::from_bits_truncate(type_mask),
                    x: position_ned_m[0],
                    y: position_ned_m[1],
                    z: position_ned_m[2],
                    vx: velocity_ned_mps[0],
                    vy: velocity_ned_mps[1],
                    vz: velocity_ned_mps[2],
                    afx: 0.0,
                    afy: 0.0,
                    afz: 0.0,
                    yaw: 0.0,
                    yaw_rate: 0.0,
                },
            ))
            .await;
            // Drain what arrives until the next one is due.
            let next_at = Instant::now() + Duration::from_millis(50);
            while let Some(left) = next_at.checked_duration_since(Instant::now()) {
                let _ = self.next(left).await;
            }
        }
    }
}
