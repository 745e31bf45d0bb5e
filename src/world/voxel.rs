//! A voxel coordinate: integer cell indices along x (east), y (north), z (up).

use serde::{Deserialize, Serialize};
use std::fmt;

/// One cell of the world, written `[x, y, z]` in files.
///
/// ```
/// use swarmctl::world::Voxel;
/// let v = Voxel::new(1, 2, 3);
/// assert_eq!(v.to_string(), "[1, 2, 3]");
/// assert_eq!(serde_json::to_string(&v).unwrap(), "[1,2,3]");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(from = "[u32; 3]", into = "[u32; 3]")]
pub struct Voxel {
    /// Index along x (east), from the world's west face.
    pub x: u32,
    /// Index along y (north), from the world's south face.
    pub y: u32,
    /// Index along z (up), from the world's floor.
    pub z: u32,
}

impl Voxel {
    /// The voxel `[x, y, z]`; usable in constants.
    pub const fn new(x: u32, y: u32, z: u32) -> Self {
        Self { x, y, z }
    }

    /// Manhattan distance: the number of face moves between two voxels in free space.
    pub fn manhattan(self, other: Voxel) -> u32 {
        self.x.abs_diff(other.x) + self.y.abs_diff(other.y) + self.z.abs_diff(other.z)
    }
}

impl From<[u32; 3]> for Voxel {
    fn from([x, y, z]: [u32; 3]) -> Self {
        Self { x, y, z }
    }
}

impl From<Voxel> for [u32; 3] {
    fn from(v: Voxel) -> Self {
        [v.x, v.y, v.z]
    }
}

impl fmt::Display for Voxel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{}, {}, {}]", self.x, self.y, self.z)
    }
}
