//! Scene loaders (Mitsuba 3 XML), meshes, bitmaps, named material data.
//!
//! Filled in by a later issue; see ../../shared/DESIGN.md for its place in the workspace.
