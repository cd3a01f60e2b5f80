//! The metrics table (`metrics.csv`): one row per sample of the run.

use crate::math::{Real, Vec3};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// One row of `metrics.csv`.
#[derive(Clone, Debug, Default)]
pub struct MetricsRow {
    /// Step number.
    pub step: u64,
    /// Simulated time (s).
    pub t: Real,
    /// Last step size (s).
    pub dt: Real,
    /// Live vertices.
    pub vertices: usize,
    /// Edges.
    pub edges: usize,
    /// Faces.
    pub faces: usize,
    /// Smallest vertex mass (kg).
    pub min_mass: Real,
    /// Largest spring stiffness (N/m).
    pub max_stiffness: Real,
    /// Total mass (kg).
    pub total_mass: Real,
    /// Norm of the total linear momentum (kg m/s).
    pub linear_momentum: Real,
    /// Kinetic energy (J).
    pub kinetic_energy: Real,
    /// Largest depth of a vertex inside an obstacle (m).
    pub max_penetration: Real,
    /// Largest depth of an obstacle through the cloth surface, faces included (m).
    pub max_surface_penetration: Real,
    /// The cloth's crossings with itself (edge-face pairs sharing no vertex, the edge through the
    /// face); `None` (an empty cell) on a row where it was not measured.
    pub self_intersections: Option<usize>,
    /// Vertices in contact during the last step.
    pub contacts: usize,
    /// Vertices resting on an obstacle that the last step's implicit solve held (0 for an
    /// integrator that holds none).
    pub held_contacts: usize,
    /// Adaptation events in the last step.
    pub adapt_events: usize,
    /// Kinetic-energy change of those events (J).
    pub adapt_energy_change: Real,
    /// Total-energy change of those events (J): kinetic, gravity, stretch and bending after the
    /// step's adaptation (and the contact passes that follow it) minus before.
    pub adapt_total_energy_change: Real,
    /// Gravitational potential energy `-sum m g . x` (J).
    pub gravity_energy: Real,
    /// Stretch potential energy of the springs (J).
    pub stretch_energy: Real,
    /// Bending potential energy (J).
    pub bending_energy: Real,
    /// Kinetic plus gravitational, stretch and bending energy (J).
    pub total_energy: Real,
    /// Conjugate-gradient iterations of the last step (`implicit_euler`; 0 otherwise).
    pub cg_iterations: usize,
    /// Steps since the start of the run whose linear solve ended above its tolerance
    /// (cumulative, so the last row holds the run's total; `implicit_euler`; 0 otherwise).
    pub cg_unconverged: u64,
    /// World positions of the tracked points (m).
    pub tracked: Vec<Vec3>,
}

/// The column stem of tracked point `k` named `name`: the name made CSV- and file-safe
/// ([`super::file_safe`]: `free corner` -> `free_corner`), or `p<k>` when that is empty or already
/// in `used`.
fn tracked_column(name: &str, k: usize, used: &[String]) -> String {
    let safe = super::file_safe(name);
    if safe.is_empty() || used.contains(&safe) {
        format!("p{k}")
    } else {
        safe
    }
}

/// Streams rows to `metrics.csv.partial`; [`MetricsWriter::finish`] renames it to `metrics.csv`.
pub struct MetricsWriter {
    out: BufWriter<File>,
    partial: PathBuf,
    done: PathBuf,
}

impl MetricsWriter {
    /// Creates the table with its header; `tracked` names the tracked points, whose columns are
    /// `NAME_x,NAME_y,NAME_z` ([`tracked_column`]).
    pub fn create(out_dir: &Path, tracked: &[String]) -> std::io::Result<MetricsWriter> {
        let done = out_dir.join("metrics.csv");
        let partial = out_dir.join("metrics.csv.partial");
        let _ = std::fs::remove_file(&done);
        let mut out = BufWriter::new(super::create_for_writing(&partial)?);
        write!(
            out,
            "step,t,dt,vertices,edges,faces,min_mass,max_stiffness,total_mass,linear_momentum,\
             kinetic_energy,max_penetration,max_surface_penetration,self_intersections,contacts,held_contacts,adapt_events,adapt_energy_change,adapt_total_energy_change,gravity_energy,\
             stretch_energy,bending_energy,total_energy,cg_iterations,cg_unconverged"
        )?;
        let mut used = Vec::new();
        for (k, name) in tracked.iter().enumerate() {
            let column = tracked_column(name, k, &used);
            write!(out, ",{column}_x,{column}_y,{column}_z")?;
            used.push(column);
        }
        writeln!(out)?;
        Ok(MetricsWriter { out, partial, done })
    }

    /// Appends a row.
    pub fn row(&mut self, r: &MetricsRow) -> std::io::Result<()> {
        write!(
            self.out,
            "{},{:.9e},{:.6e},{},{},{},{:.6e},{:.6e},{:.9e},{:.6e},{:.6e},{:.6e},{:.6e},{},{},{},{},{:.6e},{:.6e},{:.9e},\
             {:.9e},{:.9e},{:.9e},{},{}",
            r.step,
            r.t,
            r.dt,
            r.vertices,
            r.edges,
            r.faces,
            r.min_mass,
            r.max_stiffness,
            r.total_mass,
            r.linear_momentum,
            r.kinetic_energy,
            r.max_penetration,
            r.max_surface_penetration,
            r.self_intersections.map_or(String::new(), |n| n.to_string()),
            r.contacts,
            r.held_contacts,
            r.adapt_events,
            r.adapt_energy_change,
            r.adapt_total_energy_change,
            r.gravity_energy,
            r.stretch_energy,
            r.bending_energy,
            r.total_energy,
            r.cg_iterations,
            r.cg_unconverged
        )?;
        for p in &r.tracked {
            write!(self.out, ",{:.9e},{:.9e},{:.9e}", p.x, p.y, p.z)?;
        }
        writeln!(self.out)
    }

    /// Flushes buffered rows to disk (the file keeps its `.partial` name).
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }

    /// Flushes and renames the table to `metrics.csv`. A table whose write failed is dropped
    /// instead and keeps its `.partial` name.
    pub fn finish(mut self) -> std::io::Result<()> {
        self.out.flush()?;
        self.out.get_ref().sync_all()?;
        std::fs::rename(&self.partial, &self.done)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tracked points' columns carry their scene names (issue 15), made CSV-safe and unique.
    #[test]
    fn tracked_columns_are_named_after_the_points() {
        let dir = tempfile::tempdir().unwrap();
        let names = ["P", "free corner", "P", "", "a,b"].map(String::from);
        MetricsWriter::create(dir.path(), &names)
            .unwrap()
            .finish()
            .unwrap();
        let text = std::fs::read_to_string(dir.path().join("metrics.csv")).unwrap();
        let header = text.lines().next().unwrap();
        assert!(
            header.ends_with(
                ",cg_iterations,cg_unconverged,P_x,P_y,P_z,free_corner_x,free_corner_y,free_corner_z,\
                 p2_x,p2_y,p2_z,p3_x,p3_y,p3_z,a_b_x,a_b_y,a_b_z"
            ),
            "{header}"
        );
    }
}
