//! The fault flags of `swarmctl sitl`: `--fault KIND=VALUE`, the grammar every
//! command shares (see [`crate::faults`]), with a vehicle's system id as the
//! drone it names; and the older one-kind flags (`--loss 3:25`, `--drop
//! 4@5s+3s`, …), kept as other spellings of the same faults: each is rewritten
//! to its `KIND=VALUE` form and read by the one parser.

use crate::config::Faults;
use crate::faults::{FaultSpec, faults_for, parse_fault};
use anyhow::bail;

/// Which faults the vehicles run with.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct FaultFlags {
    /// Fault, repeatable, as `swarmctl fly --fault` writes it with the vehicle's
    /// system id as its drone: loss=10% (or loss=2:10% for vehicle 2 only),
    /// latency=50ms, dup=5%, reorder=10%, slow=2:0.5, drop=2@5s+3s (or +inf),
    /// lose=2@5s, crash=2@5s, refuse-arm=2, low-battery=2@10s (critical 45 s
    /// later; +inf: a warning only), critical-battery=2@10s.
    #[arg(long = "fault", value_name = "KIND=VALUE")]
    pub fault: Vec<String>,
    /// Packet loss in percent: `10` for all vehicles or `SYSID:10` for one (repeatable).
    #[arg(long = "loss", value_name = "[SYSID:]PERCENT")]
    pub loss: Vec<String>,
    /// Duplicated datagrams in percent, each direction: `5` for all or `SYSID:5` for one (repeatable).
    #[arg(long = "duplicate", value_name = "[SYSID:]PERCENT")]
    pub duplicate: Vec<String>,
    /// Reordered datagrams in percent, each direction (held back 10–60 ms so
    /// later ones overtake them): `5` for all or `SYSID:5` for one (repeatable).
    #[arg(long = "reorder", value_name = "[SYSID:]PERCENT")]
    pub reorder: Vec<String>,
    /// Added one-way latency in ms: `50` for all or `SYSID:50` for one (repeatable).
    #[arg(long = "latency-ms", value_name = "[SYSID:]MS")]
    pub latency_ms: Vec<String>,
    /// Slow drone: `SYSID:0.5` flies at half speed (repeatable).
    #[arg(long = "slow", value_name = "SYSID:FACTOR")]
    pub slow: Vec<String>,
    /// Link drop: `SYSID@5s+3s` cuts the link 5 s after takeoff for 3 s;
    /// `SYSID@5s+inf` cuts it for good (repeatable).
    #[arg(long = "drop", value_name = "SYSID@AFTERs+FORs")]
    pub drop: Vec<String>,
    /// Refuse arming for this system id (repeatable).
    #[arg(long = "refuse-arm", value_name = "SYSID")]
    pub refuse_arm: Vec<u8>,
    /// Low-battery warning: `SYSID@60s` turns the battery LOW (warning
    /// only, ≤ 25 %) after 60 s armed (repeatable).
    #[arg(long = "low-battery", value_name = "SYSID@SECONDSs")]
    pub low_battery: Vec<String>,
    /// Critical-battery failsafe: `SYSID@90s` turns the battery CRITICAL
    /// after 90 s armed: PX4 lands, ArduPilot returns and lands (repeatable).
    #[arg(long = "critical-battery", value_name = "SYSID@SECONDSs")]
    pub critical_battery: Vec<String>,
    /// Crash: `SYSID@20s` stops the motors 20 s after takeoff; the vehicle falls
    /// to the ground below it and its link goes silent for good (repeatable).
    #[arg(long = "crash", value_name = "SYSID@SECONDSs")]
    pub crash: Vec<String>,
}

/// How a one-kind flag's value is written as the value of its `KIND=VALUE` form.
type Respell = fn(&str) -> String;

/// One flag as given (for errors) and in the shared grammar (for the parser).
struct Flag {
    given: String,
    fault: String,
}

impl FaultFlags {
    /// The faults of each vehicle of `system_ids`, in that order; an error names
    /// the flag as given and what is wrong with it, or the vehicle it names that
    /// does not exist.
    pub fn per_vehicle(&self, system_ids: &[u8]) -> anyhow::Result<Vec<Faults>> {
        let names: Vec<String> = system_ids.iter().map(u8::to_string).collect();
        let mut specs: Vec<FaultSpec> = Vec::new();
        for flag in self.flags() {
            let spec = match parse_fault(&flag.fault) {
                Ok(spec) => spec,
                Err(e) => bail!("{}: {}", flag.given, e.reason),
            };
            if let Some(drone) = spec.drone()
                && !names.iter().any(|n| n == drone)
            {
                bail!(
                    "{}: no vehicle with system id {drone} (the vehicles are {})",
                    flag.given,
                    names.join(", ")
                );
            }
            specs.push(spec);
        }
        Ok(names.iter().map(|n| faults_for(n, &specs)).collect())
    }

    /// Every flag in the shared grammar: the one-kind flags kind by kind, as
    /// they were always applied, then `--fault` in the order given (where two
    /// set the same thing, the later wins).
    fn flags(&self) -> Vec<Flag> {
        // The one-kind flags leave out the unit their name implies.
        let percent: Respell = |v| format!("{}%", v.strip_suffix('%').unwrap_or(v));
        let as_is: Respell = str::to_string;
        let legacy: [(&str, &[String], &str, Respell); 9] = [
            ("--loss", &self.loss, "loss", percent),
            ("--duplicate", &self.duplicate, "dup", percent),
            ("--reorder", &self.reorder, "reorder", percent),
            ("--latency-ms", &self.latency_ms, "latency", |v| {
                format!("{v}ms")
            }),
            ("--slow", &self.slow, "slow", as_is),
            ("--drop", &self.drop, "drop", as_is),
            // This flag has always been a warning only.
            ("--low-battery", &self.low_battery, "low-battery", |v| {
                format!("{v}+inf")
            }),
            (
                "--critical-battery",
                &self.critical_battery,
                "critical-battery",
                as_is,
            ),
            ("--crash", &self.crash, "crash", as_is),
        ];
        let mut flags = Vec::new();
        for (name, values, kind, value) in legacy {
            flags.extend(values.iter().map(|v| Flag {
                given: format!("{name} {v}"),
                fault: format!("{kind}={}", value(v)),
            }));
        }
        flags.extend(self.refuse_arm.iter().map(|id| Flag {
            given: format!("--refuse-arm {id}"),
            fault: format!("refuse-arm={id}"),
        }));
        flags.extend(self.fault.iter().map(|f| Flag {
            given: format!("--fault {f}"),
            fault: f.clone(),
        }));
        flags
    }
}
