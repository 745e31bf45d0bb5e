//! Pre-flight: the autopilot's own speed and acceleration limits set to the
//! mission's, and read back.
//!
//! Both autopilots shape a position target that runs ahead of the vehicle with
//! their own kinematic limits: ArduCopter's guided mode chases it at up to
//! `WPNAV_SPEED` (10 m/s by default), so a vehicle that lagged would race to catch
//! up, far above the mission's limit. Setting the autopilot's limits to the
//! mission's keeps a lagging vehicle within them too.

use crate::link::{Flavour, Session};
use crate::mission::Limits;

/// The parameters set, with the value each gets from the limits.
pub fn parameters(flavour: Flavour, limits: &Limits) -> Vec<(&'static str, f32)> {
    let v = limits.max_speed_mps as f32;
    let a = limits.max_accel_mps2 as f32;
    match flavour {
        // Centimetres per second (squared), ArduCopter's units.
        Flavour::Ardupilot => vec![
            ("WPNAV_SPEED", 100.0 * v),
            ("WPNAV_SPEED_UP", 100.0 * v),
            ("WPNAV_SPEED_DN", 100.0 * v),
            ("WPNAV_ACCEL", 100.0 * a),
        ],
        Flavour::Px4 => vec![("MPC_XY_VEL_MAX", v), ("MPC_ACC_HOR_MAX", a)],
    }
}

/// Sets and reads back every parameter of [`parameters`]; `Err` names the drone
/// and the parameter the vehicle would not take.
pub async fn apply(
    id: &str,
    session: &Session,
    flavour: Flavour,
    limits: &Limits,
) -> Result<(), String> {
    for (name, value) in parameters(flavour, limits) {
        session
            .set_param(name, value)
            .await
            .map_err(|e| format!("{id}: cannot set its speed limits: {e}"))?;
    }
    Ok(())
}
