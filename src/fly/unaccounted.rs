//! Whether a flight accounted for every drone: the success `swarmctl fly` exits 0
//! for, and the one summary line naming the drones not known to be on the ground.

use super::log::{Summary, Unaccounted};

impl Summary {
    /// The flight did all `swarmctl fly` exits 0 for: completed within its
    /// limits, and every drone landed (on its pad, or where its plan put it). A
    /// lost or handed-over drone fails it even when the survivors completed.
    pub fn succeeded(&self) -> bool {
        self.completed && self.safety_held && self.speed_held && self.all_accounted_for()
    }

    /// No drone is unaccounted for (nor, in a log from before that list was kept,
    /// lost or handed over).
    pub(super) fn all_accounted_for(&self) -> bool {
        self.unaccounted.is_empty() && self.lost.is_empty() && self.handed_over.is_empty()
    }

    /// How many drones are unaccounted for and, for each, what is known: one line,
    /// so each lost drone is named once. Logs from before `unaccounted` was kept
    /// still have their lost and handed-over drones counted.
    pub(super) fn unaccounted_line(&self) -> Option<String> {
        let mut all = self.unaccounted.clone();
        for (phase, ids) in [("LOST", &self.lost), ("HANDED OVER", &self.handed_over)] {
            for id in ids {
                if all.iter().all(|u| &u.id != id) {
                    all.push(Unaccounted {
                        id: id.clone(),
                        phase: phase.into(),
                        reason: None,
                    });
                }
            }
        }
        let who: Vec<String> = all
            .iter()
            .map(|u| {
                let known = match self.lost_last_known.iter().find(|l| l.id == u.id) {
                    Some(last) => Some(last.whereabouts()),
                    None => u.reason.clone(),
                };
                let name = if u.phase.chars().any(char::is_lowercase) {
                    format!("{} ({})", u.id, u.phase)
                } else {
                    format!("{} {}", u.phase, u.id)
                };
                match known {
                    Some(k) => format!("{name} ({k})"),
                    None => name,
                }
            })
            .collect();
        let n = all.len();
        (n > 0).then(|| {
            let drones = if n == 1 { "drone" } else { "drones" };
            format!("  unaccounted for      {n} {drones}: {}", who.join("; "))
        })
    }
}
