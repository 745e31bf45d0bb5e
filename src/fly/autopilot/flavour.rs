//! The [`Flavour`] trait: what one autopilot family does its own way.

use super::takeoff::Takeoff;
use crate::fly::command::Modes;
use crate::fly::fence::VehicleFence;
use crate::link::{ModeRequest, ParamValue};
use crate::mission::Autopilot;
use mavlink::dialects::common::MavAutopilot;

/// One autopilot family: its modes, how it takes off, how it behaves when our
/// setpoint stream stops, and which of its parameters carry the mission's limits.
pub trait Flavour: Sync {
    /// The mission's name for this family.
    fn autopilot(&self) -> Autopilot;

    /// The HEARTBEAT `autopilot` field by which a vehicle of this family is known.
    fn heartbeat_autopilot(&self) -> MavAutopilot;

    /// The mode in which the vehicle follows our SET_POSITION_TARGET stream.
    fn external_control_mode(&self) -> ModeRequest;

    /// That mode's name, as the autopilot's own ground station shows it.
    fn external_control_name(&self) -> &'static str;

    /// A mode that holds position without our stream.
    fn hold_mode(&self) -> ModeRequest;

    /// The mode that lands where the vehicle is.
    fn land_mode(&self) -> ModeRequest;

    /// The mode that flies the vehicle home by itself.
    fn return_mode(&self) -> ModeRequest;

    /// Whether the vehicle must be in [`Flavour::external_control_mode`] before it
    /// is armed (ArduCopter takes off only from GUIDED).
    fn external_control_before_arming(&self) -> bool;

    /// Whether the vehicle leaves external control by itself when our stream
    /// stops (PX4's offboard-loss failsafe), so that it must be asked back in once
    /// it is heard again.
    fn leaves_external_control_without_stream(&self) -> bool;

    /// The takeoff from the pad to the start voxel, fresh for one armed vehicle.
    fn takeoff(&self) -> Box<dyn Takeoff>;

    /// How far past its own speed maximum a vehicle goes, as a fraction, by truth
    /// (see [`crate::fly::vehicle_limits::parameters`]).
    fn own_speed_overshoot(&self) -> f64;

    /// The parameters that carry the mission's limits, in the order they are set.
    fn limit_parameters(&self, limits: OwnLimits) -> Vec<(&'static str, Setting)>;

    /// The parameters that carry a vehicle's fence, in the order they are set:
    /// the switch that turns it on last (see [`crate::fly::fence`]).
    fn fence_parameters(&self, fence: &VehicleFence) -> Vec<(&'static str, ParamValue)>;

    /// The parameter holding the vehicle's attitude time constant, seconds, when
    /// the acceleration feed-forward must lead by it (see
    /// [`crate::fly::vehicle_limits::accel_lead_s`]); `None` for no lead.
    fn accel_lead_parameter(&self) -> Option<&'static str>;

    /// The parameters holding the horizontal and vertical position gains (1/s) of
    /// a controller that clamps its velocity setpoint at the vehicle's own maximum
    /// *before* adding the acceleration feed-forward, which must then be tapered
    /// (see [`crate::fly::feedforward`]); `None` when the autopilot keeps the
    /// feed-forward within its own limits itself.
    fn position_gain_parameters(&self) -> Option<[&'static str; 2]>;

    /// Whether `custom_mode` is one the autopilot enters by itself to bring a
    /// vehicle home or down (land, return): a failsafe we never fight.
    fn is_failsafe_mode(&self, custom_mode: u32) -> bool {
        custom_mode == self.land_mode().custom_mode || custom_mode == self.return_mode().custom_mode
    }

    /// The modes the flight's commands switch to.
    fn modes(&self) -> Modes {
        Modes {
            external_control: self.external_control_mode(),
            hold: self.hold_mode(),
            land: self.land_mode(),
        }
    }
}

/// The limits an autopilot's own controller is given, SI units: what
/// [`Flavour::limit_parameters`] converts to its parameters' units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OwnLimits {
    /// The vehicle's own speed maximum, m/s.
    pub max_speed_mps: f32,
    /// The speed trajectories are flown at, m/s: the most its own landing may go.
    pub commanded_speed_mps: f32,
    /// Acceleration limit, m/s².
    pub max_accel_mps2: f32,
    /// Jerk limit, m/s³.
    pub max_jerk_mps3: f32,
}

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

impl std::fmt::Debug for dyn Flavour {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.autopilot())
    }
}
