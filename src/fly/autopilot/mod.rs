//! Everything swarmctl does differently for one autopilot family, behind one
//! trait: [`Flavour`], implemented once per family in its own file (`px4`,
//! `ardupilot`), the way ArduPilot keeps one `mode_*.cpp` per flight mode.
//!
//! The rest of the flight library is written against the trait: the link speaks
//! plain MAVLink (a [`ModeRequest`] is just numbers), the drone's phase machine
//! runs a [`Takeoff`] it is handed, and pre-flight sets the parameters a flavour
//! names. Adding a family is one file here implementing [`Flavour`], one variant
//! of [`Autopilot`] (the mission's enum, the only autopilot enum in the library)
//! with its arm in [`flavour`], and one file in the simulator (`sitl/src/`).

mod ardupilot;
mod flavour;
mod px4;
mod takeoff;

pub use flavour::{Flavour, OwnLimits, Setting};
pub use takeoff::{Takeoff, TakeoffStep, TakeoffTick};

use crate::mission::Autopilot;
use mavlink::dialects::common::MavAutopilot;

/// The implementation of `autopilot`: the one place that lists the families.
pub fn flavour(autopilot: Autopilot) -> &'static dyn Flavour {
    match autopilot {
        Autopilot::Px4 => &px4::Px4,
        Autopilot::Ardupilot => &ardupilot::ArduCopter,
    }
}

/// The family a HEARTBEAT's autopilot field announces; `None` for anything else
/// (a GCS, a companion computer, or an autopilot we do not know how to fly).
pub fn from_heartbeat(autopilot: MavAutopilot) -> Option<&'static dyn Flavour> {
    Autopilot::ALL
        .into_iter()
        .map(flavour)
        .find(|f| f.heartbeat_autopilot() == autopilot)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_autopilot_is_its_own_flavour_and_known_by_its_heartbeat() {
        for autopilot in Autopilot::ALL {
            let f = flavour(autopilot);
            assert_eq!(f.autopilot(), autopilot);
            let found = from_heartbeat(f.heartbeat_autopilot()).map(|f| f.autopilot());
            assert_eq!(found, Some(autopilot));
        }
        assert!(from_heartbeat(MavAutopilot::MAV_AUTOPILOT_INVALID).is_none());
    }

    #[test]
    fn autopilots_are_named_as_mission_files_name_them() {
        for autopilot in Autopilot::ALL {
            assert_eq!(autopilot.name().parse::<Autopilot>(), Ok(autopilot));
        }
        let wrong = "arducopter".parse::<Autopilot>().unwrap_err();
        assert!(wrong.contains("px4, ardupilot"), "{wrong}");
    }

    #[test]
    fn failsafe_modes_are_land_and_return() {
        for autopilot in Autopilot::ALL {
            let f = flavour(autopilot);
            assert!(f.is_failsafe_mode(f.land_mode().custom_mode));
            assert!(f.is_failsafe_mode(f.return_mode().custom_mode));
            assert!(!f.is_failsafe_mode(f.external_control_mode().custom_mode));
            assert!(!f.is_failsafe_mode(f.hold_mode().custom_mode));
        }
    }
}
