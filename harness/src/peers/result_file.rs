//! The `key=value` result files LaCAM3 and tswap both write (one setting per
//! line; a value may itself hold `key:value` pairs, as tswap's
//! `internal_info`).

/// The value of `key` in a `key=value` result file (`None` if absent).
pub fn value<'a>(text: &'a str, key: &str) -> Option<&'a str> {
    text.lines().find_map(|line| {
        let (k, v) = line.split_once('=')?;
        (k.trim() == key).then(|| v.trim())
    })
}

/// The number after `key:` on its own line (tswap's `internal_info` block).
pub fn inner_number(text: &str, key: &str) -> Option<u64> {
    text.lines().find_map(|line| {
        let (k, v) = line.split_once(':')?;
        (k.trim() == key).then(|| v.trim().parse().ok()).flatten()
    })
}

/// `key` as a whole number.
pub fn number(text: &str, key: &str) -> Option<u64> {
    value(text, key)?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_settings_and_inner_numbers() {
        let text = "solver=TSWAP\nsolved=1\nmakespan=30\ncomp_time=91\ninternal_info=\nelapsed_assignment:82\nestimated_makespan:29\nstarts=(1,2),\n";
        assert_eq!(value(text, "solver"), Some("TSWAP"));
        assert_eq!(number(text, "makespan"), Some(30));
        assert_eq!(number(text, "comp_time"), Some(91));
        assert_eq!(inner_number(text, "estimated_makespan"), Some(29));
        assert_eq!(number(text, "soc"), None);
        assert_eq!(number(text, "starts"), None, "not a number");
    }
}
