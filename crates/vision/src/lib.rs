//! The vision pipeline: visual mode, glare, adaptation, night shift, gamut mapping.
//!
//! Filled in by a later issue; see ../../shared/DESIGN.md for its place in the workspace.
