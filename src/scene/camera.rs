//! The pinhole camera: its basis, its rays (the oracle's) and its view-projection (the GPU's),
//! and the window of a larger image it may render (tiled supersampling).

use crate::error::{Error, Result};
use glam::{DMat4, DVec3, DVec4, Mat4};

crate::schema! {
    /// Pinhole camera. Use `Camera.look_at`. fov_y is the vertical field of view in degrees;
    /// the ray of pixel (i, j) passes through the pixel centre (j + 0.5, i + 0.5), row 0 at the top.
    pub struct Camera {
        /// the eye's position
        pub eye: [f64; 3] = Vec3;
        /// the point looked at
        pub target: [f64; 3] = Vec3, "(0.0, 0.0, 0.0)";
        /// the up direction (not parallel to the view direction)
        pub up: [f64; 3] = Vec3, "(0.0, 1.0, 0.0)";
        /// the vertical field of view in degrees
        pub fov_y: f64 = Real(1e-6, 179.999), "45.0";
        /// the image's width in pixels
        pub width: u32 = Integer(1, 1 << 30), "256";
        /// the image's height in pixels
        pub height: u32 = Integer(1, 1 << 30), "256";
    }
    internal {
        /// When set, the image is one window of a larger one: its `width` x `height` pixels are
        /// those from `origin` of a `full`-sized image of the same camera (tiled passes of a
        /// supersampled frame). None: the whole image.
        pub window: Option<Window> = None;
        /// k when this image's pixels are the k x k samples of a supersampled frame's pixels
        /// (the exact shadows share their directions among them), 1 otherwise.
        pub samples: u32 = 1;
    }
}

/// Where a camera's image lies in the full image it is a window of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Window {
    pub full: (u32, u32),
    pub origin: (u32, u32),
}

/// Orthonormal camera basis (right, up, back) in f64.
pub struct CameraBasis {
    pub eye: DVec3,
    pub forward: DVec3,
    pub right: DVec3,
    pub up: DVec3,
    pub tan_half_y: f64,
    pub aspect: f64,
}

impl Camera {
    pub fn validate(&self) -> Result<()> {
        self.check_fields()?;
        let eye = DVec3::from(self.eye);
        let target = DVec3::from(self.target);
        let fwd = target - eye;
        if fwd.length() < 1e-9 {
            return Err(Error::arg(
                "eye",
                "eye and target coincide; move the eye away from the target",
            ));
        }
        let up = DVec3::from(self.up);
        if up.length() < 1e-12 || fwd.normalize().cross(up.normalize()).length() < 1e-6 {
            return Err(Error::arg(
                "up",
                "up is zero or parallel to the view direction; pass another up vector",
            ));
        }
        Ok(())
    }

    /// The full image's size and this image's origin in it.
    pub fn full(&self) -> ((u32, u32), (u32, u32)) {
        match self.window {
            Some(w) => (w.full, w.origin),
            None => ((self.width, self.height), (0, 0)),
        }
    }

    pub fn basis(&self) -> CameraBasis {
        let eye = DVec3::from(self.eye);
        let forward = (DVec3::from(self.target) - eye).normalize();
        let right = forward.cross(DVec3::from(self.up)).normalize();
        let up = right.cross(forward);
        CameraBasis {
            eye,
            forward,
            right,
            up,
            tan_half_y: (self.fov_y.to_radians() * 0.5).tan(),
            aspect: {
                let ((fw, fh), _) = self.full();
                fw as f64 / fh as f64
            },
        }
    }

    /// Unit direction of the ray through the centre of pixel (row i, column j).
    pub fn ray_dir(&self, b: &CameraBasis, i: u32, j: u32) -> DVec3 {
        let ((fw, fh), (x0, y0)) = self.full();
        let x = (((x0 + j) as f64 + 0.5) / fw as f64) * 2.0 - 1.0;
        let y = 1.0 - (((y0 + i) as f64 + 0.5) / fh as f64) * 2.0;
        (b.forward + b.right * (x * b.tan_half_y * b.aspect) + b.up * (y * b.tan_half_y))
            .normalize()
    }

    /// View-projection matrix (wgpu clip space: y up, depth in [0, 1]) for the given clip
    /// range, computed in f64. Right-handed view space looking down -z.
    pub fn view_proj(&self, near: f64, far: f64) -> Mat4 {
        let b = self.basis();
        let view = DMat4::from_cols(
            DVec4::new(b.right.x, b.up.x, -b.forward.x, 0.0),
            DVec4::new(b.right.y, b.up.y, -b.forward.y, 0.0),
            DVec4::new(b.right.z, b.up.z, -b.forward.z, 0.0),
            DVec4::new(
                -b.right.dot(b.eye),
                -b.up.dot(b.eye),
                b.forward.dot(b.eye),
                1.0,
            ),
        );
        let f = 1.0 / b.tan_half_y;
        let r = far / (near - far);
        let proj = DMat4::from_cols(
            DVec4::new(f / b.aspect, 0.0, 0.0, 0.0),
            DVec4::new(0.0, f, 0.0, 0.0),
            DVec4::new(0.0, 0.0, r, -1.0),
            DVec4::new(0.0, 0.0, r * near, 0.0),
        );
        // a window: the full image's clip space, scaled and shifted so that the window's pixels
        // fill [-1, 1]
        let ((fw, fh), (x0, y0)) = self.full();
        let (sx, sy) = (
            fw as f64 / self.width as f64,
            fh as f64 / self.height as f64,
        );
        let cx = (2.0 * x0 as f64 + self.width as f64) / fw as f64 - 1.0;
        let cy = 1.0 - (2.0 * y0 as f64 + self.height as f64) / fh as f64;
        let crop = DMat4::from_cols(
            DVec4::new(sx, 0.0, 0.0, 0.0),
            DVec4::new(0.0, sy, 0.0, 0.0),
            DVec4::new(0.0, 0.0, 1.0, 0.0),
            DVec4::new(-sx * cx, -sy * cy, 0.0, 1.0),
        );
        (crop * proj * view).as_mat4()
    }
}
