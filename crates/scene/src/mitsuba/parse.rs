//! Parse: a Mitsuba 3 XML file (and its includes) to a tree of plain nodes
//! that remember where they came from, with `<default>` parameters and
//! `$name` substitutions applied. Nothing here knows what a BSDF is.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::error::{Location, SceneError};

/// One element: an object (`<bsdf type="diffuse">`), a property
/// (`<float name="alpha" value="0.1"/>`), or a transform operation.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    pub tag: String,
    /// Attributes after `$param` substitution, in document order.
    pub attributes: Vec<(String, String)>,
    pub children: Vec<Node>,
    pub location: Location,
    /// The folder of the file the node came from (relative paths resolve there).
    pub dir: PathBuf,
}

impl Node {
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// An error at this node.
    pub fn error(&self, message: impl Into<String>) -> SceneError {
        SceneError::new(&self.location, &self.tag, message)
    }

    /// A required attribute.
    pub fn require(&self, name: &str) -> Result<&str, SceneError> {
        self.attr(name)
            .ok_or_else(|| self.error(format!("missing attribute '{name}'")))
    }
}

/// Command-line or API parameters (`-D name=value`), overriding `<default>`.
pub type Parameters = HashMap<String, String>;

/// Reads `path` and the files it includes into the root `<scene>` node.
pub fn parse_file(path: &Path, params: &Parameters) -> Result<Node, SceneError> {
    let mut stack = Vec::new();
    let mut root = parse_into(path, params, &mut stack, None)?;
    root.tag = "scene".into();
    Ok(root)
}

fn io_error(path: &Path, from: Option<&Location>, e: std::io::Error) -> SceneError {
    let location = from.cloned().unwrap_or(Location {
        file: path.display().to_string(),
        line: 0,
        column: 0,
    });
    let element = if from.is_some() { "include" } else { "scene" };
    SceneError::new(
        &location,
        element,
        format!("cannot read {}: {e}", path.display()),
    )
}

fn parse_into(
    path: &Path,
    params: &Parameters,
    stack: &mut Vec<PathBuf>,
    from: Option<&Location>,
) -> Result<Node, SceneError> {
    let canonical = path.canonicalize().map_err(|e| io_error(path, from, e))?;
    if stack.contains(&canonical) {
        let location = from.cloned().unwrap_or_else(|| Location {
            file: path.display().to_string(),
            line: 0,
            column: 0,
        });
        return Err(SceneError::new(
            &location,
            "include",
            format!("{} includes itself", path.display()),
        ));
    }
    let text = std::fs::read_to_string(path).map_err(|e| io_error(path, from, e))?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    stack.push(canonical);
    let scene = parse_text(
        &text,
        &path.display().to_string(),
        &dir,
        params,
        stack,
        true,
    )?;
    stack.pop();
    Ok(scene)
}

/// Parses XML `text` (called `name` in error locations) whose root element is one
/// object, e.g. a `<bsdf>` (`<scene>` too); relative paths and includes
/// resolve against `dir`.
pub fn parse_str(
    text: &str,
    name: &str,
    dir: &Path,
    params: &Parameters,
) -> Result<Node, SceneError> {
    parse_text(text, name, dir, params, &mut Vec::new(), false)
}

/// The document `text` as a tree of nodes; its root must be `<scene>` when
/// `scene` is set.
fn parse_text(
    text: &str,
    file: &str,
    dir: &Path,
    params: &Parameters,
    stack: &mut Vec<PathBuf>,
    scene: bool,
) -> Result<Node, SceneError> {
    let file = file.to_string();
    let doc = roxmltree::Document::parse(text).map_err(|e| {
        let pos = e.pos();
        SceneError::new(
            &Location {
                file: file.clone(),
                line: pos.row,
                column: pos.col,
            },
            "xml",
            e.to_string(),
        )
    })?;
    let root = doc.root_element();
    let loc = |n: roxmltree::Node| {
        let p = doc.text_pos_at(n.range().start);
        Location {
            file: file.clone(),
            line: p.row,
            column: p.col,
        }
    };
    if scene && root.tag_name().name() != "scene" {
        return Err(SceneError::new(
            &loc(root),
            root.tag_name().name(),
            "the root element must be <scene>",
        ));
    }

    // Defaults first (anywhere at the top level), overridden by `params`.
    let mut values = HashMap::new();
    for n in root
        .children()
        .filter(|n| n.is_element() && n.tag_name().name() == "default")
    {
        let name = n.attribute("name");
        let value = n.attribute("value");
        match (name, value) {
            (Some(k), Some(v)) => {
                values.entry(k.to_string()).or_insert_with(|| v.to_string());
            }
            _ => {
                return Err(SceneError::new(
                    &loc(n),
                    "default",
                    "needs 'name' and 'value'",
                ))
            }
        }
    }
    for (k, v) in params {
        values.insert(k.clone(), v.clone());
    }

    let tag = root.tag_name().name();
    let location = loc(root);
    let mut attributes = Vec::new();
    for a in root.attributes() {
        let value = substitute(a.value(), &values, &location, tag)?;
        attributes.push((a.name().to_string(), value));
    }
    let mut node = Node {
        tag: tag.to_string(),
        attributes,
        children: Vec::new(),
        location,
        dir: dir.to_path_buf(),
    };
    convert_children(root, &mut node, &values, &loc, dir, params, stack)?;
    Ok(node)
}

/// Replaces `$name` by its parameter value.
fn substitute(
    value: &str,
    values: &HashMap<String, String>,
    location: &Location,
    tag: &str,
) -> Result<String, SceneError> {
    if !value.contains('$') {
        return Ok(value.to_string());
    }
    let mut out = String::new();
    let mut rest = value;
    while let Some(i) = rest.find('$') {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        let end = after
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(after.len());
        let name = &after[..end];
        let v = values.get(name).ok_or_else(|| {
            SceneError::new(
                location,
                tag,
                format!("parameter '${name}' has no <default> and was not given"),
            )
        })?;
        out.push_str(v);
        rest = &after[end..];
    }
    out.push_str(rest);
    Ok(out)
}

#[allow(clippy::too_many_arguments)]
fn convert_children<'a>(
    element: roxmltree::Node<'a, 'a>,
    into: &mut Node,
    values: &HashMap<String, String>,
    loc: &dyn Fn(roxmltree::Node) -> Location,
    dir: &Path,
    params: &Parameters,
    stack: &mut Vec<PathBuf>,
) -> Result<(), SceneError> {
    for child in element.children().filter(|n| n.is_element()) {
        let tag = child.tag_name().name();
        let location = loc(child);
        if tag == "default" {
            continue;
        }
        let mut attributes = Vec::new();
        for a in child.attributes() {
            attributes.push((
                a.name().to_string(),
                substitute(a.value(), values, &location, tag)?,
            ));
        }
        if tag == "include" {
            let file = attributes
                .iter()
                .find(|(k, _)| k == "filename")
                .map(|(_, v)| v.clone())
                .ok_or_else(|| SceneError::new(&location, tag, "missing attribute 'filename'"))?;
            let included = parse_into(&dir.join(&file), params, stack, Some(&location))?;
            into.children.extend(included.children);
            continue;
        }
        let mut node = Node {
            tag: tag.to_string(),
            attributes,
            children: Vec::new(),
            location,
            dir: dir.to_path_buf(),
        };
        convert_children(child, &mut node, values, loc, dir, params, stack)?;
        into.children.push(node);
    }
    Ok(())
}
