//! The collision module's own parameters: the contact response shared by all obstacles and the
//! geometry of each static obstacle. Plain structs with documented defaults (the scene's
//! defaults); the scene converts its `[collision]` and `[[obstacles]]` sections into them, with
//! mesh files already resolved to a path.

use super::ObstacleMotion;
use crate::math::Real;
use std::path::PathBuf;

/// Contact response parameters shared by all obstacles (MODEL.md §5).
#[derive(Clone, Debug, PartialEq)]
pub struct ContactParams {
    /// Collision margin (m): the cloth is kept this far off every obstacle surface. Default 2e-3.
    pub margin: Real,
    /// Restitution `gamma` in (0, 1) (4.16), for obstacles that do not set their own.
    /// Default 0.5.
    pub restitution: Real,
    /// Whether faces collide too ([`crate::collision::Obstacles::respond_faces`]), not only
    /// vertices. Default true.
    pub faces: bool,
}

impl Default for ContactParams {
    fn default() -> Self {
        ContactParams {
            margin: 2e-3,
            restitution: 0.5,
            faces: true,
        }
    }
}

/// The geometry of a static obstacle (world frame, m).
#[derive(Clone, Debug, PartialEq)]
pub enum ObstacleShape {
    /// Ground half-space `z <= height`.
    Ground {
        /// Height of the ground plane (m).
        height: Real,
    },
    /// Sphere.
    Sphere {
        /// Centre (m).
        center: [Real; 3],
        /// Radius (m), positive.
        radius: Real,
    },
    /// Cylinder with a vertical axis.
    Cylinder {
        /// Centre (m): halfway between its bottom and top faces.
        center: [Real; 3],
        /// Radius (m), positive.
        radius: Real,
        /// Height (m), positive.
        height: Real,
    },
    /// Axis-aligned box.
    Box {
        /// Centre (m).
        center: [Real; 3],
        /// Half extents along x, y, z (m), positive.
        half_extents: [Real; 3],
    },
    /// Closed, outward-oriented triangle mesh read from an OBJ file.
    Mesh {
        /// The OBJ file (already resolved: not relative to anything but the working folder).
        file: PathBuf,
        /// Uniform scale applied first (dimensionless), positive.
        scale: Real,
        /// Translation applied after scaling (m).
        translation: [Real; 3],
    },
}

/// One obstacle: its geometry, its contact parameters and how it moves.
#[derive(Clone, Debug, PartialEq)]
pub struct Obstacle {
    /// The geometry.
    pub shape: ObstacleShape,
    /// Friction coefficient of the surface (dimensionless, averaged with the cloth's `mu`).
    /// Default 0.
    pub friction: Real,
    /// Restitution in (0, 1) for this obstacle; 0 (the default) uses
    /// [`ContactParams::restitution`].
    pub restitution: Real,
    /// How it moves (rigidly, from the geometry as built). Default still; the ground cannot
    /// move.
    pub motion: ObstacleMotion,
}

impl Obstacle {
    /// A still obstacle of this shape with the default contact parameters (no friction, the
    /// shared restitution).
    pub fn new(shape: ObstacleShape) -> Self {
        Obstacle {
            shape,
            friction: 0.0,
            restitution: 0.0,
            motion: ObstacleMotion::Still,
        }
    }
}
