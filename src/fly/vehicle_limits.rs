//! Pre-flight: the autopilot's own speed, acceleration and jerk limits set to the
//! mission's, and read back.
//!
//! Both autopilots shape a position target that runs ahead of the vehicle with
//! their own kinematic limits: ArduCopter's guided mode chases it at up to
//! `WPNAV_SPEED` (10 m/s by default), so a vehicle that lagged would race to catch
//! up, far above the mission's limit. Setting the autopilot's limits to the
//! mission's keeps a lagging vehicle within them too. ArduCopter also shapes every
//! target with its own jerk limit (`PSC_JERK_XY`, `PSC_JERK_Z`, m/s³): set to the
//! mission's, the S-curves swarmctl streams are exactly what its shaping can follow,
//! so its target does not fall behind and overshoot to catch up.

use crate::link::{Flavour, Session};
use crate::mission::Limits;

/// The parameters set, with the value each gets from the limits.
pub fn parameters(flavour: Flavour, limits: &Limits) -> Vec<(&'static str, f32)> {
    let v = limits.max_speed_mps as f32;
    let a = limits.max_accel_mps2 as f32;
    let j = limits.max_jerk_mps3 as f32;
    match flavour {
        // Centimetres per second (squared), ArduCopter's units.
        Flavour::Ardupilot => vec![
            ("WPNAV_SPEED", 100.0 * v),
            ("WPNAV_SPEED_UP", 100.0 * v),
            ("WPNAV_SPEED_DN", 100.0 * v),
            ("WPNAV_ACCEL", 100.0 * a),
            ("WPNAV_ACCEL_Z", 100.0 * a),
            // Metres per second cubed.
            ("PSC_JERK_XY", j),
            ("PSC_JERK_Z", j),
        ],
        Flavour::Px4 => vec![("MPC_XY_VEL_MAX", v), ("MPC_ACC_HOR_MAX", a)],
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
) -> Result<f64, String> {
    for (name, value) in parameters(flavour, limits) {
        session
            .set_param(name, value)
            .await
            .map_err(|e| format!("{id}: cannot set its speed limits: {e}"))?;
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
