//! A small rust-mavlink ground-station client for the UDP tests.
#![allow(dead_code)] // each test binary uses a different subset

use mavlink::dialects::common::*;
use mavlink::{AsyncConnection, AsyncMavConnection, MavHeader, SigningConfig};
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::sync::atomic::{AtomicU8, Ordering};
use std::time::Duration;
use tokio::time::{Instant, timeout};

/// Loopback, where every test vehicle listens.
pub const LOOPBACK: IpAddr = IpAddr::V4(Ipv4Addr::LOCALHOST);

/// A ground station (system 255) talking to one vehicle over `udpout:`.
pub struct Client {
    connection: AsyncConnection<MavMessage>,
    /// System id of the vehicle this client commands.
    pub target: u8,
    sequence: AtomicU8,
}

impl Client {
    /// Connects to a vehicle and announces itself with a heartbeat so the
    /// vehicle learns where to answer.
    pub async fn connect(address: SocketAddr, target: u8) -> Client {
        Self::connect_signed(address, target, None).await
    }

    /// Like [`Client::connect`], signing outgoing messages with `key` and
    /// accepting only correctly signed input.
    pub async fn connect_signed(address: SocketAddr, target: u8, key: Option<[u8; 32]>) -> Client {
        let mut connection = mavlink::connect_async::<MavMessage>(&format!("udpout:{address}"))
            .await
            .expect("udpout connection");
        if let Some(key) = key {
            connection.setup_signing(Some(SigningConfig::new(key, 0, true, false)));
        }
        let client = Client {
            connection,
            target,
            sequence: AtomicU8::new(0),
        };
        client.send(&gcs_heartbeat()).await;
        client
    }

    /// Sends one message as system 255, component 190.
    pub async fn send(&self, message: &MavMessage) {
        let header = MavHeader {
            system_id: 255,
            component_id: 190,
            sequence: self.sequence.fetch_add(1, Ordering::Relaxed),
        };
        self.connection.send(&header, message).await.expect("send");
    }

    /// Receives until `pick` returns something or `within` elapses.
    pub async fn recv_until<T>(
        &self,
        within: Duration,
        mut pick: impl FnMut(&MavHeader, &MavMessage) -> Option<T>,
    ) -> Option<T> {
        let deadline = Instant::now() + within;
        while let Some(left) = deadline.checked_duration_since(Instant::now()) {
            match timeout(left, self.connection.recv()).await {
                Ok(Ok((header, message))) => {
                    if let Some(found) = pick(&header, &message) {
                        return Some(found);
                    }
                }
                Ok(Err(_)) => {}
                Err(_) => return None,
            }
        }
        None
    }

    /// Every message received during `window`.
    pub async fn collect(&self, window: Duration) -> Vec<(Instant, MavHeader, MavMessage)> {
        let mut all = Vec::new();
        self.recv_until(window, |h, m| {
            all.push((Instant::now(), *h, m.clone()));
            None::<()>
        })
        .await;
        all
    }

    /// Sends a COMMAND_LONG, retrying like MAVSDK (4 tries, 0.5 s apart),
    /// and returns the ACK result.
    pub async fn command(&self, command: MavCmd, params: [f32; 7]) -> Option<MavResult> {
        let [param1, param2, param3, param4, param5, param6, param7] = params;
        let message = MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            param1,
            param2,
            param3,
            param4,
            param5,
            param6,
            param7,
            command,
            target_system: self.target,
            target_component: 1,
            confirmation: 0,
        });
        for _ in 0..4 {
            self.send(&message).await;
            let target = self.target;
            let ack = self
                .recv_until(Duration::from_millis(500), |h, m| match m {
                    MavMessage::COMMAND_ACK(a)
                        if a.command == command && h.system_id == u32::from(target) =>
                    {
                        Some(a.result)
                    }
                    _ => None,
                })
                .await;
            if ack.is_some() {
                return ack;
            }
        }
        None
    }

    /// Arms (param1 = 1).
    pub async fn arm(&self) -> Option<MavResult> {
        self.command(
            MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        )
        .await
    }

    /// MAV_CMD_DO_SET_MODE with a custom main/sub mode.
    pub async fn set_mode(&self, main: f32, sub: f32) -> Option<MavResult> {
        self.command(
            MavCmd::MAV_CMD_DO_SET_MODE,
            [1.0, main, sub, 0.0, 0.0, 0.0, 0.0],
        )
        .await
    }

    /// A position-only SET_POSITION_TARGET_LOCAL_NED.
    pub async fn position_target(&self, ned_m: [f32; 3]) {
        self.send(&position_target(self.target, ned_m)).await;
    }
}

/// The heartbeat a ground station sends (explicit base_mode: the default has ARMED set).
pub fn gcs_heartbeat() -> MavMessage {
    MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        custom_mode: 0,
        mavtype: MavType::MAV_TYPE_GCS,
        autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
        base_mode: MavModeFlag::empty(),
        system_status: MavState::MAV_STATE_ACTIVE,
        mavlink_version: 3,
    })
}

/// Position-only local NED target (type_mask 3576: velocity, acceleration, yaw rate ignored).
pub fn position_target(target_system: u8, ned_m: [f32; 3]) -> MavMessage {
    MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
        time_boot_ms: 0,
        x: ned_m[0],
        y: ned_m[1],
        z: ned_m[2],
        vx: 0.0,
        vy: 0.0,
        vz: 0.0,
        afx: 0.0,
        afy: 0.0,
        afz: 0.0,
        yaw: 0.0,
        yaw_rate: 0.0,
        type_mask: PositionTargetTypemask::from_bits_truncate(3576),
        target_system,
        target_component: 1,
        coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
    })
}

/// Euclidean distance between two points.
pub fn distance(a: [f32; 3], b: [f32; 3]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// NaN parameters (PX4 reads NaN as "use the default").
pub const NAN7: [f32; 7] = [f32::NAN; 7];
