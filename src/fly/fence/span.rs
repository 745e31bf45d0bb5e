//! The fences of a whole swarm in one line: each vehicle's fence is measured from
//! its own pad, so their circles and ceilings differ by where the pads stand, and
//! an operator reads them as one range each.

use super::VehicleFence;
use crate::mission::FenceAction;

/// The range of the swarm's fence circles and ceilings, and the breach action.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FenceSpan {
    /// How many vehicles' fences it spans.
    pub vehicles: usize,
    /// Smallest and largest circle radius around a pad, metres.
    pub radius_m: (f64, f64),
    /// Smallest and largest ceiling above a pad, metres.
    pub max_altitude_m: (f64, f64),
    /// What the autopilots do on a breach (the mission's, the same on every one).
    pub action: FenceAction,
}

impl FenceSpan {
    /// The span of `fences`; `None` when there are none.
    pub fn of<'a>(fences: impl IntoIterator<Item = &'a VehicleFence>) -> Option<FenceSpan> {
        let widen = |(lo, hi): (f64, f64), v: f64| (lo.min(v), hi.max(v));
        let mut fences = fences.into_iter();
        let first = fences.next()?;
        let mut span = FenceSpan {
            vehicles: 1,
            radius_m: (first.radius_m, first.radius_m),
            max_altitude_m: (first.max_altitude_m, first.max_altitude_m),
            action: first.action,
        };
        for f in fences {
            span.vehicles += 1;
            span.radius_m = widen(span.radius_m, f.radius_m);
            span.max_altitude_m = widen(span.max_altitude_m, f.max_altitude_m);
        }
        Some(span)
    }
}

/// One range at a decimetre: a single figure when its ends print the same.
fn range((lo, hi): (f64, f64)) -> String {
    let (lo, hi) = (format!("{lo:.1}"), format!("{hi:.1}"));
    if lo == hi { lo } else { format!("{lo}–{hi}") }
}

/// `10.3–10.7 m around each pad, 6.0 m above it`.
impl std::fmt::Display for FenceSpan {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} m around each pad, {} m above it",
            range(self.radius_m),
            range(self.max_altitude_m)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fence(radius_m: f64, max_altitude_m: f64) -> VehicleFence {
        VehicleFence {
            radius_m,
            max_altitude_m,
            margin_m: 2.0,
            action: FenceAction::Land,
        }
    }

    #[test]
    fn ranges_collapse_where_their_ends_print_alike() {
        let span = FenceSpan::of(&[fence(10.31, 6.0), fence(10.66, 6.01), fence(10.5, 6.0)])
            .expect("three fences");
        assert_eq!(span.vehicles, 3);
        assert_eq!(span.radius_m, (10.31, 10.66));
        assert_eq!(
            span.to_string(),
            "10.3–10.7 m around each pad, 6.0 m above it"
        );
    }

    #[test]
    fn no_fences_have_no_span() {
        assert_eq!(FenceSpan::of(&[]), None);
    }
}
