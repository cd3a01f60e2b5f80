//! Helpers shared by the unit tests of the core and the strategies (test builds only).

use crate::cloth::Cloth;
use crate::collision::{ContactParams, Obstacle, Obstacles};
use crate::math::Vec3;
use crate::mesh::{union_jack, Mesh};
use crate::physics::{Forces, Material};

/// A cloth of the default material and forces over `mesh` at world positions `x` (m), at rest.
pub fn cloth(mesh: Mesh, x: Vec<Vec3>) -> Cloth {
    Cloth::new(
        mesh,
        x,
        Vec3::zeros(),
        &Material::default(),
        &Forces::default(),
    )
}

/// The `n` x `n` union-jack grid of 1 m x 1 m lying flat: the vertex at rest point `(u, v)` is at
/// `(u + offset.x, v + offset.y, offset.z)` (m).
pub fn flat_cloth(n: usize, offset: Vec3) -> Cloth {
    let mesh = union_jack(n, n, 1.0, 1.0);
    let x = mesh
        .vertices()
        .map(|v| {
            let p = mesh.rest(v);
            Vec3::new(p.x + offset.x, p.y + offset.y, offset.z)
        })
        .collect();
    cloth(mesh, x)
}

/// The flat `n` x `n` grid of [`flat_cloth`] folded by 90 degrees along `u = 0.5`: the half
/// `u > 0.5` stands up along +z.
pub fn folded_cloth(n: usize) -> Cloth {
    let mut cloth = flat_cloth(n, Vec3::zeros());
    for v in cloth.mesh.vertices().collect::<Vec<_>>() {
        let p = cloth.mesh.rest(v);
        if p.x > 0.5 {
            cloth.x[v.0 as usize] = Vec3::new(0.5, p.y, p.x - 0.5);
        }
    }
    cloth
}

/// These obstacles with the default contact parameters.
pub fn obstacles(list: &[Obstacle]) -> Obstacles {
    Obstacles::build(list, &ContactParams::default()).expect("valid test obstacles")
}
