//! `swarmctl relay`: one process that owns the MAVLink links of a set of drones
//! (its own MAVLink network, its own system ids) and carries their frames to and
//! from the controller over Zenoh.
//!
//! Per drone, two tasks: the uplink reads every frame the vehicle sends and
//! publishes it on the drone's `telemetry` key; the downlink writes to the
//! vehicle every frame the controller publishes on its `setpoint` and `command`
//! keys. The relay flies nothing itself: heartbeats, commands and their retries
//! all come from the controller, so a controller that goes silent is, to the
//! vehicles, a ground station gone (their own failsafe applies), exactly as on
//! a direct link. Liveliness tokens announce the relay and each drone it serves;
//! when the relay dies, Zenoh withdraws them and the controller knows at once.

use crate::endpoints::ZenohEndpoints;
use crate::error::RelayError;
use crate::keys::KeySpace;
use mavlink::dialects::common::MavMessage;
use mavlink::error::MessageReadError;
use mavlink::{AsyncConnection, AsyncMavConnection};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;
use swarmctl::link::SigningKey;
use swarmctl::link::wire::{decode_frame, encode_frame};
use tokio::sync::mpsc;
use tokio::task::JoinHandle;
use zenoh::liveliness::LivelinessToken;
use zenoh::pubsub::Subscriber;
use zenoh::qos::{CongestionControl, Priority};

/// One drone a relay serves.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RelayedDrone {
    /// The mission's drone id (its identity across relays).
    pub id: String,
    /// How the relay reaches its autopilot (any rust-mavlink address).
    pub endpoint: String,
    /// Its MAVLink system id in this relay's network.
    pub system_id: u8,
}

/// What a relay serves and where it meets the controller.
#[derive(Debug, Clone)]
pub struct RelaySpec {
    /// Unique among the mission's relays; names it in the flight log.
    pub name: String,
    /// The mission's name (its key space).
    pub mission: String,
    /// The drones it serves.
    pub drones: Vec<RelayedDrone>,
    /// MAVLink 2 signing towards the vehicles, when the mission signs.
    pub signing: Option<SigningKey>,
    /// Zenoh endpoints.
    pub zenoh: ZenohEndpoints,
}

/// Frames carried for one drone so far.
#[derive(Debug, Default)]
struct Counters {
    to_vehicle: AtomicU64,
    from_vehicle: AtomicU64,
}

/// Frames a relay carried for one drone.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CarriedFrames {
    /// The drone.
    pub drone: String,
    /// Frames from the controller written to the vehicle.
    pub to_vehicle: u64,
    /// Frames from the vehicle published to the controller.
    pub from_vehicle: u64,
}

/// A running relay; [`Relay::close`] stops it (dropping it stops it too, less tidily).
pub struct Relay {
    name: String,
    keys: KeySpace,
    session: zenoh::Session,
    drones: Vec<String>,
    counters: Vec<Arc<Counters>>,
    // Held for their effect: dropping one undeclares it.
    _tokens: Vec<LivelinessToken>,
    _subscribers: Vec<Subscriber<()>>,
    tasks: Vec<JoinHandle<()>>,
}

impl Drop for Relay {
    fn drop(&mut self) {
        for t in &self.tasks {
            t.abort();
        }
    }
}

impl Relay {
    /// Opens every vehicle link and the Zenoh session, starts carrying frames,
    /// then announces the relay and its drones. Any link that cannot be opened
    /// fails the whole relay, naming the drone: a relay half up would look, to
    /// the controller, like drones nobody serves.
    pub async fn start(spec: RelaySpec) -> Result<Relay, RelayError> {
        let keys = KeySpace::new(&spec.mission);
        let mut connections = Vec::new();
        for d in &spec.drones {
            let mut connection = mavlink::connect_async::<MavMessage>(&d.endpoint)
                .await
                .map_err(|e| RelayError::Vehicle {
                    drone: d.id.clone(),
                    endpoint: d.endpoint.clone(),
                    reason: e.to_string(),
                })?;
            if let Some(key) = &spec.signing {
                connection.setup_signing(Some(key.config()));
            }
            connections.push(Arc::new(connection));
        }
        let session = spec.zenoh.open().await?;
        let mut relay = Relay {
            name: spec.name.clone(),
            keys,
            session,
            drones: spec.drones.iter().map(|d| d.id.clone()).collect(),
            counters: Vec::new(),
            _tokens: Vec::new(),
            _subscribers: Vec::new(),
            tasks: Vec::new(),
        };
        for (d, connection) in spec.drones.iter().zip(connections) {
            relay.carry(d, connection).await?;
        }
        let mut tokens = Vec::new();
        for d in &spec.drones {
            tokens.push(
                relay
                    .token(relay.keys.served(&d.id, &spec.name, d.system_id))
                    .await?,
            );
        }
        tokens.push(relay.token(relay.keys.relay(&spec.name)).await?);
        relay._tokens = tokens;
        Ok(relay)
    }

    /// Starts the uplink and downlink of drone `d`.
    async fn carry(
        &mut self,
        d: &RelayedDrone,
        connection: Arc<AsyncConnection<MavMessage>>,
    ) -> Result<(), RelayError> {
        let counters = Arc::new(Counters::default());
        let telemetry_key = self.keys.telemetry(&d.id);
        let telemetry = self
            .session
            .declare_publisher(telemetry_key.clone())
            .congestion_control(CongestionControl::Block)
            .priority(Priority::InteractiveHigh)
            .await
            .map_err(|e| declare_error(&telemetry_key, e))?;
        let (to_vehicle, mut frames) =
            mpsc::channel::<Vec<u8>>(swarmctl::link::wire::CARRIED_QUEUE_FRAMES);
        for key in [self.keys.setpoint(&d.id), self.keys.command(&d.id)] {
            let to_vehicle = to_vehicle.clone();
            let subscriber = self
                .session
                .declare_subscriber(key.clone())
                .callback(move |sample| {
                    // A full queue means the vehicle link is stuck: drop, as a radio would.
                    let _ = to_vehicle.try_send(sample.payload().to_bytes().into_owned());
                })
                .await
                .map_err(|e| declare_error(&key, e))?;
            self._subscribers.push(subscriber);
        }
        let up = connection.clone();
        let up_counters = counters.clone();
        self.tasks.push(tokio::spawn(async move {
            loop {
                match up.recv().await {
                    Ok((header, message)) => {
                        up_counters.from_vehicle.fetch_add(1, Ordering::Relaxed);
                        // A put fails only when the session closes.
                        if telemetry.put(encode_frame(header, &message)).await.is_err() {
                            return;
                        }
                    }
                    Err(MessageReadError::Parse(_)) => continue,
                    Err(_) => tokio::time::sleep(Duration::from_millis(20)).await,
                }
            }
        }));
        let down_counters = counters.clone();
        self.tasks.push(tokio::spawn(async move {
            while let Some(frame) = frames.recv().await {
                let Some((header, message)) = decode_frame(&frame) else {
                    continue;
                };
                if connection.send(&header, &message).await.is_ok() {
                    down_counters.to_vehicle.fetch_add(1, Ordering::Relaxed);
                }
            }
        }));
        self.counters.push(counters);
        Ok(())
    }

    async fn token(&self, key: String) -> Result<LivelinessToken, RelayError> {
        self.session
            .liveliness()
            .declare_token(key.clone())
            .await
            .map_err(|e| declare_error(&key, e))
    }

    /// The relay's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The relay's Zenoh session (to publish more on it, as the bundled
    /// simulator's truth).
    pub fn session(&self) -> &zenoh::Session {
        &self.session
    }

    /// The mission's key space.
    pub fn keys(&self) -> &KeySpace {
        &self.keys
    }

    /// Frames carried per drone so far.
    pub fn carried(&self) -> Vec<CarriedFrames> {
        self.drones
            .iter()
            .zip(&self.counters)
            .map(|(drone, c)| CarriedFrames {
                drone: drone.clone(),
                to_vehicle: c.to_vehicle.load(Ordering::Relaxed),
                from_vehicle: c.from_vehicle.load(Ordering::Relaxed),
            })
            .collect()
    }

    /// Withdraws the relay's tokens (the controller sees its drones' links go)
    /// and closes the Zenoh session.
    pub async fn close(mut self) {
        for t in &self.tasks {
            t.abort();
        }
        self._tokens.clear();
        self._subscribers.clear();
        // Closing fails only if already closed.
        let _ = self.session.close().await;
    }
}

pub(crate) fn declare_error(key: &str, e: zenoh::Error) -> RelayError {
    RelayError::Declare {
        what: key.to_string(),
        reason: e.to_string(),
    }
}
