//! One vehicle's UDP link: answers whoever spoke last (plus an optional
//! ground-station port) and injects the link faults — loss, latency, drops.

use crate::codec::{self, Rejection, Signing};
use mavlink::MavHeader;
use mavlink::dialects::common::MavMessage;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
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
    /// Sends the OS refused (buffer full, unreachable).
    pub tx_errors: u64,
}

#[derive(Default)]
struct AtomicStats {
    rx_datagrams: AtomicU64,
    rx_dropped_by_fault: AtomicU64,
    rx_messages: AtomicU64,
    rx_bad_signature: AtomicU64,
    rx_undecodable: AtomicU64,
    tx_datagrams: AtomicU64,
    tx_dropped_by_fault: AtomicU64,
    tx_errors: AtomicU64,
}

fn bump(counter: &AtomicU64, by: u64) {
    counter.fetch_add(by, Ordering::Relaxed);
}

/// A datagram held back by the latency fault.
pub(crate) struct Delayed {
    due: Instant,
    bytes: Vec<u8>,
    /// Destinations (outgoing) or the sender (incoming).
    addresses: Vec<SocketAddr>,
}

/// The link of one vehicle.
pub(crate) struct Link {
    system_id: u8,
    pub(crate) socket: Arc<UdpSocket>,
    pub(crate) local_address: SocketAddr,
    peer: Mutex<Option<SocketAddr>>,
    gcs: Option<SocketAddr>,
    loss_fraction: f64,
    pub(crate) latency: Duration,
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
    /// latency task when the latency fault is set.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        system_id: u8,
        socket: Arc<UdpSocket>,
        local_address: SocketAddr,
        gcs: Option<SocketAddr>,
        loss_percent: f64,
        latency: Duration,
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
            loss_fraction: loss_percent / 100.0,
            latency,
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

    /// Draws whether a packet is lost to the loss fault (deterministic per seed).
    fn lose(&self) -> bool {
        if self.loss_fraction <= 0.0 {
            return false;
        }
        let mut rng = self.rng.lock().unwrap_or_else(PoisonError::into_inner);
        rng.random::<f64>() < self.loss_fraction
    }

    /// Current counters.
    pub(crate) fn stats(&self) -> LinkStats {
        let s = &self.stats;
        let get = |c: &AtomicU64| c.load(Ordering::Relaxed);
        LinkStats {
            rx_datagrams: get(&s.rx_datagrams),
            rx_dropped_by_fault: get(&s.rx_dropped_by_fault),
            rx_messages: get(&s.rx_messages),
            rx_bad_signature: get(&s.rx_bad_signature),
            rx_undecodable: get(&s.rx_undecodable),
            tx_datagrams: get(&s.tx_datagrams),
            tx_dropped_by_fault: get(&s.tx_dropped_by_fault),
            tx_errors: get(&s.tx_errors),
        }
    }

    /// Incoming side of fault injection: true if the datagram survives.
    pub(crate) fn admit_incoming(&self) -> bool {
        bump(&self.stats.rx_datagrams, 1);
        if self.is_down() || self.lose() {
            bump(&self.stats.rx_dropped_by_fault, 1);
            return false;
        }
        true
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
    /// applying loss, link drop and latency.
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
            if self.is_down() || self.lose() {
                bump(&self.stats.tx_dropped_by_fault, 1);
                continue;
            }
            let bytes = codec::encode(header, message, self.signing.as_ref());
            match &self.delayed_tx {
                Some(queue) if !self.latency.is_zero() => {
                    let due = Instant::now() + self.latency;
                    // A closed queue means the swarm is shutting down: dropping is right.
                    let _ = queue.send(Delayed {
                        due,
                        bytes,
                        addresses: addresses.clone(),
                    });
                }
                _ => self.send_now(&bytes, &addresses),
            }
        }
    }

    /// Sends one datagram to each address without waiting (UDP never blocks
    /// for long; a full buffer is counted as an error, like a lost packet).
    fn send_now(&self, bytes: &[u8], addresses: &[SocketAddr]) {
        for address in addresses {
            match self.socket.try_send_to(bytes, *address) {
                Ok(_) => bump(&self.stats.tx_datagrams, 1),
                Err(_) => bump(&self.stats.tx_errors, 1),
            }
        }
    }

    /// Runs the outgoing latency queue: sends each datagram when it is due.
    pub(crate) async fn run_delayed_tx(
        self: Arc<Self>,
        mut queue: mpsc::UnboundedReceiver<Delayed>,
    ) {
        while let Some(item) = queue.recv().await {
            tokio::time::sleep_until(item.due).await;
            self.send_now(&item.bytes, &item.addresses);
        }
    }
}

/// Queues an incoming datagram for delivery after the latency fault.
pub(crate) fn delay_incoming(
    queue: &mpsc::UnboundedSender<Delayed>,
    latency: Duration,
    bytes: Vec<u8>,
    from: SocketAddr,
) {
    let _ = queue.send(Delayed {
        due: Instant::now() + latency,
        bytes,
        addresses: vec![from],
    });
}

/// Waits until a delayed incoming datagram is due; `None` when the queue closed.
pub(crate) async fn next_delayed(
    queue: &mut mpsc::UnboundedReceiver<Delayed>,
) -> Option<(Vec<u8>, SocketAddr)> {
    let item = queue.recv().await?;
    tokio::time::sleep_until(item.due).await;
    let from = item.addresses.first().copied()?;
    Some((item.bytes, from))
}
