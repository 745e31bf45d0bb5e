//! Branching on a conflict: the constraints that split a conflict-tree node into
//! children, at least one of which keeps every valid plan.

use crate::plan::conflict::Conflict;

/// One constraint a branch adds to one group: a cell at a step, or a move
/// (from, to) at a step.
pub(super) enum Branch {
    Vertex(u32, u32),
    Edge(u32, u32, u32),
}

/// The ways out of a conflict. A vertex or edge conflict is forbidden to one group
/// or the other. A rotation gets one branch per move: any valid plan leaves at least
/// one move of the cycle unmade (else it holds that very rotation), so forbidding
/// each move in turn to its group loses no solution.
pub(super) fn branches(conflict: Conflict) -> Vec<(usize, Branch)> {
    match conflict {
        Conflict::Vertex {
            groups: [a, b],
            cell,
            step,
        } => {
            vec![
                (a, Branch::Vertex(cell, step)),
                (b, Branch::Vertex(cell, step)),
            ]
        }
        Conflict::Edge {
            groups: [a, b],
            from,
            to,
            step,
        } => {
            vec![
                (a, Branch::Edge(from, to, step)),
                (b, Branch::Edge(to, from, step)),
            ]
        }
        Conflict::Stacked {
            groups: [a, b],
            cells: [x, y],
            step,
        } => {
            vec![(a, Branch::Vertex(x, step)), (b, Branch::Vertex(y, step))]
        }
        Conflict::Rotation { moves, step } => moves
            .into_iter()
            .map(|(group, from, to)| (group, Branch::Edge(from, to, step)))
            .collect(),
    }
}
