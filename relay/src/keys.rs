//! The Zenoh key space swarmctl's controller and relays share, in one place.
//!
//! ```text
//! swarmctl/<mission>/relays/<relay>                          liveliness: the relay is up
//! swarmctl/<mission>/drones/<drone>/served-by/<relay>/<sys>  liveliness: <relay> serves <drone>,
//!                                                            MAVLink system <sys> in its network
//! swarmctl/<mission>/drones/<drone>/setpoint                 controller → relay: position setpoints
//! swarmctl/<mission>/drones/<drone>/command                  controller → relay: every other frame
//! swarmctl/<mission>/drones/<drone>/telemetry                relay → controller: every vehicle frame
//! swarmctl/<mission>/truth/<relay>                           bundled simulator only: true states
//! ```
//!
//! Payloads of `setpoint`, `command` and `telemetry` are single MAVLink 2 frames
//! (unsigned: signing, when the mission signs, is between relay and vehicle).
//! Setpoints have a key of their own so they can be sent best-effort at real-time
//! priority while commands are never dropped by Zenoh. `<drone>` is the mission's
//! drone id — not the MAVLink system id, which is only unique within one relay's
//! network — so a swarm may have more than 254 drones across relays.

/// Key expressions for one mission.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KeySpace {
    root: String,
}

/// What a `served-by` liveliness key says.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Served {
    /// The mission's drone id.
    pub drone: String,
    /// The relay's name.
    pub relay: String,
    /// The vehicle's system id in the relay's MAVLink network.
    pub system_id: u8,
}

impl KeySpace {
    /// The key space of mission `mission` (its name; any text: key-unsafe
    /// characters are escaped).
    pub fn new(mission: &str) -> Self {
        Self {
            root: format!("swarmctl/{}", chunk(mission)),
        }
    }

    /// The liveliness key of relay `relay`.
    pub fn relay(&self, relay: &str) -> String {
        format!("{}/relays/{}", self.root, chunk(relay))
    }

    /// Every relay's liveliness key.
    pub fn all_relays(&self) -> String {
        format!("{}/relays/*", self.root)
    }

    /// The liveliness key saying `relay` serves `drone` as MAVLink system `system_id`.
    pub fn served(&self, drone: &str, relay: &str, system_id: u8) -> String {
        format!(
            "{}/drones/{}/served-by/{}/{system_id}",
            self.root,
            chunk(drone),
            chunk(relay)
        )
    }

    /// Every `served-by` liveliness key.
    pub fn all_served(&self) -> String {
        format!("{}/drones/*/served-by/*/*", self.root)
    }

    /// Reads a `served-by` key back; `None` for any other key.
    pub fn parse_served(&self, key: &str) -> Option<Served> {
        let rest = key.strip_prefix(&self.root)?.strip_prefix("/drones/")?;
        let mut parts = rest.split('/');
        let drone = unchunk(parts.next()?)?;
        if parts.next()? != "served-by" {
            return None;
        }
        let relay = unchunk(parts.next()?)?;
        let system_id = parts.next()?.parse().ok()?;
        parts.next().is_none().then_some(Served {
            drone,
            relay,
            system_id,
        })
    }

    /// Where the controller publishes `drone`'s position setpoints.
    pub fn setpoint(&self, drone: &str) -> String {
        format!("{}/drones/{}/setpoint", self.root, chunk(drone))
    }

    /// Where the controller publishes every other frame for `drone`.
    pub fn command(&self, drone: &str) -> String {
        format!("{}/drones/{}/command", self.root, chunk(drone))
    }

    /// Where the relay publishes every frame `drone`'s vehicle sends.
    pub fn telemetry(&self, drone: &str) -> String {
        format!("{}/drones/{}/telemetry", self.root, chunk(drone))
    }

    /// Where a relay running the bundled simulator publishes its true states.
    pub fn truth(&self, relay: &str) -> String {
        format!("{}/truth/{}", self.root, chunk(relay))
    }

    /// Every relay's true states.
    pub fn all_truth(&self) -> String {
        format!("{}/truth/*", self.root)
    }
}

/// `text` as one key chunk: ASCII letters, digits, `-`, `_` and `.` kept, every
/// other byte as `%XX` (so `/`, `*`, `$`, `?`, `#` never reach Zenoh), and the
/// empty text as `%`.
pub fn chunk(text: &str) -> String {
    if text.is_empty() {
        return "%".to_string();
    }
    let mut out = String::with_capacity(text.len());
    for b in text.bytes() {
        if b.is_ascii_alphanumeric() || matches!(b, b'-' | b'_' | b'.') {
            out.push(char::from(b));
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

/// The text a [`chunk`] holds; `None` if it is not one.
pub fn unchunk(chunk: &str) -> Option<String> {
    if chunk == "%" {
        return Some(String::new());
    }
    let mut bytes = Vec::with_capacity(chunk.len());
    let mut rest = chunk.as_bytes();
    while let Some((&b, tail)) = rest.split_first() {
        if b == b'%' {
            let hex = std::str::from_utf8(tail.get(..2)?).ok()?;
            bytes.push(u8::from_str_radix(hex, 16).ok()?);
            rest = &tail[2..];
        } else {
            bytes.push(b);
            rest = tail;
        }
    }
    String::from_utf8(bytes).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_escape_what_zenoh_reserves_and_read_back() {
        for text in ["d1", "north relay", "a/b*c$?#", "", "é", "%", "x.y-z_1"] {
            let c = chunk(text);
            assert!(!c.contains(['/', '*', '$', '?', '#', ' ']), "{c}");
            assert_eq!(unchunk(&c).as_deref(), Some(text));
        }
        assert_eq!(chunk("d1"), "d1");
        assert_eq!(unchunk("%4"), None);
    }

    #[test]
    fn served_keys_read_back_and_others_do_not() {
        let keys = KeySpace::new("formation change");
        let key = keys.served("d/3", "north", 7);
        assert_eq!(
            key,
            "swarmctl/formation%20change/drones/d%2F3/served-by/north/7"
        );
        assert_eq!(
            keys.parse_served(&key),
            Some(Served {
                drone: "d/3".into(),
                relay: "north".into(),
                system_id: 7
            })
        );
        assert_eq!(keys.parse_served(&keys.telemetry("d1")), None);
        assert_eq!(keys.parse_served(&format!("{key}/extra")), None);
        assert_eq!(
            KeySpace::new("other").parse_served(&key),
            None,
            "another mission's key"
        );
    }
}
