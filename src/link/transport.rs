//! How a session's MAVLink frames reach its vehicle: over a connection the
//! session opens itself (UDP, TCP, serial: rust-mavlink), or over a link that
//! something else carries — a relay on another machine, reached over Zenoh.
//!
//! A carried link is a pair of frame queues: [`carried`] returns the
//! controller's end ([`CarriedLink`], which a [`Session`](super::Session) speaks
//! MAVLink over exactly as over a socket) and the carrier's end ([`Carrier`],
//! which moves whole MAVLink 2 frames to and from wherever the vehicle is).
//! The library knows nothing of Zenoh; the carrier lives in `swarmctl-relay`.
//!
//! Frames, not decoded messages, cross the carrier: any MAVLink tool can read
//! them, the relay re-signs them for its vehicles when the mission signs, and
//! the session's command retries, acknowledgements and telemetry fold stay the
//! one implementation whatever carries the bytes.

use super::error::LinkError;
use mavlink::dialects::common::MavMessage;
use mavlink::error::MessageReadError;
use mavlink::{
    AsyncConnection, AsyncMavConnection, MAVLinkMessageRaw, MavHeader, MavlinkReader,
    MavlinkVersion, Message,
};
use std::sync::atomic::{AtomicU8, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use tokio::sync::mpsc;

/// Frames queued each way before the newest are dropped: at 20 Hz setpoints and
/// some 40 telemetry messages a second, several seconds of traffic. A full
/// queue means the carrier is stuck; dropping is what a radio link does too.
pub const CARRIED_QUEUE_FRAMES: usize = 256;

/// Where a session's frames go, and how many bytes went each way.
pub(crate) struct Transport {
    carriage: Carriage,
    sent_bytes: AtomicU64,
    received_bytes: AtomicU64,
}

/// What carries a session's frames.
enum Carriage {
    /// A rust-mavlink connection of the session's own.
    Direct(Box<AsyncConnection<MavMessage>>),
    /// Frames carried by someone else (a relay).
    Carried(CarriedEnd),
}

/// What one receive produced.
// Returned by value once per message and folded at once: boxing the message
// would allocate for every one received.
#[allow(clippy::large_enum_variant)]
pub(crate) enum Received {
    /// A message decoded.
    Message(MavHeader, MavMessage),
    /// A frame that did not decode (unknown message, bad enum): try the next.
    Undecodable,
    /// The link failed for now (ICMP unreachable, a closed TCP link): wait a little.
    Failed,
    /// The carrier is gone for good: nothing more will come.
    Closed,
}

/// The bytes a link has moved each way since it opened: whole MAVLink frames,
/// signatures included, as they crossed the socket or the carrier.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct LinkBytes {
    /// From the controller to the vehicle.
    pub sent: u64,
    /// From the vehicle to the controller (every frame with a valid CRC,
    /// whether or not it was meant for us or decoded).
    pub received: u64,
}

impl LinkBytes {
    /// What moved between `earlier` and `self`.
    pub fn since(self, earlier: LinkBytes) -> LinkBytes {
        LinkBytes {
            sent: self.sent.saturating_sub(earlier.sent),
            received: self.received.saturating_sub(earlier.received),
        }
    }
}

impl Transport {
    /// A connection the session opened itself.
    pub(crate) fn direct(connection: AsyncConnection<MavMessage>) -> Transport {
        Self::over(Carriage::Direct(Box::new(connection)))
    }

    /// A link something else carries.
    pub(crate) fn carried(end: CarriedEnd) -> Transport {
        Self::over(Carriage::Carried(end))
    }

    fn over(carriage: Carriage) -> Transport {
        Transport {
            carriage,
            sent_bytes: AtomicU64::new(0),
            received_bytes: AtomicU64::new(0),
        }
    }

    /// The bytes moved each way so far.
    pub(crate) fn bytes(&self) -> LinkBytes {
        LinkBytes {
            sent: self.sent_bytes.load(Ordering::Relaxed),
            received: self.received_bytes.load(Ordering::Relaxed),
        }
    }

    /// Sends one message with our header (the sequence number is filled in here
    /// or by the connection).
    pub(crate) async fn send(
        &self,
        header: &MavHeader,
        message: &MavMessage,
    ) -> Result<(), LinkError> {
        let sent = match &self.carriage {
            Carriage::Direct(connection) => connection
                .send(header, message)
                .await
                .map_err(|e| LinkError::Send(e.to_string()))?,
            Carriage::Carried(end) => end.send(header, message)?,
        };
        self.sent_bytes.fetch_add(sent as u64, Ordering::Relaxed);
        Ok(())
    }

    /// Receives the next message.
    pub(crate) async fn recv(&self) -> Received {
        let (bytes, received) = match &self.carriage {
            Carriage::Direct(connection) => match connection.recv_raw().await {
                Ok(raw) => (raw_len(&raw), decode_raw(&raw)),
                Err(MessageReadError::Parse(_)) => (0, Received::Undecodable),
                Err(_) => (0, Received::Failed),
            },
            Carriage::Carried(end) => end.recv().await,
        };
        self.received_bytes
            .fetch_add(bytes as u64, Ordering::Relaxed);
        received
    }

    /// Why the carrier says the vehicle cannot be reached now (a relay that
    /// left), if it says so; a direct link never does.
    pub(crate) fn down(&self) -> Option<String> {
        match &self.carriage {
            Carriage::Direct(_) => None,
            Carriage::Carried(end) => end.link.down(),
        }
    }
}

/// A raw frame's length on the wire, bytes.
fn raw_len(raw: &MAVLinkMessageRaw) -> usize {
    match raw {
        MAVLinkMessageRaw::V1(frame) => frame.raw_bytes().len(),
        MAVLinkMessageRaw::V2(frame) => frame.raw_bytes().len(),
    }
}

/// The message in a CRC-checked (and, on a signed link, signature-checked) frame.
fn decode_raw(raw: &MAVLinkMessageRaw) -> Received {
    match MavMessage::parse(raw.version(), raw.message_id(), raw.payload()) {
        Ok(message) => Received::Message(
            MavHeader {
                system_id: raw.system_id(),
                component_id: raw.component_id(),
                sequence: raw.sequence(),
            },
            message,
        ),
        Err(_) => Received::Undecodable,
    }
}

/// The controller's end of a carried link, before a session takes it.
pub struct CarriedLink {
    label: String,
    to_vehicle: mpsc::Sender<Vec<u8>>,
    from_vehicle: Mutex<Option<mpsc::Receiver<Vec<u8>>>>,
    down: Arc<Mutex<Option<String>>>,
}

impl std::fmt::Debug for CarriedLink {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CarriedLink")
            .field("label", &self.label)
            .field("down", &self.down())
            .finish_non_exhaustive()
    }
}

impl CarriedLink {
    /// What carries it, for messages and the flight log (e.g. `zenoh relay north`).
    pub fn label(&self) -> &str {
        &self.label
    }

    /// Why the carrier says the vehicle is unreachable now, if it does.
    pub fn down(&self) -> Option<String> {
        lock(&self.down).clone()
    }

    /// The session's end; `None` once a session has taken it (one session per link).
    pub(crate) fn take(self: &Arc<Self>) -> Option<CarriedEnd> {
        let from_vehicle = lock(&self.from_vehicle).take()?;
        Some(CarriedEnd {
            link: self.clone(),
            from_vehicle: tokio::sync::Mutex::new(from_vehicle),
            sequence: AtomicU8::new(0),
        })
    }
}

/// The carrier's end: frames from the controller to forward to the vehicle, a
/// queue for the vehicle's frames back, and the word on whether it can reach
/// the vehicle at all.
pub struct Carrier {
    /// MAVLink 2 frames the controller sends, in order.
    pub from_controller: mpsc::Receiver<Vec<u8>>,
    to_controller: mpsc::Sender<Vec<u8>>,
    down: Arc<Mutex<Option<String>>>,
}

impl std::fmt::Debug for Carrier {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Carrier").finish_non_exhaustive()
    }
}

impl Carrier {
    /// A handle that delivers the vehicle's frames to the controller, for
    /// whatever task or callback receives them.
    pub fn to_controller(&self) -> CarrierInbox {
        CarrierInbox {
            to_controller: self.to_controller.clone(),
            down: self.down.clone(),
        }
    }
}

/// Delivers a vehicle's frames to the controller and tells it when the vehicle
/// cannot be reached (cloneable: a Zenoh callback owns one).
#[derive(Clone)]
pub struct CarrierInbox {
    to_controller: mpsc::Sender<Vec<u8>>,
    down: Arc<Mutex<Option<String>>>,
}

impl std::fmt::Debug for CarrierInbox {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CarrierInbox").finish_non_exhaustive()
    }
}

impl CarrierInbox {
    /// Hands one frame from the vehicle to the controller; `false` if it was
    /// dropped (queue full: the controller is not keeping up) or the session is gone.
    pub fn deliver(&self, frame: Vec<u8>) -> bool {
        self.to_controller.try_send(frame).is_ok()
    }

    /// Says the vehicle cannot be reached (`Some(why)`: its relay left) or can
    /// again (`None`). The flight treats the first as a link loss at once.
    pub fn set_down(&self, why: Option<String>) {
        *lock(&self.down) = why;
    }
}

/// A carried link labelled `label` (e.g. `zenoh relay north`): the controller's
/// end, for a [`VehicleLink`](crate::fly::VehicleLink), and the carrier's.
pub fn carried(label: &str) -> (Arc<CarriedLink>, Carrier) {
    let (to_vehicle, from_controller) = mpsc::channel(CARRIED_QUEUE_FRAMES);
    let (to_controller, from_vehicle) = mpsc::channel(CARRIED_QUEUE_FRAMES);
    let down = Arc::new(Mutex::new(None));
    let link = Arc::new(CarriedLink {
        label: label.to_string(),
        to_vehicle,
        from_vehicle: Mutex::new(Some(from_vehicle)),
        down: down.clone(),
    });
    let carrier = Carrier {
        from_controller,
        to_controller,
        down,
    };
    (link, carrier)
}

/// A session's end of a carried link.
pub(crate) struct CarriedEnd {
    link: Arc<CarriedLink>,
    // Only the session's reader task receives; the lock is never contended.
    from_vehicle: tokio::sync::Mutex<mpsc::Receiver<Vec<u8>>>,
    sequence: AtomicU8,
}

impl CarriedEnd {
    /// Queues one frame for the carrier; returns its length in bytes.
    fn send(&self, header: &MavHeader, message: &MavMessage) -> Result<usize, LinkError> {
        let header = MavHeader {
            sequence: self.sequence.fetch_add(1, Ordering::Relaxed),
            ..*header
        };
        let frame = encode_frame(header, message);
        let len = frame.len();
        self.link
            .to_vehicle
            .try_send(frame)
            .map(|()| len)
            .map_err(|e| {
                LinkError::Send(match e {
                    mpsc::error::TrySendError::Full(_) => {
                        format!("{} is not keeping up (queue full)", self.link.label)
                    }
                    mpsc::error::TrySendError::Closed(_) => {
                        format!("{} has stopped", self.link.label)
                    }
                })
            })
    }

    /// The next frame's length in bytes and what it held.
    async fn recv(&self) -> (usize, Received) {
        let frame = self.from_vehicle.lock().await.recv().await;
        match frame {
            None => (0, Received::Closed),
            Some(frame) => (
                frame.len(),
                match decode_frame(&frame) {
                    Some((header, message)) => Received::Message(header, message),
                    None => Received::Undecodable,
                },
            ),
        }
    }
}

/// One MAVLink 2 frame (unsigned) holding `message`.
pub fn encode_frame(header: MavHeader, message: &MavMessage) -> Vec<u8> {
    let mut frame = Vec::with_capacity(64);
    // Writing into a Vec cannot fail.
    let _ = mavlink::write_v2_msg(&mut frame, header, message);
    frame
}

/// The message in a MAVLink 2 frame, if it is one (CRC-valid, decodable).
pub fn decode_frame(frame: &[u8]) -> Option<(MavHeader, MavMessage)> {
    MavlinkReader::new(frame)
        .read_message::<MavMessage>(MavlinkVersion::V2)
        .ok()
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    // A poisoned lock only means a holder panicked; the value is still usable.
    m.lock().unwrap_or_else(|e| e.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::common::{HEARTBEAT_DATA, MavAutopilot, MavType};

    fn heartbeat() -> MavMessage {
        MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            autopilot: MavAutopilot::MAV_AUTOPILOT_PX4,
            mavtype: MavType::MAV_TYPE_QUADROTOR,
            ..HEARTBEAT_DATA::default()
        })
    }

    #[test]
    fn frames_round_trip_and_junk_does_not_decode() {
        let header = MavHeader {
            system_id: 7,
            component_id: 1,
            sequence: 42,
        };
        let frame = encode_frame(header, &heartbeat());
        let (h, m) = decode_frame(&frame).unwrap();
        assert_eq!((h.system_id, h.sequence), (7, 42));
        assert!(matches!(m, MavMessage::HEARTBEAT(_)));
        let mut broken = frame.clone();
        let last = broken.len() - 1;
        broken[last] ^= 0xff; // CRC
        assert!(decode_frame(&broken).is_none());
        assert!(decode_frame(&frame[..frame.len() - 3]).is_none());
        assert!(decode_frame(b"not mavlink").is_none());
    }

    #[tokio::test]
    async fn a_carried_link_moves_frames_both_ways_and_says_when_it_is_down() {
        let (link, mut carrier) = carried("test carrier");
        let end = link.take().unwrap();
        assert!(link.take().is_none(), "one session per link");
        let header = MavHeader {
            system_id: 255,
            component_id: 190,
            sequence: 0,
        };
        end.send(&header, &heartbeat()).unwrap();
        end.send(&header, &heartbeat()).unwrap();
        let first = decode_frame(&carrier.from_controller.recv().await.unwrap()).unwrap();
        let second = decode_frame(&carrier.from_controller.recv().await.unwrap()).unwrap();
        assert_eq!((first.0.sequence, second.0.sequence), (0, 1));
        let inbox = carrier.to_controller();
        assert!(inbox.deliver(encode_frame(header, &heartbeat())));
        assert!(inbox.deliver(b"junk".to_vec()));
        assert!(matches!(end.recv().await, (_, Received::Message(..))));
        assert!(matches!(end.recv().await, (4, Received::Undecodable)));
        assert_eq!(link.down(), None);
        inbox.set_down(Some("relay north left".into()));
        assert_eq!(link.down().as_deref(), Some("relay north left"));
        drop(inbox);
        drop(carrier);
        assert!(matches!(end.recv().await, (0, Received::Closed)));
    }
}
