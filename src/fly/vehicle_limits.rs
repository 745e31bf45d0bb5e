//! Pre-flight: the autopilot's own speed, acceleration and jerk limits set from the
//! mission's, and read back.
//!
//! Both autopilots shape a position target that runs ahead of the vehicle with
//! their own kinematic limits: ArduCopter's guided mode chases it at up to
//! `WPNAV_SPEED` (10 m/s by default), so a vehicle that lagged would race to catch
//! up, far above the mission's limit. Setting the autopilot's limits keeps a
//! lagging vehicle within them too. ArduCopter also shapes every
//! target with its own jerk limit (`PSC_JERK_XY`, `PSC_JERK_Z`, m/s³): set to the
//! mission's, the S-curves swarmctl streams are exactly what its shaping can follow,
//! so its target does not fall behind and overshoot to catch up. The autopilot's
//! own landing is slowed to the commanded speed, never sped up (see [`parameters`]).

use super::autopilot::{Flavour, OwnLimits, Setting};
use crate::fly::feedforward::SpeedClamp;
use crate::link::Session;
use crate::mission::Limits;

/// How far past its own speed maximum a vehicle goes, as a fraction, by truth:
/// the room [`parameters`] leaves between that maximum and the mission's limit
/// (PX4 SIH 0.6, ArduCopter none: see each flavour's
/// [`Flavour::own_speed_overshoot`]).
pub fn own_speed_overshoot(flavour: &dyn Flavour) -> f64 {
    flavour.own_speed_overshoot()
}

/// The parameters set, in the order they are set, with what each gets from the
/// mission's `limits` and the `commanded` limits trajectories are flown with
/// (`Mission::commanded_limits`).
///
/// The autopilot's own speed maxima bound how fast a lagging vehicle catches up
/// with its setpoints: the limit over (1 + [`own_speed_overshoot`]), so that the
/// vehicle, overshooting what it asks itself for, stays within the limit — but
/// never below the commanded speed, or it could not fly the trajectories at all.
/// Not the commanded speed itself: clamped there, PX4 SIH on the wide formation
/// (0.5 m/s commanded) could never catch up, trailed its setpoints by up to 1.46 m
/// against a 1.2 m bound and waited 80 s at gates (2026-12-02). Acceleration and
/// jerk are the mission's. The speeds of motions the autopilot plans itself — PX4's
/// LAND descent (`MPC_Z_V_AUTO_DN` above `MPC_LAND_ALT2`, `MPC_LAND_SPEED` below,
/// `MPC_LAND_CRWL` near the ground) — are lowered to the commanded speed, never
/// raised (an operator may land slower); ArduCopter's `LAND_SPEED` (below
/// `LAND_ALT_LOW`) likewise. Measured on PX4 SIH at its defaults (1.5 m/s above
/// `MPC_LAND_ALT2`, 0.7 m/s below): 1.06 m/s during one LAND against a 1 m/s limit.
/// PX4 clamps the landing speeds to `MPC_Z_VEL_MAX_DN` itself, so they are set
/// before the maxima.
pub fn parameters(
    flavour: &dyn Flavour,
    limits: &Limits,
    commanded: &Limits,
) -> Vec<(&'static str, Setting)> {
    flavour.limit_parameters(OwnLimits {
        max_speed_mps: own_max_speed_mps(flavour, limits, commanded) as f32,
        commanded_speed_mps: commanded.max_speed_mps as f32,
        max_accel_mps2: limits.max_accel_mps2 as f32,
        max_jerk_mps3: limits.max_jerk_mps3 as f32,
    })
}

/// The speed maximum [`parameters`] gives the autopilot, on every axis, m/s: the
/// limit over (1 + [`own_speed_overshoot`]), never below the commanded speed.
pub fn own_max_speed_mps(flavour: &dyn Flavour, limits: &Limits, commanded: &Limits) -> f64 {
    (limits.max_speed_mps / (1.0 + own_speed_overshoot(flavour))).max(commanded.max_speed_mps)
}

/// How the vehicle's own controller takes our feed-forward, learnt in pre-flight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OwnResponse {
    /// How far ahead its acceleration feed-forward is sent, seconds (see
    /// [`accel_lead_s`]).
    pub accel_lead_s: f64,
    /// Its velocity clamp, when its controller adds the acceleration feed-forward
    /// after it (see [`crate::fly::feedforward`]).
    pub speed_clamp: Option<SpeedClamp>,
}

/// Sets and reads back every parameter of [`parameters`], and returns how the
/// vehicle takes our feed-forward: the acceleration lead it needs and the
/// velocity clamp to taper it by; `Err` names the drone and the parameter the
/// vehicle would not take or tell.
pub async fn apply(
    id: &str,
    session: &Session,
    flavour: &dyn Flavour,
    limits: &Limits,
    commanded: &Limits,
) -> Result<OwnResponse, String> {
    let refused = |e| format!("{id}: cannot set its speed limits: {e}");
    for (name, setting) in parameters(flavour, limits, commanded) {
        let value = match setting {
            Setting::To(value) => value,
            Setting::AtMost(most) => {
                let own = session.read_param(name).await.map_err(refused)?;
                if own <= most {
                    continue;
                }
                most
            }
        };
        session.set_param(name, value).await.map_err(refused)?;
    }
    let accel_lead_s = accel_lead_s(session, flavour)
        .await
        .map_err(|e| format!("{id}: cannot read its attitude response: {e}"))?;
    let speed_clamp = match flavour.position_gain_parameters() {
        Some([horizontal, vertical]) => {
            let gain = |name| async move {
                session
                    .read_param(name)
                    .await
                    .map(f64::from)
                    .map_err(|e| format!("{id}: cannot read its position gain {name}: {e}"))
            };
            Some(SpeedClamp {
                max_speed_mps: own_max_speed_mps(flavour, limits, commanded),
                horizontal_gain_per_s: gain(horizontal).await?,
                vertical_gain_per_s: gain(vertical).await?,
            })
        }
        None => None,
    };
    Ok(OwnResponse {
        accel_lead_s,
        speed_clamp,
    })
}

/// How far ahead of the trajectory the acceleration feed-forward is sent, seconds.
///
/// An autopilot realises a commanded acceleration only once it has tilted, and
/// ArduCopter smooths every attitude command with `ATC_INPUT_TC` (0.15 s by
/// default): its acceleration trails ours by about that, so it falls behind while
/// speeding up and its position controller overshoots the speed limit catching up.
/// Sending the acceleration of `t + ATC_INPUT_TC` with the position and velocity of
/// `t` lines the realised acceleration up with the trajectory. Measured on real
/// ArduCopter SITL (5 m legs at 1 m/s, 2 m/s², 5 m/s³): top speed 1.28 m/s without
/// the lead, 1.05 m/s at 0.10 s, 1.03 m/s at 0.15 s; p95 tracking error 0.15 m →
/// 0.11 m. Vertically (its thrust loop lags too) 0.15 s measured best as well:
/// 2.5 m climbs at 1 m/s, 2.5 m/s³ top out at 1.15 m/s without the lead, 1.03 m/s
/// with it (and `WPNAV_ACCEL_Z`, `PSC_JERK_Z` set), p95 error 0.11 m → 0.03 m;
/// 0.25 s undershoots (0.96 m/s) and trails by 0.09 m. PX4's offboard controller
/// applies the feed-forward to its thrust setpoint directly: no lead.
pub async fn accel_lead_s(
    session: &Session,
    flavour: &dyn Flavour,
) -> Result<f64, crate::link::LinkError> {
    match flavour.accel_lead_parameter() {
        Some(time_constant) => {
            let tc_s = session.read_param(time_constant).await?;
            Ok(f64::from(tc_s).clamp(0.0, MAX_ACCEL_LEAD_S))
        }
        None => Ok(0.0),
    }
}

/// The longest acceleration lead used, seconds (ArduCopter allows `ATC_INPUT_TC` up
/// to 1 s, far beyond what the lead compensates well).
pub const MAX_ACCEL_LEAD_S: f64 = 0.3;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fly::autopilot::flavour;
    use crate::mission::Autopilot;

    fn limits(max_speed_mps: f64) -> Limits {
        Limits {
            max_speed_mps,
            max_accel_mps2: 2.0,
            max_jerk_mps3: 5.0,
            safety_distance_m: 0.4,
            vertical_separation_m: None,
            tracking_error_m: 0.2,
        }
    }

    /// The autopilot's own landing is never allowed above the commanded speed, on
    /// PX4 it is lowered before the vertical maximum that PX4 clamps it to, and the
    /// maxima leave the vehicle room to overshoot them within the limit.
    #[test]
    fn landing_speeds_are_capped_at_the_commanded_speed_and_maxima_below_the_limit() {
        let (mission, commanded) = (limits(1.0), limits(0.5));
        for autopilot in Autopilot::ALL {
            let set = parameters(flavour(autopilot), &mission, &commanded);
            let capped: Vec<_> = set
                .iter()
                .filter_map(|(name, s)| match s {
                    Setting::AtMost(v) => Some((*name, *v)),
                    Setting::To(_) => None,
                })
                .collect();
            assert!(
                capped.iter().any(|(name, _)| name.contains("LAND_SPEED")),
                "{autopilot}: {set:?}"
            );
            assert!(capped.iter().all(|&(_, v)| match autopilot {
                Autopilot::Px4 => v == 0.5,
                Autopilot::Ardupilot => v == 50.0,
            }));
            let position = |wanted: &str| set.iter().position(|(name, _)| *name == wanted);
            if autopilot == Autopilot::Px4 {
                assert!(position("MPC_LAND_SPEED") < position("MPC_Z_VEL_MAX_DN"));
                assert!(position("MPC_Z_V_AUTO_DN") < position("MPC_Z_VEL_MAX_DN"));
            }
            // The vehicle's own maxima leave it room to overshoot them within the
            // limit (PX4: 1 / 1.6 m/s), above the 0.5 m/s commanded.
            let maxima: &[(&str, f32)] = match autopilot {
                Autopilot::Px4 => &[
                    ("MPC_XY_VEL_MAX", (1.0 / 1.6) as f32),
                    ("MPC_Z_VEL_MAX_UP", (1.0 / 1.6) as f32),
                    ("MPC_Z_VEL_MAX_DN", (1.0 / 1.6) as f32),
                ],
                Autopilot::Ardupilot => &[
                    ("WPNAV_SPEED", 100.0),
                    ("WPNAV_SPEED_UP", 100.0),
                    ("WPNAV_SPEED_DN", 100.0),
                ],
            };
            for &(name, value) in maxima {
                assert!(set.contains(&(name, Setting::To(value))), "{name}: {set:?}");
            }
        }
    }

    /// A vehicle flown at the limit itself keeps its maxima there: below the
    /// commanded speed it could not follow its trajectories.
    #[test]
    fn speed_maxima_are_never_below_the_commanded_speed() {
        let set = parameters(flavour(Autopilot::Px4), &limits(1.0), &limits(1.0));
        assert!(
            set.contains(&("MPC_XY_VEL_MAX", Setting::To(1.0))),
            "{set:?}"
        );
        let set = parameters(flavour(Autopilot::Px4), &limits(1.0), &limits(0.9));
        assert!(
            set.contains(&("MPC_XY_VEL_MAX", Setting::To(0.9))),
            "{set:?}"
        );
    }
}
