//! The controller's side: one carried link per drone, found through the relays'
//! liveliness tokens, so the plan-gated executor flies through relays exactly
//! as it flies over its own sockets.
//!
//! `RelayLinks::connect` waits until every drone of the flight is served by
//! exactly one relay, then gives each drone a [`VehicleLink`] whose frames go
//! out on the drone's `setpoint` (best effort, real-time priority) or `command`
//! (reliable) key and come back from its `telemetry` key. When a relay's tokens
//! are withdrawn (it stopped, its machine or network died) every drone it served
//! is marked down at once: the flight reports a link loss for each and the
//! existing contingencies apply (dependants hold, the rest finish).

use crate::endpoints::ZenohEndpoints;
use crate::error::RelayError;
use crate::keys::{KeySpace, Served};
use crate::relay::declare_error;
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use swarmctl::fly::VehicleLink;
use swarmctl::link::{CarrierInbox, carried};
use tokio::sync::mpsc;
use tokio::task::JoinHandle;
use zenoh::pubsub::Subscriber;
use zenoh::qos::{CongestionControl, Priority};
use zenoh::sample::SampleKind;

/// MAVLink's SET_POSITION_TARGET_LOCAL_NED: the frames that go on the setpoint key.
const SET_POSITION_TARGET_LOCAL_NED: u32 = 84;

/// Which relay serves a drone, as the flight log records it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ServedDrone {
    /// The mission's drone id.
    pub drone: String,
    /// The relay's name.
    pub relay: String,
    /// The vehicle's system id in the relay's network.
    pub system_id: u8,
}

/// The controller's links through the relays, for one flight.
pub struct RelayLinks {
    session: zenoh::Session,
    served: Vec<ServedDrone>,
    links: Vec<VehicleLink>,
    _subscribers: Vec<Subscriber<()>>,
    tasks: Vec<JoinHandle<()>>,
}

impl Drop for RelayLinks {
    fn drop(&mut self) {
        for t in &self.tasks {
            t.abort();
        }
    }
}

/// A liveliness change the discovery callback saw.
type Change = (SampleKind, Served);

impl RelayLinks {
    /// Opens the controller's Zenoh session and waits up to `wait` until every
    /// drone in `drones` (plan order) is served by a relay of mission `mission`;
    /// `progress(found, total)` is told as drones are found.
    pub async fn connect(
        zenoh: &ZenohEndpoints,
        mission: &str,
        drones: &[String],
        wait: Duration,
        progress: impl Fn(usize, usize),
    ) -> Result<RelayLinks, RelayError> {
        let keys = KeySpace::new(mission);
        let session = zenoh.open().await?;
        let (changes_tx, mut changes) = mpsc::unbounded_channel::<Change>();
        let parse = keys.clone();
        let served_key = keys.all_served();
        let discovery = session
            .liveliness()
            .declare_subscriber(served_key.clone())
            .history(true)
            .callback(move |sample| {
                if let Some(served) = parse.parse_served(sample.key_expr().as_str()) {
                    let _ = changes_tx.send((sample.kind(), served));
                }
            })
            .await
            .map_err(|e| declare_error(&served_key, e))?;
        let found = discover(drones, &mut changes, wait, progress).await?;
        let mut links = RelayLinks {
            session,
            served: Vec::new(),
            links: Vec::new(),
            _subscribers: vec![discovery],
            tasks: Vec::new(),
        };
        let mut inboxes = BTreeMap::new();
        for id in drones {
            let Some(served) = found.get(id) else {
                continue; // discover() returned only once every drone was found
            };
            let inbox = links.carry(&keys, served).await?;
            inboxes.insert(id.clone(), (served.relay.clone(), inbox));
            links.served.push(served.clone());
        }
        links.tasks.push(tokio::spawn(watch_relays(
            changes,
            Arc::new(Mutex::new(inboxes)),
        )));
        Ok(links)
    }

    /// Starts carrying drone `served`'s frames; returns its inbox.
    async fn carry(
        &mut self,
        keys: &KeySpace,
        served: &ServedDrone,
    ) -> Result<CarrierInbox, RelayError> {
        let label = format!("zenoh relay {}", served.relay);
        let (link, mut carrier) = carried(&label);
        let inbox = carrier.to_controller();
        let telemetry_key = keys.telemetry(&served.drone);
        let deliver = inbox.clone();
        let telemetry = self
            .session
            .declare_subscriber(telemetry_key.clone())
            .callback(move |sample| {
                // Dropped when the session's queue is full: it is not keeping up.
                let _ = deliver.deliver(sample.payload().to_bytes().into_owned());
            })
            .await
            .map_err(|e| declare_error(&telemetry_key, e))?;
        self._subscribers.push(telemetry);
        let setpoint_key = keys.setpoint(&served.drone);
        let setpoints = self
            .session
            .declare_publisher(setpoint_key.clone())
            .congestion_control(CongestionControl::Drop)
            .priority(Priority::RealTime)
            .await
            .map_err(|e| declare_error(&setpoint_key, e))?;
        let command_key = keys.command(&served.drone);
        let commands = self
            .session
            .declare_publisher(command_key.clone())
            .congestion_control(CongestionControl::Block)
            .priority(Priority::InteractiveHigh)
            .await
            .map_err(|e| declare_error(&command_key, e))?;
        self.tasks.push(tokio::spawn(async move {
            while let Some(frame) = carrier.from_controller.recv().await {
                let publisher = if message_id(&frame) == Some(SET_POSITION_TARGET_LOCAL_NED) {
                    &setpoints
                } else {
                    &commands
                };
                // A put fails only when the session closes.
                if publisher.put(frame).await.is_err() {
                    return;
                }
            }
        }));
        self.links
            .push(VehicleLink::carried(link, served.system_id));
        Ok(inbox)
    }

    /// One link per drone, in the order `connect` was given.
    pub fn vehicle_links(&self) -> Vec<VehicleLink> {
        self.links.clone()
    }

    /// Which relay serves which drone, in the same order.
    pub fn served(&self) -> &[ServedDrone] {
        &self.served
    }

    /// The controller's Zenoh session.
    pub fn session(&self) -> &zenoh::Session {
        &self.session
    }

    /// Stops carrying and closes the session.
    pub async fn close(mut self) {
        for t in &self.tasks {
            t.abort();
        }
        self._subscribers.clear();
        let _ = self.session.close().await;
    }
}

/// Collects `served-by` announcements until every drone has a relay.
async fn discover(
    drones: &[String],
    changes: &mut mpsc::UnboundedReceiver<Change>,
    wait: Duration,
    progress: impl Fn(usize, usize),
) -> Result<BTreeMap<String, ServedDrone>, RelayError> {
    let wanted: std::collections::BTreeSet<&str> = drones.iter().map(String::as_str).collect();
    let mut found: BTreeMap<String, ServedDrone> = BTreeMap::new();
    let mut relays = std::collections::BTreeSet::new();
    let deadline = Instant::now() + wait;
    while found.len() < wanted.len() {
        let left = deadline.saturating_duration_since(Instant::now());
        let change = match tokio::time::timeout(left, changes.recv()).await {
            Ok(Some(change)) => change,
            Ok(None) | Err(_) => {
                return Err(RelayError::Unserved {
                    missing: drones
                        .iter()
                        .filter(|d| !found.contains_key(*d))
                        .cloned()
                        .collect(),
                    total: drones.len(),
                    relays: relays.into_iter().collect(),
                    waited_s: wait.as_secs_f64(),
                });
            }
        };
        let (kind, s) = change;
        relays.insert(s.relay.clone());
        if !wanted.contains(s.drone.as_str()) {
            continue;
        }
        match kind {
            SampleKind::Put => {
                if let Some(other) = found.get(&s.drone)
                    && other.relay != s.relay
                {
                    return Err(RelayError::ServedTwice {
                        drone: s.drone,
                        first: other.relay.clone(),
                        second: s.relay,
                    });
                }
                found.insert(
                    s.drone.clone(),
                    ServedDrone {
                        drone: s.drone,
                        relay: s.relay,
                        system_id: s.system_id,
                    },
                );
                progress(found.len(), wanted.len());
            }
            SampleKind::Delete => {
                found.remove(&s.drone);
            }
        }
    }
    Ok(found)
}

/// For the rest of the flight: a relay withdrawing a drone's token marks that
/// drone's link down (a link loss, at once); announcing it again clears it.
async fn watch_relays(
    mut changes: mpsc::UnboundedReceiver<Change>,
    inboxes: Arc<Mutex<BTreeMap<String, (String, CarrierInbox)>>>,
) {
    while let Some((kind, s)) = changes.recv().await {
        let inboxes = inboxes.lock().unwrap_or_else(|e| e.into_inner());
        let Some((relay, inbox)) = inboxes.get(&s.drone) else {
            continue;
        };
        if *relay != s.relay {
            continue;
        }
        match kind {
            SampleKind::Delete => inbox.set_down(Some(format!(
                "relay {relay} left (its Zenoh liveliness token is gone)"
            ))),
            SampleKind::Put => inbox.set_down(None),
        }
    }
}

/// The message id of a MAVLink 2 frame (bytes 7–9, little-endian), if it is one.
fn message_id(frame: &[u8]) -> Option<u32> {
    match frame {
        [0xFD, _, _, _, _, _, _, a, b, c, ..] => {
            Some(u32::from(*a) | (u32::from(*b) << 8) | (u32::from(*c) << 16))
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::message_id;
    use mavlink::MavHeader;
    use mavlink::dialects::common::{MavMessage, SET_POSITION_TARGET_LOCAL_NED_DATA};
    use swarmctl::link::wire::encode_frame;

    #[test]
    fn setpoint_frames_are_told_apart_by_their_message_id() {
        let frame = encode_frame(
            MavHeader::default(),
            &MavMessage::SET_POSITION_TARGET_LOCAL_NED(
                SET_POSITION_TARGET_LOCAL_NED_DATA::default(),
            ),
        );
        assert_eq!(
            message_id(&frame),
            Some(super::SET_POSITION_TARGET_LOCAL_NED)
        );
        assert_eq!(message_id(b"junk"), None);
    }
}
