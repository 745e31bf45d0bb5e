//! Free-text fields with a grammar of their own: drone ids and MAVLink endpoints.

/// Ids appear in command-line flags (`--fault slow=ID:0.5`) and log paths, so they
/// keep to characters that need no quoting there.
pub(super) fn check_drone_id(id: &str) -> Result<(), String> {
    if id.is_empty() {
        return Err("must not be empty".into());
    }
    if id.len() > 64 {
        return Err(format!("{id:?} is longer than 64 characters"));
    }
    if let Some(c) = id
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.')))
    {
        return Err(format!(
            "{id:?} contains {c:?}; use letters, digits, '-', '_' or '.'"
        ));
    }
    Ok(())
}

/// Accepts the connection strings rust-mavlink understands.
pub(super) fn check_endpoint(endpoint: &str) -> Result<(), String> {
    const NETWORK: [&str; 5] = ["udpin", "udpout", "udpcast", "tcpin", "tcpout"];
    let Some((scheme, rest)) = endpoint.split_once(':') else {
        return Err(format!(
            "{endpoint:?} lacks a scheme; write e.g. \"udpout:127.0.0.1:14541\""
        ));
    };
    if scheme == "serial" {
        return match rest.rsplit_once(':') {
            Some((port, baud)) if !port.is_empty() && baud.parse::<u32>().is_ok() => Ok(()),
            _ => Err(format!(
                "{endpoint:?}: write serial endpoints as \"serial:/dev/ttyUSB0:57600\""
            )),
        };
    }
    if !NETWORK.contains(&scheme) {
        return Err(format!(
            "unknown scheme {scheme:?} in {endpoint:?}; use one of {}, serial",
            NETWORK.join(", ")
        ));
    }
    match rest.rsplit_once(':') {
        Some((host, port)) if !host.is_empty() && port.parse::<u16>().is_ok_and(|p| p > 0) => {
            Ok(())
        }
        _ => Err(format!(
            "{endpoint:?}: expected {scheme}:HOST:PORT with a port from 1 to 65535"
        )),
    }
}
