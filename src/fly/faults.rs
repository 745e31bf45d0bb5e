//! `--fault` flags for the bundled SITL: `loss=10%`, `latency=50ms`, `dup=5%`,
//! `reorder=10%`, `slow=DRONE_ID:0.5`, `drop=DRONE_ID@5s+3s`, `lose=DRONE_ID@5s`,
//! `refuse-arm=DRONE_ID`, `low-battery=DRONE_ID@10s`, `critical-battery=DRONE_ID@10s`.

use std::time::Duration;

/// One parsed `--fault` flag.
#[derive(Debug, Clone, PartialEq)]
pub enum FaultSpec {
    /// Drop this share of packets (percent) in each direction, every vehicle.
    Loss {
        /// Share of packets dropped, 0–100 %.
        percent: f64,
    },
    /// Add this latency in each direction, every vehicle.
    Latency {
        /// Extra one-way delay.
        latency: Duration,
    },
    /// Deliver this share of packets (percent) twice, each direction, every vehicle.
    Duplicate {
        /// Share of packets sent twice, 0–100 %.
        percent: f64,
    },
    /// Hold back this share of packets (percent) so later ones overtake them.
    Reorder {
        /// Share of packets held back, 0–100 %.
        percent: f64,
    },
    /// Cut this drone's link `after` takeoff, for good.
    Lose {
        /// The drone's mission id.
        drone: String,
        /// Time after takeoff when the link is cut.
        after: Duration,
    },
    /// This drone's battery turns low `after` arming (a warning; it turns critical,
    /// and the autopilot lands it, 45 s later).
    LowBattery {
        /// The drone's mission id.
        drone: String,
        /// Time after arming when the battery turns low.
        after: Duration,
    },
    /// This drone's battery turns critical `after` arming with no warning first:
    /// its autopilot's failsafe lands it (PX4) or returns it (ArduPilot).
    CriticalBattery {
        /// The drone's mission id.
        drone: String,
        /// Time after arming when the battery turns critical.
        after: Duration,
    },
    /// This drone crashes `after` takeoff: its motors stop, it falls to the ground
    /// below it and never speaks again (a lost drone that is not hovering).
    Crash {
        /// The drone's mission id.
        drone: String,
        /// Time after takeoff when it crashes.
        after: Duration,
    },
    /// This drone flies at `factor` times the speed it is commanded.
    Slow {
        /// The drone's mission id.
        drone: String,
        /// Flown speed over commanded speed, in (0, 1].
        factor: f64,
    },
    /// Cut this drone's link `after` takeoff, for `duration`.
    Drop {
        /// The drone's mission id.
        drone: String,
        /// Time after takeoff when the link is cut.
        after: Duration,
        /// How long it stays cut.
        duration: Duration,
    },
    /// This drone refuses to arm (fails its pre-arm checks).
    RefuseArm {
        /// The drone's mission id.
        drone: String,
    },
}

/// A `--fault` value that does not parse; names the flag and what is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("--fault {flag}: {reason}")]
pub struct FaultError {
    /// The flag's value as given.
    pub flag: String,
    /// What is wrong with it, with an example of the right form.
    pub reason: String,
}

impl FaultSpec {
    /// The drone the fault names, if it names one.
    pub fn drone(&self) -> Option<&str> {
        match self {
            FaultSpec::Slow { drone, .. }
            | FaultSpec::Drop { drone, .. }
            | FaultSpec::Lose { drone, .. }
            | FaultSpec::Crash { drone, .. }
            | FaultSpec::LowBattery { drone, .. }
            | FaultSpec::CriticalBattery { drone, .. }
            | FaultSpec::RefuseArm { drone } => Some(drone),
            FaultSpec::Loss { .. }
            | FaultSpec::Latency { .. }
            | FaultSpec::Duplicate { .. }
            | FaultSpec::Reorder { .. } => None,
        }
    }
}

/// Parses one `--fault` value.
pub fn parse_fault(flag: &str) -> Result<FaultSpec, FaultError> {
    let bad = |reason: &str| FaultError {
        flag: flag.to_string(),
        reason: reason.to_string(),
    };
    let (kind, value) = flag
        .split_once('=')
        .ok_or_else(|| bad("expected KIND=VALUE (loss=10%, latency=50ms, dup=5%, reorder=10%, slow=ID:0.5, drop=ID@5s+3s, lose=ID@5s, crash=ID@5s, refuse-arm=ID, low-battery=ID@10s, critical-battery=ID@10s)"))?;
    let percent = |name: &str| -> Result<f64, FaultError> {
        let number = value
            .strip_suffix('%')
            .ok_or_else(|| bad(&format!("{name} needs a percentage, like {name}=10%")))?;
        let percent: f64 = number
            .parse()
            .map_err(|_| bad(&format!("{name} is not a number")))?;
        if !(0.0..=100.0).contains(&percent) {
            return Err(bad(&format!("{name} must be between 0% and 100%")));
        }
        Ok(percent)
    };
    // DRONE_ID@AFTER
    let drone_at = |example: &str| -> Result<(String, Duration), FaultError> {
        let expected = format!("expected {kind}=DRONE_ID@AFTER, like {example}");
        let (drone, after) = value.split_once('@').ok_or_else(|| bad(&expected))?;
        non_empty(drone).ok_or_else(|| bad("missing drone id"))?;
        let after = parse_duration(after).ok_or_else(|| bad("AFTER is not a duration like 5s"))?;
        Ok((drone.to_string(), after))
    };
    match kind {
        "loss" => Ok(FaultSpec::Loss {
            percent: percent("loss")?,
        }),
        "dup" => Ok(FaultSpec::Duplicate {
            percent: percent("dup")?,
        }),
        "reorder" => Ok(FaultSpec::Reorder {
            percent: percent("reorder")?,
        }),
        "lose" => {
            let (drone, after) = drone_at("lose=b1@5s")?;
            Ok(FaultSpec::Lose { drone, after })
        }
        "crash" => {
            let (drone, after) = drone_at("crash=b1@5s")?;
            Ok(FaultSpec::Crash { drone, after })
        }
        "low-battery" => {
            let (drone, after) = drone_at("low-battery=b1@10s")?;
            Ok(FaultSpec::LowBattery { drone, after })
        }
        "critical-battery" => {
            let (drone, after) = drone_at("critical-battery=b1@10s")?;
            Ok(FaultSpec::CriticalBattery { drone, after })
        }
        "latency" => Ok(FaultSpec::Latency {
            latency: parse_duration(value)
                .ok_or_else(|| bad("latency needs a duration like 50ms or 0.2s"))?,
        }),
        "slow" => {
            let (drone, factor) = value
                .rsplit_once(':')
                .ok_or_else(|| bad("expected slow=DRONE_ID:FACTOR, like slow=b1:0.5"))?;
            let factor: f64 = factor
                .parse()
                .map_err(|_| bad("speed factor is not a number"))?;
            // A slow drone lags its plan; one faster than commanded would
            // overshoot every setpoint, which is not what the name promises.
            if !(factor > 0.0 && factor <= 1.0) {
                return Err(bad(
                    "speed factor must be in (0, 1]: the drone flies at most this share of the commanded speed",
                ));
            }
            non_empty(drone).ok_or_else(|| bad("missing drone id"))?;
            Ok(FaultSpec::Slow {
                drone: drone.to_string(),
                factor,
            })
        }
        "drop" => {
            let (drone, times) = value
                .split_once('@')
                .ok_or_else(|| bad("expected drop=DRONE_ID@AFTER+FOR, like drop=b1@5s+3s"))?;
            let (after, duration) = times
                .split_once('+')
                .ok_or_else(|| bad("expected drop=DRONE_ID@AFTER+FOR, like drop=b1@5s+3s"))?;
            non_empty(drone).ok_or_else(|| bad("missing drone id"))?;
            Ok(FaultSpec::Drop {
                drone: drone.to_string(),
                after: parse_duration(after)
                    .ok_or_else(|| bad("AFTER is not a duration like 5s"))?,
                duration: parse_duration(duration)
                    .ok_or_else(|| bad("FOR is not a duration like 3s"))?,
            })
        }
        "refuse-arm" => Ok(FaultSpec::RefuseArm {
            drone: non_empty(value)
                .ok_or_else(|| bad("missing drone id"))?
                .to_string(),
        }),
        _ => Err(bad(
            "unknown fault kind (loss, latency, dup, reorder, slow, drop, lose, crash, refuse-arm, low-battery, critical-battery)",
        )),
    }
}

fn non_empty(s: &str) -> Option<&str> {
    (!s.is_empty()).then_some(s)
}

/// `50ms`, `1.5s`.
fn parse_duration(text: &str) -> Option<Duration> {
    let (number, scale) = if let Some(n) = text.strip_suffix("ms") {
        (n, 1e-3)
    } else if let Some(n) = text.strip_suffix('s') {
        (n, 1.0)
    } else {
        return None;
    };
    let value: f64 = number.parse().ok()?;
    Duration::try_from_secs_f64(value * scale).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_kind() {
        assert_eq!(
            parse_fault("loss=10%"),
            Ok(FaultSpec::Loss { percent: 10.0 })
        );
        assert_eq!(
            parse_fault("latency=50ms"),
            Ok(FaultSpec::Latency {
                latency: Duration::from_millis(50)
            })
        );
        assert_eq!(
            parse_fault("slow=b1:0.5"),
            Ok(FaultSpec::Slow {
                drone: "b1".into(),
                factor: 0.5
            })
        );
        assert_eq!(
            parse_fault("drop=b1@5s+3s"),
            Ok(FaultSpec::Drop {
                drone: "b1".into(),
                after: Duration::from_secs(5),
                duration: Duration::from_secs(3)
            })
        );
    }

    #[test]
    fn parses_the_reliability_faults() {
        assert_eq!(
            parse_fault("dup=5%"),
            Ok(FaultSpec::Duplicate { percent: 5.0 })
        );
        assert_eq!(
            parse_fault("reorder=20%"),
            Ok(FaultSpec::Reorder { percent: 20.0 })
        );
        assert_eq!(
            parse_fault("lose=r2@8s"),
            Ok(FaultSpec::Lose {
                drone: "r2".into(),
                after: Duration::from_secs(8)
            })
        );
        assert_eq!(
            parse_fault("crash=b3@20s"),
            Ok(FaultSpec::Crash {
                drone: "b3".into(),
                after: Duration::from_secs(20)
            })
        );
        assert_eq!(
            parse_fault("low-battery=b1@12.5s"),
            Ok(FaultSpec::LowBattery {
                drone: "b1".into(),
                after: Duration::from_millis(12_500)
            })
        );
        assert_eq!(
            parse_fault("critical-battery=b1@500ms"),
            Ok(FaultSpec::CriticalBattery {
                drone: "b1".into(),
                after: Duration::from_millis(500)
            })
        );
    }

    #[test]
    fn malformed_flags_name_the_flag() {
        for flag in [
            "loss=10",
            "loss=x%",
            "slow=b1",
            "slow=b1:0",
            "slow=b1:2",
            "drop=b1@5s",
            "latency=5",
            "wind=3",
            "dup=5",
            "reorder=101%",
            "lose=b1",
            "low-battery=@5s",
            "critical-battery=b1@soon",
        ] {
            let e = parse_fault(flag).unwrap_err();
            assert!(
                e.to_string().starts_with(&format!("--fault {flag}:")),
                "{e}"
            );
        }
    }
}
