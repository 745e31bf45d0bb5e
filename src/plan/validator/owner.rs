//! What the mission says about one drone of a plan: its group, where its path must
//! begin, and where it sits in the mission.

use crate::world::Voxel;

/// Where a drone's path must begin.
#[derive(Clone, Copy)]
pub(super) enum Start {
    /// The pad-layer cell above its pad.
    Pad(Voxel),
    /// Where a replan found it.
    Live(Voxel),
}

/// What the mission says about one drone.
pub(super) struct Owner<'m> {
    /// Its group's name.
    pub(super) group: &'m str,
    /// Where its path must begin (`None`: nowhere given).
    pub(super) start: Option<Start>,
    /// Its group's and its own index in the mission.
    pub(super) at: (usize, usize),
}
