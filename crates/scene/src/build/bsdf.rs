//! `<bsdf>` elements.

use std::sync::Arc;

use scotopia_color::{io, Spectrum};
use scotopia_render::bsdf::{
    Bsdf, Conductor, Dielectric, Diffuse, Donaldson, Fluorescent, Ior, Plastic, RoadSurface,
    RoughDielectric, RoughPlastic, ThinDielectric,
};
use scotopia_render::texture::Texture;

use super::bsdf_nested::{self, NESTED_TYPES};
use super::ior::read_ior;
use super::roughness::{roughness, textured_roughness, Anisotropy};
use super::Builder;
use crate::materials::{named_conductor, CONDUCTOR_NAMES};
use crate::mitsuba::{resolve, Node, Props, SceneError, Usage};

pub fn build_bsdf(b: &mut Builder, node: &Node) -> Result<Bsdf, SceneError> {
    let kind = node.require("type")?;
    let p = Props::new(node);
    let bsdf = match kind {
        "diffuse" => Bsdf::Diffuse(Diffuse {
            reflectance: b.texture(&p, "reflectance", Usage::Reflectance, 0.5)?,
        }),
        "conductor" | "roughconductor" => {
            let distribution = if kind == "roughconductor" {
                Some(textured_roughness(b, &p, node)?)
            } else {
                None
            };
            let (eta, k) = match (
                p.spectrum("eta", Usage::Unbounded)?,
                p.spectrum("k", Usage::Unbounded)?,
            ) {
                (Some(e), Some(k)) => (e, k),
                (None, None) => {
                    let name = p.string("material")?.unwrap_or("none");
                    if name == "none" {
                        // Mitsuba's "none": a perfect mirror (η = 0, κ = 1 gives R = 1).
                        (Spectrum::Constant(0.0), Spectrum::Constant(1.0))
                    } else {
                        named_conductor(name).ok_or_else(|| {
                            node.error(format!(
                                "unknown conductor '{name}' (known: none, {})",
                                CONDUCTOR_NAMES.join(", ")
                            ))
                        })?
                    }
                }
                _ => return Err(node.error("give both 'eta' and 'k', or a 'material'")),
            };
            Bsdf::Conductor(Conductor {
                eta,
                k,
                specular_reflectance: b.texture(
                    &p,
                    "specular_reflectance",
                    Usage::Reflectance,
                    1.0,
                )?,
                distribution,
            })
        }
        "dielectric" | "roughdielectric" | "thindielectric" => {
            let ior = Ior {
                interior: read_ior(&p, "int_ior", "bk7")?,
                exterior: read_ior(&p, "ext_ior", "air")?,
            };
            let sr = b.texture(&p, "specular_reflectance", Usage::Reflectance, 1.0)?;
            let st = b.texture(&p, "specular_transmittance", Usage::Reflectance, 1.0)?;
            match kind {
                "dielectric" => Bsdf::Dielectric(Dielectric {
                    ior,
                    specular_reflectance: sr,
                    specular_transmittance: st,
                }),
                "thindielectric" => Bsdf::ThinDielectric(ThinDielectric {
                    ior,
                    specular_reflectance: sr,
                    specular_transmittance: st,
                }),
                _ => Bsdf::RoughDielectric(RoughDielectric {
                    distribution: textured_roughness(b, &p, node)?,
                    ior,
                    specular_reflectance: sr,
                    specular_transmittance: st,
                }),
            }
        }
        "plastic" | "roughplastic" => {
            // The coating model takes one index: the interior over exterior at 550 nm.
            let int = read_ior(&p, "int_ior", "polypropylene")?.eval(550.0);
            let ext = read_ior(&p, "ext_ior", "air")?.eval(550.0);
            let diffuse = b.texture(&p, "diffuse_reflectance", Usage::Reflectance, 0.5)?;
            let specular = b.texture(&p, "specular_reflectance", Usage::Reflectance, 1.0)?;
            let nonlinear = p.boolean("nonlinear", false)?;
            if kind == "plastic" {
                Bsdf::Plastic(Plastic::new(diffuse, specular, int / ext, nonlinear))
            } else {
                let distribution = roughness(b, &p, node, Anisotropy::Refused)?;
                Bsdf::RoughPlastic(RoughPlastic::new(
                    diffuse,
                    specular,
                    int / ext,
                    distribution,
                    nonlinear,
                ))
            }
        }
        "fluorescent" => fluorescent(b, &p, node)?,
        "roadsurface" => road_surface(&p, node)?,
        "twosided" => {
            let inner: Vec<&Node> = node
                .children
                .iter()
                .filter(|c| c.tag == "bsdf" || c.tag == "ref")
                .collect();
            match inner.as_slice() {
                [one] => Bsdf::TwoSided(Box::new(b.bsdf_child(one)?)),
                _ => return Err(node.error("twosided needs exactly one nested <bsdf> or <ref>")),
            }
        }
        nested if NESTED_TYPES.contains(&nested) => bsdf_nested::build(b, nested, &p, node)?,
        other => return Err(node.error(format!("BSDF type '{other}' is not supported"))),
    };
    b.report_unused(&p);
    Ok(bsdf)
}

/// scotopia's `<bsdf type="roadsurface">`: a CIE r-table `class` (R1–R4,
/// C1, C2; R3 when not given), an optional `q0` and `reflectance`
/// spectrum for its colour.
fn road_surface(p: &Props, node: &Node) -> Result<Bsdf, SceneError> {
    let class = p.string("class")?.unwrap_or("R3");
    let q0 = match p.get("q0") {
        Some(_) => {
            let q0 = p.float("q0", f32::NAN)?;
            if !(q0 > 0.0 && q0.is_finite()) {
                return Err(node.error(format!("q0 {q0} is not a positive number")));
            }
            Some(q0)
        }
        None => None,
    };
    let tint = p.spectrum("reflectance", Usage::Reflectance)?;
    let has_tint = tint.is_some();
    let road = RoadSurface::new(class, q0, tint).ok_or_else(|| {
        if has_tint && RoadSurface::new(class, q0, None).is_some() {
            node.error("the road's reflectance reflects no light the eye sees")
        } else {
            node.error(format!(
                "unknown road surface class '{class}' (R1, R2, R3, R4, C1, C2)"
            ))
        }
    })?;
    Ok(Bsdf::Road(Box::new(road)))
}

/// `<bsdf type="fluorescent">`: elastic `reflectance` (spectrum or
/// texture) and either `excitation` (the fraction absorbed for
/// re-emission), `emission` (its shape, normalised here) and
/// `quantum_yield` (photons out per photon absorbed, default 1), or a
/// measured reradiation `matrix` (a CSV file; its diagonal is the
/// reflectance unless `reflectance` is given).
fn fluorescent(b: &mut Builder, p: &Props, node: &Node) -> Result<Bsdf, SceneError> {
    if let Some(file) = p.string("matrix")? {
        return fluorescent_matrix(b, p, node, file);
    }
    let reflectance = b.texture(p, "reflectance", Usage::Reflectance, 0.0)?;
    let excitation = p
        .spectrum("excitation", Usage::Reflectance)?
        .ok_or_else(|| {
            node.error("a fluorescent BSDF needs an 'excitation' spectrum (or a 'matrix')")
        })?;
    let emission = p
        .spectrum("emission", Usage::Unbounded)?
        .ok_or_else(|| node.error("a fluorescent BSDF needs an 'emission' spectrum"))?;
    let q = p.float("quantum_yield", 1.0)?;
    if !(0.0..=1.0).contains(&q) {
        return Err(node.error(format!(
            "quantum_yield {q}: a ratio of photons, between 0 and 1"
        )));
    }
    // Light reflected and light absorbed for re-emission cannot exceed
    // the light arriving.
    check_energy(
        &reflectance,
        excitation.breakpoints(),
        |l| excitation.eval(l),
        |l, total| {
            node.error(format!(
                "reflectance + excitation is {total:.4} at {l} nm: it must not exceed 1"
            ))
        },
    )?;
    let bsdf = Fluorescent::new(reflectance, &excitation, &emission, q)
        .ok_or_else(|| node.error("the 'emission' spectrum has no positive value in 360–830 nm"))?;
    Ok(Bsdf::Fluorescent(bsdf))
}

fn fluorescent_matrix(
    b: &mut Builder,
    p: &Props,
    node: &Node,
    file: &str,
) -> Result<Bsdf, SceneError> {
    for name in ["excitation", "emission", "quantum_yield"] {
        if let Some(n) = p.get(name) {
            return Err(n.error(format!(
                "'{name}' and 'matrix' are two descriptions of the same reradiation: give one"
            )));
        }
    }
    let at = p.get("matrix").unwrap_or(node);
    let path = resolve(&node.dir, file);
    let m = io::read_matrix_file(&path).map_err(|e| at.error(e.to_string()))?;
    let (matrix, negative) = Donaldson::new(&m.excitation, &m.emission, &m.values)
        .map_err(|e| at.error(format!("{}: {e}", path.display())))?;
    if negative > 0 {
        b.warn(
            at,
            format!(
                "{}: {negative} negative cells (measurement noise) count as zero",
                path.display()
            ),
        );
    }
    if m.excitation[0] < scotopia_color::LAMBDA_MIN {
        b.warn(
            at,
            format!(
                "{}: excitation below {} nm is outside scotopia's wavelength range; \
                 those columns are ignored",
                path.display(),
                scotopia_color::LAMBDA_MIN
            ),
        );
    }
    let reflectance = match (p.get("reflectance"), matrix.diagonal()) {
        (Some(_), _) => b.texture(p, "reflectance", Usage::Reflectance, 0.0)?,
        (None, Some(d)) => Texture::Constant(d.clone()),
        (None, None) => {
            return Err(at.error(format!(
                "{}: not every emission wavelength has an equal excitation wavelength, so \
                 the diagonal cannot give the reflectance: add a 'reflectance'",
                path.display()
            )))
        }
    };
    check_energy(
        &reflectance,
        &[],
        |l| matrix.reemitted(l),
        |l, total| {
            at.error(format!(
                "{}: reflectance plus the light re-emitted from {l} nm is {total:.4} of what \
             arrives: it must not exceed 1",
                path.display()
            ))
        },
    )?;
    Ok(Bsdf::Fluorescent(Fluorescent::from_matrix(
        reflectance,
        Arc::new(matrix),
    )))
}

/// Refuses a material that sends back more light than arrives: the
/// largest reflectance over the surface plus `taken(λ)` must not exceed 1
/// (checked every nm; every 5 nm over a texture's texels, whose upsampled
/// spectra are smooth; and at the samples of every tabulated spectrum
/// involved, where a spike between grid points has its maximum).
fn check_energy(
    reflectance: &Texture,
    breakpoints: &[f32],
    taken: impl Fn(f32) -> f32,
    error: impl Fn(u32, f32) -> SceneError,
) -> Result<(), SceneError> {
    let step = if reflectance.is_varying() { 5 } else { 1 };
    let mut lambdas: Vec<f32> = (360..=830).step_by(step).map(|l| l as f32).collect();
    lambdas.extend(breakpoints);
    reflectance.breakpoints(&mut lambdas);
    lambdas.retain(|l| (360.0..=830.0).contains(l));
    let rho = reflectance.max_over_surface(&lambdas);
    for (&l, r) in lambdas.iter().zip(rho) {
        let total = r + taken(l);
        if total > 1.0 + 1e-3 {
            return Err(error(l as u32, total));
        }
    }
    Ok(())
}
