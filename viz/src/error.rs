//! Why a recording could not be made.

/// Errors from opening or writing a recording.
#[derive(Debug, thiserror::Error)]
pub enum VizError {
    #[error("cannot open the Rerun recording ({what}): {source}")]
    Open {
        what: String,
        #[source]
        source: rerun::RecordingStreamError,
    },
    #[error("cannot log {entity} to the recording: {source}")]
    Log {
        entity: String,
        #[source]
        source: rerun::RecordingStreamError,
    },
    #[error("cannot serialise {entity} for the recording: {source}")]
    Serialize {
        entity: String,
        #[source]
        source: rerun::SerializationError,
    },
    #[error("cannot flush the recording: {0}")]
    Flush(String),
    #[error("the recorder thread stopped unexpectedly")]
    RecorderGone,
}
