//! Why a primitive could not be built.

/// Why a primitive could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GeometryError {
    /// A coordinate or parameter is NaN or infinite.
    NonFinite,
    /// A radius (or half-extent, angle, focal length) is zero or negative.
    NonPositiveRadius,
    /// An axis, normal or direction has zero length (or two points coincide).
    ZeroLengthAxis,
    /// A polygon has fewer than 3 vertices (the count is given).
    TooFewVertices(u32),
    /// A polygon's vertex range lies outside the vertex pool.
    VertexRange,
    /// A quadric whose coefficients A to I are all zero.
    DegenerateQuadric,
}

impl core::fmt::Display for GeometryError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            GeometryError::NonFinite => f.write_str("a number is NaN or infinite"),
            GeometryError::NonPositiveRadius => f.write_str("a radius or size is zero or negative"),
            GeometryError::ZeroLengthAxis => f.write_str("an axis, normal or direction has zero length"),
            GeometryError::TooFewVertices(n) => write!(f, "a polygon needs at least 3 vertices, got {n}"),
            GeometryError::VertexRange => f.write_str("polygon vertices outside the vertex pool"),
            GeometryError::DegenerateQuadric => f.write_str("quadric with all of A..I zero"),
        }
    }
}

impl core::error::Error for GeometryError {}
