//! Plain input types: what a plan recording shows, independent of swarmctl's types.

/// Everything a plan recording shows. Positions are ENU metres, times seconds.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    /// Recording name shown in the viewer (the mission name).
    pub name: String,
    /// The world's box, drawn as a wireframe.
    pub bounds: Bounds,
    /// Edge length of one voxel, metres.
    pub voxel_size_m: f64,
    /// Blocked space, drawn solid.
    pub obstacles: Vec<ObstacleBox>,
    /// The mission's groups; [`Drone::group`] indexes this.
    pub groups: Vec<Group>,
    /// Every drone, planned or not; flight samples name drones by their index here.
    pub drones: Vec<Drone>,
    /// Minimum distance two drones must keep, metres: a sphere's radius, or the
    /// horizontal radius of the ellipsoid when [`Scene::vertical_separation_m`] is set.
    pub safety_distance_m: f64,
    /// The separation ellipsoid's vertical radius, metres, when drones keep an
    /// axis-aligned ellipsoid apart (downwash reaches further below a drone than
    /// beside it); `None` for a sphere of [`Scene::safety_distance_m`].
    pub vertical_separation_m: Option<f64>,
    /// Scheduled events worth reading as text (TPG waits), in plan time.
    pub events: Vec<PlanEvent>,
}

/// The world's extent: an axis-aligned box, ENU metres.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Bounds {
    /// The corner with the smallest coordinates, ENU metres.
    pub min_m: [f64; 3],
    /// The corner with the largest coordinates, ENU metres.
    pub max_m: [f64; 3],
}

/// One blocked voxel (or a merged run of them) as an axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObstacleBox {
    /// Centre of the box, ENU metres.
    pub center_m: [f64; 3],
    /// Edge lengths along x, y and z, metres.
    pub size_m: [f64; 3],
}

/// A group of interchangeable drones, drawn in one colour.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// Group name; its start and goal markers are logged under it.
    pub name: String,
    /// sRGB colour; [`Group::palette`] picks distinct ones by index.
    pub color_rgb: [u8; 3],
}

/// One drone's plan: where it starts, where it goes and how it gets there.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Drone {
    /// The drone's id: its label in the 3D view and its series name.
    pub id: String,
    /// Index into [`Scene::groups`].
    pub group: usize,
    /// Start position, ENU metres; where the drone is shown until it reports.
    pub start_m: [f64; 3],
    /// Goal position, ENU metres.
    pub goal_m: [f64; 3],
    /// The planned voxel path as a polyline of voxel centres (repeats removed).
    pub path_m: Vec<[f64; 3]>,
    /// Sampled trajectory `[t_s, x_m, y_m, z_m]`, increasing in time.
    pub trajectory: Vec<[f64; 4]>,
}

/// A text event in plan time, e.g. "b2 waits 0.8 s at [3, 4, 1] for r1".
#[derive(Debug, Clone, PartialEq)]
pub struct PlanEvent {
    /// Plan time of the event, seconds.
    pub t_s: f64,
    /// Id of the drone it concerns, if any (shown before the text).
    pub drone: Option<String>,
    /// What happens.
    pub text: String,
}

/// A timeline plus an offset: where plan time 0 falls on it.
///
/// A plan is logged on `plan_time` with offset 0; in a flight recording it is
/// logged again on `flight_time`, shifted to when plan execution began, so the
/// planned and the flown drones move together on one timeline.
#[derive(Debug, Clone, PartialEq)]
pub struct TimeAxis {
    /// One of [`crate::PLAN_TIMELINE`], [`crate::FLIGHT_TIMELINE`].
    pub timeline: &'static str,
    /// Where plan time 0 falls on `timeline`, seconds.
    pub offset_s: f64,
}

impl Group {
    /// A distinct colour for the `index`-th group (cycles after eight).
    pub fn palette(index: usize) -> [u8; 3] {
        const COLORS: [[u8; 3]; 8] = [
            [31, 119, 180],
            [255, 127, 14],
            [44, 160, 44],
            [214, 39, 40],
            [148, 103, 189],
            [140, 86, 75],
            [227, 119, 194],
            [23, 190, 207],
        ];
        COLORS[index % COLORS.len()]
    }
}

impl Scene {
    /// The separation's radii along x, y and z, metres: `[H, H, V]` for an
    /// ellipsoid, the safety distance three times for a sphere.
    pub fn separation_radii_m(&self) -> [f64; 3] {
        let h = self.safety_distance_m;
        [h, h, self.vertical_separation_m.unwrap_or(h)]
    }

    /// The radii the scaled separation divides by, for an ellipsoid only: for a
    /// sphere it is the distance over the safety distance, which the plot in
    /// metres already shows against the safety distance.
    pub fn scaled_radii_m(&self) -> Option<[f64; 3]> {
        self.vertical_separation_m
            .map(|_| self.separation_radii_m())
    }

    /// The colour of a drone's group (grey if the index is out of range).
    pub fn drone_color(&self, drone: &Drone) -> [u8; 3] {
        self.groups
            .get(drone.group)
            .map_or([128, 128, 128], |g| g.color_rgb)
    }
}
