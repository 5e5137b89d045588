//! Geometry, BVH, camera, BSDFs, lights, wavelength sampling, integrators, film.
//!
//! Filled in by a later issue; see ../../shared/DESIGN.md for its place in the workspace.
