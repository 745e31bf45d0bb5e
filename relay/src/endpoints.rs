//! Where a controller or relay listens and what it connects to, as a Zenoh
//! configuration: TCP only, no multicast scouting (a swarm's network is named,
//! not discovered: nothing answers on an interface it was not told of).
//!
//! The controller runs as a Zenoh *router*; relays and monitors (a test
//! watching the simulator's truth) are Zenoh *clients*, whose traffic the
//! router they connect to carries: a star around the controller on one site,
//! or around `zenohd` routers between sites, the controller one more router of
//! that mesh. A client keeps retrying its routers in the background, so relays
//! may start before the controller or outlive a restart of it.

use crate::error::RelayError;

/// The controller listens here unless told otherwise, and relays connect here:
/// one machine works with no flags at all, on loopback.
pub const DEFAULT_CONTROLLER_ENDPOINT: &str = "tcp/127.0.0.1:7447";

/// How a process takes part in the Zenoh network.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// Routes for the clients connected to it (the controller).
    Router,
    /// Reaches everything through the routers it connects to (relays, monitors).
    Client,
}

/// Zenoh locators to listen on and to connect to (`tcp/HOST:PORT`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ZenohEndpoints {
    /// Route for others (the controller) or connect as a client (relays, monitors).
    pub role: Role,
    /// Where this process accepts Zenoh sessions.
    pub listen: Vec<String>,
    /// Peers or routers (`zenohd`) this process connects to, retried in the
    /// background until they answer.
    pub connect: Vec<String>,
}

impl ZenohEndpoints {
    /// The controller's default: listen on [`DEFAULT_CONTROLLER_ENDPOINT`].
    pub fn controller_default() -> Self {
        Self {
            role: Role::Router,
            listen: vec![DEFAULT_CONTROLLER_ENDPOINT.to_string()],
            connect: Vec::new(),
        }
    }

    /// A relay's default: connect to [`DEFAULT_CONTROLLER_ENDPOINT`], listen nowhere.
    pub fn relay_default() -> Self {
        Self {
            role: Role::Client,
            listen: Vec::new(),
            connect: vec![DEFAULT_CONTROLLER_ENDPOINT.to_string()],
        }
    }

    /// The Zenoh configuration: router or client mode, these endpoints, TCP only,
    /// no multicast scouting. Each endpoint is checked here, naming the bad one.
    pub fn config(&self) -> Result<zenoh::Config, RelayError> {
        let mut config = zenoh::Config::default();
        let set = |config: &mut zenoh::Config, key: &str, value: String| {
            config
                .insert_json5(key, &value)
                .map_err(|e| RelayError::Config {
                    key: key.to_string(),
                    reason: e.to_string(),
                })
        };
        match self.role {
            Role::Router => set(&mut config, "mode", "\"router\"".into())?,
            Role::Client => {
                set(&mut config, "mode", "\"client\"".into())?;
                // Keep trying the routers in the background instead of failing
                // at start: the controller may come up after its relays.
                set(&mut config, "connect/timeout_ms", "-1".into())?;
                set(&mut config, "connect/exit_on_failure", "false".into())?;
            }
        }
        set(&mut config, "scouting/multicast/enabled", "false".into())?;
        for (key, endpoints) in [
            ("listen/endpoints", &self.listen),
            ("connect/endpoints", &self.connect),
        ] {
            for e in endpoints {
                e.parse::<zenoh::config::EndPoint>()
                    .map_err(|err| RelayError::Endpoint {
                        endpoint: e.clone(),
                        reason: err.to_string(),
                    })?;
            }
            let list: Vec<String> = endpoints.iter().map(|e| format!("{e:?}")).collect();
            set(&mut config, key, format!("[{}]", list.join(",")))?;
        }
        Ok(config)
    }

    /// Opens a Zenoh session with [`Self::config`].
    pub async fn open(&self) -> Result<zenoh::Session, RelayError> {
        let config = self.config()?;
        zenoh::open(config).await.map_err(|e| RelayError::Open {
            endpoints: self.describe(),
            reason: e.to_string(),
        })
    }

    /// `listen …, connect …` for messages.
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        if !self.listen.is_empty() {
            parts.push(format!("listen {}", self.listen.join(", ")));
        }
        if !self.connect.is_empty() {
            parts.push(format!("connect {}", self.connect.join(", ")));
        }
        if parts.is_empty() {
            "no endpoints".to_string()
        } else {
            parts.join("; ")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bad_endpoint_is_named() {
        let e = ZenohEndpoints {
            role: Role::Client,
            listen: vec!["tcp/127.0.0.1:0".into()],
            connect: vec!["nonsense".into()],
        };
        let err = e.config().unwrap_err().to_string();
        assert!(err.contains("nonsense"), "{err}");
        assert!(ZenohEndpoints::controller_default().config().is_ok());
    }
}
