//! Commands the flight loop sends a vehicle without waiting for them: each runs
//! in its own task (a mode switch takes a round trip and a telemetry
//! confirmation, seconds under packet loss) and reports back as a typed message
//! on one channel, which the loop drains once per tick.
//!
//! The loop drains with [`tokio::sync::mpsc::UnboundedReceiver::try_recv`], which
//! does not take part in tokio's cooperative budget (128 polls per task per
//! tick): 200 drones whose commands finish together are all seen in the same
//! tick. Polling 200 join handles inside the budget once read handle 129 onwards
//! as unfinished and failed drones whose command had succeeded.

use crate::link::{LinkError, ModeRequest, Session};
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::mpsc;

/// How long a land command waits for touchdown and disarm in telemetry.
const TOUCHDOWN_WITHIN: Duration = Duration::from_secs(60);

/// One command the loop can send a drone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Command {
    /// Switch to the mode that follows our setpoints (PX4 OFFBOARD) for takeoff.
    EnterExternalControl,
    /// Switch back to that mode after the vehicle's offboard-loss failsafe left it.
    ResumeExternalControl,
    /// ArduPilot's own takeoff, to `height_m` metres above home.
    Takeoff {
        /// Height above home, metres (MAV_CMD_NAV_TAKEOFF param7).
        height_m: f32,
    },
    /// Land where the vehicle is and wait for disarm (on the ground: just disarm).
    Land,
    /// Switch to the autopilot's position hold and leave it there.
    Hold,
}

/// Why a command did not succeed.
#[derive(Debug, thiserror::Error)]
pub enum CommandError {
    /// The vehicle refused, never acknowledged, or telemetry never confirmed it.
    #[error(transparent)]
    Link(#[from] LinkError),
    /// The task running the command stopped before it had a result.
    #[error("command task failed: it ended without a result (panicked or cancelled)")]
    TaskEnded,
}

/// A command a phase waits for: not sent yet, in flight, or answered.
#[derive(Debug, Default)]
pub enum Request {
    /// Not sent yet (some phases wait before sending).
    #[default]
    NotSent,
    /// Sent; its result has not arrived.
    Sent,
    /// Answered; the phase acts on the result on its next step.
    Done(Result<(), CommandError>),
}

impl Request {
    /// Takes an answered result out, leaving `NotSent`; `None` while unsent or in flight.
    pub fn take_done(&mut self) -> Option<Result<(), CommandError>> {
        match std::mem::take(self) {
            Request::Done(result) => Some(result),
            other => {
                *self = other;
                None
            }
        }
    }
}

/// The modes the commands switch to, in the vehicle's own numbers (its
/// flavour's: see `autopilot::Flavour::modes`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Modes {
    /// The mode that follows our setpoints (PX4 OFFBOARD, ArduPilot GUIDED).
    pub external_control: ModeRequest,
    /// Position hold without our stream.
    pub hold: ModeRequest,
    /// Land where the vehicle is.
    pub land: ModeRequest,
}

/// A finished command: the drone's index in plan order, what was asked, and how it went.
pub type CommandDone = (usize, Command, Result<(), CommandError>);

/// The sending side, one clone per drone: starts command tasks that report on the channel.
#[derive(Debug, Clone)]
pub struct CommandSender {
    tx: mpsc::UnboundedSender<CommandDone>,
}

/// The receiving side, owned by the loop.
#[derive(Debug)]
pub struct CommandInbox {
    rx: mpsc::UnboundedReceiver<CommandDone>,
}

/// A channel for command results: one sender to clone per drone, one inbox for the loop.
pub fn channel() -> (CommandSender, CommandInbox) {
    // Unbounded: a send from a command task never waits, and there are at most
    // two commands in flight per drone.
    let (tx, rx) = mpsc::unbounded_channel();
    (CommandSender { tx }, CommandInbox { rx })
}

impl CommandSender {
    /// Runs `command` for drone `drone` (plan order) in its own task; its result
    /// arrives in the [`CommandInbox`].
    pub fn spawn(&self, drone: usize, command: Command, session: Arc<Session>, modes: Modes) {
        self.spawn_future(drone, command, async move {
            execute(command, &session, modes).await
        });
    }

    /// Runs any future as the command's body (the tests use it without a vehicle).
    pub fn spawn_future<F>(&self, drone: usize, command: Command, body: F)
    where
        F: Future<Output = Result<(), LinkError>> + Send + 'static,
    {
        let reply = Reply {
            tx: self.tx.clone(),
            drone,
            command,
            sent: false,
        };
        tokio::spawn(async move {
            let mut reply = reply;
            let result = body.await;
            reply.send(result.map_err(CommandError::from));
        });
    }
}

impl CommandInbox {
    /// Every result that has arrived since the last call, in arrival order.
    pub fn drain(&mut self) -> Vec<CommandDone> {
        let mut done = Vec::new();
        // `try_recv` spends no cooperative budget, so this sees everything queued.
        while let Ok(message) = self.rx.try_recv() {
            done.push(message);
        }
        done
    }
}

/// Sends the task's result exactly once; a task dropped before it had one (a
/// panic unwinding, a runtime shutting down) reports [`CommandError::TaskEnded`],
/// so the drone waiting for it is not left waiting forever.
struct Reply {
    tx: mpsc::UnboundedSender<CommandDone>,
    drone: usize,
    command: Command,
    sent: bool,
}

impl Reply {
    fn send(&mut self, result: Result<(), CommandError>) {
        self.sent = true;
        // The loop gone means the flight is over: nobody needs the result.
        let _ = self.tx.send((self.drone, self.command, result));
    }
}

impl Drop for Reply {
    fn drop(&mut self) {
        if !self.sent {
            self.send(Err(CommandError::TaskEnded));
        }
    }
}

/// What each command does on the link.
async fn execute(command: Command, session: &Session, modes: Modes) -> Result<(), LinkError> {
    match command {
        Command::EnterExternalControl | Command::ResumeExternalControl => {
            session.set_mode(modes.external_control).await
        }
        Command::Takeoff { height_m } => session.takeoff(height_m).await,
        Command::Hold => session.set_mode(modes.hold).await,
        Command::Land => {
            if let Err(e) = session.set_mode(modes.land).await {
                // Still on the ground (takeoff never happened): disarming is the landing.
                if session.state().on_ground() {
                    return session.disarm(false).await;
                }
                return Err(e);
            }
            session
                .confirm("touchdown and disarm", TOUCHDOWN_WITHIN, |s| !s.armed)
                .await
        }
    }
}
