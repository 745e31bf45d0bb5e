//! The list of fault cases: each scenario's faults, autopilot and replan options,
//! and the behaviour swarmctl promises under them.

use std::time::Duration;
use swarmctl::fly::ReplanOptions;
use swarmctl_sitl::Flavour;

/// What a scenario must do.
#[derive(Debug, Clone, PartialEq)]
pub enum Expect {
    /// Every drone reaches its goal and lands.
    Completes,
    /// The flight is refused before anybody leaves the ground.
    AbortsOnGround,
    /// `drone` is reported lost; everybody else lands or is handed over.
    Lost {
        /// Id of the drone whose link is lost.
        drone: &'static str,
    },
    /// `drone` is reported lost, the survivors are replanned without it, reach the
    /// goals left to them and land (`completed`).
    Replanned {
        /// Id of the drone whose link is lost.
        drone: &'static str,
    },
    /// `drone` is reported lost and the replan falls back (says why): its
    /// dependants hold, the rest finish and land.
    FallsBack {
        /// Id of the drone whose link is lost.
        drone: &'static str,
    },
    /// `drone` leaves the plan early and lands; everybody else finishes and lands.
    Retires {
        /// Id of the drone that retires.
        drone: &'static str,
    },
}

impl Expect {
    /// The promise in words, for the report's "Expected" column.
    pub(super) fn describe(&self) -> String {
        match self {
            Expect::Completes => "all at goals, landed".into(),
            Expect::AbortsOnGround => "refused before takeoff, nobody airborne".into(),
            Expect::Lost { drone } => {
                format!("{drone} reported lost, dependents hold, the rest finish")
            }
            Expect::Replanned { drone } => {
                format!("{drone} reported lost, the rest replanned without it, completed")
            }
            Expect::FallsBack { drone } => {
                format!(
                    "{drone} reported lost, replan falls back: dependents hold, the rest finish"
                )
            }
            Expect::Retires { drone } => {
                format!("{drone} leaves the plan and lands, the rest replanned and finish")
            }
        }
    }
}

/// One row of the matrix.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// What the row is called in the table (and how `--only` finds it).
    pub name: &'static str,
    /// The faults as `swarmctl fly --fault` flags, e.g. `loss=10%`.
    pub faults: Vec<&'static str>,
    /// Which autopilot the SITL vehicles imitate.
    pub flavour: Flavour,
    /// The behaviour swarmctl promises under these faults.
    pub expect: Expect,
    /// How the flight replans when drones leave it (`fly --replan-deadline`).
    pub replan: ReplanOptions,
}

impl Scenario {
    fn new(name: &'static str, faults: &[&'static str], expect: Expect) -> Self {
        Self {
            name,
            faults: faults.to_vec(),
            flavour: Flavour::Px4,
            expect,
            replan: ReplanOptions::default(),
        }
    }
}

/// The scenarios, for `missions/formation-change.yaml` (drone ids b1–b4, r1–r4).
/// `reduced` keeps the ones no other end-to-end test covers, for CI.
pub fn scenarios(reduced: bool) -> Vec<Scenario> {
    let mut all = vec![
        Scenario::new("no faults", &[], Expect::Completes),
        Scenario::new("loss 10%", &["loss=10%"], Expect::Completes),
        Scenario::new("loss 30%", &["loss=30%"], Expect::Completes),
        Scenario::new(
            "latency 200 ms each way",
            &["latency=200ms"],
            Expect::Completes,
        ),
        Scenario::new(
            "duplicated 20% + reordered 20%",
            &["dup=20%", "reorder=20%"],
            Expect::Completes,
        ),
        Scenario::new(
            "b1 link cut 5 s in flight",
            &["drop=b1@5s+5s"],
            Expect::Completes,
        ),
        Scenario::new(
            "b1 lost for good",
            &["lose=b1@5s"],
            Expect::Replanned { drone: "b1" },
        ),
        Scenario::new(
            "b1 crashes (falls, silent)",
            &["crash=b1@5s"],
            Expect::Replanned { drone: "b1" },
        ),
        Scenario {
            replan: ReplanOptions {
                deadline: Duration::ZERO,
                ..ReplanOptions::default()
            },
            ..Scenario::new(
                "b1 lost, no time to replan (`--replan-deadline 0`)",
                &["lose=b1@5s"],
                Expect::FallsBack { drone: "b1" },
            )
        },
        Scenario::new(
            "r2 refuses to arm",
            &["refuse-arm=r2"],
            Expect::AbortsOnGround,
        ),
        Scenario::new("b1 at half speed", &["slow=b1:0.5"], Expect::Completes),
        Scenario::new(
            "r1 low battery",
            &["low-battery=r1@12s"],
            Expect::Retires { drone: "r1" },
        ),
        Scenario::new(
            "r1 critical battery (autopilot lands it)",
            &["critical-battery=r1@12s"],
            Expect::Retires { drone: "r1" },
        ),
        Scenario {
            flavour: Flavour::ArduPilot,
            ..Scenario::new("ArduPilot, loss 20%", &["loss=20%"], Expect::Completes)
        },
    ];
    if reduced {
        let ci = [
            "loss 30%",
            "latency 200 ms each way",
            "duplicated 20% + reordered 20%",
            "b1 lost for good",
            "b1 crashes (falls, silent)",
            "b1 lost, no time to replan (`--replan-deadline 0`)",
            "r1 low battery",
            "r1 critical battery (autopilot lands it)",
        ];
        all.retain(|s| ci.contains(&s.name));
    }
    all
}
