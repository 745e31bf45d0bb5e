//! The one parser of fault flags: `KIND=VALUE`, as `--fault` takes them. Every
//! command that starts simulated vehicles reads its faults here, so a fault is
//! written the same way wherever it is given.

use super::{CRITICAL_AFTER_LOW, FaultSpec};
use std::time::Duration;

/// A fault flag that does not parse; names the flag and what is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("--fault {flag}: {reason}")]
pub struct FaultError {
    /// The flag's value as given.
    pub flag: String,
    /// What is wrong with it, with an example of the right form.
    pub reason: String,
}

/// Every kind with its form, for the error that meets an unknown or shapeless flag.
const KINDS: &str = "loss=10%, latency=50ms, dup=5%, reorder=10%, slow=ID:0.5, drop=ID@5s+3s, lose=ID@5s, crash=ID@5s, rogue=ID@5s, refuse-arm=ID, low-battery=ID@10s, critical-battery=ID@10s";

/// Parses one fault flag, `KIND=VALUE`. The link-wide kinds (`loss`, `latency`,
/// `dup`, `reorder`) apply to every vehicle, or to one when written
/// `KIND=DRONE:VALUE`; a link cut may last for good (`drop=ID@5s+inf`); a low
/// battery turns critical 45 s later unless told when (`low-battery=ID@10s+30s`,
/// or `+inf`: a warning only).
pub fn parse_fault(flag: &str) -> Result<FaultSpec, FaultError> {
    let bad = |reason: &str| FaultError {
        flag: flag.to_string(),
        reason: reason.to_string(),
    };
    let (kind, value) = flag
        .split_once('=')
        .ok_or_else(|| bad(&format!("expected KIND=VALUE ({KINDS})")))?;
    Value { kind, value }.spec().map_err(|reason| bad(&reason))
}

/// A flag split at its `=`, with the readers of its value's parts. Errors are
/// the reason alone; [`parse_fault`] adds the flag.
struct Value<'a> {
    kind: &'a str,
    value: &'a str,
}

impl Value<'_> {
    /// The fault this flag names.
    fn spec(&self) -> Result<FaultSpec, String> {
        match self.kind {
            "loss" => {
                let (drone, percent) = self.link_wide(|v| self.percent(v))?;
                Ok(FaultSpec::Loss { drone, percent })
            }
            "dup" => {
                let (drone, percent) = self.link_wide(|v| self.percent(v))?;
                Ok(FaultSpec::Duplicate { drone, percent })
            }
            "reorder" => {
                let (drone, percent) = self.link_wide(|v| self.percent(v))?;
                Ok(FaultSpec::Reorder { drone, percent })
            }
            "latency" => {
                let (drone, latency) = self.link_wide(|v| {
                    parse_duration(v)
                        .ok_or_else(|| String::from("latency needs a duration like 50ms or 0.2s"))
                })?;
                Ok(FaultSpec::Latency { drone, latency })
            }
            "lose" => {
                let (drone, after) = self.drone_at("lose=b1@5s")?;
                Ok(FaultSpec::Lose { drone, after })
            }
            "crash" => {
                let (drone, after) = self.drone_at("crash=b1@5s")?;
                Ok(FaultSpec::Crash { drone, after })
            }
            "rogue" => {
                let (drone, after) = self.drone_at("rogue=b1@5s")?;
                Ok(FaultSpec::Rogue { drone, after })
            }
            "low-battery" => self.low_battery(),
            "critical-battery" => {
                let (drone, after) = self.drone_at("critical-battery=b1@10s")?;
                Ok(FaultSpec::CriticalBattery { drone, after })
            }
            "slow" => self.slow(),
            "drop" => self.link_drop(),
            "refuse-arm" => Ok(FaultSpec::RefuseArm {
                drone: non_empty(self.value)
                    .ok_or_else(|| String::from("missing drone id"))?
                    .to_string(),
            }),
            _ => Err(String::from(
                "unknown fault kind (loss, latency, dup, reorder, slow, drop, lose, crash, rogue, refuse-arm, low-battery, critical-battery)",
            )),
        }
    }

    /// `[DRONE:]VALUE`: every vehicle, or the one named.
    fn link_wide<T>(
        &self,
        read: impl Fn(&str) -> Result<T, String>,
    ) -> Result<(Option<String>, T), String> {
        match self.value.rsplit_once(':') {
            Some((drone, value)) => {
                non_empty(drone).ok_or_else(|| String::from("missing drone id"))?;
                Ok((Some(drone.to_string()), read(value)?))
            }
            None => Ok((None, read(self.value)?)),
        }
    }

    /// `10%`, between 0 and 100.
    fn percent(&self, value: &str) -> Result<f64, String> {
        let name = self.kind;
        let number = value
            .strip_suffix('%')
            .ok_or_else(|| format!("{name} needs a percentage, like {name}=10%"))?;
        let percent: f64 = number
            .parse()
            .map_err(|_| format!("{name} is not a number"))?;
        if !(0.0..=100.0).contains(&percent) {
            return Err(format!("{name} must be between 0% and 100%"));
        }
        Ok(percent)
    }

    /// `DRONE_ID@AFTER`.
    fn drone_at(&self, example: &str) -> Result<(String, Duration), String> {
        let (drone, after) = self
            .value
            .split_once('@')
            .ok_or_else(|| format!("expected {}=DRONE_ID@AFTER, like {example}", self.kind))?;
        non_empty(drone).ok_or_else(|| String::from("missing drone id"))?;
        let after =
            parse_duration(after).ok_or_else(|| String::from("AFTER is not a duration like 5s"))?;
        Ok((drone.to_string(), after))
    }

    /// `DRONE_ID@AFTER[+FOR]`: low after AFTER, critical FOR later.
    fn low_battery(&self) -> Result<FaultSpec, String> {
        let (at, critical_after) = match self.value.split_once('+') {
            Some((at, critical)) => (
                at,
                parse_span(critical).ok_or_else(|| {
                    String::from("FOR (low, then critical) is not a duration like 30s, or inf")
                })?,
            ),
            None => (self.value, CRITICAL_AFTER_LOW),
        };
        let (drone, after) = Value {
            kind: self.kind,
            value: at,
        }
        .drone_at("low-battery=b1@10s")?;
        Ok(FaultSpec::LowBattery {
            drone,
            after,
            critical_after,
        })
    }

    /// `DRONE_ID:FACTOR`, the factor in (0, 1].
    fn slow(&self) -> Result<FaultSpec, String> {
        let (drone, factor) = self
            .value
            .rsplit_once(':')
            .ok_or_else(|| String::from("expected slow=DRONE_ID:FACTOR, like slow=b1:0.5"))?;
        let factor: f64 = factor
            .parse()
            .map_err(|_| String::from("speed factor is not a number"))?;
        // A slow drone lags its plan; one faster than commanded would
        // overshoot every setpoint, which is not what the name promises.
        if !(factor > 0.0 && factor <= 1.0) {
            return Err(String::from(
                "speed factor must be in (0, 1]: the drone flies at most this share of the commanded speed",
            ));
        }
        non_empty(drone).ok_or_else(|| String::from("missing drone id"))?;
        Ok(FaultSpec::Slow {
            drone: drone.to_string(),
            factor,
        })
    }

    /// `DRONE_ID@AFTER+FOR`, FOR possibly `inf`.
    fn link_drop(&self) -> Result<FaultSpec, String> {
        let expected = "expected drop=DRONE_ID@AFTER+FOR, like drop=b1@5s+3s (or +inf: for good)";
        let (drone, times) = self
            .value
            .split_once('@')
            .ok_or_else(|| String::from(expected))?;
        let (after, duration) = times
            .split_once('+')
            .ok_or_else(|| String::from(expected))?;
        non_empty(drone).ok_or_else(|| String::from("missing drone id"))?;
        Ok(FaultSpec::Drop {
            drone: drone.to_string(),
            after: parse_duration(after)
                .ok_or_else(|| String::from("AFTER is not a duration like 5s"))?,
            duration: parse_span(duration)
                .ok_or_else(|| String::from("FOR is not a duration like 3s, or inf"))?,
        })
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

/// How long a state lasts: a duration, or `inf` (`never`, `forever`): for good,
/// [`Duration::MAX`].
fn parse_span(text: &str) -> Option<Duration> {
    match text {
        "inf" | "never" | "forever" => Some(Duration::MAX),
        _ => parse_duration(text),
    }
}

#[cfg(test)]
#[path = "parse_tests.rs"]
mod tests;
