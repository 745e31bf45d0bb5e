//! `--autopilot`, as `fly` and `relay` take it: which autopilot the bundled
//! simulator imitates, read by clap straight into the mission's own type, by the
//! names mission files use (so a new autopilot needs nothing here).

use clap::builder::{PossibleValuesParser, TypedValueParser};
use swarmctl::mission::{Autopilot, Mission};

/// Parses `--autopilot`: one of the mission's autopilot names, listed in the help.
pub fn parser() -> impl TypedValueParser<Value = Autopilot> {
    PossibleValuesParser::new(Autopilot::ALL.map(Autopilot::name))
        .try_map(|name| name.parse::<Autopilot>())
}

/// The autopilot to imitate: `--autopilot` when given, else the mission's
/// `link.autopilot`.
pub fn chosen(arg: Option<Autopilot>, mission: &Mission) -> Autopilot {
    arg.unwrap_or(mission.link.autopilot)
}
