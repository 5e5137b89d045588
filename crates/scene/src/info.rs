//! What a loaded scene holds: `scotopia info` prints it (as text, or
//! serialised as JSON) and Python's `scene_info` returns it serialised as
//! a dict, so both show the same keys.

use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;

use scotopia_color::{SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN};
use scotopia_render::camera::Projection;
use scotopia_render::light::{Light, SceneExtent};
use scotopia_render::medium::{Field, Medium, Phase};
use scotopia_render::scene::{Filter, Scene};

/// One light's kind and power.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LightInfo {
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// Radiant power, W.
    pub watts: f64,
    /// Luminous flux, lm.
    pub lumens: f64,
}

/// One participating medium, at 550 nm. Serialised with its extinction
/// named for what it is: `sigma_t_550` or (heterogeneous) `sigma_t_max`.
#[derive(Debug, Clone, PartialEq)]
pub struct MediumInfo {
    pub kind: &'static str,
    /// Extinction per scene unit (scaled): a homogeneous medium's at
    /// 550 nm, a heterogeneous medium's largest (at any place and
    /// wavelength: its majorant).
    pub sigma_t: f32,
    /// At 550 nm; `None` where the albedo is a grid.
    pub albedo: Option<f32>,
    /// The phase function's mean cosine (0: isotropic).
    pub g: f32,
    /// σ_t times the diameter of the scene's bounding sphere: how many
    /// mean free paths a ray across the scene meets (a heterogeneous
    /// medium: its largest σ_t times the shorter of that diameter and its
    /// box's diagonal, an upper bound).
    pub optical_thickness: f32,
    /// A heterogeneous medium's voxel grids.
    pub grids: Vec<GridInfo>,
}

impl Serialize for MediumInfo {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        // A heterogeneous medium's σ_t is its largest, not at 550 nm.
        let sigma_t = if self.kind == "heterogeneous" {
            "sigma_t_max"
        } else {
            "sigma_t_550"
        };
        let mut map = serializer.serialize_map(Some(6))?;
        map.serialize_entry("type", self.kind)?;
        map.serialize_entry(sigma_t, &self.sigma_t)?;
        map.serialize_entry("albedo_550", &self.albedo)?;
        map.serialize_entry("g", &self.g)?;
        map.serialize_entry("optical_thickness", &self.optical_thickness)?;
        map.serialize_entry("grids", &self.grids)?;
        map.end()
    }
}

/// One voxel grid of a medium.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GridInfo {
    /// What it gives: `sigma_t` or `albedo`.
    pub parameter: &'static str,
    pub cells: [usize; 3],
    pub channels: usize,
}

/// The sensor.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CameraInfo {
    /// Horizontal and vertical.
    pub fov_degrees: [f32; 2],
    pub thin_lens: bool,
    /// `perspective`, `orthographic`, or `angular fisheye` / `equisolid
    /// fisheye`.
    pub projection: String,
    /// The shape an irradiancemeter measures over, if that is the sensor.
    #[serde(rename = "irradiancemeter_shape")]
    pub meter_shape: Option<u32>,
}

/// The film.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FilmInfo {
    pub width: u32,
    pub height: u32,
    /// The reconstruction filter, e.g. `box` or `gaussian (stddev 0.5)`.
    pub filter: String,
}

/// A summary of a scene; its fields serialise in this order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneInfo {
    /// Shapes outside shape groups, then those of the groups (each once).
    pub shapes: usize,
    /// Triangles held in memory (each group's once).
    pub triangles: usize,
    /// Placements of shape groups.
    pub instances: usize,
    pub materials: usize,
    pub emitters: usize,
    pub camera: CameraInfo,
    pub film: FilmInfo,
    pub samples_per_pixel: u32,
    /// Longest path; −1 is unlimited.
    pub max_depth: i32,
    pub lights: Vec<LightInfo>,
    pub media: Vec<MediumInfo>,
    pub warnings: Vec<String>,
}

impl SceneInfo {
    pub fn of(scene: &Scene) -> Self {
        let bounds = scene.geometry.bounds();
        let (center, radius) = if bounds.is_empty() {
            (Default::default(), 1.0)
        } else {
            (bounds.centroid(), 0.5 * bounds.extent().length())
        };
        let extent = SceneExtent {
            shapes: &scene.geometry.shapes,
            center,
            radius,
            casters: &[],
        };
        let lights = scene
            .lights
            .iter()
            .map(|l| {
                let power = l.power(&extent);
                LightInfo {
                    kind: match l {
                        Light::Point(_) => "point",
                        Light::Spot(_) => "spot",
                        Light::Projector(_) => "projector",
                        Light::Goniometric(_) => "ies",
                        Light::Directional(_) => "directional",
                        Light::Area(_) => "area",
                        Light::Constant(_) => "constant",
                        Light::EnvMap(_) => "envmap",
                    },
                    watts: power.watts,
                    lumens: power.lumens,
                }
            })
            .collect();
        let fov = scene.camera.fov_degrees();
        Self {
            shapes: scene.geometry.shapes.len()
                + scene
                    .geometry
                    .groups()
                    .iter()
                    .map(|g| g.shapes().len())
                    .sum::<usize>(),
            triangles: scene.geometry.stored_triangles(),
            instances: scene.geometry.instances().len(),
            materials: scene.materials.len(),
            emitters: scene.lights.len(),
            camera: CameraInfo {
                fov_degrees: fov.into(),
                thin_lens: scene.camera.aperture_radius > 0.0,
                projection: match scene.camera.projection {
                    Projection::Perspective => "perspective".into(),
                    Projection::Orthographic => "orthographic".into(),
                    Projection::Fisheye(map) => format!("{} fisheye", map.name()),
                },
                meter_shape: scene.meter.as_ref().map(|m| m.shape),
            },
            film: FilmInfo {
                width: scene.camera.width,
                height: scene.camera.height,
                filter: match scene.filter {
                    Filter::Box => "box".into(),
                    Filter::Gaussian { stddev } => format!("gaussian (stddev {stddev})"),
                },
            },
            samples_per_pixel: scene.samples_per_pixel,
            max_depth: scene.integrator.max_depth,
            lights,
            media: scene
                .media
                .iter()
                .map(|m| medium_info(m, 2.0 * radius))
                .collect(),
            warnings: scene.warnings.clone(),
        }
    }
}

fn medium_info(m: &Medium, diameter: f32) -> MediumInfo {
    let wl = SampledWavelengths::<1>::new([550.0], [1.0]);
    let g_of = |p: &Phase| match *p {
        Phase::Isotropic => 0.0,
        Phase::HenyeyGreenstein { g } => g,
    };
    match m {
        Medium::Homogeneous(h) => {
            let sigma_t = h.sigma_t(&wl).0[0];
            MediumInfo {
                kind: "homogeneous",
                sigma_t,
                albedo: Some(h.albedo.sample(&wl).0[0]),
                g: g_of(&h.phase),
                optical_thickness: sigma_t * diameter,
                grids: Vec::new(),
            }
        }
        Medium::Heterogeneous(h) => {
            let mut grids = Vec::new();
            for (parameter, field) in [("sigma_t", h.sigma_t_field()), ("albedo", h.albedo_field())]
            {
                if let Field::Grid(g) = field {
                    grids.push(GridInfo {
                        parameter,
                        cells: g.grid().resolution(),
                        channels: g.grid().channels(),
                    });
                }
            }
            let sigma_t = match h.sigma_t_field() {
                Field::Constant { value, .. } => {
                    // Its largest over the visible range, 1 nm apart.
                    let top = (LAMBDA_MIN as u32..=LAMBDA_MAX as u32)
                        .map(|l| value.eval(l as f32))
                        .fold(0.0f32, f32::max);
                    top * h.scale()
                }
                Field::Grid(g) => g.max() * h.scale(),
            };
            let albedo = match h.albedo_field() {
                Field::Constant { value, .. } => Some(value.eval(550.0).clamp(0.0, 1.0)),
                Field::Grid(_) => None,
            };
            MediumInfo {
                kind: "heterogeneous",
                sigma_t,
                albedo,
                g: g_of(&h.phase),
                optical_thickness: sigma_t * diameter.min(h.world_bounds().extent().length()),
                grids,
            }
        }
    }
}
