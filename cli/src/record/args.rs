//! The recording flags shared by `plan`, `fly` and `replay`.

use super::Sink;
use std::path::{Path, PathBuf};

/// Where to send a Rerun recording; at most one of the three.
#[derive(Debug, Clone, Default, clap::Args)]
#[group(multiple = false)]
pub struct ViewerArgs {
    /// Write a Rerun recording to this file (open it with `rerun FILE.rrd`).
    #[arg(long, value_name = "FILE.rrd")]
    pub rrd: Option<PathBuf>,
    /// Start a Rerun viewer (`rerun` on PATH) and stream the recording to it.
    #[arg(long)]
    pub spawn: bool,
    /// Stream the recording to a running Rerun viewer, e.g. 127.0.0.1:9876.
    #[arg(long, value_name = "ADDR")]
    pub connect: Option<String>,
}

impl ViewerArgs {
    /// The sink the flags ask for, if any.
    pub fn sink(&self) -> Option<Sink> {
        if self.spawn {
            Some(Sink::Spawn)
        } else if let Some(addr) = &self.connect {
            Some(Sink::Connect(addr.clone()))
        } else {
            self.rrd.clone().map(Sink::File)
        }
    }

    /// The sink the flags ask for, or a file next to `default_beside` (same name, `.rrd`).
    pub fn sink_or_beside(&self, default_beside: &Path) -> Sink {
        self.sink()
            .unwrap_or_else(|| Sink::File(default_beside.with_extension("rrd")))
    }
}
