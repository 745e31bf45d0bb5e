//! A voxel coordinate: integer cell indices along x (east), y (north), z (up).

use serde::{Deserialize, Serialize};
use std::fmt;

/// One cell of the world, written `[x, y, z]` in files.
///
/// Signed: the mission's world spans `0..dimensions`, but the airspace the planner
/// flies in adds the pad layer at `z = -1` and launch areas beside the world, at
/// negative `x`/`y` as well.
///
/// ```
/// use swarmctl::world::Voxel;
/// let v = Voxel::new(1, 2, 3);
/// assert_eq!(v.to_string(), "[1, 2, 3]");
/// assert_eq!(serde_json::to_string(&v).unwrap(), "[1,2,3]");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(from = "[i32; 3]", into = "[i32; 3]")]
pub struct Voxel {
    /// Index along x (east), from the world's west face.
    pub x: i32,
    /// Index along y (north), from the world's south face.
    pub y: i32,
    /// Index along z (up), from the world's floor (`-1` is the pad layer).
    pub z: i32,
}

impl Voxel {
    /// The voxel `[x, y, z]`; usable in constants.
    pub const fn new(x: i32, y: i32, z: i32) -> Self {
        Self { x, y, z }
    }

    /// The cell straight below on the pad layer (`z = -1`): where a drone in this
    /// column hovers before touchdown.
    pub const fn pad_below(self) -> Voxel {
        Voxel::new(self.x, self.y, -1)
    }

    /// Manhattan distance: the number of face moves between two voxels in free space.
    pub fn manhattan(self, other: Voxel) -> u32 {
        self.x.abs_diff(other.x) + self.y.abs_diff(other.y) + self.z.abs_diff(other.z)
    }
}

impl From<[i32; 3]> for Voxel {
    fn from([x, y, z]: [i32; 3]) -> Self {
        Self { x, y, z }
    }
}

impl From<Voxel> for [i32; 3] {
    fn from(v: Voxel) -> Self {
        [v.x, v.y, v.z]
    }
}

impl fmt::Display for Voxel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{}, {}, {}]", self.x, self.y, self.z)
    }
}
