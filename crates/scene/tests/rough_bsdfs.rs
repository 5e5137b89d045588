//! Rough BSDFs read as Mitsuba 3 reads them: `distribution` (Beckmann by
//! default), `alpha` or `alpha_u` + `alpha_v`, `sample_visible`.

use std::path::PathBuf;

use scotopia_render::bsdf::{Bsdf, MicrofacetDistribution, MicrofacetKind};
use scotopia_render::scene::Scene;
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn load(name: &str, bsdfs: &str) -> Result<Scene, String> {
    let dir = std::env::temp_dir().join(format!("scotopia-rough-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f: PathBuf = dir.join(format!("{name}.xml"));
    std::fs::write(
        &f,
        format!(
            "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n{bsdfs}\n</scene>"
        ),
    )
    .unwrap();
    load_scene(&f, &Parameters::new()).map_err(|e| e.to_string())
}

fn distribution(b: &Bsdf) -> MicrofacetDistribution {
    match b {
        Bsdf::Conductor(c) => c
            .distribution
            .as_ref()
            .and_then(|r| r.constant())
            .expect("rough"),
        Bsdf::RoughDielectric(d) => d.distribution.constant().expect("constant"),
        Bsdf::RoughPlastic(p) => p.distribution,
        other => panic!("not rough: {other:?}"),
    }
}

#[test]
fn distribution_and_roughness_follow_mitsuba() {
    let s = load(
        "ok",
        r#"<shape type="sphere"><bsdf type="roughconductor"/></shape>
<shape type="sphere"><bsdf type="roughconductor"><string name="distribution" value="GGX"/>
  <float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.3"/></bsdf></shape>
<shape type="sphere"><bsdf type="roughdielectric"><float name="alpha_u" value="0.2"/>
  <float name="alpha_v" value="0.4"/></bsdf></shape>
<shape type="sphere"><bsdf type="roughplastic"><string name="distribution" value="ggx"/>
  <float name="alpha" value="0.4"/></bsdf></shape>
<shape type="sphere"><bsdf type="roughplastic"><boolean name="sample_visible" value="false"/></bsdf></shape>"#,
    )
    .unwrap();
    let d: Vec<_> = s.materials.iter().map(distribution).collect();
    use MicrofacetKind::{Beckmann, Ggx};
    // Mitsuba's defaults: Beckmann, α = 0.1.
    assert_eq!(d[0], MicrofacetDistribution::isotropic(Beckmann, 0.1));
    assert_eq!(d[1], MicrofacetDistribution::new(Ggx, 0.05, 0.3));
    assert_eq!(d[2], MicrofacetDistribution::new(Beckmann, 0.2, 0.4));
    assert_eq!(d[3], MicrofacetDistribution::isotropic(Ggx, 0.4));
    assert_eq!(d[4], MicrofacetDistribution::isotropic(Beckmann, 0.1));
    // No warning for the default distribution; one for sample_visible.
    assert!(
        !s.warnings.iter().any(|w| w.contains("distribution")),
        "{:?}",
        s.warnings
    );
    assert_eq!(
        s.warnings
            .iter()
            .filter(|w| w.contains("sample_visible"))
            .count(),
        1,
        "{:?}",
        s.warnings
    );
    // Anisotropy follows the ∂p/∂u shading frame, as Mitsuba's: no warning.
    assert!(
        !s.warnings
            .iter()
            .any(|w| w.contains("anisotropic roughness")),
        "{:?}",
        s.warnings
    );
}

#[test]
fn unreadable_roughness_is_an_error_naming_the_place() {
    let cases = [
        (
            r#"<bsdf type="roughconductor"><float name="alpha" value="0.1"/><float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.2"/></bsdf>"#,
            "either 'alpha' or 'alpha_u' and 'alpha_v'",
        ),
        (
            r#"<bsdf type="roughdielectric"><float name="alpha_u" value="0.1"/></bsdf>"#,
            "give both 'alpha_u' and 'alpha_v'",
        ),
        (
            r#"<bsdf type="roughplastic"><float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.2"/></bsdf>"#,
            "anisotropic roughness",
        ),
        (
            r#"<bsdf type="roughplastic"><texture type="checkerboard" name="alpha"/></bsdf>"#,
            "a textured roughness ('alpha') is not supported by 'roughplastic'",
        ),
        (
            r#"<bsdf type="roughconductor"><float name="alpha" value="-0.1"/></bsdf>"#,
            "roughness must be positive",
        ),
        (
            r#"<bsdf type="roughplastic"><string name="distribution" value="phong"/></bsdf>"#,
            "invalid microfacet distribution 'phong'",
        ),
    ];
    for (i, (bsdf, needle)) in cases.into_iter().enumerate() {
        let e = load(
            &format!("bad{i}"),
            &format!("<shape type=\"sphere\">{bsdf}</shape>"),
        )
        .err()
        .unwrap_or_else(|| panic!("{bsdf} loaded"));
        assert!(e.contains(needle), "{bsdf}: {e}");
        assert!(e.contains(&format!("bad{i}.xml:")), "{bsdf}: {e}");
    }
}
