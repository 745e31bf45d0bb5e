//! The largest world a mission may ask for.

/// Largest accepted edge of the world, in voxels.
pub const MAX_DIMENSION: i64 = 4096;
/// Largest accepted world, in voxels (the planner's time-expanded networks grow with it).
pub const MAX_VOXELS: i64 = 1 << 24;
