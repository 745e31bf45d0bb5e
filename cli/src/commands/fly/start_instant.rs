//! `fly --start-at TIME`: when plan time 0 falls, as the operator writes it.

use std::time::{Duration, SystemTime};

/// Seconds in a day (UTC days have no leap seconds in Unix time).
const DAY_S: u64 = 86_400;

/// Reads `--start-at` at `now`: `+SECONDS` from now, an RFC 3339 UTC instant
/// (`2026-12-05T20:30:00Z`, fractions allowed), or a UTC time of day today
/// (`20:30`, `20:30:15.5`). An instant already past is refused.
pub(super) fn parse(text: &str, now: SystemTime) -> Result<SystemTime, String> {
    let text = text.trim();
    let at = if let Some(seconds) = text.strip_prefix('+') {
        let s: f64 = seconds
            .parse()
            .map_err(|_| format!("`{text}`: expected +SECONDS, e.g. +90"))?;
        let ahead = Duration::try_from_secs_f64(s)
            .map_err(|_| format!("`{text}`: seconds must be a non-negative number"))?;
        now + ahead
    } else if text.contains('-') {
        humantime::parse_rfc3339_weak(text).map_err(|e| {
            format!("`{text}`: {e} (expected an RFC 3339 UTC instant such as 2026-12-05T20:30:00Z)")
        })?
    } else {
        time_of_day_today(text, now)?
    };
    if at < now {
        let past_s = now.duration_since(at).unwrap_or_default().as_secs_f64();
        return Err(format!("`{text}` was {past_s:.1} s ago"));
    }
    Ok(at)
}

/// `HH:MM` or `HH:MM:SS[.fff]`, UTC, today.
fn time_of_day_today(text: &str, now: SystemTime) -> Result<SystemTime, String> {
    let bad = || {
        format!(
            "`{text}`: expected +SECONDS, an RFC 3339 UTC instant (2026-12-05T20:30:00Z) or a UTC time of day (20:30:00)"
        )
    };
    let parts: Vec<&str> = text.split(':').collect();
    if !(2..=3).contains(&parts.len()) {
        return Err(bad());
    }
    let hours: u64 = parts[0].parse().map_err(|_| bad())?;
    let minutes: u64 = parts[1].parse().map_err(|_| bad())?;
    let seconds: f64 = match parts.get(2) {
        Some(s) => s.parse().map_err(|_| bad())?,
        None => 0.0,
    };
    if hours > 23 || minutes > 59 || !(0.0..60.0).contains(&seconds) {
        return Err(bad());
    }
    let since_epoch = now
        .duration_since(SystemTime::UNIX_EPOCH)
        .map_err(|_| "the system clock is before 1970".to_string())?;
    let midnight =
        SystemTime::UNIX_EPOCH + Duration::from_secs(since_epoch.as_secs() / DAY_S * DAY_S);
    Ok(midnight
        + Duration::from_secs(hours * 3600 + minutes * 60)
        + Duration::from_secs_f64(seconds))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2026-12-05T13:07:51Z.
    fn now() -> SystemTime {
        SystemTime::UNIX_EPOCH + Duration::from_secs(1_796_476_071)
    }

    fn unix_s(t: SystemTime) -> f64 {
        t.duration_since(SystemTime::UNIX_EPOCH)
            .expect("after 1970")
            .as_secs_f64()
    }

    #[test]
    fn the_three_spellings_of_a_start_instant() {
        let base = unix_s(now());
        assert_eq!(unix_s(parse("+90", now()).expect("relative")), base + 90.0);
        assert_eq!(
            unix_s(parse("2026-12-05T13:30:00Z", now()).expect("rfc 3339")),
            1_796_477_400.0
        );
        assert_eq!(
            unix_s(parse("13:30", now()).expect("time of day")),
            1_796_477_400.0
        );
        assert_eq!(
            unix_s(parse("13:30:00.5", now()).expect("fractional")),
            1_796_477_400.5
        );
    }

    #[test]
    fn past_and_malformed_instants_are_refused_with_the_text() {
        for (text, says) in [
            ("13:00", "ago"),
            ("2026-12-05T13:00:00Z", "ago"),
            ("+-5", "non-negative"),
            ("+soon", "+SECONDS"),
            ("25:00", "UTC time of day"),
            ("noon", "UTC time of day"),
            ("2026-13-05T13:00:00Z", "RFC 3339"),
        ] {
            let e = parse(text, now()).expect_err(text);
            assert!(e.contains(text) && e.contains(says), "{text}: {e}");
        }
    }
}
