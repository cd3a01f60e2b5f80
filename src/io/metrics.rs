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
    /// Largest depth inside an obstacle (m).
    pub max_penetration: Real,
    /// Vertices in contact during the last step.
    pub contacts: usize,
    /// Adaptation events in the last step.
    pub adapt_events: usize,
    /// Kinetic-energy change of those events (J).
    pub adapt_energy_change: Real,
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
    /// World positions of the tracked points (m).
    pub tracked: Vec<Vec3>,
}

/// Streams rows to `metrics.csv.partial`; [`MetricsWriter::finish`] renames it to `metrics.csv`.
pub struct MetricsWriter {
    out: BufWriter<File>,
    partial: PathBuf,
    done: PathBuf,
}

impl MetricsWriter {
    /// Creates the table with its header; `tracked` is the number of tracked points (columns
    /// `p<k>_x,p<k>_y,p<k>_z`).
    pub fn create(out_dir: &Path, tracked: usize) -> std::io::Result<MetricsWriter> {
        let done = out_dir.join("metrics.csv");
        let partial = out_dir.join("metrics.csv.partial");
        let _ = std::fs::remove_file(&done);
        let mut out = BufWriter::new(File::create(&partial)?);
        write!(
            out,
            "step,t,dt,vertices,edges,faces,min_mass,max_stiffness,total_mass,linear_momentum,\
             kinetic_energy,max_penetration,contacts,adapt_events,adapt_energy_change,gravity_energy,\
             stretch_energy,bending_energy,total_energy,cg_iterations"
        )?;
        for k in 0..tracked {
            write!(out, ",p{k}_x,p{k}_y,p{k}_z")?;
        }
        writeln!(out)?;
        Ok(MetricsWriter { out, partial, done })
    }

    /// Appends a row.
    pub fn row(&mut self, r: &MetricsRow) -> std::io::Result<()> {
        write!(
            self.out,
            "{},{:.9e},{:.6e},{},{},{},{:.6e},{:.6e},{:.9e},{:.6e},{:.6e},{:.6e},{},{},{:.6e},{:.9e},{:.9e},\
             {:.9e},{:.9e},{}",
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
            r.contacts,
            r.adapt_events,
            r.adapt_energy_change,
            r.gravity_energy,
            r.stretch_energy,
            r.bending_energy,
            r.total_energy,
            r.cg_iterations
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

    /// Flushes and renames the table to `metrics.csv`.
    pub fn finish(mut self) -> std::io::Result<()> {
        self.out.flush()?;
        self.out.get_ref().sync_all()?;
        std::fs::rename(&self.partial, &self.done)
    }
}
