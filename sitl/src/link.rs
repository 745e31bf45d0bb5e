//! One vehicle's UDP link: answers whoever spoke last (plus an optional
//! ground-station port) and injects the link faults — loss, duplication,
//! reordering, latency, drops.

use crate::codec::{self, Rejection, Signing};
use crate::config::Faults;
use mavlink::MavHeader;
use mavlink::dialects::common::MavMessage;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::cmp::Ordering as CmpOrdering;
use std::collections::BinaryHeap;
use std::collections::binary_heap::PeekMut;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, AtomicU8, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;
use tokio::net::UdpSocket;
use tokio::sync::mpsc;
use tokio::time::Instant;

/// Counters of what happened on a link, for tests and diagnostics.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LinkStats {
    /// Datagrams received from the socket (before fault injection).
    pub rx_datagrams: u64,
    /// Incoming datagrams discarded by injected loss or a link drop.
    pub rx_dropped_by_fault: u64,
    /// Incoming datagrams delivered twice by the duplicate fault (counted once each).
    pub rx_duplicated: u64,
    /// Incoming datagram copies held back by the reorder fault.
    pub rx_reordered: u64,
    /// Messages decoded and handed to the autopilot.
    pub rx_messages: u64,
    /// Frames refused for a missing or wrong signature.
    pub rx_bad_signature: u64,
    /// Well-framed messages outside the common dialect (or with bad enums).
    pub rx_undecodable: u64,
    /// Datagrams sent (one per message per destination).
    pub tx_datagrams: u64,
    /// Outgoing messages discarded by injected loss or a link drop.
    pub tx_dropped_by_fault: u64,
    /// Outgoing messages sent twice by the duplicate fault (counted once each).
    pub tx_duplicated: u64,
    /// Outgoing message copies held back by the reorder fault.
    pub tx_reordered: u64,
    /// Sends the OS refused (buffer full, unreachable).
    pub tx_errors: u64,
}

#[derive(Default)]
struct AtomicStats {
    rx_datagrams: AtomicU64,
    rx_dropped_by_fault: AtomicU64,
    rx_duplicated: AtomicU64,
    rx_reordered: AtomicU64,
    rx_messages: AtomicU64,
    rx_bad_signature: AtomicU64,
    rx_undecodable: AtomicU64,
    tx_datagrams: AtomicU64,
    tx_dropped_by_fault: AtomicU64,
    tx_duplicated: AtomicU64,
    tx_reordered: AtomicU64,
    tx_errors: AtomicU64,
}

fn bump(counter: &AtomicU64, by: u64) {
    counter.fetch_add(by, Ordering::Relaxed);
}

/// A datagram held back by the latency or reorder fault.
pub(crate) struct Delayed {
    due: Instant,
    bytes: Vec<u8>,
    /// Destinations (outgoing) or the sender (incoming).
    addresses: Vec<SocketAddr>,
}

/// Shortest and longest hold-back of a reordered datagram, milliseconds.
const REORDER_DELAY_MS: std::ops::RangeInclusive<u64> = 10..=60;

/// What the faults do to one datagram: the extra delay of each copy to
/// deliver (both `None` when it is lost; the second is the duplicate).
type Copies = [Option<Duration>; 2];

/// The counters of one direction.
struct DirectionStats<'a> {
    dropped: &'a AtomicU64,
    duplicated: &'a AtomicU64,
    reordered: &'a AtomicU64,
}

/// The link of one vehicle.
pub(crate) struct Link {
    system_id: u8,
    pub(crate) socket: Arc<UdpSocket>,
    pub(crate) local_address: SocketAddr,
    peer: Mutex<Option<SocketAddr>>,
    gcs: Option<SocketAddr>,
    loss_fraction: f64,
    duplicate_fraction: f64,
    reorder_fraction: f64,
    latency: Duration,
    rng: Mutex<ChaCha8Rng>,
    down: AtomicBool,
    sequence: AtomicU8,
    signing: Option<Signing>,
    stats: AtomicStats,
    delayed_tx: Option<mpsc::UnboundedSender<Delayed>>,
}

/// Component id every outgoing message carries (the autopilot).
const AUTOPILOT_COMPONENT_ID: u8 = crate::commands::AUTOPILOT_COMPONENT_ID;

impl Link {
    /// Wraps a bound socket. `delayed_tx` carries outgoing datagrams to the
    /// delay task; it must be set when [`needs_delay_queue`] is true.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        system_id: u8,
        socket: Arc<UdpSocket>,
        local_address: SocketAddr,
        gcs: Option<SocketAddr>,
        faults: &Faults,
        seed: u64,
        signing_key: Option<[u8; 32]>,
        delayed_tx: Option<mpsc::UnboundedSender<Delayed>>,
    ) -> Self {
        Self {
            system_id,
            socket,
            local_address,
            peer: Mutex::new(None),
            gcs,
            loss_fraction: faults.loss_percent / 100.0,
            duplicate_fraction: faults.duplicate_percent / 100.0,
            reorder_fraction: faults.reorder_percent / 100.0,
            latency: faults.latency,
            rng: Mutex::new(ChaCha8Rng::seed_from_u64(seed ^ 0x1055_1055)),
            down: AtomicBool::new(false),
            sequence: AtomicU8::new(0),
            signing: signing_key.map(Signing::new),
            stats: AtomicStats::default(),
            delayed_tx,
        }
    }

    /// Cuts or restores the link (driven by the link-drop fault).
    pub(crate) fn set_down(&self, down: bool) {
        self.down.store(down, Ordering::Relaxed);
    }

    /// Whether the link is cut.
    pub(crate) fn is_down(&self) -> bool {
        self.down.load(Ordering::Relaxed)
    }

    /// Draws an event of probability `fraction`, deterministically per seed.
    /// A zero fraction draws nothing, so a fault that is off leaves the
    /// draws of the others exactly as they were before it existed.
    fn draw(&self, fraction: f64) -> bool {
        if fraction <= 0.0 {
            return false;
        }
        let mut rng = self.rng.lock().unwrap_or_else(PoisonError::into_inner);
        rng.random::<f64>() < fraction
    }

    /// Extra delay of one copy: the latency, plus a random hold-back if the
    /// reorder fault picks it.
    fn copy_delay(&self, reordered: &AtomicU64) -> Duration {
        if !self.draw(self.reorder_fraction) {
            return self.latency;
        }
        bump(reordered, 1);
        let mut rng = self.rng.lock().unwrap_or_else(PoisonError::into_inner);
        self.latency + Duration::from_millis(rng.random_range(REORDER_DELAY_MS))
    }

    /// Applies drop, loss, duplication and reordering to one datagram.
    fn copies(&self, stats: DirectionStats<'_>) -> Copies {
        if self.is_down() || self.draw(self.loss_fraction) {
            bump(stats.dropped, 1);
            return [None, None];
        }
        let first = Some(self.copy_delay(stats.reordered));
        let second = if self.draw(self.duplicate_fraction) {
            bump(stats.duplicated, 1);
            Some(self.copy_delay(stats.reordered))
        } else {
            None
        };
        [first, second]
    }

    /// Current counters.
    pub(crate) fn stats(&self) -> LinkStats {
        let s = &self.stats;
        let get = |c: &AtomicU64| c.load(Ordering::Relaxed);
        LinkStats {
            rx_datagrams: get(&s.rx_datagrams),
            rx_dropped_by_fault: get(&s.rx_dropped_by_fault),
            rx_duplicated: get(&s.rx_duplicated),
            rx_reordered: get(&s.rx_reordered),
            rx_messages: get(&s.rx_messages),
            rx_bad_signature: get(&s.rx_bad_signature),
            rx_undecodable: get(&s.rx_undecodable),
            tx_datagrams: get(&s.tx_datagrams),
            tx_dropped_by_fault: get(&s.tx_dropped_by_fault),
            tx_duplicated: get(&s.tx_duplicated),
            tx_reordered: get(&s.tx_reordered),
            tx_errors: get(&s.tx_errors),
        }
    }

    /// Incoming side of fault injection: the extra delay of each copy of
    /// the datagram to deliver (none if it is lost).
    pub(crate) fn admit_incoming(&self) -> Copies {
        bump(&self.stats.rx_datagrams, 1);
        self.copies(DirectionStats {
            dropped: &self.stats.rx_dropped_by_fault,
            duplicated: &self.stats.rx_duplicated,
            reordered: &self.stats.rx_reordered,
        })
    }

    /// Decodes a datagram that survived the faults; the sender becomes the
    /// peer if it contained at least one acceptable message.
    pub(crate) fn decode(&self, datagram: &[u8], from: SocketAddr) -> Vec<(MavHeader, MavMessage)> {
        let decoded = codec::decode(datagram, self.signing.as_ref());
        for rejection in &decoded.rejected {
            match rejection {
                Rejection::BadSignature => bump(&self.stats.rx_bad_signature, 1),
                Rejection::Undecodable { .. } => bump(&self.stats.rx_undecodable, 1),
            }
        }
        if !decoded.messages.is_empty() {
            bump(&self.stats.rx_messages, decoded.messages.len() as u64);
            *self.peer.lock().unwrap_or_else(PoisonError::into_inner) = Some(from);
        }
        decoded.messages
    }

    /// Frames and sends messages to the peer and the ground-station port,
    /// applying loss, link drop, duplication, reordering and latency.
    pub(crate) fn send(&self, messages: &[MavMessage]) {
        if messages.is_empty() {
            return;
        }
        let mut addresses: Vec<SocketAddr> = Vec::with_capacity(2);
        if let Some(peer) = *self.peer.lock().unwrap_or_else(PoisonError::into_inner) {
            addresses.push(peer);
        }
        if let Some(gcs) = self.gcs
            && !addresses.contains(&gcs)
        {
            addresses.push(gcs);
        }
        for message in messages {
            let header = MavHeader {
                system_id: u32::from(self.system_id),
                component_id: AUTOPILOT_COMPONENT_ID,
                sequence: self.sequence.fetch_add(1, Ordering::Relaxed),
            };
            if addresses.is_empty() {
                continue; // nobody to talk to yet; the sequence still advances
            }
            let copies = self.copies(DirectionStats {
                dropped: &self.stats.tx_dropped_by_fault,
                duplicated: &self.stats.tx_duplicated,
                reordered: &self.stats.tx_reordered,
            });
            if copies[0].is_none() {
                continue;
            }
            let bytes = codec::encode(header, message, self.signing.as_ref());
            for delay in copies.into_iter().flatten() {
                match &self.delayed_tx {
                    Some(queue) if !delay.is_zero() => {
                        // A closed queue means the swarm is shutting down: dropping is right.
                        let _ = queue.send(Delayed {
                            due: due_after(delay),
                            bytes: bytes.clone(),
                            addresses: addresses.clone(),
                        });
                    }
                    _ => self.send_now(&bytes, &addresses),
                }
            }
        }
    }

    /// Sends one datagram to each address without waiting (UDP never blocks
    /// for long; a full buffer is counted as an error, like a lost packet).
    pub(crate) fn send_now(&self, bytes: &[u8], addresses: &[SocketAddr]) {
        for address in addresses {
            match self.socket.try_send_to(bytes, *address) {
                Ok(_) => bump(&self.stats.tx_datagrams, 1),
                Err(_) => bump(&self.stats.tx_errors, 1),
            }
        }
    }
}

/// Whether a vehicle with these faults needs delay queues (latency or reordering).
pub(crate) fn needs_delay_queue(faults: &Faults) -> bool {
    !faults.latency.is_zero() || faults.reorder_percent > 0.0
}

/// `delay` from now, saturating far in the future instead of overflowing
/// (latency is validated to at most an hour, so this never really saturates).
fn due_after(delay: Duration) -> Instant {
    let now = Instant::now();
    now.checked_add(delay)
        .unwrap_or_else(|| now + Duration::from_secs(86_400 * 365))
}

/// Queues an incoming datagram for delivery after `delay`.
pub(crate) fn delay_incoming(
    queue: &mpsc::UnboundedSender<Delayed>,
    delay: Duration,
    bytes: Vec<u8>,
    from: SocketAddr,
) {
    let _ = queue.send(Delayed {
        due: due_after(delay),
        bytes,
        addresses: vec![from],
    });
}

/// A queued datagram ordered by due time, then by arrival (a min-heap entry).
struct Pending {
    due: Instant,
    arrival: u64,
    item: Delayed,
}

impl PartialEq for Pending {
    fn eq(&self, other: &Self) -> bool {
        (self.due, self.arrival) == (other.due, other.arrival)
    }
}

impl Eq for Pending {}

impl PartialOrd for Pending {
    fn partial_cmp(&self, other: &Self) -> Option<CmpOrdering> {
        Some(self.cmp(other))
    }
}

impl Ord for Pending {
    /// Reversed, so `BinaryHeap` pops the earliest due datagram first.
    fn cmp(&self, other: &Self) -> CmpOrdering {
        (other.due, other.arrival).cmp(&(self.due, self.arrival))
    }
}

/// Runs one direction's delay queue: hands each datagram (bytes and
/// addresses) to `handle` when it is due, earliest first, so a datagram
/// held back longer is overtaken by later ones. Returns once the queue is
/// closed and empty.
pub(crate) async fn run_delay_queue(
    mut queue: mpsc::UnboundedReceiver<Delayed>,
    mut handle: impl FnMut(Vec<u8>, Vec<SocketAddr>),
) {
    let mut pending: BinaryHeap<Pending> = BinaryHeap::new();
    let mut arrivals: u64 = 0;
    let mut open = true;
    loop {
        if !open && pending.is_empty() {
            return;
        }
        let next_due = pending.peek().map(|p| p.due);
        tokio::select! {
            received = queue.recv(), if open => match received {
                Some(item) => {
                    pending.push(Pending { due: item.due, arrival: arrivals, item });
                    arrivals += 1;
                }
                None => open = false,
            },
            () = tokio::time::sleep_until(next_due.unwrap_or_else(Instant::now)), if next_due.is_some() => {
                let now = Instant::now();
                while let Some(top) = pending.peek_mut() {
                    if top.due > now {
                        break;
                    }
                    let Pending { item, .. } = PeekMut::pop(top);
                    handle(item.bytes, item.addresses);
                }
            }
        }
    }
}
