//! Hold edges: a stage with a hold keeps every drone in formation until the whole
//! swarm has been there that long (see **Holds** in the module docs of
//! [`schedule`](crate::schedule)).

use super::events::Visit;
use super::{CrossEdge, EventId, TpgDrone};
use crate::plan::DiscretePlan;
use crate::world::Voxel;

/// Hold edges for every leg with a hold: each drone's rest event in the formation
/// (forced to be a rest) waits `hold_s` after every drone's, its own included, so
/// nobody leaves before the whole swarm has held the formation that long.
///
/// A drone whose formation cell is its last (a spare holding above a pad it lands
/// on, a drone that never moves) never leaves it: nothing of it waits, though
/// the others still wait for it to arrive. An edge into its last event would
/// ask its arrival to follow its own arrival by the hold, a cycle.
pub(super) fn hold_edges(
    plan: &DiscretePlan,
    visits: &[Vec<Visit>],
    drones: &mut [TpgDrone],
) -> Vec<CrossEdge> {
    let mut edges = Vec::new();
    for leg in plan.legs.iter().filter(|l| l.hold_s > 0.0) {
        // Per drone: its rest event in the formation, the voxel, and whether it
        // ever leaves that voxel.
        let at: Vec<(u32, Voxel, bool)> = visits
            .iter()
            .map(|dv| {
                let k = dv
                    .iter()
                    .position(|v| v.first_step <= leg.end_step && leg.end_step <= v.last_step)
                    .unwrap_or(dv.len().saturating_sub(1));
                let index = if k == 0 { 0 } else { dv[k].enter + 2 };
                let voxel = dv.get(k).map_or(Voxel::new(0, 0, 0), |v| v.voxel);
                (index, voxel, k + 1 < dv.len())
            })
            .collect();
        for (i, &(index, voxel, leaves)) in at.iter().enumerate() {
            if let Some(e) = drones[i].events.get_mut(index as usize) {
                e.rest = true;
            }
            if !leaves {
                continue;
            }
            for (j, &(from, _, _)) in at.iter().enumerate() {
                edges.push(CrossEdge {
                    from: EventId {
                        drone: j as u32,
                        index: from,
                    },
                    to: EventId {
                        drone: i as u32,
                        index,
                    },
                    voxel,
                    delay_s: leg.hold_s,
                });
            }
        }
    }
    edges
}
