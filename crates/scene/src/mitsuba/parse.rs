//! Parse: a Mitsuba 3 XML file (and its includes) to a tree of plain nodes
//! that remember where they came from, with `<default>` parameters and
//! `$name` substitutions applied, and `<path>` folders collected into the
//! search path every node resolves its files with. Nothing here knows what
//! a BSDF is.

use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::error::{Location, SceneError};
use super::search::SearchPath;

/// One element: an object (`<bsdf type="diffuse">`), a property
/// (`<float name="alpha" value="0.1"/>`), or a transform operation.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    pub tag: String,
    /// Attributes after `$param` substitution, in document order.
    pub attributes: Vec<(String, String)>,
    pub children: Vec<Node>,
    pub location: Location,
    /// Where files this node names are looked for (`resolve(&node.dir, f)`).
    pub dir: Arc<SearchPath>,
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

/// The deepest nesting of elements read, counted from `<scene>` (an
/// included file's elements count from where it is included). Mitsuba
/// scenes nest a handful deep (scene → shape → bsdf → twosided's bsdf →
/// blend's bsdf → texture → transform's operation ≈ 7); 64 leaves room for
/// any real scene and stops a runaway one (thousands deep) long before the
/// stack would overflow in this parser or in the builders that walk the tree.
pub const MAX_DEPTH: usize = 64;

/// The longest chain of `<include>`s (a file including a file …). Real
/// scenes include one or two levels; 32 stops a runaway chain.
pub const MAX_INCLUDE_DEPTH: usize = 32;

/// The largest XML file (scene or include) read: Mitsuba XML holds
/// parameters and names mesh files, so even scenes of 100 000 objects are
/// tens of MiB; 256 MiB stops `/dev/zero` or a runaway file.
pub const XML_LIMIT: u64 = 256 * scotopia_color::io::MIB;

/// Command-line or API parameters (`-D name=value`), overriding `<default>`.
pub type Parameters = HashMap<String, String>;

/// A parsed scene: its root `<scene>` node and what parsing noticed.
#[derive(Debug, Clone)]
pub struct Parsed {
    pub root: Node,
    /// Parameters given that the scene does not declare or use.
    pub warnings: Vec<String>,
}

/// Reads `path` and the files it includes into the root `<scene>` node.
pub fn parse_file(path: &Path, params: &Parameters) -> Result<Node, SceneError> {
    parse_scene(path, params).map(|p| p.root)
}

/// State shared by a file and the files it includes.
struct Parser {
    /// Parameter values: those given, then `<default>`s in the order
    /// files are read, the first value of a name winning. One map for the
    /// scene and its includes, as Mitsuba's parser shares one list: an
    /// included file sees the including file's values and the other way.
    values: HashMap<String, String>,
    /// Files being read, innermost last, to refuse include cycles.
    stack: Vec<PathBuf>,
    /// `<path>` folders in document order.
    paths: Vec<PathBuf>,
    /// The scene file's folder.
    scene_dir: PathBuf,
    /// Parameter names the scene declares (`<default>`) or uses (`$name`).
    known: BTreeSet<String>,
}

impl Parser {
    /// Mitsuba's resolver list: `<path>` folders (last first), the scene's
    /// folder, the working directory; then (scotopia) `own`, the folder of
    /// the file an element is written in.
    fn search(&self, own: Option<&Path>) -> SearchPath {
        let mut folders: Vec<PathBuf> = self.paths.iter().rev().cloned().collect();
        folders.push(self.scene_dir.clone());
        if let Ok(cwd) = std::env::current_dir() {
            folders.push(cwd);
        }
        if let Some(own) = own {
            if !folders.iter().any(|f| f == own) {
                folders.push(own.to_path_buf());
            }
        }
        SearchPath::new(folders)
    }
}

/// Reads `path` and its includes, and reports parameters it ignores.
pub fn parse_scene(path: &Path, params: &Parameters) -> Result<Parsed, SceneError> {
    let scene_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut parser = Parser {
        values: params.clone(),
        stack: Vec::new(),
        paths: Vec::new(),
        scene_dir,
        known: BTreeSet::new(),
    };
    let mut root = parser.file(path, None, 1)?;
    root.tag = "scene".into();
    // Every node resolves files with the final search path (plugins
    // resolve after parsing in Mitsuba too, so `<path>` applies to all).
    let mut cache: HashMap<Vec<PathBuf>, Arc<SearchPath>> = HashMap::new();
    set_search(&mut root, &parser, &mut cache);

    let mut unknown: Vec<&String> = params
        .keys()
        .filter(|k| !parser.known.contains(*k))
        .collect();
    unknown.sort();
    let warnings = unknown
        .into_iter()
        .map(|k| {
            let declared = if parser.known.is_empty() {
                "it has none".to_string()
            } else {
                let names: Vec<&str> = parser.known.iter().map(String::as_str).collect();
                format!("its parameters are {}", names.join(", "))
            };
            format!(
                "{}: parameter '{k}' is not used by the scene ({declared}); ignored",
                path.display()
            )
        })
        .collect();
    Ok(Parsed { root, warnings })
}

/// Replaces each node's provisional folder by the full search path.
fn set_search(
    node: &mut Node,
    parser: &Parser,
    cache: &mut HashMap<Vec<PathBuf>, Arc<SearchPath>>,
) {
    let own = node.dir.folders().to_vec();
    let search = cache
        .entry(own.clone())
        .or_insert_with(|| Arc::new(parser.search(own.first().map(PathBuf::as_path))))
        .clone();
    node.dir = search;
    for c in &mut node.children {
        set_search(c, parser, cache);
    }
}

fn io_error(path: &Path, from: Option<&Location>, e: std::io::Error) -> SceneError {
    let location = from.cloned().unwrap_or(Location {
        file: path.display().to_string(),
        line: 0,
        column: 0,
        via: None,
    });
    let element = if from.is_some() { "include" } else { "scene" };
    SceneError::new(
        &location,
        element,
        format!("cannot read {}: {e}", path.display()),
    )
}

impl Parser {
    /// One file: its root's children (or, for an included file whose root
    /// is a single object, that object) under a `<scene>` node; `depth`:
    /// how deep its root's children are nested in the scene.
    fn file(
        &mut self,
        path: &Path,
        from: Option<&Location>,
        depth: usize,
    ) -> Result<Node, SceneError> {
        let canonical = path.canonicalize().map_err(|e| io_error(path, from, e))?;
        let refused = if self.stack.contains(&canonical) {
            Some(format!("{} includes itself", path.display()))
        } else if self.stack.len() >= MAX_INCLUDE_DEPTH {
            Some(format!(
                "includes are nested more than {MAX_INCLUDE_DEPTH} files deep"
            ))
        } else {
            None
        };
        if let Some(message) = refused {
            let location = from.cloned().unwrap_or_else(|| Location {
                file: path.display().to_string(),
                line: 0,
                column: 0,
                via: None,
            });
            let chain: Vec<String> = self
                .stack
                .iter()
                .map(|p| p.display().to_string())
                .chain(std::iter::once(canonical.display().to_string()))
                .collect();
            return Err(SceneError::new(
                &location,
                "include",
                format!("{message} ({})", chain.join(" → ")),
            ));
        }
        let text = scotopia_color::io::read_text_limited(path, XML_LIMIT)
            .map_err(|e| io_error(path, from, e))?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        self.stack.push(canonical);
        let file = path.display().to_string();
        let via = from.cloned().map(Arc::new);
        let scene = self.text(&text, &file, &dir, via.is_some(), via, depth);
        self.stack.pop();
        scene
    }

    /// XML `text` (called `file` in error locations, included at `via`)
    /// whose relative paths resolve against `dir`: its root's children
    /// (or, when `fragment`, a root that is a single object, kept) under a
    /// `<scene>` node.
    fn text(
        &mut self,
        text: &str,
        file: &str,
        dir: &Path,
        fragment: bool,
        via: Option<Arc<Location>>,
        depth: usize,
    ) -> Result<Node, SceneError> {
        let file = file.to_string();
        let doc = roxmltree::Document::parse(text).map_err(|e| {
            let pos = e.pos();
            SceneError::new(
                &Location {
                    file: file.clone(),
                    line: pos.row,
                    column: pos.col,
                    via: via.clone(),
                },
                "xml",
                e.to_string(),
            )
        })?;
        let root = doc.root_element();
        // Line starts, found once: roxmltree's `text_pos_at` scans from the
        // file's start on every call, quadratic in a file of many elements
        // (a forest of 37 000 instances took minutes).
        let line_starts: Vec<usize> = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        let loc = |n: roxmltree::Node| {
            let at = n.range().start;
            let line = line_starts.partition_point(|&s| s <= at);
            let start = line_starts[line - 1];
            Location {
                file: file.clone(),
                line: line as u32,
                column: text[start..at].chars().count() as u32 + 1,
                via: via.clone(),
            }
        };
        let is_scene = root.tag_name().name() == "scene";
        if !is_scene && !fragment {
            return Err(SceneError::new(
                &loc(root),
                root.tag_name().name(),
                "the root element must be <scene>",
            ));
        }
        // This file's defaults (anywhere at its top level) fill the gaps.
        for n in root
            .children()
            .filter(|n| n.is_element() && n.tag_name().name() == "default")
        {
            let name = n.attribute("name");
            let value = n.attribute("value");
            match (name, value) {
                (Some(k), Some(v)) => {
                    self.known.insert(k.to_string());
                    self.values
                        .entry(k.to_string())
                        .or_insert_with(|| v.to_string());
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

        let own = Arc::new(SearchPath::single(dir));
        let mut scene = Node {
            tag: "scene".into(),
            attributes: root
                .attributes()
                .map(|a| (a.name().to_string(), a.value().to_string()))
                .collect(),
            children: Vec::new(),
            location: loc(root),
            dir: own.clone(),
        };
        let context = FileContext {
            loc: &loc,
            dir,
            own: &own,
        };
        if is_scene {
            self.children(root, &mut scene, &context, true, depth)?;
        } else {
            // An included fragment that is one object: keep the object.
            let mut holder = Node {
                children: Vec::new(),
                ..scene.clone()
            };
            self.element(root, &mut holder, &context, false, depth)?;
            scene.children = holder.children;
        }
        Ok(scene)
    }
}

/// Parses XML `text` (called `name` in error locations) whose root is a
/// `<scene>` or one object, e.g. a `<bsdf>`, returned as a `<scene>` node
/// holding it; relative paths and includes resolve against `dir`.
pub fn parse_str(
    text: &str,
    name: &str,
    dir: &Path,
    params: &Parameters,
) -> Result<Node, SceneError> {
    let mut parser = Parser {
        values: params.clone(),
        stack: Vec::new(),
        paths: Vec::new(),
        scene_dir: dir.to_path_buf(),
        known: BTreeSet::new(),
    };
    let mut root = parser.text(text, name, dir, true, None, 1)?;
    let mut cache = HashMap::new();
    set_search(&mut root, &parser, &mut cache);
    Ok(root)
}

/// What the elements of one file share while they are converted.
struct FileContext<'a> {
    loc: &'a dyn Fn(roxmltree::Node) -> Location,
    dir: &'a Path,
    own: &'a Arc<SearchPath>,
}

impl Parser {
    /// Replaces `$name` by its parameter value.
    fn substitute(
        &mut self,
        value: &str,
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
            self.known.insert(name.to_string());
            let v = self.values.get(name).ok_or_else(|| {
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

    fn children(
        &mut self,
        element: roxmltree::Node,
        into: &mut Node,
        cx: &FileContext,
        top: bool,
        depth: usize,
    ) -> Result<(), SceneError> {
        for child in element.children().filter(|n| n.is_element()) {
            self.element(child, into, cx, top, depth)?;
        }
        Ok(())
    }

    /// Converts `child` (and its subtree) into `into`'s children; `top`
    /// when `into` is the file's root; `depth`: `child`'s nesting below
    /// `<scene>` (1 for its children).
    fn element(
        &mut self,
        child: roxmltree::Node,
        into: &mut Node,
        cx: &FileContext,
        top: bool,
        depth: usize,
    ) -> Result<(), SceneError> {
        let tag = child.tag_name().name();
        let location = (cx.loc)(child);
        if tag == "default" {
            return Ok(());
        }
        if depth > MAX_DEPTH {
            return Err(SceneError::new(
                &location,
                tag,
                format!(
                    "elements are nested more than {MAX_DEPTH} deep (Mitsuba scenes nest a \
                     handful deep; is an element not closed where it should be?)"
                ),
            ));
        }
        let mut attributes = Vec::new();
        for a in child.attributes() {
            attributes.push((
                a.name().to_string(),
                self.substitute(a.value(), &location, tag)?,
            ));
        }
        let attr = |name: &str| {
            attributes
                .iter()
                .find(|(k, _)| k == name)
                .map(|(_, v)| v.clone())
                .ok_or_else(|| {
                    SceneError::new(&location, tag, format!("missing attribute '{name}'"))
                })
        };
        match tag {
            "include" => {
                // Mitsuba: the including file's folder first, then the
                // resolver as it stands.
                let file = attr("filename")?;
                let mut search = vec![cx.dir.to_path_buf()];
                search.extend(self.search(None).folders().iter().cloned());
                let path = SearchPath::new(search).resolve(&file);
                let included = self.file(&path, Some(&location), depth)?;
                into.children.extend(included.children);
                return Ok(());
            }
            "path" => {
                if !top {
                    return Err(SceneError::new(
                        &location,
                        tag,
                        "<path> must be a child of <scene>",
                    ));
                }
                let value = attr("value")?;
                let mut folder = cx.dir.join(&value);
                if !folder.is_dir() {
                    folder = self.search(None).resolve(&value);
                }
                if !folder.is_dir() {
                    return Err(SceneError::new(
                        &location,
                        tag,
                        format!("folder {value} not found (looked in {})", cx.dir.display()),
                    ));
                }
                self.paths.push(folder);
                return Ok(());
            }
            _ => {}
        }
        let mut node = Node {
            tag: tag.to_string(),
            attributes,
            children: Vec::new(),
            location,
            dir: cx.own.clone(),
        };
        self.children(child, &mut node, cx, false, depth + 1)?;
        into.children.push(node);
        Ok(())
    }
}
