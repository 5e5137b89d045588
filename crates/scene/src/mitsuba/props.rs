//! Properties of an object node: `<float name=…>`, `<integer>`,
//! `<boolean>`, `<string>`, `<rgb>`, `<spectrum>`, `<point>`, `<vector>`,
//! `<transform>`. Each read is remembered, so what a scene sets but
//! scotopia does not use can be reported once as a warning. Spectral
//! properties are read in `spectrum.rs`, which reads spectra's own
//! properties through these.

use std::cell::RefCell;

use scotopia_render::math::{Transform, Vec3};

use super::error::SceneError;
use super::parse::Node;
use super::values::{parse_floats, read_transform};

/// What a colour is used as: it decides how `<rgb>` is upsampled and
/// whether negative values are allowed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Usage {
    /// A reflectance or transmittance in [0, 1].
    Reflectance,
    /// A non-negative factor that may exceed 1 (an index, a scale).
    Unbounded,
    /// Emission: spectral radiance, `<rgb>` upsampled as an illuminant.
    Emission,
}

/// The property tags (a `<texture>` nested under a parameter's name is one).
pub(crate) const PROPERTY_TAGS: [&str; 10] = [
    "float",
    "integer",
    "boolean",
    "string",
    "rgb",
    "spectrum",
    "point",
    "vector",
    "transform",
    "texture",
];

/// Whether `c` sets a named parameter: a property tag, or a `<ref name="…">`
/// to a top-level object (a shape's unnamed `<ref>` to its BSDF is not).
fn is_property(c: &Node, name: Option<&str>) -> bool {
    let named = match name {
        Some(want) => c.attr("name") == Some(want),
        None => true,
    };
    named
        && (PROPERTY_TAGS.contains(&c.tag.as_str())
            || (c.tag == "ref" && c.attr("name").is_some_and(|n| n != "bsdf")))
}

/// Read access to an object's properties.
pub struct Props<'a> {
    pub node: &'a Node,
    used: RefCell<Vec<&'a str>>,
    /// Values read with an adjustment the user should hear of: (property
    /// node, what was done), reported as warnings with the unused ones.
    pub(super) notes: RefCell<Vec<(&'a Node, String)>>,
}

impl<'a> Props<'a> {
    pub fn new(node: &'a Node) -> Self {
        Self {
            node,
            used: RefCell::new(Vec::new()),
            notes: RefCell::new(Vec::new()),
        }
    }

    /// Adjustments made while reading (see `notes`), drained.
    pub fn take_notes(&self) -> Vec<(&'a Node, String)> {
        std::mem::take(&mut self.notes.borrow_mut())
    }

    /// The property child named `name`.
    pub fn get(&self, name: &str) -> Option<&'a Node> {
        let n = self
            .node
            .children
            .iter()
            .find(|c| is_property(c, Some(name)))?;
        self.used.borrow_mut().push(n.attr("name").unwrap_or(""));
        Some(n)
    }

    /// Marks the unnamed properties as read (a plugin that takes its one
    /// nested texture whatever its name, as Mitsuba's `bumpmap`).
    pub fn mark_unnamed_used(&self) {
        self.used.borrow_mut().push("");
    }

    /// Properties set but never read: (node, name), for one warning each.
    pub fn unused(&self) -> Vec<&'a Node> {
        let used = self.used.borrow();
        self.node
            .children
            .iter()
            .filter(|c| is_property(c, None))
            .filter(|c| !used.contains(&c.attr("name").unwrap_or("")))
            .collect()
    }

    pub(super) fn number(&self, n: &Node) -> Result<f32, SceneError> {
        self.one(n, n.require("value")?)
    }

    pub fn float(&self, name: &str, default: f32) -> Result<f32, SceneError> {
        match self.get(name) {
            Some(n) if n.tag == "float" || n.tag == "integer" => self.number(n),
            Some(n) => Err(n.error(format!("'{name}' must be a <float>"))),
            None => Ok(default),
        }
    }

    pub fn integer(&self, name: &str, default: i64) -> Result<i64, SceneError> {
        match self.get(name) {
            Some(n) if n.tag == "integer" => n.require("value")?.trim().parse().map_err(|_| {
                n.error(format!(
                    "'{}' is not an integer",
                    n.attr("value").unwrap_or("")
                ))
            }),
            Some(n) => Err(n.error(format!("'{name}' must be an <integer>"))),
            None => Ok(default),
        }
    }

    pub fn boolean(&self, name: &str, default: bool) -> Result<bool, SceneError> {
        match self.get(name) {
            Some(n) if n.tag == "boolean" => match n.require("value")?.trim() {
                "true" => Ok(true),
                "false" => Ok(false),
                v => Err(n.error(format!("'{v}' is not true or false"))),
            },
            Some(n) => Err(n.error(format!("'{name}' must be a <boolean>"))),
            None => Ok(default),
        }
    }

    pub fn string(&self, name: &str) -> Result<Option<&'a str>, SceneError> {
        match self.get(name) {
            Some(n) if n.tag == "string" => Ok(Some(n.require("value")?)),
            Some(n) => Err(n.error(format!("'{name}' must be a <string>"))),
            None => Ok(None),
        }
    }

    pub fn point(&self, name: &str, default: Vec3) -> Result<Vec3, SceneError> {
        match self.get(name) {
            Some(n) if n.tag == "point" || n.tag == "vector" => {
                if let Some(v) = n.attr("value") {
                    let f = parse_floats(n, v)?;
                    return match f.as_slice() {
                        [x, y, z] => Ok(Vec3::new(*x, *y, *z)),
                        _ => Err(n.error("expected 3 numbers")),
                    };
                }
                let c = |k: &str| n.attr(k).map_or(Ok(0.0), |v| self.one(n, v));
                Ok(Vec3::new(c("x")?, c("y")?, c("z")?))
            }
            Some(n) => Err(n.error(format!("'{name}' must be a <point>"))),
            None => Ok(default),
        }
    }

    fn one(&self, n: &Node, text: &str) -> Result<f32, SceneError> {
        match parse_floats(n, text)?.as_slice() {
            [x] => Ok(*x),
            _ => Err(n.error("expected one number")),
        }
    }

    pub fn transform(&self, name: &str) -> Result<Transform, SceneError> {
        match self.get(name) {
            Some(n) if n.tag == "transform" => read_transform(n),
            Some(n) => Err(n.error(format!("'{name}' must be a <transform>"))),
            None => Ok(Transform::IDENTITY),
        }
    }
}
