//! Analytic disk.

use caustica_core::Vec3;

/// Disk of `radius` (m) around `center`, facing `normal` (unit).
#[derive(Clone, Copy, Debug)]
pub struct Disk {
    pub center: Vec3,
    pub normal: Vec3,
    pub radius: f32,
}
