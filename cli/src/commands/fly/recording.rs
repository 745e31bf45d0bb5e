//! The flight's live Rerun recording: opened before the flight, discarded if
//! the flight never flew, finished and reported after it.

use super::Args;
use std::path::Path;
use swarmctl::compiled::CompiledPlan;
use swarmctl::fly;
use swarmctl::mission::Mission;
use swarmctl_cli::record::{LiveFlight, RecorderOptions, Sink};

/// Opens the flight's Rerun recording (beside the log unless --rrd, --spawn or
/// --connect say otherwise); `None`, with a warning, if it cannot be opened.
pub(super) fn start_recording(
    args: &Args,
    mission: &Mission,
    plan: &CompiledPlan,
    log_path: &Path,
) -> Option<(LiveFlight, Sink)> {
    let sink = args.viewer.sink_or_beside(log_path);
    match LiveFlight::start(mission, plan, &sink, RecorderOptions::for_sink(&sink)) {
        Ok(recording) => Some((recording, sink)),
        Err(e) => {
            eprintln!("warning: flying without a Rerun recording: {e:#}");
            None
        }
    }
}

/// Removes the recording of a flight that never flew (refused before arming, or
/// failed): a recording with no flight log beside it only misleads. A viewer
/// the recording streamed to keeps what it was sent.
pub(super) fn discard_recording((recording, sink): (LiveFlight, Sink)) {
    drop(recording);
    if let Sink::File(path) = sink
        && let Err(e) = std::fs::remove_file(&path)
        && e.kind() != std::io::ErrorKind::NotFound
    {
        eprintln!(
            "warning: cannot remove the recording of the refused flight, {}: {e}",
            path.display()
        );
    }
}

/// Finishes the live recording and reports it, with samples dropped to keep the
/// setpoint streams on time.
pub(super) fn finish_recording((recording, sink): (LiveFlight, Sink), log: &fly::FlightLog) {
    match recording.finish(log) {
        Ok(stats) => println!(
            "  recording            {} ({} samples live, {} dropped)",
            crate::commands::replay::describe(&sink),
            stats.samples_logged,
            stats.samples_dropped
        ),
        Err(e) => eprintln!("warning: the Rerun recording is incomplete: {e:#}"),
    }
}
