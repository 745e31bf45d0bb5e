//! Where a recording goes: a file, a freshly spawned viewer, or a running one.

use crate::VizError;
use std::path::PathBuf;
use std::time::Duration;

/// The destination of a recording.
#[derive(Debug, Clone, PartialEq)]
pub enum Sink {
    /// An `.rrd` file, opened later with `rerun FILE.rrd`.
    File(PathBuf),
    /// Start a `rerun` viewer from `PATH` (or reuse one on the default port).
    Spawn,
    /// Stream to a running viewer, e.g. `rerun+http://127.0.0.1:9876/proxy`.
    /// A bare `HOST:PORT` is completed to that form.
    Connect(String),
}

impl Sink {
    /// The gRPC URL for [`Sink::Connect`], accepting `HOST:PORT` for convenience.
    fn url(addr: &str) -> String {
        if addr.contains("://") {
            addr.to_string()
        } else {
            format!("rerun+http://{addr}/proxy")
        }
    }
}

/// How often rerun's batcher thread wakes to send logged rows (static styles and
/// events; the bulk goes as ready-made columns, which skip the batcher's wait).
/// Rerun's default for a viewer is 8 ms: 125 wake-ups a second for nothing here,
/// and a wake-up costs tens of microseconds in a virtual machine.
const BATCHER_TICK: Duration = Duration::from_secs(1);

/// Opens a recording of `scene` with the swarmctl blueprint (3D view beside the
/// time series), showing `timeline` first.
pub(crate) fn open(
    scene: &crate::Scene,
    sink: &Sink,
    timeline: &str,
) -> Result<rerun::RecordingStream, VizError> {
    let scaled = scene.scaled_radii_m().is_some();
    let builder = rerun::RecordingStreamBuilder::new("swarmctl")
        .recording_name(&scene.name)
        .batcher_config(rerun::log::ChunkBatcherConfig {
            flush_tick: BATCHER_TICK,
            ..rerun::log::ChunkBatcherConfig::DEFAULT
        })
        .with_blueprint(crate::blueprint::layout(timeline, scaled));
    let (what, result) = match sink {
        Sink::File(path) => (format!("file {}", path.display()), builder.save(path)),
        Sink::Spawn => ("spawned viewer".to_string(), builder.spawn()),
        Sink::Connect(addr) => {
            let url = Sink::url(addr);
            (
                format!("viewer at {url}"),
                builder.connect_grpc_opts(url.clone()),
            )
        }
    };
    result.map_err(|source| VizError::Open { what, source })
}
