//! Pre-flight: a vehicle's fence set through its flavour's parameters and read
//! back, the switch that turns it on last.

use super::VehicleFence;
use crate::fly::autopilot::Flavour;
use crate::link::Session;

/// Sets the vehicle's fence parameters ([`Flavour::fence_parameters`], the switch
/// that turns the fence on last), then reads every one back; `Err` names the drone
/// and the parameter that would not take or reads back otherwise.
pub async fn apply(
    id: &str,
    session: &Session,
    flavour: &dyn Flavour,
    fence: &VehicleFence,
) -> Result<(), String> {
    let parameters = flavour.fence_parameters(fence);
    for &(name, value) in &parameters {
        session
            .set_param_value(name, value)
            .await
            .map_err(|e| format!("{id}: cannot set its fence: {e}"))?;
    }
    for &(name, value) in &parameters {
        let read = session
            .read_param(name)
            .await
            .map_err(|e| format!("{id}: cannot read its fence back: {e}"))?;
        if !value.matches(read) {
            return Err(format!(
                "{id}: its fence differs from the mission's: {name} reads back {}, set {value} (another ground station, or the autopilot refused it)",
                value.decode_like(read)
            ));
        }
    }
    Ok(())
}
