//! How the command prints an error: its chain of causes, each said once.
//!
//! Many errors both print their cause in their own message (`cannot read
//! plan.json: No such file or directory`) and keep it as their `source()`, so a
//! naive walk of the chain (anyhow's `{:#}`) prints it twice. Rather than make
//! every error type choose one of the two, the chain is joined here, at the one
//! place errors leave the program, skipping a cause that its predecessor already
//! said.

/// The error and its causes joined by `: `, outermost first, each cause once.
///
/// ```
/// use std::io;
/// #[derive(Debug, thiserror::Error)]
/// #[error("cannot read plan.json: {source}")]
/// struct ReadError {
///     #[source]
///     source: io::Error,
/// }
/// let error = anyhow::Error::new(ReadError {
///     source: io::Error::new(io::ErrorKind::NotFound, "no such file"),
/// });
/// assert_eq!(swarmctl_cli::error_text::chain(&error), "cannot read plan.json: no such file");
/// ```
pub fn chain(error: &anyhow::Error) -> String {
    let mut text = String::new();
    let mut said = String::new();
    for cause in error.chain() {
        let message = cause.to_string();
        if message.is_empty() || said.contains(&message) {
            continue;
        }
        if !text.is_empty() {
            text.push_str(": ");
        }
        text.push_str(&message);
        said = message;
    }
    text
}

#[cfg(test)]
mod tests {
    use super::chain;
    use anyhow::Context;

    #[derive(Debug, thiserror::Error)]
    #[error("port 14540 is busy: {source}")]
    struct Busy {
        #[source]
        source: std::io::Error,
    }

    fn busy() -> anyhow::Error {
        anyhow::Error::new(Busy {
            source: std::io::Error::new(std::io::ErrorKind::AddrInUse, "Address in use"),
        })
    }

    #[test]
    fn a_cause_the_message_already_says_is_not_repeated() {
        assert_eq!(chain(&busy()), "port 14540 is busy: Address in use");
    }

    #[test]
    fn context_and_causes_it_does_not_say_are_all_kept() {
        let error = Err::<(), _>(busy())
            .context("cannot start the simulator")
            .unwrap_err();
        assert_eq!(
            chain(&error),
            "cannot start the simulator: port 14540 is busy: Address in use"
        );
        let plain = anyhow::anyhow!("no such file").context("cannot read m.yaml");
        assert_eq!(chain(&plain), "cannot read m.yaml: no such file");
    }
}
