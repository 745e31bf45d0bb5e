//! The bundled simulator's truth, carried out of relay processes: a relay that
//! runs simulated vehicles publishes their true states, and a [`TruthWatch`]
//! anywhere on the Zenoh network measures the whole swarm's separation and speed
//! from them — independently of the telemetry the controller flew on.
//!
//! Payload: one record per vehicle, `[id length: u8][id: UTF-8][position NED m:
//! 3 × f32 LE][velocity NED m/s: 3 × f32 LE]`, in the mission's NED frame.
//! States from different relays are paired as last received, so a pair across
//! relays may be up to one publishing period apart (50 ms at 20 Hz: 5 cm at
//! 1 m/s), which the reports below do not hide: they say what they compared.

use crate::error::RelayError;
use crate::keys::KeySpace;
use crate::relay::declare_error;
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};
use std::time::Duration;
use swarmctl::world::Separation;
use swarmctl_sitl::truth;
use tokio::task::JoinHandle;
use zenoh::pubsub::Subscriber;

/// One vehicle's true state.
#[derive(Debug, Clone, PartialEq)]
pub struct TruthRecord {
    /// The mission's drone id.
    pub drone: String,
    /// Position, mission NED metres.
    pub position_ned_m: [f32; 3],
    /// Velocity, NED metres per second.
    pub velocity_ned_mps: [f32; 3],
}

/// The records as one payload.
pub fn encode(records: &[TruthRecord]) -> Vec<u8> {
    let mut out = Vec::with_capacity(records.len() * 32);
    for r in records {
        let id = r.drone.as_bytes();
        let len = u8::try_from(id.len()).unwrap_or(u8::MAX);
        out.push(len);
        out.extend_from_slice(&id[..usize::from(len)]);
        for v in r.position_ned_m.iter().chain(&r.velocity_ned_mps) {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out
}

/// The records in a payload; `None` if it is not one.
pub fn decode(mut bytes: &[u8]) -> Option<Vec<TruthRecord>> {
    let mut out = Vec::new();
    while let Some((&len, rest)) = bytes.split_first() {
        let id = rest.get(..usize::from(len))?;
        let rest = &rest[usize::from(len)..];
        let floats = rest.get(..24)?;
        let f = |i: usize| {
            let mut b = [0u8; 4];
            b.copy_from_slice(&floats[i * 4..i * 4 + 4]);
            f32::from_le_bytes(b)
        };
        out.push(TruthRecord {
            drone: String::from_utf8(id.to_vec()).ok()?,
            position_ned_m: [f(0), f(1), f(2)],
            velocity_ned_mps: [f(3), f(4), f(5)],
        });
        bytes = &rest[24..];
    }
    Some(out)
}

/// Publishes `sample()` on relay `relay`'s truth key at `rate_hz` until aborted.
pub async fn publish(
    session: &zenoh::Session,
    keys: &KeySpace,
    relay: &str,
    rate_hz: f64,
    sample: impl Fn() -> Vec<TruthRecord> + Send + 'static,
) -> Result<JoinHandle<()>, RelayError> {
    let key = keys.truth(relay);
    let publisher = session
        .declare_publisher(key.clone())
        .await
        .map_err(|e| declare_error(&key, e))?;
    let period = Duration::from_secs_f64(1.0 / rate_hz.clamp(1.0, 100.0));
    Ok(tokio::spawn(async move {
        let mut tick = tokio::time::interval(period);
        loop {
            tick.tick().await;
            if publisher.put(encode(&sample())).await.is_err() {
                return;
            }
        }
    }))
}

/// What the truth showed over a watch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruthReport {
    /// Smallest distance between two airborne vehicles, metres (∞: never two up).
    pub min_separation_m: f64,
    /// Smallest scaled separation under the mission's ellipsoid (separated at
    /// 1; `None` for a sphere mission).
    pub min_scaled_separation: Option<f64>,
    /// Largest true speed of any vehicle, m/s.
    pub top_speed_mps: f64,
    /// Times the whole swarm was compared.
    pub comparisons: u64,
    /// Vehicles in the latest comparison.
    pub vehicles: usize,
}

#[derive(Debug)]
struct Watched {
    latest: BTreeMap<String, Vec<TruthRecord>>,
    report: TruthReport,
}

/// Watches every relay's truth and keeps the swarm's worst figures.
pub struct TruthWatch {
    state: Arc<Mutex<Watched>>,
    _subscriber: Subscriber<()>,
    task: JoinHandle<()>,
}

impl Drop for TruthWatch {
    fn drop(&mut self) {
        self.task.abort();
    }
}

impl TruthWatch {
    /// Starts watching mission `keys`' truth on `session`, comparing the latest
    /// states of every relay `rate_hz` times a second (under `ellipsoid` too,
    /// when the mission has one).
    pub async fn start(
        session: &zenoh::Session,
        keys: &KeySpace,
        ellipsoid: Option<Separation>,
        rate_hz: f64,
    ) -> Result<TruthWatch, RelayError> {
        let state = Arc::new(Mutex::new(Watched {
            latest: BTreeMap::new(),
            report: TruthReport {
                min_separation_m: f64::INFINITY,
                min_scaled_separation: ellipsoid.map(|_| f64::INFINITY),
                top_speed_mps: 0.0,
                comparisons: 0,
                vehicles: 0,
            },
        }));
        let key = keys.all_truth();
        let inbox = state.clone();
        let subscriber = session
            .declare_subscriber(key.clone())
            .callback(move |sample| {
                let relay = sample
                    .key_expr()
                    .as_str()
                    .rsplit('/')
                    .next()
                    .unwrap_or("")
                    .to_string();
                if let Some(records) = decode(&sample.payload().to_bytes()) {
                    let mut s = inbox.lock().unwrap_or_else(|e| e.into_inner());
                    s.latest.insert(relay, records);
                }
            })
            .await
            .map_err(|e| declare_error(&key, e))?;
        let compare = state.clone();
        let period = Duration::from_secs_f64(1.0 / rate_hz.clamp(1.0, 100.0));
        let task = tokio::spawn(async move {
            let mut tick = tokio::time::interval(period);
            let mut airborne: Vec<[f32; 3]> = Vec::new();
            loop {
                tick.tick().await;
                let mut s = compare.lock().unwrap_or_else(|e| e.into_inner());
                airborne.clear();
                let mut vehicles = 0;
                let mut top_speed_mps: f32 = 0.0;
                for r in s.latest.values().flatten() {
                    vehicles += 1;
                    let speed = r.velocity_ned_mps.iter().map(|v| v * v).sum::<f32>().sqrt();
                    top_speed_mps = top_speed_mps.max(speed);
                    // On the ground, close pairs are parked, not a separation
                    // loss (as the in-process truth counts).
                    if truth::is_airborne(&r.position_ned_m) {
                        airborne.push(r.position_ned_m);
                    }
                }
                s.report.top_speed_mps = s.report.top_speed_mps.max(f64::from(top_speed_mps));
                let min_m = truth::min_separation_m(&airborne);
                let min_scaled = ellipsoid
                    .as_ref()
                    .map(|e| truth::min_scaled_separation(&airborne, |d| e.scaled(d)));
                let report = &mut s.report;
                report.min_separation_m = report.min_separation_m.min(min_m);
                if let (Some(worst), Some(now)) =
                    (report.min_scaled_separation.as_mut(), min_scaled)
                {
                    *worst = worst.min(now);
                }
                report.comparisons += 1;
                report.vehicles = vehicles;
            }
        });
        Ok(TruthWatch {
            state,
            _subscriber: subscriber,
            task,
        })
    }

    /// The worst figures so far.
    pub fn report(&self) -> TruthReport {
        self.state.lock().unwrap_or_else(|e| e.into_inner()).report
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_round_trip_and_truncated_payloads_do_not_decode() {
        let records = vec![
            TruthRecord {
                drone: "d1".into(),
                position_ned_m: [1.0, 2.0, -3.0],
                velocity_ned_mps: [0.5, 0.0, 0.0],
            },
            TruthRecord {
                drone: "south-7".into(),
                position_ned_m: [-1.0, 0.25, 0.0],
                velocity_ned_mps: [0.0, 0.0, -1.0],
            },
        ];
        let bytes = encode(&records);
        assert_eq!(decode(&bytes), Some(records));
        assert_eq!(decode(&bytes[..bytes.len() - 1]), None);
        assert_eq!(decode(&[]), Some(Vec::new()));
    }
}
