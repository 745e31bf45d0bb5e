//! Mock autopilots for swarmctl (in progress).
