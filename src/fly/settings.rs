//! The flight loop's tunables, taken from the mission and the fly options once.

/// Seconds added to the scaled makespan for the execution timeout.
pub const TIMEOUT_MARGIN_S: f64 = 30.0;

/// Tunables of the loop.
#[derive(Debug, Clone, Copy)]
pub struct LoopSettings {
    /// Setpoints per second to every drone; also the loop's tick rate, hertz.
    pub setpoint_rate_hz: f64,
    /// Nothing heard for this long counts as a lost link (the follower pauses), seconds.
    pub link_timeout_s: f64,
    /// Nothing heard for this long: the drone is given up for the flight (LOST), seconds.
    pub lost_after_s: f64,
    /// The mission's speed, acceleration and jerk limits, for the PX4 climb profile.
    pub limits: crate::profile::Kinematics,
    /// The tracking error the vehicles are trusted to keep, metres: a drone's
    /// setpoint waits while the drone is further from it (0: not enforced).
    pub tracking_error_m: f64,
    /// Telemetry this close to a commanded rest point counts as settled there.
    pub settle_tolerance_m: f64,
    /// Give up on plan execution (hold, then land) after this long.
    pub execution_timeout_s: f64,
    /// `execution_timeout_s` is this many times the makespan plus
    /// [`TIMEOUT_MARGIN_S`] (recomputed when a replan is spliced in).
    pub timeout_factor: f64,
    /// The mission's minimum separation: a drone descends only when no other is
    /// below it within this distance horizontally, metres.
    pub safety_distance_m: f64,
    /// The separation ellipsoid the vehicles keep, when the mission has one: the
    /// flight measures the scaled separation against it (`None`: a sphere of
    /// `safety_distance_m`).
    pub ellipsoid: Option<crate::world::Separation>,
    /// The ground lies below the pad layer, the airspace's lowest, by at least the
    /// safety distance, so a drone landed out of the plan is in nobody's way.
    pub ground_clear: bool,
    /// Plan time 0 (`fly --start-at`): the plan clock starts at this instant, and
    /// a drone not above its pad by then aborts the flight. `None`: as soon as
    /// every drone is above its pad.
    pub plan_start: Option<std::time::Instant>,
    /// The box of the mission's airspace: a drone outside it by more than
    /// `tracking_error_m` has left the plan for good (`contingency`).
    pub airspace: super::fence::AirspaceBox,
}
