//! The simulators' truth, measured apart from swarmctl: each firmware's simulated
//! position and velocity as it reports them on a link of its own, turned into
//! mission ENU metres with geodesy written here (not swarmctl's), so the check
//! shares no code with what it checks.

use mavlink::dialects::common::{COMMAND_LONG_DATA, MavCmd, MavMessage, MavModeFlag};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use swarmctl::mission::Geodetic;

/// One true state as it arrived: latitude and longitude (degrees), altitude
/// (metres AMSL) and velocity north, east, down (m/s).
#[derive(Debug, Clone, Copy)]
pub struct TruthSample {
    pub at: Instant,
    pub lat_deg: f64,
    pub lon_deg: f64,
    pub alt_m: f64,
    pub velocity_ned_mps: [f64; 3],
}

/// One vehicle's true states, filled by its reader task.
pub type Track = Arc<Mutex<Vec<TruthSample>>>;

/// Metres east, north, up of a sample from `origin`, on a local flat earth with the
/// WGS84 radii of curvature (centimetre-exact over a few hundred metres).
pub fn enu_m(origin: &Geodetic, s: &TruthSample) -> [f64; 3] {
    const A_M: f64 = 6_378_137.0;
    const E2: f64 = 6.694_379_990_14e-3;
    let lat0 = origin.lat_deg.to_radians();
    let w2 = 1.0 - E2 * lat0.sin().powi(2);
    let prime_m = A_M / w2.sqrt();
    let meridian_m = prime_m * (1.0 - E2) / w2;
    [
        (s.lon_deg - origin.lon_deg).to_radians() * prime_m * lat0.cos(),
        (s.lat_deg - origin.lat_deg).to_radians() * meridian_m,
        s.alt_m - origin.alt_m,
    ]
}

/// Connects to `address` (retrying until `stop`: the firmware opens its ports a
/// moment after it starts), asks `system_id` for message `message_id` every 20 ms
/// (again every 2 s, as a firmware may drop a request it got before it was ready),
/// and pushes what `sample` makes of each message it receives onto `track` until
/// `stop`.
pub async fn read(
    address: String,
    system_id: u8,
    message_id: u32,
    sample: impl Fn(&MavMessage, Instant) -> Option<TruthSample>,
    track: Track,
    armed_seen: Arc<AtomicBool>,
    stop: Instant,
) {
    use mavlink::AsyncMavConnection;
    let connection = loop {
        match mavlink::connect_async::<MavMessage>(&address).await {
            Ok(c) => break c,
            Err(_) if Instant::now() < stop => tokio::time::sleep(Duration::from_secs(1)).await,
            Err(e) => panic!("no truth link to {address}: {e}"),
        }
    };
    let header = mavlink::MavHeader {
        system_id: 251,
        component_id: 190,
        sequence: 0,
    };
    let ask = MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        target_system: system_id,
        target_component: 1,
        command: MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
        confirmation: 0,
        param1: message_id as f32,
        param2: 20_000.0,
        param3: 0.0,
        param4: 0.0,
        param5: 0.0,
        param6: 0.0,
        param7: 0.0,
    });
    let mut asked_at: Option<Instant> = None;
    while Instant::now() < stop {
        if asked_at.is_none_or(|t| t.elapsed() > Duration::from_secs(2)) {
            let _ = connection.send(&header, &ask).await;
            asked_at = Some(Instant::now());
        }
        let Ok(Ok((from, message))) =
            tokio::time::timeout(Duration::from_millis(500), connection.recv()).await
        else {
            continue;
        };
        // The autopilot's own word on a link swarmctl never speaks over.
        if let MavMessage::HEARTBEAT(h) = &message
            && from.system_id == u32::from(system_id)
            && from.component_id == 1
            && h.base_mode
                .contains(MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED)
        {
            armed_seen.store(true, Ordering::Relaxed);
        }
        if let Some(s) = sample(&message, Instant::now()) {
            track.lock().unwrap().push(s);
        }
    }
}

fn distance_m(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// What the truth says about a whole flight.
#[derive(Debug)]
pub struct Figures {
    /// Smallest distance between two vehicles, metres, and the pair (by index).
    pub min_separation_m: f64,
    pub closest_pair: (usize, usize),
    /// Highest speed of any vehicle, m/s, and which.
    pub top_speed_mps: f64,
    pub fastest: usize,
    /// The sample the top speed was read from (`None` without samples).
    pub top_speed_sample: Option<TruthSample>,
    /// Where each vehicle was at the end, ENU metres.
    pub final_enu_m: Vec<[f64; 3]>,
    /// Samples read in all.
    pub samples: usize,
}

/// Separation every 20 ms from the first time all vehicles have a sample to the
/// last sample of any (each vehicle at its latest state), top speed, and the
/// final positions.
pub fn figures(origin: &Geodetic, tracks: &[Track]) -> Figures {
    let tracks: Vec<Vec<TruthSample>> = tracks.iter().map(|t| t.lock().unwrap().clone()).collect();
    let samples = tracks.iter().map(Vec::len).sum();
    let start = tracks.iter().filter_map(|t| t.first()).map(|s| s.at).max();
    let end = tracks.iter().filter_map(|t| t.last()).map(|s| s.at).max();
    let mut out = Figures {
        min_separation_m: f64::INFINITY,
        closest_pair: (0, 0),
        top_speed_mps: 0.0,
        fastest: 0,
        top_speed_sample: None,
        final_enu_m: tracks
            .iter()
            .map(|t| t.last().map_or([f64::NAN; 3], |s| enu_m(origin, s)))
            .collect(),
        samples,
    };
    let (Some(start), Some(end)) = (start, end) else {
        return out;
    };
    let mut cursor = vec![0usize; tracks.len()];
    let mut t = start;
    while t <= end {
        let at: Vec<[f64; 3]> = tracks
            .iter()
            .zip(&mut cursor)
            .map(|(track, k)| {
                while *k + 1 < track.len() && track[*k + 1].at <= t {
                    *k += 1;
                }
                enu_m(origin, &track[*k])
            })
            .collect();
        for (i, a) in at.iter().enumerate() {
            for (j, b) in at.iter().enumerate().skip(i + 1) {
                let d = distance_m(*a, *b);
                if d < out.min_separation_m {
                    out.min_separation_m = d;
                    out.closest_pair = (i, j);
                }
            }
        }
        t += Duration::from_millis(20);
    }
    for (i, track) in tracks.iter().enumerate() {
        for s in track {
            let v = s.velocity_ned_mps;
            let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if speed > out.top_speed_mps {
                out.top_speed_mps = speed;
                out.fastest = i;
                out.top_speed_sample = Some(*s);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tenth_of_a_millidegree_north_is_eleven_metres() {
        let origin = Geodetic {
            lat_deg: -35.363261,
            lon_deg: 149.16523,
            alt_m: 584.0,
        };
        let s = TruthSample {
            at: Instant::now(),
            lat_deg: origin.lat_deg + 1e-4,
            lon_deg: origin.lon_deg + 1e-4,
            alt_m: 585.5,
            velocity_ned_mps: [0.0; 3],
        };
        let p = enu_m(&origin, &s);
        // One arc-degree of latitude at 35° S is 110.95 km, of longitude 90.94 km.
        assert!((p[1] - 11.095).abs() < 0.01, "{p:?}");
        assert!((p[0] - 9.094).abs() < 0.01, "{p:?}");
        assert!((p[2] - 1.5).abs() < 1e-9);
    }
}
