//! Output frames written beside the step loop: the loop's thread copies the state it records
//! ([`Frame::capture`]); formatting the text and writing the file go to another thread of the
//! pool when the pool has one to spare ([`FrameSink`]), so the frames cost the step loop only
//! the copy. One frame is written at a time, each after the one before has been written, and
//! none after a failed one: the frames on disk are always the first ones, numbered without a
//! gap. Each frame is its own file, written by the same function either way, so the files do not
//! depend on where they were written.

use crate::math::Vec3;
use crate::mesh::Mesh;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// One output frame: the mesh's live vertices renumbered in slot order.
pub struct Frame {
    path: PathBuf,
    /// Simulated time (s).
    time: f64,
    /// World positions (m).
    positions: Vec<[f64; 3]>,
    /// Rest coordinates (m).
    rest: Vec<[f64; 2]>,
    /// Triangles, indices into `positions`.
    triangles: Vec<[usize; 3]>,
}

impl Frame {
    /// The frame of `mesh` at world positions `x` (indexed by slot) at `time` (s), to be
    /// written to `path`.
    pub fn capture(path: PathBuf, mesh: &Mesh, x: &[Vec3], time: f64) -> Frame {
        let mut number = vec![0usize; mesh.vertex_slots()];
        let (mut positions, mut rest) = (Vec::new(), Vec::new());
        for (k, v) in mesh.vertices().enumerate() {
            number[v.0 as usize] = k;
            let p = x[v.0 as usize];
            positions.push([p.x, p.y, p.z]);
            let r = mesh.rest(v);
            rest.push([r.x, r.y]);
        }
        let triangles = mesh
            .faces()
            .map(|f| mesh.face(f).map(|v| number[v.0 as usize]))
            .collect();
        Frame {
            path,
            time,
            positions,
            rest,
            triangles,
        }
    }

    /// Writes the frame through [`crate::io::write_frame`] (atomically, unsynced).
    pub fn write(&self) -> std::io::Result<()> {
        crate::io::write_frame(
            &self.path,
            self.time,
            &self.positions,
            &self.rest,
            &self.triangles,
        )
    }
}

/// What the writes of one run came to, shared with the threads writing.
#[derive(Default)]
struct Outcome {
    /// Frames written.
    written: AtomicUsize,
    /// Whether a frame handed to another thread is still to be written.
    writing: AtomicBool,
    /// Whether a write has failed (kept when the failure itself has been taken).
    failed: AtomicBool,
    /// The first write that failed: its file and error.
    failure: Mutex<Option<(PathBuf, std::io::Error)>>,
}

impl Outcome {
    fn record(&self, path: &std::path::Path, result: std::io::Result<()>) {
        match result {
            Ok(()) => {
                self.written.fetch_add(1, Ordering::AcqRel);
            }
            Err(e) => {
                self.failed.store(true, Ordering::Release);
                let mut failure = self.failure.lock().unwrap_or_else(|p| p.into_inner());
                failure.get_or_insert((path.to_path_buf(), e));
            }
        }
    }

    fn failed(&self) -> bool {
        self.failed.load(Ordering::Acquire)
    }
}

/// Clears its flag when dropped: the end of a frame's write on another thread.
struct Written<'a>(&'a AtomicBool);

impl Drop for Written<'_> {
    fn drop(&mut self) {
        self.0.store(false, Ordering::Release);
    }
}

/// The writes of one run's frames: hands out the [`FrameSink`] the loop submits to, and says
/// how they went once it is done.
#[derive(Default)]
pub struct FrameWrites(Arc<Outcome>);

impl FrameWrites {
    /// A sink writing on `scope`'s pool (a rayon scope that outlives the run's loop, so every
    /// frame handed over is written before the run ends), or on the caller's thread with `None`.
    pub fn sink<'a, 's>(&self, scope: Option<&'a rayon::Scope<'s>>) -> FrameSink<'a, 's> {
        FrameSink {
            scope,
            outcome: Arc::clone(&self.0),
        }
    }

    /// The first failed write so far (its file and error), taken: later calls return `None`
    /// until another write fails.
    pub fn failure(&self) -> Option<(PathBuf, std::io::Error)> {
        let mut failure = self.0.failure.lock().unwrap_or_else(|p| p.into_inner());
        failure.take()
    }

    /// Frames written so far (all of them once the sinks' scope has ended).
    pub fn written(&self) -> usize {
        self.0.written.load(Ordering::Acquire)
    }
}

/// Where a run's loop submits its frames (see [`FrameWrites::sink`]).
pub struct FrameSink<'a, 's> {
    scope: Option<&'a rayon::Scope<'s>>,
    outcome: Arc<Outcome>,
}

impl FrameSink<'_, '_> {
    /// Writes `frame`, on another thread when there is a scope, once the frame handed over
    /// before it has been written (waiting for it, or writing it here if no thread has taken
    /// it yet); not at all after a failed write, which is kept for [`FrameWrites::failure`].
    pub fn submit(&self, frame: Frame) {
        let outcome = &self.outcome;
        while outcome.writing.load(Ordering::Acquire) {
            // On a pool thread, run the write here if no other thread has taken it; else wait
            // without holding the core (a frame's write takes about a millisecond).
            if rayon::yield_now() != Some(rayon::Yield::Executed) {
                std::thread::sleep(std::time::Duration::from_micros(50));
            }
        }
        if outcome.failed() {
            return;
        }
        match self.scope {
            Some(scope) => {
                outcome.writing.store(true, Ordering::Release);
                let outcome = Arc::clone(outcome);
                scope.spawn(move |_| {
                    // Cleared however the write ends, a panic included (the scope then re-raises
                    // it), so the next submit never waits for ever.
                    let _done = Written(&outcome.writing);
                    outcome.record(&frame.path, frame.write());
                });
            }
            None => outcome.record(&frame.path, frame.write()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::union_jack;
    use crate::testing::in_pool;

    /// Twenty frames handed to a pool of two threads are all written, counted, and equal to
    /// frames written in line; a write into a missing folder is the failure reported, once, and
    /// no frame handed over after it is written.
    #[test]
    fn frames_written_on_the_pool_are_the_frames_written_in_line() {
        let dir = tempfile::tempdir().unwrap();
        let mesh = union_jack(9, 9, 1.0, 1.0);
        let states: Vec<Vec<Vec3>> = (0..20)
            .map(|k| {
                (0..mesh.vertex_slots())
                    .map(|i| Vec3::new(i as f64 * 0.01, k as f64 * 0.1, 0.3))
                    .collect()
            })
            .collect();
        let name = |how: &str, k: usize| dir.path().join(format!("{how}_{k:02}.obj"));
        let inline = FrameWrites::default();
        let sink = inline.sink(None);
        for (k, x) in states.iter().enumerate() {
            sink.submit(Frame::capture(name("inline", k), &mesh, x, k as f64));
        }
        let pooled = FrameWrites::default();
        in_pool(2, || {
            rayon::in_place_scope(|scope| {
                let sink = pooled.sink(Some(scope));
                for (k, x) in states.iter().enumerate() {
                    sink.submit(Frame::capture(name("pooled", k), &mesh, x, k as f64));
                }
                let missing = dir.path().join("no such folder/frame.obj");
                sink.submit(Frame::capture(missing, &mesh, &states[0], 0.0));
                sink.submit(Frame::capture(name("after", 0), &mesh, &states[0], 0.0));
            })
        });
        assert!(
            !name("after", 0).exists(),
            "a frame after a failed one is not written"
        );
        assert_eq!((inline.written(), pooled.written()), (20, 20));
        assert!(inline.failure().is_none());
        let (path, _) = pooled
            .failure()
            .expect("the write into a missing folder fails");
        assert!(path.ends_with("no such folder/frame.obj"), "{path:?}");
        assert!(pooled.failure().is_none(), "a failure is reported once");
        for k in 0..20 {
            let read = |how| std::fs::read(name(how, k)).unwrap();
            assert!(read("inline") == read("pooled"), "frame {k} differs");
        }
    }
}
