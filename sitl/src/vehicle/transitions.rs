//! Mode transitions driven by time, and the failsafes: takeoff completion,
//! offboard loss, ArduPilot's velocity timeout, the RTL phases, the battery
//! faults and the automatic disarm after landing.

use super::{
    CRITICAL_BATTERY_PCT, LOW_BATTERY_PCT, OFFBOARD_LOSS_TIMEOUT_S, Vehicle, seconds_or_never,
};
use crate::ardupilot;
use crate::dynamics::{Setpoint, norm};
use crate::mode::FlightMode;
use mavlink::dialects::common::MavSeverity;
use std::time::Duration;

/// Landed this long in LAND or RTL before the vehicle disarms itself (PX4 COM_DISARM_LAND).
const AUTO_DISARM_AFTER_LANDING_S: f64 = 2.0;
/// Height error at which a takeoff counts as complete, metres.
const TAKEOFF_DONE_M: f32 = 0.15;
/// Horizontal distance to home at which RTL starts descending, metres.
const RTL_OVER_HOME_M: f32 = 0.3;

impl Vehicle {
    /// Battery faults: LOW is a warning; CRITICAL starts the flavour's failsafe.
    pub(super) fn check_battery(&mut self) {
        if !self.armed {
            return;
        }
        let faults = &self.config.faults;
        let reached = |after: Option<Duration>| {
            after.is_some_and(|after| self.armed_time_s >= seconds_or_never(after))
        };
        if !self.battery_critical && reached(faults.critical_battery_after) {
            self.battery_critical_now();
        } else if !self.battery_low && reached(faults.low_battery_after) {
            self.battery_low = true;
            self.battery_pct = self.battery_pct.min(LOW_BATTERY_PCT);
            let text = self.flavour.imitation().low_battery_text();
            self.status_text(MavSeverity::MAV_SEVERITY_WARNING, text);
        }
    }

    /// Turns the battery critical and starts the flavour's failsafe.
    pub(super) fn battery_critical_now(&mut self) {
        self.battery_critical = true;
        self.battery_low = true;
        self.battery_pct = self.battery_pct.min(CRITICAL_BATTERY_PCT);
        if self.landed() {
            self.status_text(MavSeverity::MAV_SEVERITY_CRITICAL, "Battery critical");
            return;
        }
        let (text, failsafe) = self.flavour.imitation().critical_battery_failsafe();
        self.status_text(MavSeverity::MAV_SEVERITY_CRITICAL, text);
        self.set_mode(failsafe);
    }

    /// Mode transitions driven by time: takeoff completion, offboard loss,
    /// velocity timeouts, RTL phases.
    pub(super) fn update_mode(&mut self) {
        match self.mode {
            FlightMode::Takeoff => {
                if self.takeoff_complete() {
                    self.takeoff_height_m = None;
                    self.set_mode(FlightMode::Hold);
                }
            }
            FlightMode::Guided => {
                if self.takeoff_complete() {
                    self.takeoff_height_m = None;
                    self.hold = Setpoint::hold(self.body.position_ned_m);
                }
                let stale_velocity = self.external.is_some_and(|e| {
                    e.setpoint
                        .velocity_ned_mps
                        .iter()
                        .any(|v| v.is_some_and(|v| v != 0.0))
                        && self.time_s - e.received_s > ardupilot::VELOCITY_TIMEOUT_S
                });
                if stale_velocity && !self.velocity_timed_out {
                    self.velocity_timed_out = true;
                    self.external = None;
                    self.hold = Setpoint::hold(self.body.position_ned_m);
                }
            }
            FlightMode::Offboard => {
                // A rogue ground station's stream keeps OFFBOARD alive too.
                let lost = !self.rogue_active()
                    && self
                        .external
                        .is_none_or(|e| self.time_s - e.received_s > OFFBOARD_LOSS_TIMEOUT_S);
                if lost && self.armed {
                    self.status_text(
                        MavSeverity::MAV_SEVERITY_WARNING,
                        "Failsafe: offboard lost, holding",
                    );
                    self.set_mode(FlightMode::Hold);
                    self.offboard_lost_since_s = Some(self.time_s);
                }
            }
            FlightMode::Hold => {
                if let Some(since) = self.offboard_lost_since_s
                    && self.time_s - since > seconds_or_never(self.config.offboard_loss_land_after)
                {
                    self.status_text(
                        MavSeverity::MAV_SEVERITY_WARNING,
                        "Failsafe: offboard lost, landing",
                    );
                    self.set_mode(FlightMode::Land);
                }
            }
            FlightMode::ReturnToLaunch => {
                let home = self.initial_position_ned_m;
                let p = self.body.position_ned_m;
                if !self.rtl_descending
                    && norm([home[0] - p[0], home[1] - p[1], 0.0]) < RTL_OVER_HOME_M
                {
                    self.rtl_descending = true;
                }
            }
            FlightMode::Manual | FlightMode::Land => {}
        }
    }

    fn takeoff_complete(&self) -> bool {
        self.takeoff_height_m
            .is_some_and(|h| self.armed && (self.body.height_m() - h).abs() < TAKEOFF_DONE_M)
    }

    /// Disarms a vehicle that has landed in LAND or RTL, as both autopilots do.
    pub(super) fn check_auto_disarm(&mut self) {
        let landing = matches!(self.mode, FlightMode::Land | FlightMode::ReturnToLaunch);
        if !(self.armed && landing && self.landed()) {
            self.resting_since_s = None;
            return;
        }
        let since = *self.resting_since_s.get_or_insert(self.time_s);
        if self.time_s - since >= AUTO_DISARM_AFTER_LANDING_S {
            self.status_text(MavSeverity::MAV_SEVERITY_INFO, "Landing detected, disarmed");
            self.set_armed(false);
        }
    }
}
