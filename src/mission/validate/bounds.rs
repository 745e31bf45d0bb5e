//! The largest world a mission may ask for, and how far beside it pads may lie.

/// Largest accepted edge of the world, in voxels.
pub const MAX_DIMENSION: i64 = 4096;
/// Largest accepted world, in voxels (the planner's time-expanded networks grow with it).
pub const MAX_VOXELS: i64 = 1 << 24;

/// Pads (and obstacles in the pad layer) lie at most this many cells beside the
/// world's footprint: the launch area.
pub(super) const PAD_REACH: u32 = 64;
