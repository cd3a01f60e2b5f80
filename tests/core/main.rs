//! Integration tests of the core: scenes run end to end, physics laws hold through the whole
//! pipeline, outputs are complete, bad input fails cleanly.
mod browser;
mod cli;
mod common;
mod compare;
mod consistency;
mod console;
mod contact;
mod folders;
mod golden;
mod integrators;
mod moving;
mod output_paths;
mod physics_laws;
mod resolution;
mod resting;
mod run_outputs;
mod runs;
mod scene_fuzz;
mod self_collision;
mod study;
mod study_cli;
mod threads;
mod transfer;
mod trial_inputs;
