//! Time integrators behind one interface.
