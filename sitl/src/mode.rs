//! Flight modes shared by both flavours; `px4` and `ardupilot` map them to
//! and from each autopilot's custom-mode numbers.

/// What the vehicle is doing, independent of how an autopilot names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FlightMode {
    /// Initial ground mode: ArduPilot STABILIZE; PX4 POSCTL. Holds position when flying.
    Manual,
    /// Hold position: PX4 AUTO.LOITER ("Hold"), ArduPilot LOITER / BRAKE.
    Hold,
    /// Climb to the takeoff altitude: PX4 AUTO.TAKEOFF. (ArduPilot takes off inside GUIDED.)
    Takeoff,
    /// Track externally streamed setpoints: PX4 OFFBOARD.
    Offboard,
    /// Track the last commanded target: ArduPilot GUIDED.
    Guided,
    /// Descend and land where it is, then disarm: PX4 AUTO.LAND, ArduPilot LAND.
    Land,
    /// Fly back over home, then land: PX4 AUTO.RTL, ArduPilot RTL.
    ReturnToLaunch,
}
