//! Drawable triangle meshes of the scene's obstacles: closed meshes with outward
//! (counter-clockwise seen from outside) faces for the solids, an upward-facing square for the
//! ground; moving obstacles are drawn where they stand at a frame's time.

use super::{FrameMesh, RenderError};
use crate::collision::ObstacleMotion;
use crate::scene::{ObstacleShape, ObstacleSpec};
use std::borrow::Cow;
use std::f32::consts::PI;
use std::path::Path;

/// The scene's obstacles for drawing: each one's mesh where the scene places it (what this
/// dereferences to) and its motion (`[obstacles.motion]`), to draw it where it stands at a time.
#[derive(Clone, Debug, Default)]
pub struct ObstacleMeshes {
    meshes: Vec<FrameMesh>,
    /// One per mesh; `Still` for a still obstacle.
    motions: Vec<ObstacleMotion>,
}

impl From<Vec<FrameMesh>> for ObstacleMeshes {
    /// Still obstacles with these meshes.
    fn from(meshes: Vec<FrameMesh>) -> Self {
        let motions = vec![ObstacleMotion::Still; meshes.len()];
        ObstacleMeshes { meshes, motions }
    }
}

impl std::ops::Deref for ObstacleMeshes {
    type Target = [FrameMesh];
    fn deref(&self) -> &[FrameMesh] {
        &self.meshes
    }
}

impl ObstacleMeshes {
    /// Whether any obstacle moves.
    pub fn moves(&self) -> bool {
        !self.motions.iter().all(ObstacleMotion::is_still)
    }

    /// Each obstacle's rigid motion at time `t` (s), as [`ObstacleMotion::matrix`] gives it
    /// (row-major rotation, then translation in m; the identity for a still one); `None` when
    /// no obstacle moves.
    pub fn poses(&self, t: f64) -> Option<Vec<[f64; 12]>> {
        if !self.moves() {
            return None;
        }
        Some(self.motions.iter().map(|m| m.matrix(t)).collect())
    }

    /// The meshes where the obstacles stand at time `t` (s): borrowed when none moves.
    pub fn at(&self, t: f64) -> Cow<'_, [FrameMesh]> {
        let Some(poses) = self.poses(t) else {
            return Cow::Borrowed(&self.meshes);
        };
        let moved = self.meshes.iter().zip(&self.motions).zip(poses);
        Cow::Owned(
            moved
                .map(|((mesh, motion), m)| {
                    let mut mesh = mesh.clone();
                    if !motion.is_still() {
                        for p in &mut mesh.positions {
                            let q = p.map(f64::from);
                            *p = [0, 1, 2].map(|i| {
                                let row = &m[3 * i..3 * i + 3];
                                (row[0] * q[0] + row[1] * q[1] + row[2] * q[2] + m[9 + i]) as f32
                            });
                        }
                    }
                    mesh
                })
                .collect(),
        )
    }
}

/// Segments around a sphere's or cylinder's axis.
const SEGMENTS: usize = 48;
/// Rings from pole to pole of a sphere.
const SPHERE_RINGS: usize = 24;
/// 1-to-4 subdivision passes of the cylinder and the box: their large flat faces are cut into
/// triangles of a size similar to the sphere's, so a painter's-algorithm renderer (the HTML
/// replay) sorts them correctly against the cloth lying on them.
const CYLINDER_SUBDIVISIONS: usize = 2;
const BOX_SUBDIVISIONS: usize = 3;
/// Smallest half side of the ground square (m).
const GROUND_MIN_HALF_SIDE: f32 = 1.5;
/// Ground half side as a multiple of the other obstacles' horizontal reach from the origin.
const GROUND_REACH_FACTOR: f32 = 1.5;

/// Triangle meshes of the scene's obstacles, in the order of `specs`, for drawing, with their
/// motions ([`ObstacleMeshes::at`] moves them to a time).
///
/// - sphere: a UV sphere of 48 segments and 24 rings;
/// - cylinder (vertical axis, `center` halfway up): 48 segments with both caps, each triangle
///   then split 1-to-4 twice;
/// - box: 12 triangles, each split 1-to-4 three times;
/// - ground: a horizontal square at `height`, centred on the origin (where scenes put the cloth),
///   of half side `max(1.5 m, 1.5 x the largest |x| or |y| reached by the other obstacles)`;
/// - mesh: the OBJ file (relative to `base_dir`, the scene file's folder:
///   [`crate::scene::mesh_path`]), scaled then translated.
///
/// Errors: a non-positive or non-finite size or an unusable motion ([`RenderError::Obstacle`]);
/// a mesh file that cannot be read or parsed ([`RenderError::Io`], [`RenderError::Obj`]).
pub fn obstacle_meshes(
    specs: &[ObstacleSpec],
    base_dir: &Path,
) -> Result<ObstacleMeshes, RenderError> {
    let mut motions = Vec::with_capacity(specs.len());
    for (index, spec) in specs.iter().enumerate() {
        let motion = spec
            .motion
            .as_ref()
            .map_or(ObstacleMotion::Still, Into::into);
        if let Some(why) = motion.problem() {
            return Err(RenderError::Obstacle {
                index,
                reason: format!("motion: {why}"),
            });
        }
        motions.push(motion);
    }
    let mut meshes: Vec<Option<FrameMesh>> = Vec::with_capacity(specs.len());
    for (index, spec) in specs.iter().enumerate() {
        let bad = |reason: &str| RenderError::Obstacle {
            index,
            reason: reason.to_string(),
        };
        let mesh = match &spec.shape {
            ObstacleShape::Ground { .. } => None,
            ObstacleShape::Sphere { center, radius } => {
                if !(*radius > 0.0 && radius.is_finite()) {
                    return Err(bad("sphere radius must be positive"));
                }
                Some(sphere(to_f32(center), *radius as f32))
            }
            ObstacleShape::Cylinder {
                center,
                radius,
                height,
            } => {
                if !(*radius > 0.0 && *height > 0.0 && radius.is_finite() && height.is_finite()) {
                    return Err(bad("cylinder radius and height must be positive"));
                }
                Some(subdivide(
                    cylinder(to_f32(center), *radius as f32, *height as f32),
                    CYLINDER_SUBDIVISIONS,
                ))
            }
            ObstacleShape::Box {
                center,
                half_extents,
            } => {
                if !half_extents.iter().all(|h| *h > 0.0 && h.is_finite()) {
                    return Err(bad("box half extents must be positive"));
                }
                Some(subdivide(
                    cuboid(to_f32(center), to_f32(half_extents)),
                    BOX_SUBDIVISIONS,
                ))
            }
            ObstacleShape::Mesh {
                file,
                scale,
                translation,
            } => {
                let mut m = FrameMesh::read(&crate::scene::mesh_path(base_dir, file))?;
                let (s, t) = (*scale as f32, to_f32(translation));
                for p in &mut m.positions {
                    *p = [p[0] * s + t[0], p[1] * s + t[1], p[2] * s + t[2]];
                }
                Some(m)
            }
        };
        meshes.push(mesh);
    }
    // The ground is sized after the other obstacles.
    let reach = meshes
        .iter()
        .flatten()
        .flat_map(|m| m.positions.iter())
        .fold(0f32, |r, p| r.max(p[0].abs()).max(p[1].abs()));
    let half = GROUND_MIN_HALF_SIDE.max(GROUND_REACH_FACTOR * reach);
    let meshes = specs
        .iter()
        .zip(meshes)
        .map(|(spec, mesh)| match (&spec.shape, mesh) {
            (ObstacleShape::Ground { height }, _) => ground(*height as f32, half),
            (_, Some(m)) => m,
            (_, None) => unreachable!("every solid obstacle has a mesh"),
        })
        .collect();
    Ok(ObstacleMeshes { meshes, motions })
}

fn to_f32(a: &[f64; 3]) -> [f32; 3] {
    [a[0] as f32, a[1] as f32, a[2] as f32]
}

/// Horizontal square `|x|, |y| <= half` at height `z`, facing up.
fn ground(z: f32, half: f32) -> FrameMesh {
    FrameMesh {
        positions: vec![
            [-half, -half, z],
            [half, -half, z],
            [half, half, z],
            [-half, half, z],
        ],
        faces: vec![[0, 1, 2], [0, 2, 3]],
    }
}

/// Adds the faces joining an upper ring (`a`, first index) to a lower ring (`b`), both of
/// `SEGMENTS` vertices counter-clockwise seen from above, facing outwards.
fn join_rings(faces: &mut Vec<[u32; 3]>, a: u32, b: u32) {
    let n = SEGMENTS as u32;
    for j in 0..n {
        let k = (j + 1) % n;
        faces.push([a + j, b + j, b + k]);
        faces.push([a + j, b + k, a + k]);
    }
}

/// Adds a fan from `apex` to a ring; `up` says whether the fan faces up (+z) or down.
fn cap(faces: &mut Vec<[u32; 3]>, apex: u32, ring: u32, up: bool) {
    let n = SEGMENTS as u32;
    for j in 0..n {
        let k = (j + 1) % n;
        faces.push(if up {
            [apex, ring + j, ring + k]
        } else {
            [apex, ring + k, ring + j]
        });
    }
}

fn ring(positions: &mut Vec<[f32; 3]>, c: [f32; 3], r: f32, z: f32) -> u32 {
    let first = positions.len() as u32;
    for j in 0..SEGMENTS {
        let phi = 2.0 * PI * j as f32 / SEGMENTS as f32;
        positions.push([c[0] + r * phi.cos(), c[1] + r * phi.sin(), z]);
    }
    first
}

fn sphere(c: [f32; 3], r: f32) -> FrameMesh {
    let mut positions = vec![[c[0], c[1], c[2] + r], [c[0], c[1], c[2] - r]];
    let mut faces = Vec::new();
    let mut previous = None;
    for i in 1..SPHERE_RINGS {
        let theta = PI * i as f32 / SPHERE_RINGS as f32;
        let this = ring(&mut positions, c, r * theta.sin(), c[2] + r * theta.cos());
        match previous {
            None => cap(&mut faces, 0, this, true),
            Some(above) => join_rings(&mut faces, above, this),
        }
        previous = Some(this);
    }
    if let Some(last) = previous {
        cap(&mut faces, 1, last, false);
    }
    FrameMesh { positions, faces }
}

fn cylinder(c: [f32; 3], r: f32, h: f32) -> FrameMesh {
    let (z0, z1) = (c[2] - 0.5 * h, c[2] + 0.5 * h);
    let mut positions = vec![[c[0], c[1], z1], [c[0], c[1], z0]];
    let top = ring(&mut positions, c, r, z1);
    let bottom = ring(&mut positions, c, r, z0);
    let mut faces = Vec::new();
    cap(&mut faces, 0, top, true);
    join_rings(&mut faces, top, bottom);
    cap(&mut faces, 1, bottom, false);
    FrameMesh { positions, faces }
}

fn cuboid(c: [f32; 3], h: [f32; 3]) -> FrameMesh {
    // Corner k has x, y, z at the high side when bit 0, 1, 2 of k is set.
    let positions = (0..8)
        .map(|k| {
            let s = |bit: usize, i: usize| if k >> bit & 1 == 1 { h[i] } else { -h[i] };
            [c[0] + s(0, 0), c[1] + s(1, 1), c[2] + s(2, 2)]
        })
        .collect();
    // Quads counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
    let quads = [
        [0, 4, 6, 2],
        [1, 3, 7, 5],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 2, 3, 1],
        [4, 5, 7, 6],
    ];
    let faces = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    FrameMesh { positions, faces }
}

/// Splits every triangle into four at its edge midpoints, `passes` times; midpoints are shared
/// between neighbours, so a closed mesh stays closed (and its volume unchanged).
fn subdivide(mut mesh: FrameMesh, passes: usize) -> FrameMesh {
    for _ in 0..passes {
        let mut midpoints = std::collections::BTreeMap::new();
        let mut faces = Vec::with_capacity(4 * mesh.faces.len());
        for f in std::mem::take(&mut mesh.faces) {
            let mut mid = |a: u32, b: u32| {
                *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    let (p, q) = (mesh.positions[a as usize], mesh.positions[b as usize]);
                    mesh.positions.push([0, 1, 2].map(|k| 0.5 * (p[k] + q[k])));
                    mesh.positions.len() as u32 - 1
                })
            };
            let [a, b, c] = f;
            let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
            faces.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        mesh.faces = faces;
    }
    mesh
}
