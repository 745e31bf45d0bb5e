//! MAVLink 2 message signing: the swarm's secret key, where it comes from, and
//! the rust-mavlink configuration that signs what we send and refuses unsigned
//! or wrongly signed input.
//!
//! The key is a secret: it is read when a flight starts, from a file or an
//! environment variable the mission names, and it never appears in `Debug`
//! output, error messages or logs.

use crate::mission::KeySource;
use mavlink::SigningConfig;
use std::path::PathBuf;

/// Signing link id we use on every connection (one ground station per swarm).
const GCS_LINK_ID: u8 = 1;

/// A 32-byte MAVLink 2 signing key.
///
/// ```
/// use swarmctl::link::SigningKey;
/// let key = SigningKey::from_hex(&"ab".repeat(32)).unwrap();
/// assert_eq!(format!("{key:?}"), "SigningKey(<redacted>)");
/// assert!(SigningKey::from_hex("abc").is_err());
/// ```
#[derive(Clone, PartialEq, Eq)]
pub struct SigningKey([u8; 32]);

impl std::fmt::Debug for SigningKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SigningKey(<redacted>)")
    }
}

/// Why a key could not be read. Messages name the source, never the key text.
#[derive(Debug, thiserror::Error)]
pub enum SigningKeyError {
    /// The key file cannot be read or does not hold a key.
    #[error("signing key file {file}: {problem}")]
    File {
        /// The file named on the command line.
        file: PathBuf,
        /// What is wrong with it (never its contents).
        problem: String,
    },
    /// The environment variable is unset or does not hold a key.
    #[error("signing key environment variable {var}: {problem}")]
    Env {
        /// The variable's name.
        var: String,
        /// What is wrong with it (never its value).
        problem: String,
    },
}

impl SigningKey {
    /// Parses 64 hex digits (surrounding whitespace ignored). The error says what
    /// is wrong without echoing the text, which may be a mistyped secret.
    pub fn from_hex(text: &str) -> Result<Self, String> {
        let text = text.trim();
        if text.len() != 64 {
            return Err(format!(
                "must be 64 hex digits (32 bytes), found {} characters",
                text.chars().count()
            ));
        }
        let mut key = [0u8; 32];
        for (i, byte) in key.iter_mut().enumerate() {
            *byte = text
                .get(2 * i..2 * i + 2)
                .and_then(|pair| u8::from_str_radix(pair, 16).ok())
                .ok_or_else(|| "must be 64 hex digits (0-9, a-f)".to_string())?;
        }
        Ok(Self(key))
    }

    /// Reads the key from where the mission says it is.
    pub fn load(source: &KeySource) -> Result<Self, SigningKeyError> {
        match source {
            KeySource::File(file) => {
                let text = std::fs::read_to_string(file).map_err(|e| SigningKeyError::File {
                    file: file.clone(),
                    problem: e.to_string(),
                })?;
                Self::from_hex(&text).map_err(|problem| SigningKeyError::File {
                    file: file.clone(),
                    problem,
                })
            }
            KeySource::Env(var) => {
                let text = std::env::var(var).map_err(|e| SigningKeyError::Env {
                    var: var.clone(),
                    problem: match e {
                        std::env::VarError::NotPresent => "is not set".to_string(),
                        std::env::VarError::NotUnicode(_) => "is not valid text".to_string(),
                    },
                })?;
                Self::from_hex(&text).map_err(|problem| SigningKeyError::Env {
                    var: var.clone(),
                    problem,
                })
            }
        }
    }

    /// The raw key, for handing to a vehicle (the bundled SITL) that must share it.
    pub fn bytes(&self) -> [u8; 32] {
        self.0
    }

    /// Sign everything we send; accept only correctly signed input.
    pub fn config(&self) -> SigningConfig {
        SigningConfig::new(self.0, GCS_LINK_ID, true, false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_never_echo_the_key() {
        let secret = "zz".repeat(32);
        let e = SigningKey::from_hex(&secret).unwrap_err();
        assert!(!e.contains("zz"), "{e}");
        let file = std::env::temp_dir().join(format!("swarmctl-key-{}", std::process::id()));
        std::fs::write(&file, format!("{secret}\n")).unwrap();
        let e = SigningKey::load(&KeySource::File(file.clone())).unwrap_err();
        std::fs::remove_file(&file).ok();
        assert!(!e.to_string().contains("zz"), "{e}");
        assert!(e.to_string().contains("signing key file"), "{e}");
    }

    #[test]
    fn reads_hex_with_a_trailing_newline() {
        let key = SigningKey::from_hex(&format!("{}\n", "0f".repeat(32))).unwrap();
        assert_eq!(key.bytes(), [0x0f; 32]);
    }

    #[test]
    fn unset_variable_is_named() {
        let e =
            SigningKey::load(&KeySource::Env("SWARMCTL_TEST_UNSET_KEY_VAR".into())).unwrap_err();
        assert_eq!(
            e.to_string(),
            "signing key environment variable SWARMCTL_TEST_UNSET_KEY_VAR: is not set"
        );
    }
}
