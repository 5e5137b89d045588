//! A ray through a prism of a named glass, refracted by the dielectric
//! BSDF face by face: its deviation at the F, D and C lines matches
//! Snell's law with the glass's index, and with the catalogue's, to 0.1°.

use scotopia_color::{SampledWavelengths, Spectrum};
use scotopia_render::bsdf::{Dielectric, Ior, Transport};
use scotopia_render::math::{Frame, Vec3};
use scotopia_render::texture::Texture;
use scotopia_scene::materials::named_glass;

/// The deviation (degrees) of a ray meeting the first face at `incidence`
/// degrees, traced through the BSDF at wavelength `lambda`.
fn traced_deviation(glass: &Dielectric, apex: f32, incidence: f32, lambda: f32) -> f32 {
    let half = (apex / 2.0).to_radians();
    // Apex up, faces symmetric about y: outward normals of the faces.
    let n1 = Vec3::new(-half.cos(), half.sin(), 0.0);
    let n2 = Vec3::new(half.cos(), half.sin(), 0.0);
    // The incoming ray, `incidence` from the first face's inward normal,
    // turned towards the apex.
    let a = incidence.to_radians() - half;
    let d0 = Vec3::new(a.cos(), a.sin(), 0.0);
    let wl = SampledWavelengths::<1>::new([lambda], [1.0]);
    let refract = |n: Vec3, d: Vec3| -> Vec3 {
        let frame = Frame::from_normal(n);
        // u just below 1: always the refracted lobe.
        let s = glass
            .sample(
                &wl,
                [0.0, 0.0].into(),
                frame.to_local(-d),
                0.9999,
                Transport::Radiance,
            )
            .expect("a refraction");
        assert!(s.collapse, "a dispersive glass collapses the cluster");
        frame.to_world(s.wo)
    };
    let inside = refract(n1, d0);
    let out = refract(n2, inside);
    d0.dot(out).clamp(-1.0, 1.0).acos().to_degrees()
}

/// Snell's law at both faces: δ = θ1 + θ2′ − A.
fn snell_deviation(n: f64, apex: f64, incidence: f64) -> f64 {
    let t1 = incidence.to_radians();
    let r1 = (t1.sin() / n).asin();
    let r2 = apex.to_radians() - r1;
    let t2 = (n * r2.sin()).asin();
    (t1 + t2).to_degrees() - apex
}

fn glass(name: &str) -> Dielectric {
    Dielectric {
        ior: Ior {
            interior: named_glass(name).unwrap(),
            exterior: Spectrum::Constant(1.0),
        },
        specular_reflectance: Texture::constant(1.0),
        specular_transmittance: Texture::constant(1.0),
    }
}

#[test]
fn prism_deviation_follows_snell_with_the_glass_index() {
    // At the hydrogen F and C and sodium D lines, with the glass's own
    // (Sellmeier) index at each.
    for name in ["bk7", "sf11", "fused silica", "diamond"] {
        let g = glass(name);
        let n = named_glass(name).unwrap();
        // Diamond's index passes 2: a 30° prism keeps it out of total
        // internal reflection.
        let apex = if name == "diamond" { 30.0 } else { 60.0 };
        let mut last = f32::INFINITY;
        for lambda in [486.1f32, 589.3, 656.3] {
            let got = traced_deviation(&g, apex, 55.0, lambda);
            let want = snell_deviation(n.eval(lambda) as f64, apex as f64, 55.0);
            assert!(
                (got as f64 - want).abs() < 0.1,
                "{name} at {lambda} nm: {got}° vs {want}°"
            );
            // Blue is bent most.
            assert!(got < last, "{name}");
            last = got;
        }
    }
}

#[test]
fn prism_deviation_matches_catalogue_indices() {
    // Independent of the Sellmeier data: the SCHOTT data sheets' indices
    // at F (486.13 nm), d (587.56 nm) and C (656.27 nm): N-BK7 1.52238,
    // 1.51680, 1.51432; SF11 1.80645, 1.78472, 1.77599.
    let lines = [486.13f32, 587.56, 656.27];
    for (name, indices) in [
        ("bk7", [1.52238, 1.51680, 1.51432]),
        ("sf11", [1.80645, 1.78472, 1.77599]),
    ] {
        let g = glass(name);
        for (lambda, n) in lines.iter().zip(indices) {
            let got = traced_deviation(&g, 60.0, 55.0, *lambda);
            let want = snell_deviation(n, 60.0, 55.0);
            assert!(
                (got as f64 - want).abs() < 0.1,
                "{name} at {lambda} nm: {got}° vs {want}°"
            );
        }
    }
}
