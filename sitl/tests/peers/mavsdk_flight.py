"""MAVSDK (the real C++ library, through its Python binding) flies a
PX4-flavoured swarmctl-sitl vehicle: discover, arm, take off, offboard
square with every corner reached within 0.3 m, land, disarm.

Usage: python mavsdk_flight.py PORT     (exit status 0 on success)
"""

import math
import sys
import time

from mavsdk import ComponentType, Configuration, Mavsdk
from mavsdk.plugins.action import Action
from mavsdk.plugins.offboard import Offboard, PositionNedYaw
from mavsdk.plugins.telemetry import FlightMode, LandedState, Telemetry

ALTITUDE_M = 3.0
CORNER_TOLERANCE_M = 0.3
SQUARE_NE_M = [(4.0, 0.0), (4.0, 4.0), (0.0, 4.0), (0.0, 0.0)]


def log(*parts):
    print("[mavsdk]", *parts, flush=True)


def wait_for(predicate, timeout_s, what):
    """Polls predicate every 50 ms; exits the script with an error on timeout."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if predicate():
            return
        time.sleep(0.05)
    sys.exit(f"timeout after {timeout_s} s waiting for {what}")


def main():
    port = int(sys.argv[1])
    mavsdk = Mavsdk(Configuration.create_with_component_type(ComponentType.GROUND_STATION))
    result = mavsdk.add_any_connection(f"udpout://127.0.0.1:{port}")
    log("connection:", result)
    system = mavsdk.first_autopilot(10.0)
    if system is None:
        sys.exit("no autopilot discovered within 10 s")
    log("discovered system", system.get_system_id(), "autopilot", system.autopilot_type())

    action = Action(system)
    offboard = Offboard(system)
    telemetry = Telemetry(system)

    def ned():
        return telemetry.position_velocity_ned().position

    wait_for(lambda: not math.isnan(ned().north_m), 5, "LOCAL_POSITION_NED")
    action.set_takeoff_altitude(ALTITUDE_M)  # PARAM_SET MIS_TAKEOFF_ALT, needs the echo
    log("takeoff altitude set")
    action.arm()
    log("armed")
    action.takeoff()
    wait_for(lambda: telemetry.in_air(), 5, "in air")
    wait_for(lambda: ned().down_m < -(ALTITUDE_M - 0.2), 15, "takeoff altitude")
    log("took off to", round(-ned().down_m, 2), "m")

    start = ned()
    offboard.set_position_ned(PositionNedYaw(start.north_m, start.east_m, -ALTITUDE_M, 0.0))
    # MAVSDK streams the setpoint at 20 Hz from here on. The SITL, like the
    # issue's PX4 rule, accepts OFFBOARD only once setpoints have streamed at
    # more than 2 Hz (3 within a second), so let the stream run briefly first.
    time.sleep(0.5)
    offboard.start()
    wait_for(lambda: telemetry.flight_mode() == FlightMode.OFFBOARD, 3, "OFFBOARD in heartbeats")
    log("offboard started")

    for north_m, east_m in SQUARE_NE_M:
        offboard.set_position_ned(PositionNedYaw(north_m, east_m, -ALTITUDE_M, 0.0))

        def error_m():
            p = ned()
            return math.dist((p.north_m, p.east_m, p.down_m), (north_m, east_m, -ALTITUDE_M))

        wait_for(lambda: error_m() < CORNER_TOLERANCE_M, 20, f"corner ({north_m}, {east_m})")
        # Within tolerance on arrival; then it must settle there, not overshoot away.
        wait_for(lambda: error_m() < CORNER_TOLERANCE_M / 3, 5, f"settling at ({north_m}, {east_m})")
        log(f"corner ({north_m}, {east_m}) reached, settled error {error_m():.3f} m")

    offboard.stop()
    action.land()
    wait_for(lambda: telemetry.landed_state() == LandedState.ON_GROUND, 20, "landed")
    log("landed")
    action.disarm()
    wait_for(lambda: not telemetry.armed(), 5, "disarmed")
    log("disarmed: flight OK")


if __name__ == "__main__":
    main()
