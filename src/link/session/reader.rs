//! The session's reader task: every message the vehicle sends is folded into
//! its [`VehicleState`], and the COMMAND_ACKs go to whoever waits on a command.

use crate::link::receive;
use crate::link::telemetry::VehicleState;
use crate::link::transport::{Received, Transport};
use mavlink::dialects::common::COMMAND_ACK_DATA;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use tokio::sync::broadcast;

/// Reads forever, folding every decoded message into `state` with
/// [`receive::fold`] (which drops anything not from `system_id`) and passing the
/// COMMAND_ACKs meant for us to whoever waits on a command.
pub(super) async fn read_loop(
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
