//! Elements no builder reads, warned about with their location: an unknown
//! tag (`<foo name="fov" …/>`), or an object where scotopia takes none of
//! its kind (`<bsdf name="fov">` in a `<sensor>`, a `<film>` in a `<shape>`).
//! Without this they would be dropped without a word and the default used.
//! (Properties of a known tag that are never read are reported by
//! `Builder::report_unused`; top-level elements by `World::add`; media by
//! `warn_media`.)

use super::Builder;
use crate::mitsuba::Node;
use crate::mitsuba::PROPERTY_TAGS;

/// Mitsuba's object tags that scotopia reads, and the objects each holds
/// that some builder reads. `medium` is left to `warn_media`.
const HOLDS: [(&str, &[&str]); 8] = [
    ("sensor", &["film", "sampler"]),
    ("film", &["rfilter"]),
    ("shape", &["bsdf", "emitter", "shape", "sensor"]),
    ("bsdf", &["bsdf"]),
    ("emitter", &[]),
    ("integrator", &["integrator"]),
    ("sampler", &[]),
    ("rfilter", &[]),
];

/// Objects of which a holder reads one (the last given).
const ONE_EACH: [(&str, &[&str]); 2] = [("sensor", &["film", "sampler"]), ("film", &["rfilter"])];

/// Mitsuba's object tags scotopia never reads nested (phase functions and
/// volumes belong to media), so they are named as objects, not unknown.
const OTHER_OBJECTS: [&str; 2] = ["phase", "volume"];

/// Warns once for each element under the top-level objects that no
/// builder reads.
pub fn warn_unread(b: &mut Builder, root: &Node) {
    for n in &root.children {
        walk(b, n);
    }
}

/// Whether a BSDF or integrator of this type reads the nested one of its
/// own kind (a `diffuse` holding a `<bsdf>` does not: the inner one would
/// be dropped without a word).
fn takes_nested(node: &Node) -> bool {
    let kind = node.attr("type").unwrap_or("");
    match node.tag.as_str() {
        "bsdf" => ["twosided", "mask", "blendbsdf", "normalmap", "bumpmap"].contains(&kind),
        "integrator" => super::integrator::WRAPPERS.contains(&kind),
        _ => true,
    }
}

fn walk(b: &mut Builder, node: &Node) {
    // A transform's operations are read (or refused) by `read_transform`;
    // a medium's contents are warned about with the medium.
    if node.tag == "transform" || node.tag == "medium" {
        return;
    }
    let holds = HOLDS
        .iter()
        .find(|(tag, _)| *tag == node.tag)
        .map(|(_, h)| *h)
        .map(|h| if takes_nested(node) { h } else { &[][..] });
    let mut seen: Vec<&Node> = Vec::new();
    for c in &node.children {
        let tag = c.tag.as_str();
        if ONE_EACH
            .iter()
            .any(|(holder, kinds)| *holder == node.tag && kinds.contains(&tag))
        {
            if let Some(first) = seen.iter().find(|f| f.tag == tag) {
                b.warn(
                    c,
                    format!(
                        "a <{}> takes one <{tag}>: this one replaces the one at {}",
                        node.tag, first.location
                    ),
                );
            }
            seen.push(c);
        }
        let is_object = HOLDS.iter().any(|(t, _)| *t == tag) || OTHER_OBJECTS.contains(&tag);
        let named = c
            .attr("name")
            .map(|n| format!(" (named '{n}')"))
            .unwrap_or_default();
        // A `<ref>` is an object given as a property.
        if PROPERTY_TAGS.contains(&tag) || tag == "ref" || tag == "medium" {
            walk(b, c);
        } else if !is_object {
            b.warn(
                c,
                format!("unknown element <{tag}>{named} is not read by scotopia; ignored"),
            );
        } else if holds.is_some_and(|h| h.contains(&tag)) {
            walk(b, c);
        } else {
            b.warn(
                c,
                format!(
                    "a <{tag}>{named} in a <{}> is not read by scotopia; ignored",
                    node.tag
                ),
            );
        }
    }
}
