//! One `<bsdf>` from XML text, built by the scene loader's own code (for
//! BSDF-level tests against another renderer, and for tools that look at
//! one material).

use std::path::Path;

use scotopia_render::bsdf::Bsdf;

use super::{bsdf, Builder};
use crate::mitsuba::{parse_str, Parameters, SceneError};

/// Builds the BSDF that `text` describes and returns it with the loader's
/// warnings. `text` is either one `<bsdf>` element (with nested BSDFs and
/// textures), or a `<scene>` whose top-level `<bsdf id>` and `<texture id>`
/// may be referred to and whose last top-level `<bsdf>` is built. Relative
/// file names resolve against the working directory.
pub fn bsdf_from_xml(text: &str) -> Result<(Bsdf, Vec<String>), SceneError> {
    let root = parse_str(text, "<string>", Path::new(""), &Parameters::new())?;
    let mut b = Builder::new();
    // A lone object comes back as the only child of a <scene>.
    let target = match root.children.as_slice() {
        [one] if one.tag != "bsdf" && one.tag != "texture" => {
            return Err(one.error(format!(
                "expected a <bsdf> (or a <scene> holding one), got <{}>",
                one.tag
            )))
        }
        _ => {
            b.collect_ids(&root);
            if let Some(e) = b.errors.first() {
                return Err(e.clone());
            }
            root.children
                .iter()
                .rev()
                .find(|n| n.tag == "bsdf")
                .cloned()
                .ok_or_else(|| root.error("the scene has no <bsdf>"))?
        }
    };
    // Through a reference when it has an id, so a cycle back to it is refused.
    let built = match target.attr("id") {
        Some(id) => {
            let id = id.to_string();
            b.resolve(&target, &id, |b| bsdf::build_bsdf(b, &target))?
        }
        None => bsdf::build_bsdf(&mut b, &target)?,
    };
    Ok((built, b.warnings))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builds_a_nested_bsdf() {
        let (b, warnings) = bsdf_from_xml(
            r#"<bsdf type="twosided"><bsdf type="diffuse">
                 <spectrum name="reflectance" value="0.3"/></bsdf></bsdf>"#,
        )
        .unwrap();
        assert!(matches!(b, Bsdf::TwoSided(ref inner) if matches!(**inner, Bsdf::Diffuse(_))));
        assert!(warnings.is_empty(), "{warnings:?}");
    }

    #[test]
    fn resolves_references_in_a_scene() {
        let (b, _) = bsdf_from_xml(
            r#"<scene version="3.0.0">
                 <bsdf type="diffuse" id="inner"/>
                 <bsdf type="twosided"><ref id="inner"/></bsdf>
               </scene>"#,
        )
        .unwrap();
        assert!(matches!(b, Bsdf::TwoSided(_)));
    }

    #[test]
    fn reports_unused_properties() {
        let (_, warnings) =
            bsdf_from_xml(r#"<bsdf type="diffuse"><float name="sheen" value="1"/></bsdf>"#)
                .unwrap();
        assert_eq!(warnings.len(), 1);
        assert!(warnings[0].contains("'sheen'"), "{warnings:?}");
    }

    #[test]
    fn errors_name_the_place() {
        let e = bsdf_from_xml("\n<bsdf type=\"velvet\"/>").unwrap_err();
        assert_eq!((e.location.line, e.location.column), (2, 1));
        assert!(e.message.contains("velvet"), "{e}");
        let e = bsdf_from_xml("<shape type=\"sphere\"/>").unwrap_err();
        assert!(e.message.contains("<bsdf>"), "{e}");
        let e = bsdf_from_xml("<bsdf type=\"diffuse\"").unwrap_err();
        assert_eq!(e.element, "xml");
    }
}
