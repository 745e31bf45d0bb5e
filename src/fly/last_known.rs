//! Where a lost drone was last heard from, and in what state: an operator goes
//! looking for it there.

use serde::{Deserialize, Serialize};

/// A lost drone's last report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LastKnown {
    /// The drone's mission id.
    pub id: String,
    /// When its last position came, seconds since the first arm command.
    pub t_s: Option<f64>,
    /// Its last position, mission ENU metres.
    pub position_m: Option<[f64; 3]>,
    /// Armed when last heard.
    pub armed: bool,
    /// Its autopilot's landed state when last heard (`in air`, `on ground`, ...).
    pub landed_state: Option<String>,
    /// Battery remaining when last heard, percent.
    pub battery_pct: Option<i8>,
}

impl LastKnown {
    /// Where and in what state it was last heard from, for the summary.
    pub fn whereabouts(&self) -> String {
        let place = match (self.t_s, self.position_m) {
            (Some(t), Some([x, y, z])) => {
                format!("last position ({x:.2}, {y:.2}, {z:.2}) m ENU at {t:.1} s")
            }
            _ => "no position ever heard".to_string(),
        };
        let mut state = vec![if self.armed { "armed" } else { "disarmed" }.to_string()];
        state.extend(self.landed_state.clone());
        state.extend(self.battery_pct.map(|b| format!("battery {b} %")));
        format!("{place}; {}", state.join(", "))
    }
}
