//! Integration tests of the core: scenes run end to end, physics laws hold through the whole
//! pipeline, outputs are complete, bad input fails cleanly.
mod cli;
mod common;
mod integrators;
mod physics_laws;
mod runs;
mod transfer;
