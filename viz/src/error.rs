//! Why a recording could not be made, and the adapters every logging module
//! uses to name the entity that failed.

/// Errors from opening or writing a recording.
#[derive(Debug, thiserror::Error)]
pub enum VizError {
    /// The sink could not be opened: the file not created, the viewer not
    /// spawned or not reachable.
    #[error("cannot open the Rerun recording ({what}): {source}")]
    Open {
        /// The sink, as a person would name it ("file out.rrd", "spawned viewer").
        what: String,
        /// Rerun's reason.
        #[source]
        source: rerun::RecordingStreamError,
    },
    /// Rerun refused to log an entity.
    #[error("cannot log {entity} to the recording: {source}")]
    Log {
        /// Entity path that was being logged.
        entity: String,
        /// Rerun's reason.
        #[source]
        source: rerun::RecordingStreamError,
    },
    /// An entity's components could not be serialised into columns.
    #[error("cannot serialise {entity} for the recording: {source}")]
    Serialize {
        /// Entity path that was being logged.
        entity: String,
        /// Rerun's reason.
        #[source]
        source: rerun::SerializationError,
    },
    /// The stream could not be flushed at the end: the recording may be incomplete.
    #[error("cannot flush the recording: {0}")]
    Flush(String),
    /// The recorder thread ended (on an error of its own, or by panicking)
    /// while it was still being sent to, or could not be started.
    #[error("the recorder thread stopped unexpectedly")]
    RecorderGone,
}

/// `map_err` adapter: a logging failure, naming `entity`.
pub(crate) fn log_err(
    entity: &rerun::EntityPath,
) -> impl FnOnce(rerun::RecordingStreamError) -> VizError + '_ {
    move |source| VizError::Log {
        entity: entity.to_string(),
        source,
    }
}

/// `map_err` adapter: a serialisation failure, naming `entity`.
pub(crate) fn ser_err(
    entity: &rerun::EntityPath,
) -> impl FnOnce(rerun::SerializationError) -> VizError + '_ {
    move |source| VizError::Serialize {
        entity: entity.to_string(),
        source,
    }
}
