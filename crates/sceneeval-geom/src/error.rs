use thiserror::Error;

/// What was wrong with geometry handed to a constructor in this crate.
///
/// Every variant names the offending element (vertex, triangle, polygon point) so the caller
/// can add its own context (file, JSON pointer, asset id) on top.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum GeomError {
    /// A mesh was given no triangles (or no vertices).
    #[error("mesh has no triangles")]
    EmptyMesh,
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {index} is not finite: {value:?}")]
    NonFiniteVertex {
        /// Index of the vertex.
        index: usize,
        /// Its coordinates.
        value: [f64; 3],
    },
    /// A triangle refers to a vertex that does not exist.
    #[error("triangle {triangle} refers to vertex {index}, but the mesh has {vertex_count} vertices")]
    IndexOutOfRange {
        /// Index of the triangle.
        triangle: usize,
        /// The bad vertex index.
        index: u32,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// Every triangle of a mesh has zero area.
    #[error("mesh has {triangles} triangles, all of zero area")]
    DegenerateMesh {
        /// Number of triangles given.
        triangles: usize,
    },
    /// A polygon has fewer than three distinct points.
    #[error("polygon needs at least 3 distinct points, got {count}")]
    TooFewPoints {
        /// Number of distinct points.
        count: usize,
    },
    /// A polygon point is NaN or infinite.
    #[error("polygon point {index} is not finite: {value:?}")]
    NonFinitePoint {
        /// Index of the point.
        index: usize,
        /// Its coordinates.
        value: [f64; 2],
    },
    /// A polygon encloses no area.
    #[error("polygon has zero area")]
    ZeroArea,
    /// Two non-adjacent polygon edges cross.
    #[error("polygon is self-intersecting: edge {first} crosses edge {second}")]
    SelfIntersecting {
        /// Index of the first edge (from point `first` to `first + 1`).
        first: usize,
        /// Index of the second edge.
        second: usize,
    },
    /// An input is too large or too intricate to process within a stated bound on the work.
    #[error("{what} is too complex to check: it needs more than {limit} steps")]
    TooComplex {
        /// What was refused.
        what: &'static str,
        /// The bound on the work.
        limit: usize,
    },
    /// A value that must be finite is not.
    #[error("{what} is not finite")]
    NonFinite {
        /// Which value.
        what: &'static str,
    },
    /// A box has a negative half extent.
    #[error("half extents must be non-negative, got {0:?}")]
    NegativeExtent([f64; 3]),
    /// A direction has zero length.
    #[error("{what} has zero length")]
    ZeroDirection {
        /// Which direction.
        what: &'static str,
    },
    /// A matrix meant to be a rotation is not orthonormal with determinant +1.
    #[error("matrix is not a rotation (orthonormality error {error:.3e}, determinant {det:.6})")]
    NotARotation {
        /// Largest deviation of `R^T R` from the identity.
        error: f64,
        /// Determinant.
        det: f64,
    },
}
