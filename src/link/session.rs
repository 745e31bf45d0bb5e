//! One MAVLink session with one vehicle: a reader task that keeps its
//! [`VehicleState`] current, a 1 Hz ground-station heartbeat task, and the
//! request/acknowledge logic for commands.
//!
//! The connection is shared (`Arc`) between the tasks: rust-mavlink's async
//! connection locks reader and writer separately, so sending setpoints never
//! waits for a receive. Messages from any system other than the one we fly are
//! ignored, so a stray vehicle or a second ground station cannot move our state.

use super::error::LinkError;
use super::flavour::{Flavour, ModeRequest};
use super::messages::{
    GCS_COMPONENT_ID, GCS_SYSTEM_ID, command_long, gcs_heartbeat, position_target,
};
use super::receive;
use super::signing::SigningKey;
use super::telemetry::VehicleState;
use super::transport::{CarriedLink, Received, Transport};
use mavlink::dialects::common::{
    COMMAND_ACK_DATA, MavCmd, MavMessage, MavModeFlag, MavParamType, MavResult,
    PARAM_REQUEST_READ_DATA, PARAM_SET_DATA,
};
use mavlink::{AsyncMavConnection, MavHeader};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};
use tokio::sync::broadcast;
use tokio::task::JoinHandle;

/// How often and how long a command is tried before giving up.
#[derive(Debug, Clone, Copy)]
pub struct CommandPolicy {
    /// Tries before a silent vehicle counts as not acknowledging.
    pub attempts: u8,
    /// How long each try waits for its COMMAND_ACK.
    pub ack_timeout: Duration,
}

impl Default for CommandPolicy {
    /// Twelve tries, 0.6 s each: at 30 % loss each way a try gets through with
    /// p = 0.49, so a command fails with p = 0.51^12 ≈ 3e-4 — and a swarm sends
    /// dozens per flight, which the CI's 8-drone 30 % run hit twice (2026-12-02,
    /// first on a rate request, then on OFFBOARD). So a vehicle that is still heard
    /// gets up to twice the tries (`Session::keeps_trying`): p ≈ 1e-7.
    /// A refusal still comes back at once; only a silent vehicle costs the 7 s.
    fn default() -> Self {
        Self {
            attempts: 12,
            ack_timeout: Duration::from_millis(600),
        }
    }
}

/// How long telemetry gets to confirm a command's effect. Heartbeats come at
/// 1 Hz; at 30 % loss three in a row go missing with p ≈ 3 %, six with p ≈ 0.07 %.
const CONFIRM_WITHIN: Duration = Duration::from_secs(6);

/// A vehicle heard this recently is lossy, not silent: its commands get extra tries.
/// Before any stream is requested only 1 Hz heartbeats come; at 30 % loss three
/// in a row are lost with p ≈ 3 %.
const HEARD_WITHIN_S: f64 = 3.0;

/// MAVLink message ids we ask the vehicle to stream.
const LOCAL_POSITION_NED_ID: f32 = 32.0;
const EXTENDED_SYS_STATE_ID: f32 = 245.0;
const SYS_STATUS_ID: f32 = 1.0;

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
            Transport::Direct(Box::new(connection)),
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
            Transport::Carried(end),
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
        let reader = tokio::spawn(read_loop(
            transport.clone(),
            system_id,
            state.clone(),
            acks.clone(),
        ));
        let heartbeat = tokio::spawn(heartbeat_loop(transport.clone()));
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

    /// The vehicle state (locked briefly: never hold it across an await).
    pub fn state(&self) -> MutexGuard<'_, VehicleState> {
        // A poisoned lock only means a reader panicked mid-update; the data is still
        // the best we have.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Waits for the vehicle's first heartbeat and returns its autopilot family.
    pub async fn wait_heartbeat(&self, within: Duration) -> Result<Flavour, LinkError> {
        let start = Instant::now();
        loop {
            {
                let s = self.state();
                if s.last_heartbeat.is_some() {
                    return s.flavour.ok_or_else(|| LinkError::UnknownAutopilot {
                        system_id: self.system_id,
                        autopilot: s.autopilot_name.clone().unwrap_or_default(),
                    });
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

    /// Asks for position at `position_hz`, landed state at 5 Hz and health at 1 Hz.
    pub async fn request_rates(&self, position_hz: f64) -> Result<(), LinkError> {
        for (id, hz) in [
            (LOCAL_POSITION_NED_ID, position_hz),
            (EXTENDED_SYS_STATE_ID, 5.0),
            (SYS_STATUS_ID, 1.0),
        ] {
            let interval_us = (1e6 / hz.max(0.1)) as f32;
            self.command(
                MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
                [id, interval_us, 0.0, 0.0, 0.0, 0.0, 0.0],
            )
            .await?;
        }
        Ok(())
    }

    /// Sends a COMMAND_LONG until acknowledged, incrementing the confirmation
    /// counter on each retry (as MAVLink asks, so the vehicle can tell a retry from
    /// a new command). ACCEPTED is `Ok`; a refusal carries the vehicle's STATUSTEXT.
    pub async fn command(&self, command: MavCmd, params: [f32; 7]) -> Result<(), LinkError> {
        let mut acks = self.acks.subscribe();
        let mut attempt: u8 = 0;
        while self.keeps_trying(attempt) {
            self.send(&command_long(self.system_id, command, params, attempt))
                .await?;
            let deadline = tokio::time::Instant::now() + self.policy.ack_timeout;
            loop {
                let ack = match tokio::time::timeout_at(deadline, acks.recv()).await {
                    Err(_) => break, // this attempt timed out
                    Ok(Err(broadcast::error::RecvError::Lagged(_))) => continue,
                    Ok(Err(broadcast::error::RecvError::Closed)) => {
                        return Err(LinkError::Send("session reader stopped".into()));
                    }
                    Ok(Ok(ack)) => ack,
                };
                if ack.command != command {
                    continue;
                }
                match ack.result {
                    MavResult::MAV_RESULT_ACCEPTED => return Ok(()),
                    MavResult::MAV_RESULT_IN_PROGRESS => continue,
                    // Worth another try after the timeout (PX4 offboard without a stream yet).
                    MavResult::MAV_RESULT_TEMPORARILY_REJECTED => {
                        if !self.keeps_trying(attempt.saturating_add(1)) {
                            return Err(self.refused(command, ack.result));
                        }
                        tokio::time::sleep_until(deadline).await;
                        break;
                    }
                    result => return Err(self.refused(command, result)),
                }
            }
            attempt = attempt.saturating_add(1);
        }
        Err(LinkError::NoAck {
            command,
            attempts: attempt,
        })
    }

    /// Whether try number `attempt` (from 0) should be made: the policy's tries,
    /// then as many again while the vehicle is still heard — a lossy link, not a
    /// silent vehicle, so giving up would strand a healthy drone.
    fn keeps_trying(&self, attempt: u8) -> bool {
        let tries = self.policy.attempts;
        if attempt < tries {
            return true;
        }
        attempt < tries.saturating_mul(2)
            && self
                .state()
                .message_age_s(Instant::now())
                .is_some_and(|age_s| age_s <= HEARD_WITHIN_S)
    }

    fn refused(&self, command: MavCmd, result: MavResult) -> LinkError {
        LinkError::Refused {
            command,
            result,
            reason: self.state().last_status_text.clone(),
        }
    }

    /// Arms and waits until the heartbeat shows SAFETY_ARMED.
    pub async fn arm(&self) -> Result<(), LinkError> {
        self.command(
            MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        )
        .await?;
        self.confirm("armed state", CONFIRM_WITHIN, |s| s.armed)
            .await
    }

    /// Disarms; `force` (param2 = 21196) also in the air — only for emergencies.
    pub async fn disarm(&self, force: bool) -> Result<(), LinkError> {
        let magic = if force { 21196.0 } else { 0.0 };
        self.command(
            MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            [0.0, magic, 0.0, 0.0, 0.0, 0.0, 0.0],
        )
        .await?;
        self.confirm("disarmed state", CONFIRM_WITHIN, |s| !s.armed)
            .await
    }

    /// Switches mode and waits for the heartbeat to show it.
    pub async fn set_mode(&self, mode: ModeRequest) -> Result<(), LinkError> {
        let base = f32::from(MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED.bits());
        self.command(
            MavCmd::MAV_CMD_DO_SET_MODE,
            [base, mode.param2, mode.param3, 0.0, 0.0, 0.0, 0.0],
        )
        .await?;
        self.confirm(
            &format!("mode {:#x}", mode.custom_mode),
            CONFIRM_WITHIN,
            |s| s.custom_mode == mode.custom_mode,
        )
        .await
    }

    /// ArduPilot-style takeoff: param7 is the height above home in metres.
    pub async fn takeoff(&self, height_m: f32) -> Result<(), LinkError> {
        self.command(
            MavCmd::MAV_CMD_NAV_TAKEOFF,
            [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, height_m],
        )
        .await
    }

    /// Sets parameter `name` (REAL32, as both autopilots take these) and waits for
    /// the vehicle's PARAM_VALUE to read back `value`, retrying like a command.
    /// Returns the value read back; a vehicle that keeps another is an error.
    pub async fn set_param(&self, name: &str, value: f32) -> Result<f32, LinkError> {
        let close = |v: f32| (v - value).abs() <= 1e-3 * value.abs().max(1.0);
        let mut attempt: u8 = 0;
        while self.keeps_trying(attempt) {
            attempt = attempt.saturating_add(1);
            self.send(&MavMessage::PARAM_SET(PARAM_SET_DATA {
                param_value: value,
                target_system: self.system_id,
                target_component: super::messages::AUTOPILOT_COMPONENT_ID,
                param_id: name.into(),
                param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
            }))
            .await?;
            let asked = Instant::now();
            while asked.elapsed() < self.policy.ack_timeout {
                if let Some(v) = self.state().params.get(name).copied()
                    && close(v)
                {
                    return Ok(v);
                }
                tokio::time::sleep(Duration::from_millis(20)).await;
            }
        }
        Err(LinkError::NotConfirmed {
            what: format!(
                "parameter {name} = {value} (reads back {})",
                self.state()
                    .params
                    .get(name)
                    .map_or("nothing".to_string(), |v| v.to_string())
            ),
            waited_s: self.policy.ack_timeout.as_secs_f64() * f64::from(attempt),
        })
    }

    /// Reads parameter `name` (PARAM_REQUEST_READ, answered by PARAM_VALUE), retrying
    /// like a command; a vehicle that never answers (no such parameter) is an error.
    pub async fn read_param(&self, name: &str) -> Result<f32, LinkError> {
        self.state().params.remove(name);
        let mut attempt: u8 = 0;
        while self.keeps_trying(attempt) {
            attempt = attempt.saturating_add(1);
            self.send(&MavMessage::PARAM_REQUEST_READ(PARAM_REQUEST_READ_DATA {
                param_index: -1,
                target_system: self.system_id,
                target_component: super::messages::AUTOPILOT_COMPONENT_ID,
                param_id: name.into(),
            }))
            .await?;
            let asked = Instant::now();
            while asked.elapsed() < self.policy.ack_timeout {
                if let Some(v) = self.state().params.get(name).copied() {
                    return Ok(v);
                }
                tokio::time::sleep(Duration::from_millis(20)).await;
            }
        }
        Err(LinkError::NotConfirmed {
            what: format!("parameter {name} (no PARAM_VALUE)"),
            waited_s: self.policy.ack_timeout.as_secs_f64() * f64::from(attempt),
        })
    }

    /// Asks the vehicle to send message `message_id` once (MAV_CMD_REQUEST_MESSAGE).
    pub async fn request_message(&self, message_id: u32) -> Result<(), LinkError> {
        self.command(
            MavCmd::MAV_CMD_REQUEST_MESSAGE,
            [message_id as f32, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        )
        .await
    }

    /// Asks the autopilot to run its pre-arm checks now, which makes it repeat why
    /// they fail in STATUSTEXT (ArduPilot; PX4 answers unsupported, and says why on
    /// its own).
    pub async fn run_prearm_checks(&self) -> Result<(), LinkError> {
        self.command(MavCmd::MAV_CMD_RUN_PREARM_CHECKS, [0.0; 7])
            .await
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
        self.transport.send(&gcs_header(), message).await
    }
}

/// Our header; the connection fills in the sequence number itself.
fn gcs_header() -> MavHeader {
    MavHeader {
        system_id: u32::from(GCS_SYSTEM_ID),
        component_id: GCS_COMPONENT_ID,
        sequence: 0,
    }
}

/// The ground-station heartbeat, once a second for the session's lifetime.
async fn heartbeat_loop(transport: Arc<Transport>) {
    let mut tick = tokio::time::interval(Duration::from_secs(1));
    let heartbeat = gcs_heartbeat();
    loop {
        tick.tick().await;
        // A failed send is retried next second; link loss is detected from the
        // vehicle's side (its heartbeats stop), not from ours.
        let _ = transport.send(&gcs_header(), &heartbeat).await;
    }
}

/// Reads forever, folding every decoded message into `state` with
/// [`receive::fold`] (which drops anything not from `system_id`) and passing the
/// COMMAND_ACKs meant for us to whoever waits on a command.
async fn read_loop(
    transport: Arc<Transport>,
    system_id: u8,
    state: Arc<Mutex<VehicleState>>,
    acks: broadcast::Sender<COMMAND_ACK_DATA>,
) {
    loop {
        let (header, message) = match transport.recv().await {
            Received::Message(header, message) => (header, message),
            // A frame with a valid CRC that does not decode (unknown message, bad
            // enum value): the next one may be fine. Never sleep on these, or a
            // sender of junk could starve the vehicle's own messages.
            Received::Undecodable => continue,
            // A TCP link closed, ICMP "port unreachable" and the like: the
            // vehicle may come back.
            Received::Failed => {
                tokio::time::sleep(Duration::from_millis(20)).await;
                continue;
            }
            // The carrier is gone: silence from here on, which the flight
            // sees as a lost link.
            Received::Closed => return,
        };
        let ack = {
            let mut s = state.lock().unwrap_or_else(|e| e.into_inner());
            receive::fold(&mut s, &header, message, system_id, Instant::now())
        };
        if let Some(ack) = ack {
            // No subscriber just means nobody is waiting for an answer.
            let _ = acks.send(ack);
        }
    }
}
