//! Vectors, rays, transforms and bounding boxes.

mod aabb;
mod frame;
mod ray;
mod transform;
mod vec3;

pub use aabb::Aabb;
pub(crate) use aabb::GAMMA3;
pub use frame::Frame;
pub use ray::{offset_ray_origin, Ray};
pub use transform::{invert, Mat4, Transform};
pub use vec3::Vec3;
