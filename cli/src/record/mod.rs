//! Rerun recordings of missions, plans and flights.
//!
//! The one place that turns swarmctl's types into `swarmctl-viz`'s plain input
//! types (`viz` must not depend on this crate: the binary depends on it). One file
//! per source type; the CLI calls [`record_plan`], [`LiveFlight`] (a flight as it
//! happens) and [`record_flight`] (a flight log, afterwards).

mod args;
mod flight;
mod live;
mod mission;
mod plan;

pub use args::ViewerArgs;
pub use flight::{flight_plan_offset_s, lateness_series, record_flight, scaled_summary_event};
pub use live::LiveFlight;
pub use mission::mission_scene;
pub use plan::{plan_scene, record_plan};
pub use swarmctl_viz::{RecorderOptions, RecorderStats, Sink, VizError};

/// Why a recording could not be made.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// The recorder could not open its sink or log to it.
    #[error(transparent)]
    Viz(#[from] VizError),
    /// The directory a file sink goes into could not be created.
    #[error("cannot create {dir}: {source}")]
    CreateDir {
        /// The directory.
        dir: std::path::PathBuf,
        /// What the file system said.
        #[source]
        source: std::io::Error,
    },
}

/// Creates the parent directory of a file sink, so `--rrd out/x.rrd` just works.
fn prepare(sink: &Sink) -> Result<(), RecordError> {
    if let Sink::File(path) = sink
        && let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
    {
        std::fs::create_dir_all(dir).map_err(|source| RecordError::CreateDir {
            dir: dir.to_path_buf(),
            source,
        })?;
    }
    Ok(())
}
