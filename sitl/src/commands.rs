//! Incoming messages: COMMAND_LONG/INT with their COMMAND_ACKs, parameters,
//! TIMESYNC. Commands that cannot be carried out are refused with a result
//! code and, like the real autopilots do, a STATUSTEXT saying why.

use crate::imitation::ModeRequestError;
use crate::mode::FlightMode;
use crate::vehicle::Vehicle;
use mavlink::MavHeader;
use mavlink::dialects::common::{
    COMMAND_ACK_DATA, MavCmd, MavMessage, MavModeFlag, MavResult, MavSeverity, TIMESYNC_DATA,
};

/// PX4's magic param2 of MAV_CMD_COMPONENT_ARM_DISARM that forces (dis)arming.
const FORCE_ARM_MAGIC: f32 = 21196.0;

/// MAVLink component id of the autopilot.
pub const AUTOPILOT_COMPONENT_ID: u8 = 1;

/// The seven float parameters of a command, however it arrived.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CommandParams(pub [f32; 7]);

impl Vehicle {
    /// Handles one message from the wire. Never panics, whatever the content.
    // SET_MODE is deprecated in favour of MAV_CMD_DO_SET_MODE but still sent by ground stations.
    #[allow(deprecated)]
    pub fn handle(&mut self, header: MavHeader, message: &MavMessage) {
        if header.system_id == u32::from(self.system_id) {
            return; // our own echo, or a clone with our id: ignore
        }
        match message {
            MavMessage::COMMAND_LONG(c) if self.addressed(c.target_system, c.target_component) => {
                let p = [
                    c.param1, c.param2, c.param3, c.param4, c.param5, c.param6, c.param7,
                ];
                self.command(header, c.command, CommandParams(p));
            }
            MavMessage::COMMAND_INT(c) if self.addressed(c.target_system, c.target_component) => {
                let p = [
                    c.param1, c.param2, c.param3, c.param4, c.x as f32, c.y as f32, c.z,
                ];
                self.command(header, c.command, CommandParams(p));
            }
            MavMessage::SET_POSITION_TARGET_LOCAL_NED(sp) if sp.target_system == self.system_id => {
                self.position_target_local(sp);
            }
            MavMessage::SET_POSITION_TARGET_GLOBAL_INT(sp)
                if sp.target_system == self.system_id =>
            {
                self.position_target_global(sp);
            }
            MavMessage::SET_MODE(m) if m.target_system == self.system_id => {
                // The (deprecated) message form of MAV_CMD_DO_SET_MODE: same
                // rules, no COMMAND_ACK — the heartbeat shows the outcome.
                let (custom, sub) = self.flavour.imitation().mode_request_of(m.custom_mode);
                let _ = self.set_mode_command(f32::from(m.base_mode.bits()), custom, sub);
            }
            MavMessage::PARAM_SET(p) if self.addressed(p.target_system, p.target_component) => {
                let name = p.param_id.to_str().unwrap_or("");
                if let Some(echo) = self.params.set(name, p.param_value) {
                    self.outbox.push(echo);
                }
            }
            MavMessage::PARAM_REQUEST_READ(p)
                if self.addressed(p.target_system, p.target_component) =>
            {
                let name = p.param_id.to_str().unwrap_or("");
                if let Some(value) = self.params.read(name, p.param_index) {
                    self.outbox.push(value);
                }
            }
            MavMessage::PARAM_REQUEST_LIST(p)
                if self.addressed(p.target_system, p.target_component) =>
            {
                let all = self.params.list();
                self.outbox.extend(all);
            }
            // A request (tc1 = 0) for us or broadcast (0/0, as senders without
            // the target extension fields send); one for another system is not ours to answer.
            MavMessage::TIMESYNC(t)
                if t.tc1 == 0 && self.addressed(t.target_system, t.target_component) =>
            {
                self.outbox.push(MavMessage::TIMESYNC(TIMESYNC_DATA {
                    // Never 0: a tc1 of 0 would make the reply look like a request.
                    tc1: ((self.time_s * 1e9) as i64).max(1),
                    ts1: t.ts1,
                    target_system: u8::try_from(header.system_id).unwrap_or(0),
                    target_component: header.component_id,
                }));
            }
            _ => {}
        }
    }

    /// Whether a message's target fields name this autopilot (0 = broadcast).
    fn addressed(&self, target_system: u8, target_component: u8) -> bool {
        (target_system == self.system_id || target_system == 0)
            && (target_component == AUTOPILOT_COMPONENT_ID || target_component == 0)
    }

    /// Executes a command and queues its COMMAND_ACK (and any reply message).
    // Deprecated request commands are still sent by older ground stations.
    #[allow(deprecated)]
    fn command(&mut self, header: MavHeader, command: MavCmd, p: CommandParams) {
        let result = self.execute(command, p);
        self.outbox.push(MavMessage::COMMAND_ACK(COMMAND_ACK_DATA {
            command,
            result,
            progress: 0,
            result_param2: 0,
            target_system: u8::try_from(header.system_id).unwrap_or(0),
            target_component: header.component_id,
        }));
        // Requested messages follow their ACK, as on PX4.
        if result == MavResult::MAV_RESULT_ACCEPTED {
            let requested = match command {
                MavCmd::MAV_CMD_REQUEST_MESSAGE => Some(p.0[0] as u32),
                MavCmd::MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES => Some(148),
                MavCmd::MAV_CMD_GET_HOME_POSITION => Some(242),
                _ => None,
            };
            if let Some(message) = requested.and_then(|id| self.build_message(id)) {
                self.outbox.push(message);
            }
        }
    }

    /// Runs the pre-arm checks again: a failing one is explained by STATUSTEXT, in
    /// the words of the autopilot imitated.
    fn run_prearm_checks(&mut self) -> MavResult {
        if self.config.faults.refuse_arm {
            let text = self.config.flavour.imitation().prearm_failure_text();
            self.status_text(MavSeverity::MAV_SEVERITY_CRITICAL, text);
        }
        MavResult::MAV_RESULT_ACCEPTED
    }

    #[allow(deprecated)]
    fn execute(&mut self, command: MavCmd, p: CommandParams) -> MavResult {
        let [p1, p2, p3, _, _, _, p7] = p.0;
        match command {
            MavCmd::MAV_CMD_COMPONENT_ARM_DISARM => self.arm_disarm(p1, p2),
            MavCmd::MAV_CMD_DO_SET_MODE => self.set_mode_command(p1, p2, p3),
            MavCmd::MAV_CMD_NAV_TAKEOFF => self.takeoff(p7),
            MavCmd::MAV_CMD_NAV_LAND => {
                self.set_mode(FlightMode::Land);
                MavResult::MAV_RESULT_ACCEPTED
            }
            MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH => {
                self.set_mode(FlightMode::ReturnToLaunch);
                MavResult::MAV_RESULT_ACCEPTED
            }
            MavCmd::MAV_CMD_REQUEST_MESSAGE => {
                let known = p1.is_finite() && p1 >= 0.0 && self.build_message(p1 as u32).is_some();
                if known {
                    MavResult::MAV_RESULT_ACCEPTED
                } else {
                    MavResult::MAV_RESULT_UNSUPPORTED
                }
            }
            MavCmd::MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES | MavCmd::MAV_CMD_GET_HOME_POSITION => {
                MavResult::MAV_RESULT_ACCEPTED
            }
            MavCmd::MAV_CMD_RUN_PREARM_CHECKS => self.run_prearm_checks(),
            MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL => {
                let ok = p1.is_finite() && p1 >= 0.0 && self.streams.set_interval(p1 as u32, p2);
                if ok {
                    MavResult::MAV_RESULT_ACCEPTED
                } else {
                    MavResult::MAV_RESULT_UNSUPPORTED
                }
            }
            _ => MavResult::MAV_RESULT_UNSUPPORTED,
        }
    }

    /// Refuses a command, saying why (STATUSTEXT) as the autopilot would.
    pub(crate) fn refuse(&mut self, result: MavResult, reason: &str) -> MavResult {
        self.status_text(MavSeverity::MAV_SEVERITY_CRITICAL, reason);
        result
    }

    fn arm_disarm(&mut self, p1: f32, p2: f32) -> MavResult {
        let force = p2 == FORCE_ARM_MAGIC;
        if p1 == 0.0 {
            if self.armed && !self.landed() && !force {
                return self.refuse(MavResult::MAV_RESULT_DENIED, "Disarming denied: not landed");
            }
            self.set_armed(false);
            return MavResult::MAV_RESULT_ACCEPTED;
        }
        if p1 != 1.0 {
            return MavResult::MAV_RESULT_DENIED;
        }
        if self.armed {
            return MavResult::MAV_RESULT_ACCEPTED;
        }
        if self.config.faults.refuse_arm {
            return self.refuse(
                MavResult::MAV_RESULT_DENIED,
                "Arming denied: preflight checks failed",
            );
        }
        if self.battery_critical {
            return self.refuse(
                MavResult::MAV_RESULT_DENIED,
                "Arming denied: battery critical",
            );
        }
        if !self.landed() && !force {
            return self.refuse(MavResult::MAV_RESULT_DENIED, "Arming denied: not landed");
        }
        if !self.flavour.imitation().armable(self.mode) {
            return self.refuse(MavResult::MAV_RESULT_DENIED, "Arm: Mode not armable");
        }
        self.set_armed(true);
        MavResult::MAV_RESULT_ACCEPTED
    }

    fn set_mode_command(&mut self, base_mode: f32, custom: f32, sub: f32) -> MavResult {
        let base = if base_mode.is_finite() && (0.0..=255.0).contains(&base_mode) {
            base_mode as u8
        } else {
            0
        };
        if !MavModeFlag::from_bits_truncate(base)
            .contains(MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED)
        {
            return MavResult::MAV_RESULT_UNSUPPORTED;
        }
        let mode = match self.flavour.imitation().mode_from_request(custom, sub) {
            Ok(mode) => mode,
            Err(ModeRequestError::Unsupported) => {
                return self.refuse(
                    MavResult::MAV_RESULT_DENIED,
                    "Mode not available in SITL (no RC, no mission)",
                );
            }
            Err(ModeRequestError::Unknown) => return MavResult::MAV_RESULT_UNSUPPORTED,
        };
        if mode == FlightMode::Offboard && !self.setpoint_stream_ok() {
            return self.refuse(
                MavResult::MAV_RESULT_TEMPORARILY_REJECTED,
                "Offboard denied: no setpoint stream (> 2 Hz needed)",
            );
        }
        if mode != self.mode {
            self.set_mode(mode);
        }
        MavResult::MAV_RESULT_ACCEPTED
    }

    /// MAV_CMD_NAV_TAKEOFF, as the imitated firmware answers it.
    fn takeoff(&mut self, p7: f32) -> MavResult {
        self.flavour.imitation().takeoff(self, p7)
    }
}
