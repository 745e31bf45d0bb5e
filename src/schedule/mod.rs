//! From a discrete plan to a continuous-time schedule: the Temporal Plan Graph (TPG)
//! with safety markers, a Simple Temporal Network (STN) over it, and slack.
//!
//! ```text
//! DiscretePlan ── build ──► Tpg ── solve ──► Schedule ── trajectory::from_schedule ──► Trajectories
//! ```
//!
//! # The safety argument
//!
//! Let `s` be the voxel size and `d` the safety distance. Drones fly along the straight
//! edges between face-adjacent voxel centres (a waiting drone is a point at a centre).
//!
//! **Lemma 1 (far edges).** Two lattice edges of length `s` that share no voxel centre are
//! at least `s` apart: for parallel edges some coordinate differs by a multiple of `s`;
//! for perpendicular edges in one plane the only closer configuration is a crossing,
//! and edges cross only at lattice points, which would be a shared centre.
//! So if `d ≤ s`, drones closer than `d` are on edges sharing a centre `v`.
//!
//! **Holding.** A drone *holds* voxel `v` while its distance *along its path* to its
//! visit of `v`'s centre is less than the hold radius `h = (s + d) / 2`. On an edge
//! incident to `v`, path distance to `v` equals Euclidean distance `r`.
//!
//! **Lemma 2 (close drones share a held voxel).** Take two drones on edges sharing
//! centre `v`, at distances `r₁`, `r₂` from it, closer than `d`.
//! * Perpendicular edges: distance `√(r₁² + r₂²) < d`, so `r₁, r₂ < d ≤ h`: both hold `v`.
//! * Opposite edges: distance `r₁ + r₂ < d`: both hold `v`.
//! * The same edge `v–w`: distance `|r₁ − r₂| < d`. If both `r < h` both hold `v`.
//!   Otherwise say `r₁ ≥ h`; then `s − r₁ ≤ s − h < h` (as `d > 0`) and
//!   `s − r₂ < s − (h − d) = h`: both hold `w`.
//!
//! Hence, if `d ≤ s` and no two drones ever hold the same voxel at the same time, no two
//! drones are ever closer than `d`. This needs `d ≤ s`, and `d ≤ s` is also necessary:
//! the discrete plan may park drones in face-adjacent voxels, `s` apart. Missions with
//! `d > s` are rejected ([`ScheduleError::SafetyDistanceTooLarge`]).
//!
//! **Markers.** On each move `u → v` (length `s`) put two events at `δ = (s − d) / 2` from
//! each end: `Enter v` at `δ` after `u` (path distance `s − δ = h` before `v`: the drone
//! starts holding `v`), and `Leave u` at `δ` before `v` (path distance `h` past `u`: it
//! stops holding `u`). With `d = s` the markers sit at the centres.
//!
//! **Type-2 edges.** The discrete plan orders the visits of every voxel (no two drones
//! share a voxel at a step). For consecutive visits of `v` by different drones `A` then
//! `B`, the TPG has the edge `Leave v (A) → Enter v (B)`. Non-consecutive visits are
//! ordered through the visitors in between, so these edges suffice. Edges implied by
//! another edge between the same two drones are dropped (a later source on `A` and an
//! earlier target on `B` imply it through each drone's own order).
//!
//! **Continuous time.** Every trajectory moves monotonically along its path and passes
//! each event's position exactly at the event's scheduled time (rest events: reached
//! at `reach_s`, left at `leave_s`). Then `A` holds `v` only strictly between its
//! `Enter v` and `Leave v` times, and `B`'s holding of `v` starts after `A`'s ended:
//! holdings of a voxel never overlap, which with Lemma 2 proves separation `≥ d` at every
//! instant — for following on one line, perpendicular entries and exits, and drones
//! resting side by side alike.
//!
//! **The pad layer.** A whole flight runs in the mission's *airspace*: the world plus
//! a pad layer below it, whose centres sit at the pads' hover height `p` above the
//! ground rather than a whole voxel below layer 0. The lattice is still rectilinear;
//! only the gap `g` between the pad layer and layer 0 may differ from `s`, and
//! mission validation demands `g ≥ d` (as [`build`] checks again). Nothing above used
//! the length `s` except through `d ≤ s`: with every spacing at least `d`, two edges
//! sharing no centre are at least `d` apart (Lemma 1 with `min(s, g)` for `s`), and
//! Lemma 2 holds on an edge of any length `ℓ ≥ d` with its own hold radius
//! `(ℓ + d) / 2` and markers at `(ℓ − d) / 2` from each end, which is where
//! [`build`] puts them on the moves into and out of the pad layer.
//!
//! **Ground to pad layer.** Before its first move a drone climbs straight up from
//! its pad on the ground to the pad-layer cell above, and after its last it descends
//! straight down from the pad-layer cell it ended in. Both happen inside the column
//! below a cell the drone holds: its first cell from time zero until it leaves, its
//! last from its final arrival on (no other drone enters a cell after its last
//! visitor arrived for good). Every point of that column is at least `s` from every
//! other column's lattice points and edges, and at least `g ≥ d` below every
//! lattice point above the cell; no other drone is on an edge from the held cell.
//! So climbs and touchdowns keep the safety distance too, and pads being distinct
//! cells keeps drones standing on the ground `s` apart.
//!
//! **Holds.** A stage with a hold adds, for every pair of drones `(A, B)` (`A = B`
//! included), an edge from `A`'s rest at the stage's formation to `B`'s, delayed by
//! the hold: nobody leaves before the whole swarm has been in formation that long.
//! A drone that never leaves its formation cell (its last) gets no such edge: it
//! has no departure to delay. A drone still at its start holds the formation from
//! time zero. These edges only delay departures, so they never weaken the argument
//! above, and they keep the STN a set of difference constraints.
//!
//! **Tracking error.** Everything above is about *setpoints*, the points the drones
//! are commanded to be at. Real vehicles are not exactly there: the mission trusts each
//! to stay within its tracking error `e` of its setpoint (`limits.tracking_error_m`),
//! and [`build`] runs the argument with `d' = d + 2e` in place of `d` — setpoints
//! are kept `d'` apart, so two vehicles within `e` of theirs are at least `d` apart.
//! Validation demands `d'` fit between neighbouring centres (voxel size and pad-layer
//! gap). In flight `fly` holds a drone's setpoint while the vehicle is further than `e`
//! from it (and, through the gates, everyone waiting for it), and reports whether the
//! bound held.
//!
//! **Releasing gates on commanded progress.** The argument orders *setpoints*: `B`'s
//! setpoint may enter `v` once `A`'s has left it. In flight a gate is therefore
//! released as soon as the predecessor's *setpoint* has passed the event, provided
//! its vehicle is at that moment known to be within `e` of it: its newest position
//! is fresh (at most a few setpoint periods old), it lies within `e` of the
//! setpoint streamed when it was taken, and that setpoint is past the event. From
//! then on `A`'s setpoint only moves further along its path, and `A`'s vehicle is
//! within `e` of it whenever the bound holds, which is what every other step above
//! assumes too; when the bound breaks, `A`'s setpoint is held and the flight
//! reports it. A predecessor whose telemetry is stale, whose link is lost, whose
//! setpoint is held for straying, or that is off its setpoint by more than `e` is
//! not trusted: its events are released only when telemetry shows it past them, so
//! a late, lost or straying drone still makes exactly its dependants wait. With no
//! bound (`e = 0`) only telemetry releases. Waiting for telemetry at every gate
//! would add the telemetry latency and the vehicle's lag to every zero-slack
//! precedence, and along a chain of dependants those delays add up.
//!
//! *Flying through a gate that is about to open.* A follower decides to brake a
//! stopping distance ahead of a closed gate, so a drone whose predecessor passes
//! on time would still brake for every precedence with no slack. Its predecessor's
//! setpoint is *committed* to an event when braking now would still carry it past
//! (the slowest it can go: every brake starts from a validated state, and a
//! profile flown on and braked later is ahead of braking now at every moment), and
//! braking now gives the latest time `T` it passes. While the predecessor's vehicle
//! is trusted as above, the dependant may fly past the point where it could still
//! stop before its own event if, on its present motion, its setpoint reaches the
//! event no earlier than `T` (it can only be slower than that motion). The
//! setpoints then keep the order the argument needs; a gate whose predecessor is
//! not committed, or a stage's hold, is still one to stop short of.
//!
//! *Budgeting that decision.* The dependant decides a stopping distance (and a
//! setpoint period or two) before its event, and its predecessor is committed
//! only once braking would carry it past its own, to the time braking passes it,
//! which is later than flying on does: the dependant brakes although both are on
//! time. [`solve`] therefore adds to every hand-over
//! edge the least gap that has the predecessor committed, by when the dependant
//! decides, to pass its event no later than the dependant reaches its own
//! (`decision_lead`; none for an event where the dependant's run ends, as it
//! stops there anyway). The gap only delays runs, so the argument above stands;
//! the schedule now says when a flight that keeps it passes every event.
//!
//! **Ellipsoids.** Downwash reaches further below a drone than beside it, so a mission
//! may separate drones by an axis-aligned ellipsoid instead (`limits.separation`:
//! horizontal radius `H`, vertical `V`; see [`crate::world::Separation`]). The schedule
//! then keeps *setpoints* outside each other's bounding cylinder of the grown
//! ellipsoid — horizontal distance `ρ ≥ H' = H + 2e` or vertical distance
//! `|dz| ≥ V' = V + 2e` — which leaves vehicles within `e` of their setpoints `ρ ≥ H` or
//! `|dz| ≥ V` apart, outside the ellipsoid either way. Validation demands `H' ≤ s`; `V'`
//! may exceed the voxel size.
//!
//! *Projection.* Seen from above, the lattice is a square lattice of columns with
//! spacing `s`; a horizontal move projects to an edge, a vertical move (and a rest) to
//! a column's centre. Lemmas 1 and 2 hold in the plane with `H'` for `d`: two drones
//! horizontally closer than `H'` are both within `h = (s + H') / 2` (horizontal path
//! distance) of one column `c`. Horizontal moves carry their markers at
//! `(s − H') / 2` from each end as before, so each of the two holds a cell of `c`:
//! a horizontal mover the cell of `c` at its own layer, a vertical mover in `c` the
//! cell(s) its vertical markers give it.
//!
//! *Vertical markers.* On a vertical move of length `ℓ` the markers sit `σ` from each
//! end, `σ = max(0, (c − V') / 2)` with `c` the closest vertical spacing of cell
//! centres (the voxel size, or the pad layer's gap below layer 0): with `σ < ℓ / 2`
//! every point of the move holds an end, and a drone holding only the far end is
//! within `σ` of it. So two drones less than `V'` apart vertically hold cells of `c`
//! whose centres are less than `V' + 2σ` apart — the *vertical reach*
//! ([`crate::world::VerticalReach`]). Cells exactly `V'` apart are related as well:
//! setpoints that far apart are separated with nothing to spare, which the trajectory
//! checker cannot confirm for drones in motion. For `V' < c` the reach relates no two
//! distinct cells and the argument is the sphere's with `H'` across and `V'` along the
//! column.
//!
//! *Holding the reach.* The planner never puts two drones in cells of one column
//! within the reach at one step (a conflict it branches on like a vertex conflict,
//! inside a group as well as between groups), nor lets drones each move into the
//! reach of the cell the next one leaves in one step (a generalised rotation). The
//! TPG then orders every two visits of cells within reach of each other, as it orders
//! visits of one cell: from the earlier visitor's `Leave` to the later one's `Enter`
//! (the latest earlier visitor of each cell in reach suffices, as before). So no two
//! drones ever hold cells within reach at once, and by the two steps above no two
//! setpoints are ever inside each other's cylinder. Climbs from and descents to the
//! ground happen below a pad-layer cell the drone holds; any point within `V'` of
//! them above is within `V'` of that cell, so the same ordering covers them, and
//! drones standing on pads are `s ≥ H'` apart horizontally. The STN is unchanged:
//! the extra edges are difference constraints like every type-2 edge.
//!
//! **Cycles.** A rotation (drones following each other round a loop in one step) and a
//! swap make the TPG cyclic: no precedence schedule can execute them with a safety
//! distance, and [`solve`] reports [`ScheduleError::CyclicPlan`].
//!
//! # Kinematics
//!
//! A polyline with corners cannot be flown at speed with bounded acceleration, so the
//! drone stops at every corner: motion is a sequence of straight rest-to-rest runs, each
//! a time-optimal S-curve speed [`Profile`](crate::profile::Profile) within the speed,
//! acceleration and jerk limits (the acceleration ramps instead of jumping, so a real
//! autopilot can follow it). The separation argument below needs only that each run moves
//! monotonically along its straight line from rest to rest, which every profile does.
//! Runs also end where the discrete plan waits. Events inside a run are passed at fixed
//! offsets from the run's start, so the STN's timepoints are run starts, its lower bounds
//! come from the profiles (speed, acceleration and jerk), and a drone that must not pass a
//! marker too early starts its run later rather than stopping in mid-air. The earliest
//! schedule is a longest path in the DAG of runs, O(V + E).

mod decision_lead;
mod error;
mod execution;
mod solve;
mod stn;
mod tpg;

pub use decision_lead::{COMMIT_TOLERANCE_M, GATE_STOP_MARGIN_M};
pub use error::ScheduleError;
pub use execution::{ExecutionDrone, ExecutionEvent, ExecutionPlan, execution_plan};
pub use solve::{DroneSchedule, EventTime, Schedule, Segment, solve};
pub use stn::{Constraint, Stn, StnCycle};
pub use tpg::{CrossEdge, Event, EventId, EventKind, Tpg, TpgDrone, build, build_with};
