//! Flat spring and bending arrays built from the mesh and the material.
