//! A pinhole camera looking at the opal (paper fig. 10).

use glam::Vec3;

use super::Ray;

/// Pinhole camera with a vertical field of view; pixel rows run top to bottom.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    position: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half_fov: f32,
    width: usize,
    height: usize,
}

impl Camera {
    /// Camera at `position` looking at `target` with `up` roughly up, vertical field of view
    /// `fov_deg`, for an image of `width × height` pixels.
    pub fn look_at(
        position: Vec3,
        target: Vec3,
        up: Vec3,
        fov_deg: f32,
        width: usize,
        height: usize,
    ) -> Self {
        let forward = (target - position).normalize();
        let right = forward.cross(up).normalize();
        let up = right.cross(forward);
        Camera {
            position,
            forward,
            right,
            up,
            tan_half_fov: (0.5 * fov_deg.to_radians()).tan(),
            width,
            height,
        }
    }

    /// Unit direction from the camera towards its target.
    pub fn forward(&self) -> Vec3 {
        self.forward
    }

    /// Camera position, mm.
    pub fn position(&self) -> Vec3 {
        self.position
    }

    /// The ray through image point `(px, py)` in pixels (`(0.5, 0.5)` is the centre of the
    /// top-left pixel).
    pub fn ray(&self, px: f32, py: f32) -> Ray {
        let aspect = self.width as f32 / self.height as f32;
        let sx = (2.0 * px / self.width as f32 - 1.0) * aspect * self.tan_half_fov;
        let sy = (1.0 - 2.0 * py / self.height as f32) * self.tan_half_fov;
        Ray::new(self.position, self.forward + sx * self.right + sy * self.up)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_pixel_looks_at_the_target_and_corners_span_the_fov() {
        let cam = Camera::look_at(Vec3::new(0.0, 0.0, 100.0), Vec3::ZERO, Vec3::Y, 90.0, 4, 2);
        let centre = cam.ray(2.0, 1.0);
        assert!((centre.direction + Vec3::Z).length() < 1e-6);
        let top = cam.ray(2.0, 0.0).direction;
        // 90° vertical fov: the top edge is 45° above the axis.
        assert!((top.y - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-5);
        assert!(cam.ray(4.0, 1.0).direction.x > 0.0, "x grows to the right");
    }
}
