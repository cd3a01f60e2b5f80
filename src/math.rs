//! Scalar and vector aliases used everywhere (SI units, z up).

/// The floating-point type of every physical quantity.
pub type Real = f64;
/// A 3D vector (world space): positions in m, velocities in m/s, forces in N.
pub type Vec3 = nalgebra::Vector3<Real>;
/// A 2D vector (rest space, the flat cloth pattern), in m.
pub type Vec2 = nalgebra::Vector2<Real>;
/// A 3x3 matrix.
pub type Mat3 = nalgebra::Matrix3<Real>;

/// The largest absolute value of `values` (0 for none): the size of a coordinate list.
pub fn largest_abs(values: &[Real]) -> Real {
    values.iter().fold(0.0, |m: Real, x| m.max(x.abs()))
}

/// Largest coordinate (m) accepted for what input places: the cloth's centre and OBJ vertices,
/// obstacles' centres, translations and mesh vertices. A scene a million metres across is no
/// cloth scene; at 1e300 m the first step overflows and the run ended as diverged.
pub const MAX_COORDINATE: Real = 1e6;

/// Signed area of the 2D triangle `(a, b, c)`: positive when counter-clockwise (m²).
pub fn signed_area(a: Vec2, b: Vec2, c: Vec2) -> Real {
    0.5 * ((b - a).perp(&(c - a)))
}
