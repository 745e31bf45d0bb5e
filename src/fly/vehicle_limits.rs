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

use crate::link::{Flavour, Session};
use crate::mission::Limits;

/// What one parameter is set to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Setting {
    /// Exactly this value.
    To(f32),
    /// The vehicle's own value, lowered to this if above it: for the speeds of the
    /// autopilot's own landing, which an operator may have set slower than the
    /// mission's limit and which must never be raised to it (a 5 m/s mission must
    /// not touch down at 5 m/s).
    AtMost(f32),
}

/// How far past its own speed maximum a vehicle goes, as a fraction, by truth:
/// the room [`parameters`] leaves between that maximum and the mission's limit.
/// PX4 SIH's velocity estimate is noisy (its accelerometer up to 1.7 m/s² per
/// sample) and its controller follows it: with `MPC_XY_VEL_MAX` at a 1 m/s limit,
/// a vehicle catching up with its setpoints went to 1.07 m/s by telemetry and
/// 1.14 m/s by truth (CI, 2026-12-02). ArduCopter stays within 1 % of
/// `WPNAV_SPEED` (truth 1.01 m/s at 1 m/s, 8 vehicles): none.
pub fn own_speed_overshoot(flavour: Flavour) -> f64 {
    match flavour {
        Flavour::Px4 => 0.15,
        Flavour::Ardupilot => 0.0,
    }
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
    flavour: Flavour,
    limits: &Limits,
    commanded: &Limits,
) -> Vec<(&'static str, Setting)> {
    let v_commanded = commanded.max_speed_mps as f32;
    let v = (limits.max_speed_mps / (1.0 + own_speed_overshoot(flavour)))
        .max(commanded.max_speed_mps) as f32;
    let a = limits.max_accel_mps2 as f32;
    let j = limits.max_jerk_mps3 as f32;
    match flavour {
        // Centimetres per second (squared), ArduCopter's units.
        Flavour::Ardupilot => vec![
            ("WPNAV_SPEED", Setting::To(100.0 * v)),
            ("WPNAV_SPEED_UP", Setting::To(100.0 * v)),
            ("WPNAV_SPEED_DN", Setting::To(100.0 * v)),
            ("WPNAV_ACCEL", Setting::To(100.0 * a)),
            ("WPNAV_ACCEL_Z", Setting::To(100.0 * a)),
            // Metres per second cubed.
            ("PSC_JERK_XY", Setting::To(j)),
            ("PSC_JERK_Z", Setting::To(j)),
            ("LAND_SPEED", Setting::AtMost(100.0 * v_commanded)),
        ],
        Flavour::Px4 => vec![
            ("MPC_LAND_CRWL", Setting::AtMost(v_commanded)),
            ("MPC_LAND_SPEED", Setting::AtMost(v_commanded)),
            ("MPC_Z_V_AUTO_DN", Setting::AtMost(v_commanded)),
            ("MPC_Z_V_AUTO_UP", Setting::AtMost(v_commanded)),
            ("MPC_XY_VEL_MAX", Setting::To(v)),
            ("MPC_Z_VEL_MAX_UP", Setting::To(v)),
            ("MPC_Z_VEL_MAX_DN", Setting::To(v)),
            ("MPC_ACC_HOR_MAX", Setting::To(a)),
        ],
    }
}

/// Sets and reads back every parameter of [`parameters`], and returns the
/// acceleration lead the vehicle needs (see [`accel_lead_s`]); `Err` names the
/// drone and the parameter the vehicle would not take or tell.
pub async fn apply(
    id: &str,
    session: &Session,
    flavour: Flavour,
    limits: &Limits,
    commanded: &Limits,
) -> Result<f64, String> {
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
    accel_lead_s(session, flavour)
        .await
        .map_err(|e| format!("{id}: cannot read its attitude response: {e}"))
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
    flavour: Flavour,
) -> Result<f64, crate::link::LinkError> {
    match flavour {
        Flavour::Ardupilot => {
            let tc_s = session.read_param("ATC_INPUT_TC").await?;
            Ok(f64::from(tc_s).clamp(0.0, MAX_ACCEL_LEAD_S))
        }
        Flavour::Px4 => Ok(0.0),
    }
}

/// The longest acceleration lead used, seconds (ArduCopter allows `ATC_INPUT_TC` up
/// to 1 s, far beyond what the lead compensates well).
pub const MAX_ACCEL_LEAD_S: f64 = 0.3;

#[cfg(test)]
mod tests {
    use super::*;

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
        for flavour in [Flavour::Px4, Flavour::Ardupilot] {
            let set = parameters(flavour, &mission, &commanded);
            let capped: Vec<_> = set
                .iter()
                .filter_map(|(name, s)| match s {
                    Setting::AtMost(v) => Some((*name, *v)),
                    Setting::To(_) => None,
                })
                .collect();
            assert!(
                capped.iter().any(|(name, _)| name.contains("LAND_SPEED")),
                "{flavour:?}: {set:?}"
            );
            assert!(capped.iter().all(|&(_, v)| match flavour {
                Flavour::Px4 => v == 0.5,
                Flavour::Ardupilot => v == 50.0,
            }));
            let position = |wanted: &str| set.iter().position(|(name, _)| *name == wanted);
            if flavour == Flavour::Px4 {
                assert!(position("MPC_LAND_SPEED") < position("MPC_Z_VEL_MAX_DN"));
                assert!(position("MPC_Z_V_AUTO_DN") < position("MPC_Z_VEL_MAX_DN"));
            }
            // The vehicle's own maxima leave it room to overshoot them within the
            // limit (PX4: 1 / 1.15 m/s), above the 0.5 m/s commanded.
            let maxima: &[(&str, f32)] = match flavour {
                Flavour::Px4 => &[
                    ("MPC_XY_VEL_MAX", (1.0 / 1.15) as f32),
                    ("MPC_Z_VEL_MAX_UP", (1.0 / 1.15) as f32),
                    ("MPC_Z_VEL_MAX_DN", (1.0 / 1.15) as f32),
                ],
                Flavour::Ardupilot => &[
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
        let set = parameters(Flavour::Px4, &limits(1.0), &limits(1.0));
        assert!(
            set.contains(&("MPC_XY_VEL_MAX", Setting::To(1.0))),
            "{set:?}"
        );
        let set = parameters(Flavour::Px4, &limits(1.0), &limits(0.9));
        assert!(
            set.contains(&("MPC_XY_VEL_MAX", Setting::To(0.9))),
            "{set:?}"
        );
    }
}
