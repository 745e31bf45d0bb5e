//! The ways a plan can break its mission, as the validator reports them.

use crate::world::Voxel;

/// One way a plan breaks its mission. Drones are named by id; `step` counts plan steps
/// from 0; voxels are mission grid coordinates.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanViolation {
    /// A drone id of the plan that the mission does not have, or a second path for one.
    #[error("drone {0:?} is in the plan but not in the mission, or appears twice")]
    UnknownDrone(String),
    /// A drone of the mission that the plan leaves out.
    #[error("drone {0:?} of the mission has no path")]
    MissingDrone(String),
    /// The plan files a drone under another group than the mission does.
    #[error("drone {id:?} is listed in group {found:?} but belongs to {expected:?}")]
    WrongGroup {
        /// The drone.
        id: String,
        /// Its group in the mission.
        expected: String,
        /// The group the plan gives.
        found: String,
    },
    /// A path that does not cover every step from 0 to the makespan.
    #[error("drone {id:?}: path has {len} entries, expected makespan + 1 = {expected}")]
    PathLength {
        /// The drone.
        id: String,
        /// Entries in its path.
        len: usize,
        /// `makespan_steps + 1`.
        expected: usize,
    },
    /// A path that does not start above the drone's pad.
    #[error("drone {id:?}: path starts at {found} instead of above its pad, {expected}")]
    WrongStart {
        /// The drone.
        id: String,
        /// Its start in the mission.
        expected: Voxel,
        /// The path's first voxel.
        found: Voxel,
    },
    /// The rest of a flight has a path that does not start where the replan found
    /// the drone.
    #[error("drone {id:?}: path starts at {found} instead of where the drone is, {expected}")]
    WrongLiveStart {
        /// The drone.
        id: String,
        /// Its live voxel.
        expected: Voxel,
        /// The path's first voxel.
        found: Voxel,
    },
    /// The rest of a flight plans a drone no live start was given for.
    #[error("drone {0:?}: planned, but no start was given for it")]
    NoStart(String),
    /// The plan's legs are not the mission's (names, order, holds or steps).
    #[error("the plan's legs do not match the mission's: {0}")]
    Legs(String),
    /// A drone not on a target of its leg when the leg ends.
    #[error("drone {id:?}: at the end of leg {leg:?} (step {step}) it is at {found}, {expected}")]
    MissesLegTarget {
        /// The drone.
        id: String,
        /// The leg.
        leg: String,
        /// The leg's last step.
        step: usize,
        /// Where the drone is then.
        found: Voxel,
        /// What the leg asks, in words.
        expected: String,
    },
    /// A formation or stage leg through the pad layer, where the mission keeps
    /// them in the world's own voxels (`world.formations_use_pad_layer: false`).
    #[error(
        "drone {id:?}: leg {leg:?} passes through the pad layer at step {step} ({voxel}), but the mission keeps formations in the world's voxels"
    )]
    InPadLayer {
        /// The drone.
        id: String,
        /// The leg.
        leg: String,
        /// The first step in the pad layer.
        step: usize,
        /// Where the path is then.
        voxel: Voxel,
    },
    /// A path that does not end where the plan says it does (`goal`).
    #[error("drone {id:?}: path ends at {found}, not at its goal {goal}")]
    MissesGoal {
        /// The drone.
        id: String,
        /// Its assigned goal.
        goal: Voxel,
        /// The path's last voxel.
        found: Voxel,
    },
    /// A path through an obstacle or out of the world.
    #[error("drone {id:?}: step {step} at {voxel} is {}", if *.in_obstacle { "inside an obstacle" } else { "outside the airspace (the world's voxels and the pad layer's cells)" })]
    NotFree {
        /// The drone.
        id: String,
        /// The first offending step.
        step: usize,
        /// Where the path is then.
        voxel: Voxel,
        /// In an obstacle of the airspace (else outside the airspace altogether).
        in_obstacle: bool,
    },
    /// A move between voxels that are not face neighbours.
    #[error("drone {id:?}: jumps from {from} to {to} at step {step}")]
    Jump {
        /// The drone.
        id: String,
        /// The step the move starts at.
        step: usize,
        /// Where it starts.
        from: Voxel,
        /// Where it lands.
        to: Voxel,
    },
    /// Two drones in one voxel at one step.
    #[error("drones {a:?} and {b:?} are both in {voxel} at step {step}")]
    VertexConflict {
        /// One drone.
        a: String,
        /// The other.
        b: String,
        /// The shared voxel.
        voxel: Voxel,
        /// The step they share it.
        step: usize,
    },
    /// Two drones trading places in one step (they would pass through each other).
    #[error("drones {a:?} and {b:?} swap {from} and {to} between steps {step} and {}", step + 1)]
    SwapConflict {
        /// The drone moving `from` → `to`.
        a: String,
        /// The drone moving `to` → `from`.
        b: String,
        /// Where `a` starts.
        from: Voxel,
        /// Where `b` starts.
        to: Voxel,
        /// The step the swap starts at.
        step: usize,
    },
    /// Drones following each other round a loop in one step: no precedence schedule
    /// can fly it with a safety distance.
    #[error(
        "drones {} rotate between steps {step} and {}: each enters the voxel the next leaves, which no drone can fly safely",
        drones.join(", "), step + 1
    )]
    Rotation {
        /// The drones round the loop, in order.
        drones: Vec<String>,
        /// The step the rotation starts at.
        step: usize,
    },
    /// Under an ellipsoidal separation, two drones in one column closer than its
    /// vertical reach at one step.
    #[error(
        "drones {a:?} and {b:?} are at {a_voxel} and {b_voxel} at step {step}: stacked {apart_m:.2} m apart, inside the separation ellipsoid's vertical reach ({reach_m:.2} m)"
    )]
    Stacked {
        /// One drone.
        a: String,
        /// The other.
        b: String,
        /// Where `a` is.
        a_voxel: Voxel,
        /// Where `b` is.
        b_voxel: Voxel,
        /// The step.
        step: usize,
        /// Their cell centres' vertical distance, metres.
        apart_m: f64,
        /// The reach, metres.
        reach_m: f64,
    },
    /// Under an ellipsoidal separation, drones that each move in one step into the
    /// cell the next leaves or one within the vertical reach of it: each would wait
    /// for the next to be out of reach, for ever.
    #[error(
        "drones {} wait for one another in a cycle between steps {step} and {}: each moves into the reach of the cell the next one leaves",
        drones.join(", "), step + 1
    )]
    StackedCycle {
        /// The drones on the cycle (and any waiting on it), sorted.
        drones: Vec<String>,
        /// The step the moves start at.
        step: usize,
    },
    /// The plan's makespan is not when its last drone arrives.
    #[error("reported makespan {reported} but the last drone arrives at step {actual}")]
    Makespan {
        /// What the plan says, steps.
        reported: u32,
        /// What its paths give, steps.
        actual: u32,
    },
    /// The plan's sum of costs is not the sum of its drones' arrival steps.
    #[error("reported sum of costs {reported} but the arrival steps add up to {actual}")]
    SumOfCosts {
        /// What the plan says, steps.
        reported: u64,
        /// What its paths give, steps.
        actual: u64,
    },
}
