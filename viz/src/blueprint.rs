//! The layout a recording opens with: the 3D scene beside speeds, separation and events.

use rerun::blueprint::components::PanelState;
use rerun::blueprint::{
    Blueprint, BlueprintPanel, Horizontal, SelectionPanel, Spatial3DView, TextLogView, TimePanel,
    TimeSeriesView, Vertical,
};

/// 3D view on the left; on the right, minimum separation, per-drone speeds,
/// per-drone lateness against the schedule (flights) and the event log stacked, and with `scaled` (an ellipsoidal separation) the
/// minimum scaled separation under the separation in metres: unitless, so in a
/// plot of its own, and only then, so a sphere's layout has no empty plot.
/// Speeds of 100 drones in one plot are a blur, but the envelope (who exceeds
/// the limit) is what one looks for. The side panels start collapsed so the
/// views get the screen; `timeline` is the one selected at open.
pub fn layout(timeline: &str, scaled: bool) -> Blueprint {
    let mut views = vec![
        TimeSeriesView::new("min separation (m)")
            .with_origin("/metrics")
            .with_contents([
                "/metrics/plan/min_separation_m",
                "/metrics/plan/safety_distance_m",
                "/metrics/flight/min_separation_m",
                "/metrics/flight/safety_distance_m",
            ])
            .into(),
    ];
    if scaled {
        views.push(
            TimeSeriesView::new("min scaled separation (separated at 1 or more)")
                .with_origin("/metrics")
                .with_contents([
                    "/metrics/plan/min_scaled_separation",
                    "/metrics/plan/scaled_limit",
                    "/metrics/flight/min_scaled_separation",
                    "/metrics/flight/scaled_limit",
                ])
                .into(),
        );
    }
    views.push(
        TimeSeriesView::new("speed (m/s)")
            .with_origin("/metrics")
            .with_contents(["/metrics/plan/speed_mps", "/metrics/flight/speed_mps"])
            .into(),
    );
    views.push(
        TimeSeriesView::new("lateness (s)")
            .with_origin("/metrics")
            .with_contents(["/metrics/flight/lateness_s/**"])
            .into(),
    );
    views.push(TextLogView::new("events").with_origin("/events").into());
    let right = Vertical::new(views);
    Blueprint::new(
        Horizontal::new([
            Spatial3DView::new("world").with_origin("/world").into(),
            right.into(),
        ])
        .with_column_shares([0.62, 0.38]),
    )
    .with_auto_layout(false)
    .with_auto_views(false)
    .with_blueprint_panel(BlueprintPanel::from_state(PanelState::Collapsed))
    .with_selection_panel(SelectionPanel::from_state(PanelState::Collapsed))
    .with_time_panel(
        TimePanel::new()
            .with_state(PanelState::Collapsed)
            .with_timeline(timeline),
    )
}
