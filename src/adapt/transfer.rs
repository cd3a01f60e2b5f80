//! The state-transfer service: applies one mesh edit and keeps the physics consistent.

use super::crossing_check::edit_crosses_with;
use super::CrossingGuard;
use crate::cloth::Cloth;
use crate::collision::Obstacles;
use crate::math::{Real, Vec3};
use crate::mesh::{Edit, EditError, EditRecord, Mesh, Origin, VertexId};

/// What [`apply_edit`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct Transfer {
    /// The mesh's record of the edit.
    pub record: EditRecord,
    /// Linear momentum of the touched vertices before minus after, once restored (kg m/s, norm).
    pub momentum_change: Real,
    /// Kinetic energy after minus before (J): the energy lost by averaging velocities.
    pub kinetic_energy_change: Real,
}

/// How [`apply_edit_with`] transfers state.
#[derive(Clone, Copy, Default)]
pub struct TransferOptions<'a> {
    /// Push new vertices out of these obstacles. Default none.
    pub obstacles: Option<&'a Obstacles>,
    /// Restore the touched vertices' linear momentum by a uniform velocity correction. Default
    /// off here; scenes turn it on by default (`adaptivity.restore_momentum`).
    pub restore_momentum: bool,
    /// Restore the touched vertices' kinetic energy by the momentum-neutral correction of
    /// [`restore_kinetic_energy`] (MODEL.md §8.4 rule 6). Default off.
    pub restore_energy: bool,
    /// Refuse the edit ([`EditError::CrossesCloth`], cloth unchanged) when its new faces or edges,
    /// new vertices where they would be put, would cross the cloth ([`super::edit_crosses`]).
    /// Default off.
    pub refuse_crossings: bool,
    /// With `refuse_crossings`, the guard of the adaptation pass under way, which finds the faces
    /// near the edit without a pass over every face ([`CrossingGuard`]; it must follow this
    /// cloth). Default none: every face's box is looked at.
    pub crossing_guard: Option<&'a CrossingGuard>,
}

/// Applies `edit` to the cloth (MODEL.md §6): the mesh edit is checked (the cloth is untouched on
/// error); new vertices take `x`, `v` interpolated from their origin; with `obstacles`, new vertices
/// inside an obstacle are pushed out; masses and drag of every touched vertex are recomputed; with
/// `restore_momentum`, a uniform velocity correction over the touched movable vertices restores
/// their linear momentum. Spring and bending arrays are rebuilt later by [`Cloth::refresh`].
pub fn apply_edit(
    cloth: &mut Cloth,
    edit: &Edit,
    obstacles: Option<&Obstacles>,
    restore_momentum: bool,
) -> Result<Transfer, EditError> {
    apply_edit_with(
        cloth,
        edit,
        &TransferOptions {
            obstacles,
            restore_momentum,
            restore_energy: false,
            refuse_crossings: false,
            crossing_guard: None,
        },
    )
}

/// [`apply_edit`] with every option, including the kinetic-energy restoration: after the momentum
/// correction, [`restore_kinetic_energy`] gives the touched vertices back the kinetic energy they
/// had before the edit without changing their momentum (when their velocities allow it).
pub fn apply_edit_with(
    cloth: &mut Cloth,
    edit: &Edit,
    options: &TransferOptions,
) -> Result<Transfer, EditError> {
    transfer(cloth, edit, options, |mesh, edit| mesh.replace(edit))
}

/// [`apply_edit_with`] for an edit [`crate::mesh::Mesh::check_edit`] accepted on `cloth.mesh` as
/// it is now (or in a patch's local ids): not validated again ([`Mesh::replace_checked`]).
pub(crate) fn apply_checked_edit_with(
    cloth: &mut Cloth,
    edit: &Edit,
    options: &TransferOptions,
) -> Transfer {
    let done = transfer(cloth, edit, options, |mesh, edit| {
        Ok(mesh.replace_checked(edit))
    });
    done.unwrap_or_else(|_: EditError| unreachable!("a checked edit is not refused"))
}

/// The transfer of [`apply_edit_with`], the mesh edited by `replace`.
fn transfer(
    cloth: &mut Cloth,
    edit: &Edit,
    options: &TransferOptions,
    replace: impl FnOnce(&mut Mesh, &Edit) -> Result<EditRecord, EditError>,
) -> Result<Transfer, EditError> {
    let TransferOptions {
        obstacles,
        restore_momentum,
        restore_energy,
        refuse_crossings,
        crossing_guard,
    } = *options;
    // Old vertices whose mass changes: every vertex of a removed face.
    let mut touched: Vec<VertexId> = edit
        .remove
        .iter()
        .filter(|&&f| cloth.mesh.is_face(f))
        .flat_map(|&f| cloth.mesh.face(f))
        .collect();
    touched.sort_unstable();
    touched.dedup();
    let (momentum_before, energy_before) = momentum_and_energy(cloth, &touched);
    let interpolated: Vec<(Vec3, Vec3)> = edit
        .new_vertices
        .iter()
        .map(|n| {
            let (x, v) = interpolate(cloth, n.origin);
            (obstacles.map_or(x, |o| o.push_out(x)), v)
        })
        .collect();
    if refuse_crossings {
        let positions: Vec<Vec3> = interpolated.iter().map(|(x, _)| *x).collect();
        if edit_crosses_with(crossing_guard, cloth, edit, &positions) {
            return Err(EditError::CrossesCloth);
        }
    }

    let record = replace(&mut cloth.mesh, edit)?;

    cloth.refresh_state_len();
    for v in &record.removed_vertices {
        cloth.x[v.0 as usize] = Vec3::zeros();
        cloth.v[v.0 as usize] = Vec3::zeros();
    }
    for ((v, _), (x, vel)) in record.added_vertices.iter().zip(interpolated) {
        cloth.x[v.0 as usize] = x;
        cloth.v[v.0 as usize] = vel;
    }
    touched.extend(record.added_vertices.iter().map(|(v, _)| *v));
    touched.sort_unstable();
    touched.dedup();
    cloth.model.update_vertices(&cloth.mesh, &touched);

    let (mut momentum_after, _) = momentum_and_energy(cloth, &touched);
    if restore_momentum {
        let inv = cloth.model.inv_mass();
        let mass = cloth.model.mass();
        let movable_mass: Real = touched
            .iter()
            .filter(|v| inv[v.0 as usize] > 0.0)
            .map(|v| mass[v.0 as usize])
            .sum();
        if movable_mass > 0.0 {
            let dv = (momentum_before - momentum_after) / movable_mass;
            for v in &touched {
                if inv[v.0 as usize] > 0.0 {
                    cloth.v[v.0 as usize] += dv;
                }
            }
            momentum_after = momentum_and_energy(cloth, &touched).0;
        }
    }
    if restore_energy {
        restore_kinetic_energy(cloth, &touched, energy_before);
    }
    let energy_after = momentum_and_energy(cloth, &touched).1;
    Ok(Transfer {
        record,
        momentum_change: (momentum_before - momentum_after).norm(),
        kinetic_energy_change: energy_after - energy_before,
    })
}

/// Sets the kinetic energy of `vertices` to `target` (J) without changing their linear momentum
/// (MODEL.md §8.4 rule 6): the velocities of the movable ones relative to their mass-weighted mean
/// `v_mean` are scaled, `v_i <- v_mean + s (v_i - v_mean)`, which keeps `sum m_i v_i` exactly and
/// moves the energy of the relative motion to `target - |p|² / 2M`. Pinned vertices (zero inverse
/// mass) are not changed. For a split this is the "equal and opposite relative velocity" of the
/// rule spread over the touched region; it works the same for merges and re-meshed regions.
/// Returns false (and changes nothing) when it cannot: no movable mass, no relative motion to
/// scale, or a target below the energy of the mean motion.
pub fn restore_kinetic_energy(cloth: &mut Cloth, vertices: &[VertexId], target: Real) -> bool {
    let inv = cloth.model.inv_mass();
    let mass = cloth.model.mass();
    let movable: Vec<usize> = vertices
        .iter()
        .map(|v| v.0 as usize)
        .filter(|&i| inv.get(i).copied().unwrap_or(0.0) > 0.0)
        .collect();
    let total_mass: Real = movable.iter().map(|&i| mass[i]).sum();
    if total_mass <= 0.0 {
        return false;
    }
    let momentum: Vec3 = movable.iter().map(|&i| cloth.v[i] * mass[i]).sum();
    let mean = momentum / total_mass;
    let relative: Real = movable
        .iter()
        .map(|&i| 0.5 * mass[i] * (cloth.v[i] - mean).norm_squared())
        .sum();
    let fixed: Real = vertices
        .iter()
        .map(|v| v.0 as usize)
        .filter(|&i| inv.get(i).copied().unwrap_or(0.0) <= 0.0)
        .map(|i| 0.5 * mass.get(i).copied().unwrap_or(0.0) * cloth.v[i].norm_squared())
        .sum();
    let wanted = target - fixed - 0.5 * total_mass * mean.norm_squared();
    if !(relative > 0.0 && wanted >= 0.0 && wanted.is_finite()) {
        return false;
    }
    let s = (wanted / relative).sqrt();
    for &i in &movable {
        cloth.v[i] = mean + (cloth.v[i] - mean) * s;
    }
    true
}

/// World position and velocity interpolated at a new vertex's origin.
fn interpolate(cloth: &Cloth, origin: Origin) -> (Vec3, Vec3) {
    match origin {
        Origin::Midpoint(a, b) => {
            let (a, b) = (a.0 as usize, b.0 as usize);
            (
                (cloth.x[a] + cloth.x[b]) * 0.5,
                (cloth.v[a] + cloth.v[b]) * 0.5,
            )
        }
        Origin::InTriangle { corners, weights } => {
            let mut x = Vec3::zeros();
            let mut v = Vec3::zeros();
            for k in 0..3 {
                x += cloth.x[corners[k].0 as usize] * weights[k];
                v += cloth.v[corners[k].0 as usize] * weights[k];
            }
            (x, v)
        }
    }
}

/// Linear momentum (kg m/s) and kinetic energy (J) of the given vertices.
fn momentum_and_energy(cloth: &Cloth, vertices: &[VertexId]) -> (Vec3, Real) {
    let m = cloth.model.mass();
    vertices.iter().fold((Vec3::zeros(), 0.0), |(p, e), v| {
        let i = v.0 as usize;
        let mi = m.get(i).copied().unwrap_or(0.0);
        let vi = cloth.v.get(i).copied().unwrap_or_else(Vec3::zeros);
        (p + vi * mi, e + 0.5 * mi * vi.norm_squared())
    })
}
