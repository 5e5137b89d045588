//! The Mitsuba 3 XML scene format: parse to plain nodes (`parse`), then
//! read values (`values`); files named in a scene are found through the
//! search path (`search`). `crate::build` makes scene objects of them.

mod error;
mod parse;
mod props;
pub(crate) use props::PROPERTY_TAGS;
mod search;
mod spectrum;
mod values;

pub use error::{Location, SceneError, SceneErrors};
pub use parse::{
    parse_file, parse_scene, parse_str, Node, Parameters, Parsed, MAX_DEPTH, MAX_INCLUDE_DEPTH,
    XML_LIMIT,
};
pub use props::{Props, Usage};
pub(crate) use search::recording;
pub use search::{resolve, SearchPath};
pub use spectrum::{normalised_illuminant, read_spectrum, read_spectrum_as};
pub use values::{parse_floats, parse_rgb, read_transform};
