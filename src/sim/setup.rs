//! Building the cloth from the scene's `[cloth]` section: pattern, placement, pinned vertices.

use crate::cloth::Cloth;
use crate::collision::CollisionError;
use crate::io::ObjError;
use crate::math::{Real, Vec2, Vec3};
use crate::mesh::{self, Mesh, VertexId};
use crate::scene::{ClothShape, LoadedScene, ObstacleShape, SceneError};
use nalgebra::{Rotation3, Vector3};

/// Why a scene's cloth could not be built.
#[derive(Debug, thiserror::Error)]
pub enum SetupError {
    /// The OBJ cloth could not be read.
    #[error("cloth mesh: {0}")]
    Obj(#[from] mesh::ObjError),
    /// The obstacles could not be built.
    #[error("obstacles: {0}")]
    Collision(#[from] CollisionError),
    /// A pinned or tracked rest point is not on the pattern.
    #[error("{subject}: expected a rest point on the cloth pattern (m)")]
    OffPattern {
        /// Where the point was given and what it is ([`LoadedScene::subject`]):
        /// `FILE:LINE: cloth.pinned[0] = [u, v]`, or the setting that set it.
        subject: String,
    },
    /// A scene value the built cloth or obstacles contradict (`adaptivity.max_vertices` below an
    /// OBJ cloth's vertex count, an obstacle mesh file that does not read); the message names
    /// where it was given.
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),
    /// The strategy is unknown.
    #[error("{0}")]
    Strategy(#[from] crate::strategies::StrategyError),
    /// The integrator is unknown.
    #[error("{0}")]
    Integrator(#[from] crate::physics::UnknownIntegrator),
    /// The run would take more steps than [`crate::scene::MAX_STEPS`] (the message says how many
    /// and why).
    #[error("{0}")]
    TooManySteps(String),
}

/// Builds the cloth of a scene: the pattern mesh, its world placement (the pattern centre at
/// `center`, rotated by `rotation_deg` about x, y, z), initial velocity and pinned vertices.
pub fn build_cloth(loaded: &LoadedScene) -> Result<Cloth, SetupError> {
    let spec = &loaded.scene.cloth;
    let (mut mesh, positions) = match spec.shape {
        ClothShape::Grid => {
            let ny = if spec.resolution_v == 0 {
                spec.resolution
            } else {
                spec.resolution_v
            };
            let mesh = mesh::union_jack(spec.resolution, ny, spec.size[0], spec.size[1]);
            let positions = place(&mesh, spec.size, spec.center, spec.rotation_deg);
            (mesh, positions)
        }
        ClothShape::Disk => {
            let radius = 0.5 * spec.size[0];
            let mesh = mesh::disk(radius, spec.resolution);
            let positions = place(&mesh, [spec.size[0]; 2], spec.center, spec.rotation_deg);
            (mesh, positions)
        }
        ClothShape::Obj => {
            let obj = mesh::load_obj(&crate::scene::mesh_path(&loaded.base_dir, &spec.mesh))?;
            loaded.check_start_vertices(obj.mesh.vertex_count())?;
            (obj.mesh, obj.positions)
        }
    };
    for (i, p) in spec.pinned.iter().enumerate() {
        let v = nearest_vertex(&mesh, Vec2::new(p[0], p[1]))
            .ok_or_else(|| off_pattern(loaded, &format!("cloth.pinned[{i}]"), *p))?;
        mesh.set_pinned(v, true);
    }
    let s = &loaded.scene;
    Ok(Cloth::new(
        mesh,
        positions,
        Vec3::from(spec.velocity),
        &(&s.material).into(),
        &(&s.forces).into(),
    ))
}

/// The error for the rest point `p` (m) of `key` lying off the pattern, placed at its line.
pub(crate) fn off_pattern(loaded: &LoadedScene, key: &str, p: [Real; 2]) -> SetupError {
    SetupError::OffPattern {
        subject: loaded.subject(key, &format!("[{}, {}]", p[0], p[1])),
    }
}

/// `e`, an obstacle that could not be built; an unreadable mesh file named by its key and line
/// (`FILE:LINE: obstacles.N.file = F: line 3: ...`, or the setting that set it).
pub(crate) fn obstacle_error(loaded: &LoadedScene, e: CollisionError) -> SetupError {
    let CollisionError::MeshFile { index, source } = e else {
        return e.into();
    };
    let file = match &loaded.scene.obstacles.get(index).map(|o| &o.shape) {
        Some(ObstacleShape::Mesh { file, .. }) => file.clone(),
        _ => return CollisionError::MeshFile { index, source }.into(),
    };
    let why = match source {
        ObjError::Io { source, .. } => format!("cannot read the OBJ file: {source}"),
        ObjError::Parse { line, message, .. } => format!("line {line}: {message}"),
    };
    SetupError::Scene(SceneError::Invalid {
        subject: loaded.subject(&format!("obstacles.{index}.file"), &file),
        expected: why,
    })
}

/// World positions of a flat pattern of the given rest size (m) centred at `center` (m).
fn place(mesh: &Mesh, size: [Real; 2], center: [Real; 3], rotation_deg: [Real; 3]) -> Vec<Vec3> {
    let r = rotation_deg.map(Real::to_radians);
    let rotation = Rotation3::from_axis_angle(&Vector3::z_axis(), r[2])
        * Rotation3::from_axis_angle(&Vector3::y_axis(), r[1])
        * Rotation3::from_axis_angle(&Vector3::x_axis(), r[0]);
    let center = Vec3::from(center);
    let mut x = vec![Vec3::zeros(); mesh.vertex_slots()];
    for v in mesh.vertices() {
        let p = mesh.rest(v);
        let local = Vec3::new(p.x - 0.5 * size[0], p.y - 0.5 * size[1], 0.0);
        x[v.0 as usize] = center + rotation * local;
    }
    x
}

/// The vertex nearest to a rest point, if the point is within one longest edge of it.
fn nearest_vertex(mesh: &Mesh, p: Vec2) -> Option<VertexId> {
    let longest = mesh
        .edges()
        .map(|(e, _)| mesh.rest_length(e.0, e.1))
        .fold(0.0, Real::max);
    mesh.vertices()
        .map(|v| (v, (mesh.rest(v) - p).norm()))
        .filter(|&(_, d)| d <= longest)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(v, _)| v)
}

/// The driven pinned vertices of a scene: `(slot, velocity)` for every entry of
/// `cloth.pinned_velocity` that is not zero, paired with `cloth.pinned` in order.
pub(crate) fn drivers(
    loaded: &LoadedScene,
    cloth: &Cloth,
) -> Result<Vec<(usize, Vec3)>, SetupError> {
    let spec = &loaded.scene.cloth;
    // Each pinned vertex's velocity and the first entry that set it.
    let mut by_vertex: std::collections::BTreeMap<usize, (usize, Vec3)> = Default::default();
    for (i, p) in spec.pinned.iter().enumerate() {
        let vel = spec
            .pinned_velocity
            .get(i)
            .map_or(Vec3::zeros(), |v| Vec3::from(*v));
        let Some(v) = nearest_vertex(&cloth.mesh, Vec2::new(p[0], p[1])) else {
            if vel == Vec3::zeros() {
                continue; // a still pin off the pattern is the pinning's to report
            }
            return Err(off_pattern(loaded, &format!("cloth.pinned[{i}]"), *p));
        };
        match by_vertex.get(&(v.0 as usize)) {
            Some(&(j, other)) if other != vel => {
                return Err(SetupError::Scene(SceneError::Invalid {
                    subject: loaded.subject(
                        &format!("cloth.pinned[{i}]"),
                        &format!("[{}, {}]", p[0], p[1]),
                    ),
                    expected: format!(
                        "expected a point of its own: it pins the vertex cloth.pinned[{j}] pins, with \
                         another velocity ({:?} against {:?} m/s)",
                        vel.as_slice(),
                        other.as_slice()
                    ),
                }))
            }
            Some(_) => {}
            None => {
                by_vertex.insert(v.0 as usize, (i, vel));
            }
        }
    }
    Ok(by_vertex
        .into_iter()
        .filter(|(_, (_, vel))| *vel != Vec3::zeros())
        .map(|(slot, (_, vel))| (slot, vel))
        .collect())
}
