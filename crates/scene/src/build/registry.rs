//! Every Mitsuba 3 plugin, and what scotopia does with it: the loader's
//! own record of its coverage. docs/scene-format.md's compatibility table
//! and the README's summary are generated from it, and a test loads each
//! plugin's example to check that the loader behaves as recorded.

use std::fmt::Write;

/// How far scotopia follows a Mitsuba plugin.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Support {
    /// Read and rendered as Mitsuba renders it (or differing on purpose,
    /// as the note says).
    Full,
    /// Read and rendered; some properties or cases are not (the note).
    Partial,
    /// Read as the closest thing scotopia has, with a warning.
    Warned,
    /// Left out of the scene with a warning; the rest renders.
    Skipped,
    /// An error naming the plugin.
    Unsupported,
}

impl Support {
    pub fn name(self) -> &'static str {
        match self {
            Support::Full => "supported",
            Support::Partial => "partial",
            Support::Warned => "warned",
            Support::Skipped => "skipped",
            Support::Unsupported => "error",
        }
    }
}

/// One Mitsuba plugin.
#[derive(Debug, Clone, Copy)]
pub struct Plugin {
    /// The element: `bsdf`, `shape`, `emitter`, `sensor`, `integrator`,
    /// `texture`, `spectrum`, `film`, `rfilter`, `sampler`, `medium`.
    pub kind: &'static str,
    pub name: &'static str,
    pub support: Support,
    /// Properties read (others are warned about once and ignored).
    pub reads: &'static str,
    /// What differs from Mitsuba, or what is missing.
    pub note: &'static str,
}

const fn p(
    kind: &'static str,
    name: &'static str,
    support: Support,
    reads: &'static str,
    note: &'static str,
) -> Plugin {
    Plugin {
        kind,
        name,
        support,
        reads,
        note,
    }
}

use Support::{Full, Partial, Skipped, Unsupported, Warned};

const ROUGH: &str = "`alpha` or `alpha_u`/`alpha_v`, `distribution` (beckmann, ggx)";
const ROUGH_TEXTURED: &str =
    "`alpha` or `alpha_u`/`alpha_v` (numbers or textures), `distribution` (beckmann, ggx)";

/// Mitsuba 3.9's plugins, and scotopia's own additions (marked in the note).
pub const PLUGINS: &[Plugin] = &[
    // BSDFs
    p("bsdf", "diffuse", Full, "reflectance", ""),
    p("bsdf", "conductor", Full, "material, eta, k, specular_reflectance", "named metals are measured spectra, not Mitsuba's fits; negative RGB η, κ clamped to 0 with a warning"),
    p("bsdf", "roughconductor", Full, ROUGH_TEXTURED, "as conductor; textured α looked up where the BSDF is evaluated"),
    p("bsdf", "dielectric", Full, "int_ior, ext_ior, specular_reflectance, specular_transmittance", "named glasses disperse (Sellmeier)"),
    p("bsdf", "thindielectric", Full, "int_ior, ext_ior, specular_reflectance, specular_transmittance", ""),
    p("bsdf", "roughdielectric", Full, ROUGH_TEXTURED, "as dielectric; textured α looked up where the BSDF is evaluated"),
    p("bsdf", "plastic", Full, "diffuse_reflectance, specular_reflectance, int_ior, ext_ior, nonlinear", "coating index at 550 nm"),
    p("bsdf", "roughplastic", Full, ROUGH, "as plastic; α a number, as in Mitsuba"),
    p("bsdf", "twosided", Full, "one or two nested BSDFs", ""),
    p("bsdf", "fluorescent", Full, "reflectance, excitation, emission, quantum_yield, matrix", "scotopia's own: re-emission at other wavelengths"),
    p("bsdf", "roadsurface", Full, "class (R1, R2, R3, R4, C1, C2; R3), q0, reflectance (a spectrum: its colour)", "scotopia's own: the CIE r-tables (CIE 144), for road luminance; docs/lighting.md"),
    p("bsdf", "null", Full, "", "blocks shadow rays and counts as a bounce, as in Mitsuba's path"),
    p("bsdf", "mask", Full, "opacity (number or texture), nested BSDF", ""),
    p("bsdf", "blendbsdf", Full, "weight (number or texture), two nested BSDFs", ""),
    p("bsdf", "normalmap", Full, "normalmap (bitmap or rawconstant), flip_invalid_normals, nested BSDF", "frame from dp/du as Mitsuba 3.9"),
    p("bsdf", "bumpmap", Full, "a height texture, scale, nested BSDF", ""),
    p("bsdf", "pplastic", Warned, "diffuse_reflectance, specular_reflectance, int_ior, ext_ior, alpha (number or texture)", "its unpolarised form, exactly"),
    p("bsdf", "principled", Full, "base_color, roughness, anisotropic, metallic, spec_trans, eta or specular, spec_tint, sheen, sheen_tint, flatness, clearcoat, clearcoat_gloss (numbers or textures), *_sampling_rate", "tints by luminance on the path's wavelengths, as Mitsuba's spectral variants, weighted to its wavelength density"),
    p("bsdf", "principledthin", Full, "base_color, roughness, anisotropic, spec_trans, eta, spec_tint, sheen, sheen_tint, flatness, diff_trans (numbers or textures), *_sampling_rate", "tints by luminance on the path's wavelengths, as Mitsuba's spectral variants, weighted to its wavelength density"),
    p("bsdf", "polarizer", Warned, "transmittance", "passes ½ of unpolarised light"),
    p("bsdf", "retarder", Warned, "transmittance", "passes unpolarised light unchanged"),
    p("bsdf", "circular", Warned, "transmittance", "passes ½ of unpolarised light"),
    p("bsdf", "measured", Unsupported, "", "measured RGL BRDF files"),
    p("bsdf", "measured_polarized", Warned, "", "diffuse 0.5: its file format is not read"),
    p("bsdf", "hair", Unsupported, "", ""),
    // Shapes
    p("shape", "sphere", Full, "center, radius, to_world, flip_normals", "UVs turn with to_world"),
    p("shape", "rectangle", Full, "to_world, flip_normals", ""),
    p("shape", "disk", Full, "to_world, flip_normals", ""),
    p("shape", "cube", Full, "to_world, flip_normals", ""),
    p("shape", "obj", Full, "filename, to_world, face_normals, flip_normals, flip_tex_coords", "smooth normals computed as Mitsuba when the file has none"),
    p("shape", "ply", Full, "filename, to_world, face_normals, flip_normals, flip_tex_coords", "other vertex and face properties become attributes (`mesh_attribute`) by Mitsuba's naming rules"),
    p("shape", "serialized", Full, "filename, shape_index, to_world, face_normals, flip_normals", "format versions 3 and 4; vertex colours become `vertex_color` (Mitsuba 3.9 skips them)"),
    p("shape", "cylinder", Full, "p0, p1, radius, to_world, flip_normals", "open tube, as Mitsuba"),
    p("shape", "shapegroup", Full, "nested shapes with their BSDFs", "built once, under its own BVH, on its first instance; as Mitsuba, no nested groups or instances and no emitters (an error)"),
    p("shape", "instance", Full, "a shapegroup reference, to_world", "instances share their group's BVH and triangles (one placement each); any affine to_world, non-uniform scale included"),
    p("shape", "merge", Full, "nested shapes", "the shapes are added as they are"),
    p("shape", "bsplinecurve", Skipped, "", "curves are not intersected yet"),
    p("shape", "linearcurve", Skipped, "", "curves are not intersected yet"),
    p("shape", "sdfgrid", Skipped, "", "SDF grids are not intersected yet"),
    p("shape", "ellipsoids", Skipped, "", "not intersected yet"),
    p("shape", "ellipsoidsmesh", Skipped, "", "not intersected yet"),
    // Emitters
    p("emitter", "area", Full, "radiance (texture or spectrum)", "nested in a shape or referenced from one; sampled by area (Mitsuba importance-samples a texture: same expectation); wavelengths drawn from the radiance averaged over the area"),
    p("emitter", "point", Full, "intensity, position, to_world", ""),
    p("emitter", "spot", Full, "intensity, cutoff_angle, beam_width, texture, to_world", "a texture scales the light's power by its mean for choosing lights"),
    p("emitter", "directional", Full, "irradiance, direction, to_world", ""),
    p("emitter", "constant", Full, "radiance (Mitsuba's default: unit D65)", ""),
    p("emitter", "envmap", Full, "filename, scale, to_world", "interpolated as Mitsuba 3: the texels' unit spectra and their scales blended apart"),
    p("emitter", "projector", Full, "irradiance (texture or spectrum), scale, fov, fov_axis, focal_length, to_world", "light paths start uniformly over the image, not by texel power"),
    p("emitter", "ies", Full, "filename (IES LM-63 or EULUMDAT), spectrum (default Planck 4000 K), scale, to_world", "scotopia's own: a goniometric point light with the file's candela (nadir along local +z, C 0° along +x); docs/lighting.md"),
    p("emitter", "directionalarea", Unsupported, "", ""),
    p("emitter", "sunsky", Unsupported, "", ""),
    p("emitter", "timed_sunsky", Unsupported, "", ""),
    // Sensors
    p("sensor", "perspective", Full, "fov, fov_axis, focal_length, near_clip, far_clip, to_world", ""),
    p("sensor", "thinlens", Full, "the above, aperture_radius, focus_distance", ""),
    p("sensor", "orthographic", Partial, "near_clip, far_clip, to_world (its scale sets the extent)", "path tracer only: bdpt refuses it"),
    p("sensor", "fisheye", Full, "projection (angular or equisolid), fov (full angle across the width, up to 360; default 180), near_clip, far_clip, to_world", "scotopia's own (Mitsuba has none): for glare ratings; no crop window; the EXR's metadata names its projection"),
    p("sensor", "radiancemeter", Unsupported, "", ""),
    p("sensor", "irradiancemeter", Full, "a shape's child; its film and sampler", "E over the shape in lx (Y), by the path tracer's receiver; a film larger than 1×1 is read as 1×1 with a warning"),
    p("sensor", "distant", Unsupported, "", ""),
    p("sensor", "batch", Unsupported, "", ""),
    // Films, filters, samplers
    p("film", "hdrfilm", Full, "width, height, crop_offset_x/y, crop_width/height, rfilter", "always X, Y, Z, V′; pixel formats ignored"),
    p("film", "specfilm", Warned, "width, height, crop_*, rfilter", "read as hdrfilm; `--spectral` writes spectral images"),
    p("rfilter", "box", Full, "", ""),
    p("rfilter", "gaussian", Full, "stddev", ""),
    p("rfilter", "tent", Warned, "", "gaussian used"),
    p("rfilter", "mitchell", Warned, "", "gaussian used"),
    p("rfilter", "catmullrom", Warned, "", "gaussian used"),
    p("rfilter", "lanczos", Warned, "", "gaussian used"),
    p("sampler", "independent", Partial, "sample_count", "scotopia's own Owen-scrambled Sobol samples"),
    p("sampler", "stratified", Partial, "sample_count", "as independent"),
    p("sampler", "multijitter", Partial, "sample_count", "as independent"),
    p("sampler", "orthogonal", Partial, "sample_count", "as independent"),
    p("sampler", "ldsampler", Partial, "sample_count", "as independent"),
    // Integrators
    p("integrator", "path", Full, "max_depth, rr_depth", "ignores media, as Mitsuba's"),
    p("integrator", "bdpt", Full, "max_depth, rr_depth", "scotopia's own bidirectional tracer"),
    p("integrator", "direct", Warned, "", "path with max_depth 2 (the same image)"),
    p("integrator", "volpath", Full, "max_depth, rr_depth", "the volume path tracer"),
    p("integrator", "volpathmis", Warned, "max_depth, rr_depth", "the volume path tracer (volpath: the same image)"),
    p("integrator", "prbvolpath", Warned, "max_depth, rr_depth", "the volume path tracer (volpath: the same image)"),
    p("integrator", "prb", Warned, "max_depth, rr_depth", "path (the same image)"),
    p("integrator", "prb_basic", Warned, "max_depth, rr_depth", "path (the same image)"),
    p("integrator", "ptracer", Warned, "max_depth, rr_depth", "path (the same image)"),
    p("integrator", "moment", Warned, "the nested integrator", "renders the nested integrator; no moment image"),
    p("integrator", "aov", Warned, "the nested integrator", "renders the nested integrator; no AOVs"),
    p("integrator", "stokes", Warned, "the nested integrator", "renders the nested integrator; no Stokes channels"),
    p("integrator", "depth", Warned, "", "path"),
    // Textures
    p("texture", "bitmap", Full, "filename, filter_type, wrap_mode, raw, to_uv", "texel spectra blended, not coefficients"),
    p("texture", "checkerboard", Full, "color0, color1, to_uv", "read as one number (a roughness, weight, opacity) color0 and color1 trade places, as in Mitsuba 3.9.1's eval_1"),
    p("texture", "mesh_attribute", Full, "name, scale", "bound to each shape's mesh; a missing attribute is an error"),
    p("texture", "rawconstant", Full, "value", "a float anywhere; a vector for normal maps"),
    p("texture", "volume", Unsupported, "", ""),
    // Spectra
    p("spectrum", "d65", Full, "scale", "any CIE illuminant by name too (scotopia's)"),
    p("spectrum", "blackbody", Full, "temperature", ""),
    p("spectrum", "regular", Full, "wavelength_min, wavelength_max, values", ""),
    p("spectrum", "irregular", Full, "wavelengths, values", ""),
    p("spectrum", "uniform", Full, "value, wavelength_min, wavelength_max", ""),
    p("spectrum", "srgb", Full, "color, unbounded", ""),
    p("spectrum", "rawconstant", Full, "value", ""),
    // Participating media
    p("medium", "homogeneous", Full, "sigma_t, albedo, scale, phase (isotropic, hg); a shape's interior/exterior, the sensor's", "σ_t, albedo spectral; spectral MIS over the cluster"),
    p("medium", "heterogeneous", Full, "sigma_t, albedo (each a gridvolume: filename, to_world, use_grid_bbox, filter_type, raw, wrap_mode as clamp; a constvolume: value, to_world; or a spectrum), scale, phase (isotropic, hg); a shape's interior/exterior, the sensor's", "delta and ratio tracking over a majorant grid; RGB grids upsampled as Mitsuba's spectral variants"),
];

/// The entry for `<kind type="name">`.
pub fn plugin(kind: &str, name: &str) -> Option<&'static Plugin> {
    PLUGINS.iter().find(|p| p.kind == kind && p.name == name)
}

/// The full table for docs/scene-format.md.
pub fn markdown_table() -> String {
    let mut out = String::from(
        "| element | plugin | scotopia | properties read | notes |\n|---|---|---|---|---|\n",
    );
    for p in PLUGINS {
        let _ = writeln!(
            out,
            "| {} | `{}` | {} | {} | {} |",
            p.kind,
            p.name,
            p.support.name(),
            p.reads,
            p.note
        );
    }
    out
}

/// One line per element kind, plugins grouped by support: the README's.
pub fn summary_table() -> String {
    let mut kinds: Vec<&str> = Vec::new();
    for p in PLUGINS {
        if !kinds.contains(&p.kind) {
            kinds.push(p.kind);
        }
    }
    let mut out = String::from(
        "| element | supported | partial | warned | skipped | error |\n|---|---|---|---|---|---|\n",
    );
    for kind in kinds {
        let names = |s: Support| {
            PLUGINS
                .iter()
                .filter(|p| p.kind == kind && p.support == s)
                .map(|p| p.name)
                .collect::<Vec<_>>()
                .join(", ")
        };
        let _ = writeln!(
            out,
            "| {kind} | {} | {} | {} | {} | {} |",
            names(Full),
            names(Partial),
            names(Warned),
            names(Skipped),
            names(Unsupported)
        );
    }
    out
}
