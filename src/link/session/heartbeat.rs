//! Who we are on the link: the ground-station header every message we send
//! carries, and the 1 Hz heartbeat task that announces us to the vehicle.

use crate::link::messages::{GCS_COMPONENT_ID, GCS_SYSTEM_ID, gcs_heartbeat};
use crate::link::transport::Transport;
use mavlink::MavHeader;
use std::sync::Arc;
use std::time::Duration;

/// Our header; the connection fills in the sequence number itself.
pub(super) fn gcs_header() -> MavHeader {
    MavHeader {
        system_id: u32::from(GCS_SYSTEM_ID),
        component_id: GCS_COMPONENT_ID,
        sequence: 0,
    }
}

/// The ground-station heartbeat, once a second for the session's lifetime.
pub(super) async fn heartbeat_loop(transport: Arc<Transport>) {
    let mut tick = tokio::time::interval(Duration::from_secs(1));
    let heartbeat = gcs_heartbeat();
    loop {
        tick.tick().await;
        // A failed send is retried next second; link loss is detected from the
        // vehicle's side (its heartbeats stop), not from ours.
        let _ = transport.send(&gcs_header(), &heartbeat).await;
    }
}
