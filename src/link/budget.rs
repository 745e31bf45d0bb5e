//! The link budget: what a flight puts on each vehicle's link every second, and
//! whether the mission's radios (`link.radios`) can carry it.
//!
//! A session sends, per drone, one `SET_POSITION_TARGET_LOCAL_NED` each setpoint
//! period and a ground-station `HEARTBEAT` a second; it asks the vehicle for the
//! three streams of [`telemetry_streams`] and, at pre-flight, turns every other
//! periodic message off, so the vehicle sends those and its own `HEARTBEAT`.
//! Each is a MAVLink 2 frame: 10 header bytes, the payload, 2 CRC bytes and,
//! on a signed link, a 13-byte signature. MAVLink 2 drops a payload's trailing
//! zero bytes, so the full payload is an upper bound; the budget uses it.
//! Commands, acknowledgements, parameter reads and status text come in bursts
//! around takeoff and landing, not in the steady state the budget sizes: a radio
//! keeps [`RADIO_USABLE_FRACTION`] of its capacity for steady traffic, the rest
//! for them and the radio's own framing.
//!
//! A radio is shared by both directions (a SiK radio divides its air time
//! between them), so its load is every drone's uplink and downlink together.
//!
//! ```
//! let template = swarmctl::mission::TEMPLATE;
//! let mission = swarmctl::mission::from_yaml(template, "template.yaml".as_ref()).unwrap();
//! let budget = swarmctl::link::budget::Budget::of(&mission);
//! // 20 Hz setpoints: about 10.5 kbit/s up and 8 kbit/s down per drone.
//! assert!(budget.per_drone.up_kbps() > 10.0 && budget.per_drone.down_kbps() > 7.0);
//! ```

use crate::mission::{Mission, RadioSpec, SETPOINT_RATES_HZ};
use mavlink::MessageData;
use mavlink::dialects::common::{
    EXTENDED_SYS_STATE_DATA, HEARTBEAT_DATA, LOCAL_POSITION_NED_DATA,
    SET_POSITION_TARGET_LOCAL_NED_DATA, SYS_STATUS_DATA,
};

/// A MAVLink 2 frame's bytes around its payload: 10 of header, 2 of CRC.
pub const FRAME_OVERHEAD_B: usize = 12;
/// What signing adds to a MAVLink 2 frame: link id, timestamp, signature.
pub const SIGNATURE_B: usize = 13;
/// The share of a radio's capacity the steady traffic may take; the rest is
/// for the radio's own framing and for bursts of commands and parameters.
pub const RADIO_USABLE_FRACTION: f64 = 0.9;
/// The landed state is asked for this often, Hz: takeoff and touchdown are
/// confirmed from it.
const LANDED_STATE_RATE_HZ: f64 = 5.0;
/// Health (pre-arm checks, battery) is asked for this often, Hz.
const HEALTH_RATE_HZ: f64 = 1.0;
/// Both ends send a heartbeat this often, Hz (MAVLink's convention).
const HEARTBEAT_RATE_HZ: f64 = 1.0;

/// One periodic message on a link.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flow {
    /// The MAVLink message's name.
    pub message: &'static str,
    /// Its MAVLink id.
    pub message_id: u32,
    /// Its frame's size with the full payload (and the signature when signed), bytes.
    pub frame_bytes: usize,
    /// How often it is sent, Hz.
    pub rate_hz: f64,
}

impl Flow {
    fn of<M: MessageData>(rate_hz: f64, signed: bool) -> Flow {
        Flow {
            message: M::NAME,
            message_id: M::ID,
            frame_bytes: frame_bytes(M::ENCODED_LEN, signed),
            rate_hz,
        }
    }

    /// What it takes of the link, kbit/s.
    pub fn kbps(&self) -> f64 {
        self.frame_bytes as f64 * 8.0 * self.rate_hz / 1000.0
    }
}

/// A MAVLink 2 frame's size for a payload of `payload_bytes`, bytes.
pub fn frame_bytes(payload_bytes: usize, signed: bool) -> usize {
    FRAME_OVERHEAD_B + payload_bytes + if signed { SIGNATURE_B } else { 0 }
}

/// The telemetry a session asks each vehicle for (message id, rate in Hz): its
/// position at `position_rate_hz`, its landed state and its health. Everything
/// else periodic is turned off at pre-flight.
pub fn telemetry_streams(position_rate_hz: f64) -> [(u32, f64); 3] {
    [
        (LOCAL_POSITION_NED_DATA::ID, position_rate_hz),
        (EXTENDED_SYS_STATE_DATA::ID, LANDED_STATE_RATE_HZ),
        (SYS_STATUS_DATA::ID, HEALTH_RATE_HZ),
    ]
}

/// The periodic messages a vehicle may keep sending after pre-flight turned the
/// rest off: its heartbeat and the streams asked for.
pub fn kept_message_ids() -> [u32; 4] {
    let [a, b, c] = telemetry_streams(1.0).map(|(id, _)| id);
    [HEARTBEAT_DATA::ID, a, b, c]
}

/// One drone's steady traffic in flight, each way.
#[derive(Debug, Clone, PartialEq)]
pub struct DroneTraffic {
    /// From the controller to the vehicle.
    pub up: Vec<Flow>,
    /// From the vehicle to the controller.
    pub down: Vec<Flow>,
}

impl DroneTraffic {
    /// Setpoints at `setpoint_rate_hz`, position telemetry at
    /// `telemetry_rate_hz`, signed or not.
    pub fn new(setpoint_rate_hz: f64, telemetry_rate_hz: f64, signed: bool) -> DroneTraffic {
        let up = vec![
            Flow::of::<SET_POSITION_TARGET_LOCAL_NED_DATA>(setpoint_rate_hz, signed),
            Flow::of::<HEARTBEAT_DATA>(HEARTBEAT_RATE_HZ, signed),
        ];
        let streams = telemetry_streams(telemetry_rate_hz);
        let rate_of = |id: u32| {
            streams
                .iter()
                .find(|(i, _)| *i == id)
                .map_or(0.0, |(_, hz)| *hz)
        };
        let down = vec![
            Flow::of::<LOCAL_POSITION_NED_DATA>(rate_of(LOCAL_POSITION_NED_DATA::ID), signed),
            Flow::of::<EXTENDED_SYS_STATE_DATA>(rate_of(EXTENDED_SYS_STATE_DATA::ID), signed),
            Flow::of::<SYS_STATUS_DATA>(rate_of(SYS_STATUS_DATA::ID), signed),
            Flow::of::<HEARTBEAT_DATA>(HEARTBEAT_RATE_HZ, signed),
        ];
        DroneTraffic { up, down }
    }

    /// Controller to vehicle, kbit/s.
    pub fn up_kbps(&self) -> f64 {
        self.up.iter().map(Flow::kbps).sum()
    }

    /// Vehicle to controller, kbit/s.
    pub fn down_kbps(&self) -> f64 {
        self.down.iter().map(Flow::kbps).sum()
    }

    /// Both ways, kbit/s: what the drone takes of a shared radio.
    pub fn total_kbps(&self) -> f64 {
        self.up_kbps() + self.down_kbps()
    }
}

/// One radio's load.
#[derive(Debug, Clone, PartialEq)]
pub struct RadioLoad {
    /// The radio's name in the mission.
    pub name: String,
    /// How many drones it carries.
    pub drones: usize,
    /// Its capacity as written, kbit/s.
    pub capacity_kbps: f64,
    /// What the steady traffic may take of it, kbit/s.
    pub usable_kbps: f64,
    /// What its drones' steady traffic takes, kbit/s.
    pub load_kbps: f64,
}

impl RadioLoad {
    /// Whether the radio carries its drones' steady traffic.
    pub fn fits(&self) -> bool {
        self.load_kbps <= self.usable_kbps
    }
}

/// A mission's link budget.
#[derive(Debug, Clone, PartialEq)]
pub struct Budget {
    /// Every drone's steady traffic (all fly the same rates).
    pub per_drone: DroneTraffic,
    /// The mission's setpoint rate, Hz (telemetry comes at the same rate).
    pub setpoint_rate_hz: f64,
    /// The lowest setpoint rate its autopilot may be flown at, Hz
    /// ([`crate::mission::Autopilot::min_setpoint_rate_hz`]): no fix goes below it.
    pub min_setpoint_rate_hz: f64,
    /// Each radio of `link.radios`, in order.
    pub radios: Vec<RadioLoad>,
    /// Drones on no radio: each has a link of its own (Wi-Fi, loopback).
    pub own_links: usize,
}

impl Budget {
    /// The budget of `mission`: its setpoint rate (position telemetry at the
    /// same rate), its signing and its radios.
    pub fn of(mission: &Mission) -> Budget {
        let link = &mission.link;
        let rate_hz = link.setpoint_rate_hz;
        let per_drone = DroneTraffic::new(rate_hz, rate_hz, link.signing.is_some());
        let radios: Vec<RadioLoad> = link
            .radios
            .iter()
            .map(|r| load(r, per_drone.total_kbps()))
            .collect();
        let on_radios: usize = radios.iter().map(|r| r.drones).sum();
        Budget {
            per_drone,
            setpoint_rate_hz: rate_hz,
            min_setpoint_rate_hz: link
                .autopilot
                .min_setpoint_rate_hz()
                .max(*SETPOINT_RATES_HZ.start()),
            radios,
            own_links: mission.drone_count().saturating_sub(on_radios),
        }
    }

    /// One line per radio that cannot carry its drones, with the numbers and
    /// the fixes; empty when every radio fits.
    pub fn refusals(&self) -> Vec<String> {
        self.radios
            .iter()
            .filter(|r| !r.fits())
            .map(|r| self.refusal(r))
            .collect()
    }

    fn refusal(&self, radio: &RadioLoad) -> String {
        let per_kbps = self.per_drone.total_kbps();
        let mut fixes = Vec::new();
        if let Some(rate_hz) = self.fitting_rate_hz(radio) {
            fixes.push(format!("lower link.setpoint_rate_hz to {rate_hz}"));
        }
        let most = (radio.usable_kbps / per_kbps).floor() as usize;
        if most >= 1 {
            let radios = radio.drones.div_ceil(most);
            fixes.push(format!(
                "split {} into {radios} radios of at most {most} drones",
                radio.name
            ));
        } else {
            fixes.push(format!(
                "give {} more capacity than {:.1} kbit/s a drone",
                radio.name, per_kbps
            ));
        }
        format!(
            "radio {}: {} drones × {:.1} kbit/s = {:.1} kbit/s > {:.1} kbit/s usable ({:.0} % of {} kbit/s): {}",
            radio.name,
            radio.drones,
            per_kbps,
            radio.load_kbps,
            radio.usable_kbps,
            RADIO_USABLE_FRACTION * 100.0,
            radio.capacity_kbps,
            fixes.join(", or ")
        )
    }

    /// The highest whole (or, below 5, half) setpoint rate the mission's
    /// autopilot accepts at which `radio` carries its drones, if there is one.
    fn fitting_rate_hz(&self, radio: &RadioLoad) -> Option<f64> {
        let signed = self.per_drone.up.first().is_some_and(|f| {
            f.frame_bytes > frame_bytes(SET_POSITION_TARGET_LOCAL_NED_DATA::ENCODED_LEN, false)
        });
        let fits = |hz: f64| {
            radio.drones as f64 * DroneTraffic::new(hz, hz, signed).total_kbps()
                <= radio.usable_kbps
        };
        let mut hz = self.setpoint_rate_hz.floor();
        while hz >= self.min_setpoint_rate_hz {
            if fits(hz) {
                return Some(hz);
            }
            hz -= if hz > 5.0 { 1.0 } else { 0.5 };
        }
        None
    }
}

fn load(radio: &RadioSpec, per_drone_kbps: f64) -> RadioLoad {
    RadioLoad {
        name: radio.name.clone(),
        drones: radio.drones.len(),
        capacity_kbps: radio.capacity_kbps,
        usable_kbps: radio.capacity_kbps * RADIO_USABLE_FRACTION,
        load_kbps: radio.drones.len() as f64 * per_drone_kbps,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_mavlink2_sizes() {
        // SET_POSITION_TARGET_LOCAL_NED: 53-byte payload, 65 B framed, 78 B signed.
        let up = DroneTraffic::new(20.0, 20.0, false);
        assert_eq!(up.up[0].frame_bytes, 65);
        assert_eq!(DroneTraffic::new(20.0, 20.0, true).up[0].frame_bytes, 78);
        // 65 B × 20 Hz = 10.4 kbit/s, plus a 21 B heartbeat a second.
        assert!(
            (up.up_kbps() - (10.4 + 0.168)).abs() < 1e-9,
            "{}",
            up.up_kbps()
        );
        // LOCAL_POSITION_NED 40 B × 20, EXTENDED_SYS_STATE 14 B × 5,
        // SYS_STATUS (with its extensions) × 1, HEARTBEAT 21 B × 1.
        let sys_status = frame_bytes(SYS_STATUS_DATA::ENCODED_LEN, false) as f64;
        let expected_down = (40.0 * 20.0 + 14.0 * 5.0 + sys_status + 21.0) * 8.0 / 1000.0;
        assert!((up.down_kbps() - expected_down).abs() < 1e-9);
    }

    #[test]
    fn kept_ids_are_the_heartbeat_and_the_streams_asked_for() {
        assert_eq!(kept_message_ids(), [0, 32, 245, 1]);
    }
}
