//! The voxel world the swarm flies in.

mod grid;
mod voxel;

pub use grid::{Cell, UNREACHABLE, VoxelGrid};
pub use voxel::Voxel;
