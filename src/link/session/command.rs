//! The command sender: COMMAND_LONG with MAVLink's confirmation counter, retried
//! until the vehicle acknowledges it, and the policy for how long to keep trying.

use super::Session;
use crate::link::error::LinkError;
use crate::link::messages::command_long;
use mavlink::dialects::common::{MavCmd, MavResult};
use std::time::{Duration, Instant};
use tokio::sync::broadcast;

/// How often and how long a command is tried before giving up.
#[derive(Debug, Clone, Copy)]
pub struct CommandPolicy {
    /// Tries before a silent vehicle counts as not acknowledging.
    pub attempts: u8,
    /// How long each try waits for its COMMAND_ACK.
    pub ack_timeout: Duration,
}

impl Default for CommandPolicy {
    /// Twelve tries, 0.6 s each: at 30 % loss each way a try gets through with
    /// p = 0.49, so a command fails with p = 0.51^12 ≈ 3e-4 — and a swarm sends
    /// dozens per flight, which the CI's 8-drone 30 % run hit twice (2026-12-02,
    /// first on a rate request, then on OFFBOARD). So a vehicle that is still heard
    /// gets up to twice the tries (`Session::keeps_trying`): p ≈ 1e-7.
    /// A refusal still comes back at once; only a silent vehicle costs the 7 s.
    fn default() -> Self {
        Self {
            attempts: 12,
            ack_timeout: Duration::from_millis(600),
        }
    }
}

/// A vehicle heard this recently is lossy, not silent: its commands get extra tries.
/// Before any stream is requested only 1 Hz heartbeats come; at 30 % loss three
/// in a row are lost with p ≈ 3 %.
const HEARD_WITHIN_S: f64 = 3.0;

impl Session {
    /// Sends a COMMAND_LONG until acknowledged, incrementing the confirmation
    /// counter on each retry (as MAVLink asks, so the vehicle can tell a retry from
    /// a new command). ACCEPTED is `Ok`; a refusal carries the vehicle's STATUSTEXT.
    pub async fn command(&self, command: MavCmd, params: [f32; 7]) -> Result<(), LinkError> {
        let mut acks = self.acks.subscribe();
        let mut attempt: u8 = 0;
        while self.keeps_trying(attempt) {
            self.send(&command_long(self.system_id, command, params, attempt))
                .await?;
            let deadline = tokio::time::Instant::now() + self.policy.ack_timeout;
            loop {
                let ack = match tokio::time::timeout_at(deadline, acks.recv()).await {
                    Err(_) => break, // this attempt timed out
                    Ok(Err(broadcast::error::RecvError::Lagged(_))) => continue,
                    Ok(Err(broadcast::error::RecvError::Closed)) => {
                        return Err(LinkError::Send("session reader stopped".into()));
                    }
                    Ok(Ok(ack)) => ack,
                };
                if ack.command != command {
                    continue;
                }
                match ack.result {
                    MavResult::MAV_RESULT_ACCEPTED => return Ok(()),
                    MavResult::MAV_RESULT_IN_PROGRESS => continue,
                    // Worth another try after the timeout (PX4 offboard without a stream yet).
                    MavResult::MAV_RESULT_TEMPORARILY_REJECTED => {
                        if !self.keeps_trying(attempt.saturating_add(1)) {
                            return Err(self.refused(command, ack.result));
                        }
                        tokio::time::sleep_until(deadline).await;
                        break;
                    }
                    result => return Err(self.refused(command, result)),
                }
            }
            attempt = attempt.saturating_add(1);
        }
        Err(LinkError::NoAck {
            command,
            attempts: attempt,
        })
    }

    /// Whether try number `attempt` (from 0) should be made: the policy's tries,
    /// then as many again while the vehicle is still heard — a lossy link, not a
    /// silent vehicle, so giving up would strand a healthy drone.
    pub(super) fn keeps_trying(&self, attempt: u8) -> bool {
        let tries = self.policy.attempts;
        if attempt < tries {
            return true;
        }
        attempt < tries.saturating_mul(2)
            && self
                .state()
                .message_age_s(Instant::now())
                .is_some_and(|age_s| age_s <= HEARD_WITHIN_S)
    }

    fn refused(&self, command: MavCmd, result: MavResult) -> LinkError {
        LinkError::Refused {
            command,
            result,
            reason: self.state().last_status_text.clone(),
        }
    }
}
