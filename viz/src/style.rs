//! Sizes and colours shared by plan and flight logging, in one place.

/// Colour of obstacle voxels.
pub const OBSTACLE_RGB: [u8; 3] = [110, 110, 120];
/// Colour of the world's bounding box.
pub const BOUNDS_RGB: [u8; 3] = [200, 200, 200];
/// Flown positions are drawn lighter than planned ones so both read side by side.
pub fn flown(rgb: [u8; 3]) -> [u8; 3] {
    rgb.map(|c| c / 2 + 128)
}
/// Colour of the safety-distance line on the separation plot.
pub const SAFETY_RGB: [u8; 3] = [220, 40, 40];

/// Drone marker radius relative to the voxel size.
pub fn drone_radius_m(voxel_size_m: f64) -> f32 {
    (0.12 * voxel_size_m) as f32
}
/// Line radius for paths relative to the voxel size.
pub fn line_radius_m(voxel_size_m: f64) -> f32 {
    (0.02 * voxel_size_m) as f32
}

pub fn color(rgb: [u8; 3]) -> rerun::Color {
    rerun::Color::from_rgb(rgb[0], rgb[1], rgb[2])
}

pub fn f32x3(p: [f64; 3]) -> [f32; 3] {
    p.map(|v| v as f32)
}
