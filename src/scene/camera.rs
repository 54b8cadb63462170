//! The camera and its film: camera rays through a pinhole or a thin lens.

use crate::math::Ray;
use glam::DVec3;

/// A camera with an orthonormal frame: a pinhole, or a thin lens when `aperture_radius > 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub position: DVec3,
    /// Unit view direction.
    pub forward: DVec3,
    /// Unit image-right direction (`forward x up`).
    pub right: DVec3,
    /// Unit image-up direction.
    pub up: DVec3,
    /// Vertical field of view in degrees.
    pub fov_y: f64,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Thin-lens radius in world units; 0 is the pinhole (`camera.aperture_radius`).
    pub aperture_radius: f64,
    /// Distance along `forward` of the plane in focus (`camera.focus_distance`, > 0).
    pub focus_distance: f64,
}

impl Camera {
    /// The camera ray through film position `(fx, fy)` in pixels; pixel (0,0) is top-left and
    /// `(x + 0.5, y + 0.5)` is the centre of pixel (x, y). For many rays, [`Camera::film`]
    /// evaluates the field of view once.
    #[must_use]
    pub fn ray(&self, fx: f64, fy: f64) -> Ray {
        self.film().ray(fx, fy)
    }

    /// Film position to coordinates on the image plane at distance 1 along `forward`.
    #[must_use]
    pub fn film_to_plane(&self, fx: f64, fy: f64) -> (f64, f64) {
        self.film().to_plane(fx, fy)
    }

    /// The image plane's extent computed once, for generating many rays (the same rays as
    /// [`Camera::ray`], bit for bit).
    #[must_use]
    pub fn film(&self) -> Film<'_> {
        let half_h = (self.fov_y.to_radians() * 0.5).tan();
        Film {
            camera: self,
            half_w: half_h * f64::from(self.width) / f64::from(self.height),
            half_h,
        }
    }

    /// The same camera rendering `width x height`.
    #[must_use]
    pub fn with_size(&self, width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            ..self.clone()
        }
    }
}

/// A camera with its image plane's half extents evaluated ([`Camera::film`]).
#[derive(Clone, Copy, Debug)]
pub struct Film<'a> {
    camera: &'a Camera,
    half_w: f64,
    half_h: f64,
}

impl Film<'_> {
    /// [`Camera::ray`].
    #[must_use]
    #[inline]
    pub fn ray(&self, fx: f64, fy: f64) -> Ray {
        let c = self.camera;
        let (u, v) = self.to_plane(fx, fy);
        let d = (c.forward + u * c.right + v * c.up).normalize();
        Ray::new(c.position, d, 0.0)
    }

    /// Whether the camera is a thin lens (`aperture_radius > 0`): its camera rays then need a
    /// lens sample ([`Film::lens_ray`]); a pinhole's do not ([`Film::ray`]).
    #[must_use]
    #[inline]
    pub fn has_lens(&self) -> bool {
        self.camera.aperture_radius > 0.0
    }

    /// The thin-lens camera ray through film position `(fx, fy)` and lens sample `u` in
    /// `[0, 1)^2` (pbrt-v4 `PerspectiveCamera::GenerateRay`, section 5.2.3): the point on the
    /// lens is `aperture_radius` times the concentric disk map of `u`
    /// ([`crate::sampling::warp::square_to_concentric_disk`], Shirley and Chiu 1997) in the
    /// `right`/`up` plane through the eye; the ray leaves it towards the point where the pinhole
    /// ray of `(fx, fy)` meets the plane at `focus_distance` along `forward`. Every point of that
    /// plane is therefore seen at one film position from every lens sample (it is in focus).
    #[must_use]
    #[inline]
    pub fn lens_ray(&self, fx: f64, fy: f64, u: glam::DVec2) -> Ray {
        let c = self.camera;
        let (pu, pv) = self.to_plane(fx, fy);
        // The pinhole direction scaled so its `forward` component is 1 (pbrt: ft = f / d.z).
        let focus = c.focus_distance * (c.forward + pu * c.right + pv * c.up);
        let lens = c.aperture_radius * crate::sampling::warp::square_to_concentric_disk(u);
        let on_lens = lens.x * c.right + lens.y * c.up;
        // Both relative to the eye, so a far-away camera does not cancel digits.
        Ray::new(c.position + on_lens, (focus - on_lens).normalize(), 0.0)
    }

    /// [`Camera::film_to_plane`].
    #[must_use]
    #[inline]
    pub fn to_plane(&self, fx: f64, fy: f64) -> (f64, f64) {
        let c = self.camera;
        let u = (2.0 * fx / f64::from(c.width) - 1.0) * self.half_w;
        let v = (1.0 - 2.0 * fy / f64::from(c.height)) * self.half_h;
        (u, v)
    }
}
