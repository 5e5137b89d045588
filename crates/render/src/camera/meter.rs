//! Mitsuba's `irradiancemeter`: a sensor attached to a shape, measuring
//! the irradiance averaged over the shape's area, on the side its normals
//! point to. Each sample chooses a point uniformly by area; the illuminance
//! there is estimated by the path tracer's virtual receiver
//! (`integrator::measure`), so the image's one pixel holds E in lx.

use crate::geometry::{Shape, SurfacePoint};
use crate::sampling::distribution::Distribution1D;

#[derive(Debug, Clone, PartialEq)]
pub struct IrradianceMeter {
    /// Index of the measuring shape in the scene's shape list.
    pub shape: u32,
    /// Triangle areas of a mesh (`Shape::area_table`).
    triangles: Option<Distribution1D>,
}

impl IrradianceMeter {
    pub fn new(shape_index: u32, shape: &Shape) -> Self {
        Self {
            shape: shape_index,
            triangles: shape.area_table(),
        }
    }

    /// A point on the meter's shape, uniform by area, with its normal.
    pub fn sample(&self, shapes: &[Shape], u_select: f32, u: [f32; 2]) -> Option<SurfacePoint> {
        shapes
            .get(self.shape as usize)?
            .sample_area(self.triangles.as_ref(), u_select, u)
    }
}
