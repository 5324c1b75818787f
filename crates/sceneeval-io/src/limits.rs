//! Resource limits for reading scenes and assets: every file size, triangle count and memory
//! estimate is checked against them **before** anything is allocated for it, so a hostile or
//! broken file fails its scene with a clear error instead of exhausting the machine.
//!
//! An [`AssetLibrary`](crate::AssetLibrary) holds one [`Limits`] (set with
//! [`AssetLibrary::with_limits`](crate::AssetLibrary::with_limits)); it applies them to every
//! scene file it reads through [`read_scene_state`](crate::read_scene_state), every asset mesh,
//! every external glTF buffer and every metadata file.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::IoError;

/// Estimated peak memory per triangle of a loaded asset mesh, in bytes: the decoded index
/// triple, the mesh's own copy, the parry BVH, the distance hierarchy and the transient edge
/// map of the winding check. Measured on a 1,002,528-triangle grid mesh (about 420 MB peak
/// resident for the load, vertices included).
pub const ESTIMATED_BYTES_PER_TRIANGLE: u64 = 350;

/// Estimated peak memory per vertex of a loaded asset mesh, in bytes (decoded position, the
/// mesh's copy, parry's copy, the transformed copy of the frame conversion).
pub const ESTIMATED_BYTES_PER_VERTEX: u64 = 100;

/// Limits on what reading one scene or asset may cost.
///
/// Defaults: files up to 1 GiB, assets up to 4,000,000 triangles and an estimated 2 GiB of
/// memory each. A triangle count counts every instance: a mesh placed by 1,000 glTF nodes
/// counts 1,000 times.
///
/// ```
/// use sceneeval_io::Limits;
/// let limits = Limits::default();
/// assert_eq!(limits.max_triangles, 4_000_000);
/// // 1.2 million triangles over 3 vertices: about 420 MB, inside the default budget.
/// assert_eq!(Limits::estimated_mesh_bytes(3, 1_200_000), 420_000_300);
/// assert!(limits.check_mesh(std::path::Path::new("a.glb"), 3, 1_200_000).is_ok());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Limits {
    /// Largest file read (a scene file, a mesh file, an external glTF buffer, a metadata
    /// file), in bytes. Default 1 GiB.
    pub max_file_bytes: u64,
    /// Most triangles in one asset, counting every instance of a mesh. Default 4,000,000.
    pub max_triangles: u64,
    /// Largest estimated memory for one loaded asset, in bytes (see
    /// [`Limits::estimated_mesh_bytes`]). Default 2 GiB.
    pub max_asset_memory_bytes: u64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_file_bytes: 1 << 30,
            max_triangles: 4_000_000,
            max_asset_memory_bytes: 2 << 30,
        }
    }
}

impl Limits {
    /// No limit at all (for trusted input only).
    pub const UNLIMITED: Limits = Limits {
        max_file_bytes: u64::MAX,
        max_triangles: u64::MAX,
        max_asset_memory_bytes: u64::MAX,
    };

    /// The estimated peak memory of loading a mesh of `vertices` vertices and `triangles`
    /// triangles: [`ESTIMATED_BYTES_PER_VERTEX`] and [`ESTIMATED_BYTES_PER_TRIANGLE`] each
    /// (saturating).
    pub fn estimated_mesh_bytes(vertices: u64, triangles: u64) -> u64 {
        vertices
            .saturating_mul(ESTIMATED_BYTES_PER_VERTEX)
            .saturating_add(triangles.saturating_mul(ESTIMATED_BYTES_PER_TRIANGLE))
    }

    /// Checks a mesh of the given declared size against the triangle and memory budgets.
    ///
    /// # Errors
    /// [`IoError::TooManyTriangles`] or [`IoError::OverMemoryBudget`], naming `path`.
    pub fn check_mesh(&self, path: &Path, vertices: u64, triangles: u64) -> Result<(), IoError> {
        if triangles > self.max_triangles {
            return Err(IoError::TooManyTriangles {
                path: path.to_owned(),
                triangles,
                limit: self.max_triangles,
            });
        }
        let estimate = Limits::estimated_mesh_bytes(vertices, triangles);
        if estimate > self.max_asset_memory_bytes {
            return Err(IoError::OverMemoryBudget {
                path: path.to_owned(),
                vertices,
                triangles,
                estimate,
                limit: self.max_asset_memory_bytes,
            });
        }
        Ok(())
    }

    /// Checks that every limit is positive.
    ///
    /// # Errors
    /// A message naming the field that is zero.
    pub fn validate(&self) -> Result<(), String> {
        for (name, v) in [
            ("max_file_bytes", self.max_file_bytes),
            ("max_triangles", self.max_triangles),
            ("max_asset_memory_bytes", self.max_asset_memory_bytes),
        ] {
            if v == 0 {
                return Err(format!("{name} must be at least 1"));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budgets_are_checked_in_order() {
        let limits = Limits {
            max_file_bytes: 10,
            max_triangles: 100,
            max_asset_memory_bytes: 100 * 350 + 10 * 100,
        };
        let p = Path::new("x.glb");
        // 100 triangles over 10 vertices: 35,000 + 1,000 = 36,000 bytes, exactly the budget.
        assert!(limits.check_mesh(p, 10, 100).is_ok());
        assert!(matches!(
            limits.check_mesh(p, 10, 101),
            Err(IoError::TooManyTriangles {
                triangles: 101,
                limit: 100,
                ..
            })
        ));
        let err = limits.check_mesh(p, 11, 100).unwrap_err();
        assert!(matches!(err, IoError::OverMemoryBudget { estimate: 36_100, .. }));
        assert!(err.to_string().contains("x.glb"), "{err}");
        assert_eq!(Limits::estimated_mesh_bytes(u64::MAX, 1), u64::MAX);
        assert!(Limits::default().validate().is_ok());
        assert!(
            Limits {
                max_triangles: 0,
                ..Limits::default()
            }
            .validate()
            .unwrap_err()
            .contains("max_triangles")
        );
    }
}
