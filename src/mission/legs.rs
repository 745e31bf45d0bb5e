//! A mission as a sequence of legs, pad to pad: take off, fly each formation, land.
//!
//! Each leg is one TAPF instance: every drone starts where the previous leg left it
//! (on its pad for the first) and must end on one of its leg's targets. The planner
//! solves the legs one after the other; the plan validator checks each leg's end
//! against the same targets. Both read the legs from here, so they agree on *what*
//! a leg asks for while sharing nothing of *how* it is solved or checked.

use super::schema::Landing;
use super::types::{Group, Mission, Stage};
use crate::world::Voxel;

/// What a leg is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LegKind {
    /// From the pads up to the starts (or straight to the first formation).
    Takeoff,
    /// From the starts to the groups' goals, the first formation.
    Formation,
    /// One of the mission's `stages`.
    Stage,
    /// From the last formation down to the pads.
    Landing,
}

/// Where the drones of one group must be at the end of a leg.
#[derive(Debug, Clone, PartialEq)]
pub enum Targets {
    /// Any drone of the group on any of these voxels (at least one per drone).
    Any(Vec<Voxel>),
    /// Drone `i` of the group (file order) on voxel `i`.
    Own(Vec<Voxel>),
    /// Every drone where the leg found it.
    Stay,
    /// Every drone on the pad-layer cell straight below where the leg found it.
    BelowCurrent,
}

impl Targets {
    /// The target of every drone of a group given where each is when the leg starts:
    /// one voxel set per drone (a singleton for everything but [`Targets::Any`], whose
    /// set is shared; `None` then).
    pub fn per_drone(&self, at_leg_start: &[Voxel]) -> Option<Vec<Voxel>> {
        match self {
            Targets::Any(_) => None,
            Targets::Own(own) => Some(own.clone()),
            Targets::Stay => Some(at_leg_start.to_vec()),
            Targets::BelowCurrent => Some(at_leg_start.iter().map(|v| v.pad_below()).collect()),
        }
    }
}

/// One leg of the flight.
#[derive(Debug, Clone, PartialEq)]
pub struct Leg {
    /// `takeoff`, `formation`, the stage's name, or `landing`.
    pub name: String,
    /// What the leg is for.
    pub kind: LegKind,
    /// Seconds every drone holds at the leg's end once the whole swarm is there.
    pub hold_s: f64,
    /// Per group, in mission order.
    pub targets: Vec<Targets>,
    /// Whether the leg may pass through the pad layer (`z = -1`): takeoff and
    /// landing always; formations and stages when `world.formations_use_pad_layer`.
    pub pad_layer_open: bool,
}

impl Mission {
    /// The flight's legs in order: takeoff, the first formation (when any group has
    /// starts; otherwise takeoff flies to it directly), one per stage, landing.
    pub fn legs(&self) -> Vec<Leg> {
        let any_starts = self.groups.iter().any(|g| g.has_starts());
        let mut legs = Vec::with_capacity(self.stages.len() + 3);
        legs.push(Leg {
            name: "takeoff".into(),
            kind: LegKind::Takeoff,
            hold_s: 0.0,
            pad_layer_open: true,
            targets: self
                .groups
                .iter()
                .map(|g| {
                    let starts: Option<Vec<Voxel>> = g.drones.iter().map(|d| d.start).collect();
                    Targets::Any(starts.unwrap_or_else(|| g.formation_targets(&g.goals)))
                })
                .collect(),
        });
        if any_starts {
            legs.push(Leg {
                name: "formation".into(),
                kind: LegKind::Formation,
                hold_s: 0.0,
                pad_layer_open: self.formations_use_pad_layer,
                targets: self
                    .groups
                    .iter()
                    .map(|g| {
                        if g.has_starts() {
                            Targets::Any(g.formation_targets(&g.goals))
                        } else {
                            Targets::Stay
                        }
                    })
                    .collect(),
            });
        }
        for stage in &self.stages {
            legs.push(Leg {
                name: stage.name.clone(),
                kind: LegKind::Stage,
                hold_s: stage.hold_s,
                pad_layer_open: self.formations_use_pad_layer,
                targets: stage
                    .goals
                    .iter()
                    .zip(&self.groups)
                    .map(|(goals, g)| {
                        goals.as_deref().map_or(Targets::Stay, |goals| {
                            Targets::Any(g.formation_targets(goals))
                        })
                    })
                    .collect(),
            });
        }
        legs.push(Leg {
            name: "landing".into(),
            kind: LegKind::Landing,
            hold_s: 0.0,
            pad_layer_open: true,
            targets: self
                .groups
                .iter()
                .map(|g| match self.landing {
                    Landing::GroupPads => Targets::Any(
                        g.drones
                            .iter()
                            .map(|d| d.pad_voxel())
                            .chain(g.free_pads.iter().copied())
                            .collect(),
                    ),
                    Landing::OwnPad => {
                        Targets::Own(g.drones.iter().map(|d| d.pad_voxel()).collect())
                    }
                    Landing::BelowGoal => Targets::BelowCurrent,
                })
                .collect(),
        });
        legs
    }

    /// The goals of the last formation each group flies (its last stage naming it,
    /// else its own goals): where `below_goal` landing descends from.
    pub fn final_goals(&self) -> Vec<&[Voxel]> {
        last_formations(&self.groups, &self.stages)
    }
}

/// Per group, the goals of the last formation it flies (see [`Mission::final_goals`]).
pub(crate) fn last_formations<'a>(groups: &'a [Group], stages: &'a [Stage]) -> Vec<&'a [Voxel]> {
    groups
        .iter()
        .enumerate()
        .map(|(gi, g)| {
            stages
                .iter()
                .rev()
                .find_map(|s| s.goals.get(gi).and_then(|x| x.as_deref()))
                .unwrap_or(&g.goals)
        })
        .collect()
}
