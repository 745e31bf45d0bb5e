//! How the rest of a run is flown: the scheduler's rest-to-rest S-curve, or a
//! motion picked up mid-brake when the gate it braked for opened.
//!
//! Both are within the speed, acceleration and jerk limits and end at rest at the
//! run's end; the follower treats them alike through this one type.

use crate::profile::{Profile, Resume, State};

/// How the rest of a run is flown: the scheduler's rest-to-rest profile, or a
/// motion picked up mid-brake.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Course {
    /// From rest: the scheduler's own profile.
    Planned(Profile),
    /// From a moving state, after a brake for a gate that opened.
    Resumed(Resume),
}

impl Course {
    pub(super) fn length_m(&self) -> f64 {
        match self {
            Self::Planned(p) => p.length_m,
            Self::Resumed(r) => r.length_m(),
        }
    }

    pub(super) fn duration_s(&self) -> f64 {
        match self {
            Self::Planned(p) => p.duration_s(),
            Self::Resumed(r) => r.duration_s(),
        }
    }

    pub(super) fn state_at(&self, time_s: f64) -> State {
        match self {
            Self::Planned(p) => p.state_at(time_s),
            Self::Resumed(r) => r.state_at(time_s),
        }
    }

    pub(super) fn time_at_distance_s(&self, distance_m: f64) -> f64 {
        match self {
            Self::Planned(p) => p.time_at_distance_s(distance_m),
            Self::Resumed(r) => r.time_at_distance_s(distance_m),
        }
    }
}
