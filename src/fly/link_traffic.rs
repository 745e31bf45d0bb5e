//! What each drone's link carried in flight, measured at the controller, beside
//! what the link budget (`link::budget`) said it would.

use crate::link::LinkBytes;
use crate::link::budget::DroneTraffic;
use serde::{Deserialize, Serialize};

/// One drone's link from arming to the end of the flight.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LinkTraffic {
    /// Bytes the controller sent the vehicle (whole MAVLink frames).
    pub sent_bytes: u64,
    /// Bytes the vehicle sent the controller (frames the link could read).
    pub received_bytes: u64,
    /// Over how long, seconds.
    pub over_s: f64,
    /// Measured uplink, kbit/s.
    pub up_kbps: f64,
    /// Measured downlink, kbit/s.
    pub down_kbps: f64,
    /// The budget's uplink for this drone, kbit/s.
    pub budget_up_kbps: f64,
    /// The budget's downlink for this drone, kbit/s.
    pub budget_down_kbps: f64,
}

impl LinkTraffic {
    /// The traffic `bytes` moved over `over_s` seconds, against `budget`.
    pub fn measured(bytes: LinkBytes, over_s: f64, budget: &DroneTraffic) -> LinkTraffic {
        let kbps = |b: u64| {
            if over_s > 0.0 {
                b as f64 * 8.0 / over_s / 1000.0
            } else {
                0.0
            }
        };
        LinkTraffic {
            sent_bytes: bytes.sent,
            received_bytes: bytes.received,
            over_s,
            up_kbps: kbps(bytes.sent),
            down_kbps: kbps(bytes.received),
            budget_up_kbps: budget.up_kbps(),
            budget_down_kbps: budget.down_kbps(),
        }
    }
}
