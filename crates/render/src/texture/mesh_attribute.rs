//! Mitsuba 3's `mesh_attribute` texture (src/textures/mesh_attribute.cpp,
//! `Mesh::eval_attribute`): a mesh's named attribute at the hit, times
//! `scale` — a `vertex_*` attribute blended over the triangle by the
//! hit's barycentric weights, a `face_*` attribute the face's own record.
//!
//! As in Mitsuba's spectral variants (3.9): a 3-number attribute whose
//! name contains "color" is an RGB colour, upsampled per record when the
//! scene is loaded (the Jakob & Hanika 2019 sigmoid, as `bitmap` texels)
//! and blended as spectra, since the upsampling is not linear; a 1-number
//! attribute is a grey value; any other 3-number attribute reads as its
//! luminance (Mitsuba's later versions; 3.9 misreads it as sigmoid
//! coefficients). The texture is bound to one mesh: a material shared by
//! several meshes gets one copy per mesh.

use scotopia_color::spectrum::normalised_lambda;
use scotopia_color::{RgbSpace, SampledSpectrum, SampledWavelengths, SpectrumKind};

use super::bitmap::Texel;
use super::{luminance, TexPoint};
use crate::geometry::{Attribute, TriangleMesh};

#[derive(Debug, Clone, PartialEq)]
pub struct MeshAttribute {
    /// Each face's vertex indices, for a per-vertex attribute; `None`
    /// for a per-face one.
    faces: Option<Vec<[u32; 3]>>,
    values: Values,
    scale: f32,
}

#[derive(Debug, Clone, PartialEq)]
enum Values {
    /// One number per record.
    Numbers(Vec<f32>),
    /// One upsampled RGB colour per record.
    Colours(Vec<Texel>),
}

impl MeshAttribute {
    /// `name` of `mesh` as a spectrum for use as `kind` (a reflectance is
    /// clamped to [0, 1]; other uses keep colours above 1, without the
    /// illuminant that emission bitmaps take, as Mitsuba's attribute has
    /// none). Errors name what the mesh has.
    pub fn spectral(
        mesh: &TriangleMesh,
        name: &str,
        scale: f32,
        kind: SpectrumKind,
    ) -> Result<Self, String> {
        let a = find(mesh, name)?;
        let values = match a.dim {
            1 => Values::Numbers(a.values.clone()),
            3 if name.contains("color") => {
                let kind = match kind {
                    SpectrumKind::Reflectance => SpectrumKind::Reflectance,
                    _ => SpectrumKind::Unbounded,
                };
                Values::Colours(
                    a.values
                        .chunks_exact(3)
                        .map(|c| Texel::new([c[0], c[1], c[2]], RgbSpace::Srgb, kind))
                        .collect::<Result<_, _>>()
                        .map_err(|e| format!("attribute '{name}': {e}"))?,
                )
            }
            3 => Values::Numbers(
                a.values
                    .chunks_exact(3)
                    .map(|c| luminance([c[0], c[1], c[2]]))
                    .collect(),
            ),
            d => {
                return Err(format!(
                    "attribute '{name}' has {d} numbers per record; a texture reads 1 or 3"
                ))
            }
        };
        Ok(Self::bound(mesh, a, values, scale))
    }

    /// `name` of `mesh` as one number per point (a weight, a roughness):
    /// it must hold one number per record, as Mitsuba's `eval_1` requires.
    pub fn numbers(mesh: &TriangleMesh, name: &str, scale: f32) -> Result<Self, String> {
        let a = find(mesh, name)?;
        if a.dim != 1 {
            return Err(format!(
                "attribute '{name}' has {} numbers per record; a single-number input \
                 (weight, opacity, roughness) reads an attribute of 1",
                a.dim
            ));
        }
        Ok(Self::bound(
            mesh,
            a,
            Values::Numbers(a.values.clone()),
            scale,
        ))
    }

    fn bound(mesh: &TriangleMesh, a: &Attribute, values: Values, scale: f32) -> Self {
        Self {
            faces: (!a.per_face()).then(|| mesh.indices.clone()),
            values,
            scale,
        }
    }

    /// The records at `at` and their weights (zero weights where the
    /// point lies on no face of the mesh).
    #[inline]
    fn corners(&self, at: TexPoint) -> ([usize; 3], [f32; 3]) {
        let f = at.prim as usize;
        match &self.faces {
            Some(faces) => match faces.get(f) {
                Some(&[a, b, c]) => {
                    let [b1, b2] = at.bary;
                    (
                        [a as usize, b as usize, c as usize],
                        [1.0 - b1 - b2, b1, b2],
                    )
                }
                None => ([0; 3], [0.0; 3]),
            },
            None => ([f; 3], [1.0, 0.0, 0.0]),
        }
    }

    /// The value at `at` on the cluster `wl`.
    #[inline]
    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: TexPoint,
    ) -> SampledSpectrum<K> {
        match &self.values {
            Values::Numbers(_) => SampledSpectrum::splat(self.eval_1(at)),
            Values::Colours(texels) => {
                let (i, w) = self.corners(at);
                let t = wl.lambdas().map(normalised_lambda);
                let texel = |k: usize| texels.get(i[k]).copied();
                let mut sum = SampledSpectrum::splat(0.0);
                for (k, &wk) in w.iter().enumerate() {
                    if let (Some(texel), true) = (texel(k), wk != 0.0) {
                        sum += SampledSpectrum::from_fn(|j| texel.at(t[j])) * wk;
                    }
                }
                sum * self.scale
            }
        }
    }

    /// The value at `at` as one number (the luminance-free grey value;
    /// colours are refused when the texture is built).
    #[inline]
    pub fn eval_1(&self, at: TexPoint) -> f32 {
        let Values::Numbers(v) = &self.values else {
            return 0.0;
        };
        let (i, w) = self.corners(at);
        let value = |k: usize| v.get(i[k]).copied().unwrap_or(0.0);
        (w[0] * value(0) + w[1] * value(1) + w[2] * value(2)) * self.scale
    }

    /// The mean over the records (≈ the mean spectral value).
    pub fn mean(&self) -> f32 {
        let (sum, n) = match &self.values {
            Values::Numbers(v) => (v.iter().map(|&x| x as f64).sum::<f64>(), v.len()),
            Values::Colours(texels) => {
                let t: Vec<f32> = (0..48)
                    .map(|i| normalised_lambda(360.0 + 10.0 * i as f32))
                    .collect();
                let sum = texels
                    .iter()
                    .map(|texel| t.iter().map(|&t| texel.at(t) as f64).sum::<f64>() / 48.0)
                    .sum::<f64>();
                (sum, texels.len())
            }
        };
        (sum / n.max(1) as f64) as f32 * self.scale
    }

    /// The largest value any record takes at each of `lambdas` (a blend
    /// of records never exceeds it).
    pub fn max_over_records(&self, lambdas: &[f32]) -> Vec<f32> {
        lambdas
            .iter()
            .map(|&l| {
                let m = match &self.values {
                    Values::Numbers(v) => v.iter().copied().fold(f32::MIN, f32::max),
                    Values::Colours(texels) => {
                        let t = normalised_lambda(l);
                        texels.iter().map(|x| x.at(t)).fold(0.0, f32::max)
                    }
                };
                m * self.scale
            })
            .collect()
    }
}

/// The attribute `name` of `mesh`, or an error listing those it has.
fn find<'m>(mesh: &'m TriangleMesh, name: &str) -> Result<&'m Attribute, String> {
    if !name.starts_with("vertex_") && !name.starts_with("face_") {
        return Err(format!(
            "attribute name '{name}' must start with 'vertex_' or 'face_'"
        ));
    }
    mesh.attribute(name).ok_or_else(|| {
        let have: Vec<&str> = mesh.attributes.iter().map(|a| a.name.as_str()).collect();
        if have.is_empty() {
            format!("no attribute '{name}' (it has none)")
        } else {
            format!("no attribute '{name}' (it has {})", have.join(", "))
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Transform, Vec3};
    use scotopia_color::{rgb_to_spectrum, UpsampleMethod};

    /// One triangle with a colour per vertex, a weight per vertex and a
    /// colour for the face.
    fn mesh() -> TriangleMesh {
        let p = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let attribute = |name: &str, dim, values: Vec<f32>| Attribute {
            name: name.into(),
            dim,
            values,
        };
        TriangleMesh::new(p, None, None, vec![[0, 1, 2]], &Transform::IDENTITY)
            .unwrap()
            .with_attributes(vec![
                attribute(
                    "vertex_color",
                    3,
                    vec![0.8, 0.1, 0.1, 0.1, 0.8, 0.1, 0.1, 0.1, 0.8],
                ),
                attribute("vertex_weight", 1, vec![0.0, 1.0, 0.5]),
                attribute("face_color", 3, vec![0.2, 0.4, 0.6]),
                attribute("face_normal", 3, vec![1.0, 1.0, 1.0]),
            ])
            .unwrap()
    }

    fn wl() -> SampledWavelengths<4> {
        SampledWavelengths::new([450.0, 520.0, 600.0, 680.0], [1.0; 4])
    }

    fn upsampled(rgb: [f32; 3]) -> SampledSpectrum<4> {
        rgb_to_spectrum(
            rgb,
            RgbSpace::Srgb,
            UpsampleMethod::Jakob2019,
            SpectrumKind::Reflectance,
        )
        .unwrap()
        .sample(&wl())
    }

    fn close(a: SampledSpectrum<4>, b: SampledSpectrum<4>) {
        for k in 0..4 {
            assert!((a.0[k] - b.0[k]).abs() < 1e-4, "{a:?} vs {b:?}");
        }
    }

    #[test]
    fn vertex_colours_blend_as_spectra() {
        let m = mesh();
        let t =
            MeshAttribute::spectral(&m, "vertex_color", 1.0, SpectrumKind::Reflectance).unwrap();
        let at = |b1, b2| TexPoint {
            uv: [0.0; 2],
            prim: 0,
            bary: [b1, b2],
        };
        // At a corner, that vertex's colour.
        close(t.eval(&wl(), at(1.0, 0.0)), upsampled([0.1, 0.8, 0.1]));
        // Inside, the weighted sum of the corners' spectra.
        let want = upsampled([0.8, 0.1, 0.1]) * 0.5
            + upsampled([0.1, 0.8, 0.1]) * 0.2
            + upsampled([0.1, 0.1, 0.8]) * 0.3;
        close(t.eval(&wl(), at(0.2, 0.3)), want);
        // A point on no face of the mesh is black, not a panic.
        let off = TexPoint {
            prim: 7,
            ..at(0.2, 0.3)
        };
        close(t.eval(&wl(), off), SampledSpectrum::splat(0.0));
    }

    #[test]
    fn face_records_and_numbers() {
        let m = mesh();
        let face =
            MeshAttribute::spectral(&m, "face_color", 2.0, SpectrumKind::Reflectance).unwrap();
        let at = TexPoint {
            uv: [0.0; 2],
            prim: 0,
            bary: [0.3, 0.3],
        };
        close(face.eval(&wl(), at), upsampled([0.2, 0.4, 0.6]) * 2.0);
        let w = MeshAttribute::numbers(&m, "vertex_weight", 1.0).unwrap();
        // 0.4 · 0 + 0.3 · 1 + 0.3 · 0.5
        assert!((w.eval_1(at) - 0.45).abs() < 1e-6);
        close(
            MeshAttribute::spectral(&m, "vertex_weight", 1.0, SpectrumKind::Reflectance)
                .unwrap()
                .eval(&wl(), at),
            SampledSpectrum::splat(0.45),
        );
        // A 3-number attribute not named as a colour reads as its luminance.
        let n = MeshAttribute::spectral(&m, "face_normal", 1.0, SpectrumKind::Unbounded).unwrap();
        close(
            n.eval(&wl(), at),
            SampledSpectrum::splat(luminance([1.0; 3])),
        );
    }

    #[test]
    fn what_cannot_be_read_is_an_error() {
        let m = mesh();
        let e =
            MeshAttribute::spectral(&m, "vertex_uv", 1.0, SpectrumKind::Reflectance).unwrap_err();
        assert!(
            e.contains("no attribute 'vertex_uv'") && e.contains("vertex_color"),
            "{e}"
        );
        assert!(MeshAttribute::numbers(&m, "vertex_color", 1.0)
            .unwrap_err()
            .contains("has 3 numbers"));
        assert!(MeshAttribute::numbers(&m, "color", 1.0)
            .unwrap_err()
            .contains("must start with"));
    }
}
