//! One MAVLink session with one vehicle: a reader task that keeps its
//! [`VehicleState`] current, a 1 Hz ground-station heartbeat task, and the
//! request/acknowledge logic for commands.
//!
//! The connection is shared (`Arc`) between the tasks: rust-mavlink's async
//! connection locks reader and writer separately, so sending setpoints never
//! waits for a receive. Messages from any system other than the one we fly are
//! ignored, so a stray vehicle or a second ground station cannot move our state.
//!
//! One file per job, the way MAVSDK has one plugin per concern: `reader` folds
//! what the vehicle sends into its state, `heartbeat` announces us, `command`
//! sends commands until acknowledged, `actions` arms, switches modes and takes
//! off, `streams` asks for telemetry, and `parameters` reads and writes the
//! autopilot's parameters. This file holds the session itself: opening it, its
//! state, and the setpoint stream.

mod actions;
mod command;
mod heartbeat;
mod parameters;
mod reader;
mod streams;

pub use command::CommandPolicy;
pub use parameters::ParamValue;
pub use streams::Quieted;

use super::error::LinkError;
use super::messages::position_target;
use super::signing::SigningKey;
use super::telemetry::VehicleState;
use super::transport::{CarriedLink, LinkBytes, Transport};
use mavlink::AsyncMavConnection;
use mavlink::dialects::common::{COMMAND_ACK_DATA, MavAutopilot, MavMessage};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};
use tokio::sync::broadcast;
use tokio::task::JoinHandle;

/// A live session; dropping it stops its tasks.
pub struct Session {
    /// The vehicle's MAVLink system id; messages from other systems are ignored.
    pub system_id: u8,
    /// The rust-mavlink address the session was opened on, or what carries its
    /// frames (for error messages).
    pub endpoint: String,
    transport: Arc<Transport>,
    state: Arc<Mutex<VehicleState>>,
    acks: broadcast::Sender<COMMAND_ACK_DATA>,
    boot: Instant,
    policy: CommandPolicy,
    tasks: Vec<JoinHandle<()>>,
}

impl Drop for Session {
    fn drop(&mut self) {
        for task in &self.tasks {
            task.abort();
        }
    }
}

impl Session {
    /// Opens `endpoint` (any rust-mavlink address: `udpout:`, `udpin:`, `tcpout:` …)
    /// and starts the reader and heartbeat tasks for vehicle `system_id`.
    ///
    /// With a signing key every message we send is signed and unsigned or wrongly
    /// signed input is dropped before it reaches the session.
    pub async fn connect(
        endpoint: &str,
        system_id: u8,
        policy: CommandPolicy,
        signing: Option<&SigningKey>,
    ) -> Result<Session, LinkError> {
        let mut connection = mavlink::connect_async::<MavMessage>(endpoint)
            .await
            .map_err(|source| LinkError::Connect {
                endpoint: endpoint.to_string(),
                source,
            })?;
        if let Some(key) = signing {
            connection.setup_signing(Some(key.config()));
        }
        Ok(Self::start(
            Transport::direct(connection),
            endpoint,
            system_id,
            policy,
        ))
    }

    /// A session over a link something else carries (a relay): the same
    /// commands, retries and telemetry as over a socket. Signing, when the
    /// mission signs, is the carrier's to do towards its vehicles.
    ///
    /// Fails if another session already took the link.
    pub fn carried(
        link: &Arc<CarriedLink>,
        system_id: u8,
        policy: CommandPolicy,
    ) -> Result<Session, LinkError> {
        let end = link.take().ok_or_else(|| LinkError::Connect {
            endpoint: link.label().to_string(),
            source: std::io::Error::new(
                std::io::ErrorKind::AddrInUse,
                "another session already speaks over this link",
            ),
        })?;
        Ok(Self::start(
            Transport::carried(end),
            link.label(),
            system_id,
            policy,
        ))
    }

    fn start(
        transport: Transport,
        endpoint: &str,
        system_id: u8,
        policy: CommandPolicy,
    ) -> Session {
        let transport = Arc::new(transport);
        let state = Arc::new(Mutex::new(VehicleState::default()));
        let (acks, _) = broadcast::channel(32);
        let reader = tokio::spawn(reader::read_loop(
            transport.clone(),
            system_id,
            state.clone(),
            acks.clone(),
        ));
        let heartbeat = tokio::spawn(heartbeat::heartbeat_loop(transport.clone()));
        Session {
            system_id,
            endpoint: endpoint.to_string(),
            transport,
            state,
            acks,
            boot: Instant::now(),
            policy,
            tasks: vec![reader, heartbeat],
        }
    }

    /// Why whatever carries this session's frames says the vehicle cannot be
    /// reached now (its relay left), if it says so. A direct link never does:
    /// silence is how its loss shows.
    pub fn carrier_down(&self) -> Option<String> {
        self.transport.down()
    }

    /// The bytes this session has moved each way since it opened.
    pub fn bytes(&self) -> LinkBytes {
        self.transport.bytes()
    }

    /// The vehicle state (locked briefly: never hold it across an await).
    pub fn state(&self) -> MutexGuard<'_, VehicleState> {
        // A poisoned lock only means a reader panicked mid-update; the data is still
        // the best we have.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Waits for the vehicle's first heartbeat and returns the autopilot it names.
    pub async fn wait_heartbeat(&self, within: Duration) -> Result<MavAutopilot, LinkError> {
        let start = Instant::now();
        loop {
            {
                let s = self.state();
                if let (Some(_), Some(autopilot)) = (s.last_heartbeat, s.autopilot) {
                    return Ok(autopilot);
                }
            }
            if start.elapsed() >= within {
                return Err(LinkError::NoHeartbeat {
                    system_id: self.system_id,
                    waited_s: within.as_secs_f64(),
                });
            }
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
    }

    /// Waits until `ok` holds on the vehicle state.
    pub async fn confirm(
        &self,
        what: &str,
        within: Duration,
        ok: impl Fn(&VehicleState) -> bool,
    ) -> Result<(), LinkError> {
        let start = Instant::now();
        while start.elapsed() < within {
            if ok(&self.state()) {
                return Ok(());
            }
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
        Err(LinkError::NotConfirmed {
            what: what.to_string(),
            waited_s: within.as_secs_f64(),
        })
    }

    /// Streams one position setpoint with velocity and acceleration feed-forward
    /// (LOCAL_NED, the vehicle's own local frame).
    pub async fn send_setpoint(
        &self,
        position_ned_m: [f32; 3],
        velocity_ned_mps: [f32; 3],
        accel_ned_mps2: [f32; 3],
    ) -> Result<(), LinkError> {
        let time_boot_ms = self.boot.elapsed().as_millis() as u32;
        self.send(&position_target(
            self.system_id,
            time_boot_ms,
            position_ned_m,
            velocity_ned_mps,
            accel_ned_mps2,
        ))
        .await
    }

    async fn send(&self, message: &MavMessage) -> Result<(), LinkError> {
        self.transport.send(&heartbeat::gcs_header(), message).await
    }
}
