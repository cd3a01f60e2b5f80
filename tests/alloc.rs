//! The step is allocation-free in steady state: a counting global allocator (this test binary
//! only) sees no allocation during steps once the mesh stops changing. Only allocations made by
//! the thread that runs the steps are counted: the test harness's own thread prints while the test
//! runs, and counting it made the test fail now and then for reasons outside the step.
use adaptcloth::scene;
use adaptcloth::sim::Simulation;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    /// True on the thread whose allocations are counted.
    static COUNTED: Cell<bool> = const { Cell::new(false) };
}

/// Counts one allocation if it was made by the counted thread.
fn count() {
    if COUNTED.try_with(Cell::get).unwrap_or(false) {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
    }
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Steps of every shipped scene allocate nothing after a few warm-up steps (static strategy,
/// with contacts: the sphere's and the round table's cloths start 2 mm or so above their tops
/// here, the bunny's on its head; self-collision on, as those scenes ship), with the scene's
/// integrator and with
/// `implicit_euler` under each of its solvers.
#[test]
fn steady_state_steps_do_not_allocate() {
    COUNTED.with(|c| c.set(true));
    let scenes: [(&str, &[&str]); 4] = [
        ("sphere", &["cloth.center=[0.0, 0.0, 0.252]"]),
        ("round_table", &["cloth.center=[0.0, 0.0, 0.752]"]),
        ("bunny", &["cloth.center=[0.0, 0.0, 0.492]"]),
        ("hanging", &[]),
    ];
    let implicit = "integrator.name=\"implicit_euler\"";
    let integrators = [
        vec![],
        vec![implicit, "integrator.solver=\"cg\""],
        vec![implicit, "integrator.solver=\"cholesky\""],
        vec![implicit, "integrator.solver=\"auto\""],
    ];
    for ((name, setting), integrator) in scenes
        .into_iter()
        .flat_map(|s| integrators.iter().map(move |i| (s, i)))
    {
        let overrides: Vec<String> = setting
            .iter()
            .chain(integrator)
            .chain(&["cloth.resolution=9"])
            .map(|s| s.to_string())
            .collect();
        let loaded = scene::load_embedded(name, &overrides).unwrap().unwrap();
        let mut sim = Simulation::new(&loaded).unwrap();
        // Vertices the response moved, and those the implicit solve held on a surface.
        let mut contacts = 0;
        let mut step = || {
            let report = sim.step().unwrap();
            report.contacts.contacts + report.held_contacts
        };
        for _ in 0..20 {
            contacts += step();
        }
        let before = ALLOCATIONS.load(Ordering::Relaxed);
        for _ in 0..200 {
            contacts += step();
        }
        let allocated = ALLOCATIONS.load(Ordering::Relaxed) - before;
        assert_eq!(
            allocated, 0,
            "{name} {integrator:?}: {allocated} allocations in 200 steps"
        );
        if name != "hanging" {
            assert!(
                contacts > 0,
                "{name}: the test meant to exercise contacts saw none"
            );
        }
    }
}
