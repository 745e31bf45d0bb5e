//! The voxel world the swarm flies in.

mod grid;
mod separation;
mod voxel;

pub use grid::{Cell, UNREACHABLE, VoxelGrid};
pub use separation::{Separation, VerticalReach};
pub use voxel::Voxel;
