//! PX4: flies on our setpoints in OFFBOARD, takes off by climbing on them, and
//! leaves OFFBOARD by itself when they stop (its offboard-loss failsafe).
//!
//! Takeoff: stream a ground hold, switch to OFFBOARD, then climb to the start
//! voxel along a rest-to-rest vertical profile.

use super::flavour::{Flavour, OwnLimits, Setting};
use super::takeoff::{Takeoff, TakeoffStep, TakeoffTick};
use crate::fly::command::{Command, Request};
use crate::fly::fence::VehicleFence;
use crate::fly::follower::Setpoint;
use crate::link::{ModeRequest, ParamValue};
use crate::mission::{Autopilot, FenceAction};
use crate::trajectory::Profile;
use mavlink::dialects::common::MavAutopilot;
use std::time::{Duration, Instant};

/// PX4 accepts OFFBOARD only once setpoints are streaming: this long of a ground
/// hold comes first.
const STREAM_BEFORE_OFFBOARD: Duration = Duration::from_millis(500);

/// PX4 encodes modes as `main << 16 | sub << 24`.
const fn mode(main: u8, sub: u8) -> ModeRequest {
    ModeRequest {
        param2: main as f32,
        param3: sub as f32,
        custom_mode: (main as u32) << 16 | (sub as u32) << 24,
    }
}

/// The PX4 autopilot.
pub(super) struct Px4;

impl Flavour for Px4 {
    fn autopilot(&self) -> Autopilot {
        Autopilot::Px4
    }

    fn heartbeat_autopilot(&self) -> MavAutopilot {
        MavAutopilot::MAV_AUTOPILOT_PX4
    }

    fn external_control_mode(&self) -> ModeRequest {
        mode(6, 0) // OFFBOARD
    }

    fn external_control_name(&self) -> &'static str {
        "OFFBOARD"
    }

    fn hold_mode(&self) -> ModeRequest {
        mode(4, 3) // AUTO.LOITER
    }

    fn land_mode(&self) -> ModeRequest {
        mode(4, 6) // AUTO.LAND
    }

    fn return_mode(&self) -> ModeRequest {
        mode(4, 5) // AUTO.RTL
    }

    fn external_control_before_arming(&self) -> bool {
        false
    }

    fn leaves_external_control_without_stream(&self) -> bool {
        true
    }

    fn takeoff(&self) -> Box<dyn Takeoff> {
        Box::new(Px4Takeoff::EnterOffboard {
            since: Instant::now(),
            request: Request::NotSent,
        })
    }

    /// PX4 SIH's velocity estimate is noisy (its accelerometer up to 1.7 m/s² per
    /// sample) and its controller follows it: with `MPC_XY_VEL_MAX` at a 1 m/s
    /// limit, a vehicle catching up with its setpoints went to 1.07 m/s by
    /// telemetry and 1.14 m/s by truth (CI, 2026-12-02); with it at 0.87 m/s
    /// (0.15 here), one catching up 0.9 m went to 1.06 m/s by telemetry and 1.03 m/s
    /// by truth, 22 % over it (CI, 2026-12-05); at 0.8 m/s (0.25 here), the vehicle
    /// trailing furthest (0.96 m) went to 1.07 m/s by truth, 33 % over it (CI,
    /// 2026-12-06), and another run 0.98 m/s by telemetry. The overshoot is about
    /// a quarter of a metre per second whatever the maximum. At 0.71 m/s (0.4
    /// here) it went to 0.97–0.99 m/s by truth on an idle and on a loaded machine
    /// and to 1.06–1.09 m/s in two runs (2026-12-06/07): a quarter to almost 0.4
    /// m/s over. At 0.625 m/s it keeps the limit with that overshoot, and a wide
    /// formation's 0.5 m/s setpoints still leave 0.125 m/s to catch up with.
    fn own_speed_overshoot(&self) -> f64 {
        0.6
    }

    /// PX4 clamps the landing speeds to `MPC_Z_VEL_MAX_DN` itself, so they are
    /// set before the maxima. Metres per second (squared).
    fn limit_parameters(&self, l: OwnLimits) -> Vec<(&'static str, Setting)> {
        vec![
            ("MPC_LAND_CRWL", Setting::AtMost(l.commanded_speed_mps)),
            ("MPC_LAND_SPEED", Setting::AtMost(l.commanded_speed_mps)),
            ("MPC_Z_V_AUTO_DN", Setting::AtMost(l.commanded_speed_mps)),
            ("MPC_Z_V_AUTO_UP", Setting::AtMost(l.commanded_speed_mps)),
            ("MPC_XY_VEL_MAX", Setting::To(l.max_speed_mps)),
            ("MPC_Z_VEL_MAX_UP", Setting::To(l.max_speed_mps)),
            ("MPC_Z_VEL_MAX_DN", Setting::To(l.max_speed_mps)),
            ("MPC_ACC_HOR_MAX", Setting::To(l.max_accel_mps2)),
        ]
    }

    /// `GF_MAX_HOR_DIST` and `GF_MAX_VER_DIST` (from home, 0: off) are the
    /// circle and the ceiling; `GF_ACTION` (an `INT32`) 5 lands, 1 only warns. It
    /// is set last: a breach action with the old distances could fire at once.
    fn fence_parameters(&self, fence: &VehicleFence) -> Vec<(&'static str, ParamValue)> {
        let action = match fence.action {
            FenceAction::Land => 5,
            FenceAction::Report => 1,
        };
        vec![
            ("GF_MAX_HOR_DIST", ParamValue::Real(fence.radius_m as f32)),
            (
                "GF_MAX_VER_DIST",
                ParamValue::Real(fence.max_altitude_m as f32),
            ),
            ("GF_ACTION", ParamValue::Int32(action)),
        ]
    }

    /// PX4's offboard controller applies the feed-forward to its thrust setpoint
    /// directly: no lead.
    fn accel_lead_parameter(&self) -> Option<&'static str> {
        None
    }

    /// `MPC_XY_P` and `MPC_Z_P` (0.95 and 1.0 by default): `PositionControl`
    /// clamps position error × gain + velocity feed-forward at `MPC_XY_VEL_MAX`
    /// (`MPC_Z_VEL_MAX_UP`/`_DN`), then adds the acceleration feed-forward.
    fn position_gain_parameters(&self) -> Option<[&'static str; 2]> {
        Some(["MPC_XY_P", "MPC_Z_P"])
    }
}

/// Where a PX4 takeoff is.
#[derive(Debug)]
enum Px4Takeoff {
    /// Streaming a ground hold so OFFBOARD is accepted, then switching.
    EnterOffboard {
        /// When the ground hold started (OFFBOARD is asked for 0.5 s later).
        since: Instant,
        /// The OFFBOARD switch.
        request: Request,
    },
    /// Climbing on our setpoints along a vertical profile started at `t0`.
    Climb {
        /// When the climb profile started.
        t0: Instant,
        /// Height the climb started from, ENU metres.
        from_z_m: f64,
    },
}

impl Takeoff for Px4Takeoff {
    fn step(&mut self, tick: &mut TakeoffTick<'_>) -> TakeoffStep {
        match self {
            Px4Takeoff::EnterOffboard { since, request } => {
                // Holds on the ground where the vehicle is until OFFBOARD is in.
                let start_m = tick.start_m;
                let ground = tick.position_m.unwrap_or([start_m[0], start_m[1], 0.0]);
                let held = *tick.setpoint.get_or_insert(Setpoint::rest(ground));
                if matches!(request, Request::NotSent) {
                    if tick.now.duration_since(*since) > STREAM_BEFORE_OFFBOARD {
                        *request = Request::Sent;
                        return TakeoffStep::Send(Command::EnterExternalControl);
                    }
                    return TakeoffStep::Continue;
                }
                match request.take_done() {
                    None => TakeoffStep::Continue,
                    Some(Ok(())) => {
                        *self = Px4Takeoff::Climb {
                            t0: tick.now,
                            from_z_m: held.position_m[2],
                        };
                        TakeoffStep::Continue
                    }
                    Some(Err(e)) => TakeoffStep::refused("OFFBOARD", e),
                }
            }
            Px4Takeoff::Climb { t0, from_z_m } => {
                // Above its pad once the profile is done and telemetry has settled.
                let (t0, from_z_m) = (*t0, *from_z_m);
                let start_m = tick.start_m;
                let height_m = start_m[2] - from_z_m;
                let profile = Profile::new(height_m.abs(), tick.settings.limits);
                let tau = tick.now.duration_since(t0).as_secs_f64();
                let sign = height_m.signum();
                let s = profile.state_at(tau);
                *tick.setpoint = Some(Setpoint {
                    position_m: [start_m[0], start_m[1], from_z_m + sign * s.x_m],
                    velocity_mps: [0.0, 0.0, sign * s.v_mps],
                    acceleration_mps2: [0.0, 0.0, sign * s.a_mps2],
                });
                if tau >= profile.duration_s()
                    && (tick.settled_at)(start_m, tick.settings.settle_tolerance_m)
                {
                    return TakeoffStep::AtStart;
                }
                TakeoffStep::Continue
            }
        }
    }

    fn waiting_for(&mut self, command: Command) -> Option<&mut Request> {
        match (command, self) {
            (Command::EnterExternalControl, Px4Takeoff::EnterOffboard { request, .. }) => {
                Some(request)
            }
            _ => None,
        }
    }

    fn streams(&self, _has_setpoint: bool) -> bool {
        true
    }

    fn name(&self) -> &'static str {
        match self {
            Px4Takeoff::EnterOffboard { .. } => "offboard",
            Px4Takeoff::Climb { .. } => "takeoff",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn custom_modes_match_the_heartbeat_encoding() {
        assert_eq!(Px4.external_control_mode().custom_mode, 0x0006_0000);
        assert_eq!(Px4.hold_mode().custom_mode, 0x0304_0000);
        assert_eq!(Px4.land_mode().custom_mode, 0x0604_0000);
        assert_eq!(Px4.return_mode().custom_mode, 0x0504_0000);
    }
}
