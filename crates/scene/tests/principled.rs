//! Loading `principled` and `principledthin`: their parameters, Mitsuba's
//! lobe flags (absent or 0 switches a lobe off), `specular` → η, and the
//! error for both `eta` and `specular`.

use std::path::PathBuf;

use scotopia_render::bsdf::{specular_to_eta, Bsdf};
use scotopia_render::texture::FloatTexture;
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn write_scene(name: &str, body: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-principled-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let f = d.join(format!("{name}.xml"));
    std::fs::write(
        &f,
        format!("<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n<shape type=\"rectangle\">{body}</shape>\n</scene>"),
    )
    .unwrap();
    f
}

fn load(name: &str, body: &str) -> Result<(Bsdf, Vec<String>), String> {
    let s = load_scene(&write_scene(name, body), &Parameters::new()).map_err(|e| e.to_string())?;
    let warnings = s.warnings.iter().map(|w| w.to_string()).collect();
    Ok((s.materials[0].clone(), warnings))
}

#[test]
fn principled_reads_its_parameters_and_flags() {
    let (bsdf, warnings) = load(
        "principled",
        r#"<bsdf type="principled">
            <rgb name="base_color" value="0.8, 0.2, 0.1"/>
            <float name="metallic" value="0.7"/>
            <float name="specular" value="0.6"/>
            <float name="roughness" value="0.2"/>
            <float name="spec_tint" value="0.4"/>
            <float name="anisotropic" value="0.5"/>
            <float name="sheen" value="0"/>
            <float name="clearcoat" value="0.6"/>
            <float name="clearcoat_gloss" value="0.3"/>
            <float name="spec_trans" value="0.4"/>
            <float name="clearcoat_sampling_rate" value="2"/>
        </bsdf>"#,
    )
    .unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let Bsdf::Principled(p) = bsdf else {
        panic!("{bsdf:?}")
    };
    assert_eq!(p.metallic, Some(FloatTexture::Constant(0.7)));
    assert_eq!(p.roughness, FloatTexture::Constant(0.2));
    assert_eq!(p.anisotropic, Some(FloatTexture::Constant(0.5)));
    // sheen 0 switches the lobe off, as Mitsuba's get_flag does.
    assert_eq!(p.sheen, None);
    assert_eq!(p.sheen_tint, None);
    assert_eq!(p.clearcoat_gloss, FloatTexture::Constant(0.3));
    assert_eq!(p.eta, specular_to_eta(0.6));
    assert_eq!(p.rates.clearcoat, 2.0);
}

#[test]
fn principled_eta_and_specular_together_are_an_error() {
    let e = load(
        "both",
        r#"<bsdf type="principled"><float name="eta" value="1.4"/><float name="specular" value="0.5"/></bsdf>"#,
    )
    .unwrap_err();
    assert!(
        e.contains("'eta' or 'specular'") && e.contains("both.xml"),
        "{e}"
    );
    // An index-matched transmitting interface is nudged, as in Mitsuba.
    let (bsdf, _) = load(
        "matched",
        r#"<bsdf type="principled"><float name="eta" value="1"/><float name="spec_trans" value="1"/></bsdf>"#,
    )
    .unwrap();
    let Bsdf::Principled(p) = bsdf else { panic!() };
    assert_eq!(p.eta, 1.001);
}

#[test]
fn principledthin_reads_its_parameters() {
    let (bsdf, warnings) = load(
        "thin",
        r#"<bsdf type="principledthin">
            <rgb name="base_color" value="0.8, 0.2, 0.1"/>
            <float name="eta" value="1.3"/>
            <float name="diff_trans" value="0.6"/>
            <float name="spec_trans" value="0.5"/>
            <float name="flatness" value="0.2"/>
        </bsdf>"#,
    )
    .unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let Bsdf::PrincipledThin(p) = bsdf else {
        panic!("{bsdf:?}")
    };
    assert_eq!(p.eta, FloatTexture::Constant(1.3));
    assert_eq!(p.diff_trans, Some(FloatTexture::Constant(0.6)));
    assert_eq!(p.spec_trans, Some(FloatTexture::Constant(0.5)));
    assert_eq!(p.flatness, Some(FloatTexture::Constant(0.2)));
    assert_eq!(p.anisotropic, None);
}
