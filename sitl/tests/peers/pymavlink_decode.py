"""pymavlink decodes swarmctl-sitl telemetry: every expected message arrives
as MAVLink 2 and nothing is reported as bad data.

Usage: python pymavlink_decode.py PORT     (exit status 0 on success)
"""

import os
import sys
import time

os.environ["MAVLINK20"] = "1"  # before importing pymavlink: send MAVLink 2

from pymavlink import mavutil  # noqa: E402

EXPECTED = {
    "HEARTBEAT",
    "SYS_STATUS",
    "SYSTEM_TIME",
    "ATTITUDE",
    "LOCAL_POSITION_NED",
    "GLOBAL_POSITION_INT",
    "BATTERY_STATUS",
    "EXTENDED_SYS_STATE",
    "HOME_POSITION",
    "AUTOPILOT_VERSION",
    "COMMAND_ACK",
    "TIMESYNC",
    "PARAM_VALUE",
}
WINDOW_S = 5.0


def main():
    port = int(sys.argv[1])
    link = mavutil.mavlink_connection(f"udpout:127.0.0.1:{port}", source_system=255, source_component=190)
    link.mav.heartbeat_send(mavutil.mavlink.MAV_TYPE_GCS, mavutil.mavlink.MAV_AUTOPILOT_INVALID, 0, 0, 0)
    heartbeat = link.wait_heartbeat(timeout=5)
    if heartbeat is None:
        sys.exit("no heartbeat within 5 s")
    target = link.target_system
    link.mav.command_long_send(target, 1, mavutil.mavlink.MAV_CMD_REQUEST_MESSAGE, 0, 148, 0, 0, 0, 0, 0, 0)
    link.mav.timesync_send(0, 12345)
    link.mav.param_request_list_send(target, 1)

    seen = {}
    bad = 0
    not_v2 = 0
    deadline = time.monotonic() + WINDOW_S
    while time.monotonic() < deadline:
        message = link.recv_match(blocking=True, timeout=0.5)
        if message is None:
            continue
        name = message.get_type()
        if name == "BAD_DATA":
            bad += 1
            print("bad data:", message, flush=True)
            continue
        if message.get_msgbuf()[0] != 0xFD:
            not_v2 += 1
        seen[name] = seen.get(name, 0) + 1

    print("decoded:", dict(sorted(seen.items())), flush=True)
    missing = EXPECTED - set(seen)
    if bad or not_v2 or missing:
        sys.exit(f"bad frames: {bad}, MAVLink 1 frames: {not_v2}, missing: {sorted(missing)}")
    print("pymavlink decode OK", flush=True)


if __name__ == "__main__":
    main()
