//! The Mitsuba 3 XML scene format: parse to plain nodes (`parse`), then
//! read values (`values`). Building scene objects follows.

mod error;
mod parse;
mod props;
mod values;

pub use error::{Location, SceneError};
pub use parse::{parse_file, parse_str, Node, Parameters};
pub use props::{read_spectrum, resolve, Props, Usage};
pub use values::{parse_floats, read_transform};
