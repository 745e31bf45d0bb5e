//! Why an instance could not be imported: the one error type every format shares.

use crate::mission::MissionError;
use std::path::{Path, PathBuf};

/// Why an instance file could not be imported.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    /// The instance file (or the map it names) could not be read. The operating
    /// system's reason is the `source`, not part of this message, so a chain
    /// printed whole (`{:#}`) says it once.
    #[error("{}: cannot read{}", file.display(), named_by.as_ref().map(|s| format!(" (the map scenario {} names)", s.display())).unwrap_or_default())]
    Read {
        /// The file as the user (or the scenario) named it.
        file: PathBuf,
        /// The scenario that named this file, when it is a map one names.
        named_by: Option<PathBuf>,
        /// Why the operating system refused.
        #[source]
        source: std::io::Error,
    },
    /// The file is not in the format it claims, or asks for something swarmctl
    /// cannot plan.
    #[error("{}{}: {message}", file.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
    Format {
        /// The file as the user (or the scenario) named it.
        file: PathBuf,
        /// 1-based line of the problem, when it is known.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// The file was read as a mission but the mission is invalid.
    #[error(transparent)]
    Mission(#[from] MissionError),
}

impl ImportError {
    pub(crate) fn format(file: &Path, line: Option<usize>, message: impl Into<String>) -> Self {
        ImportError::Format {
            file: file.to_path_buf(),
            line,
            message: message.into(),
        }
    }
}
