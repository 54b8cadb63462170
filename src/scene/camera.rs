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

    /// The connection of point `p` to the camera, for light tracing (pbrt-v4
    /// `PerspectiveCamera::SampleWi`; Veach 1997, section 10.2): the point on the lens (the eye
    /// for a pinhole; for a thin lens `aperture_radius` times the concentric disk map of `u`, as
    /// in [`Film::lens_ray`], which a pinhole ignores), the unit direction from it to `p`, the
    /// distance, the film position the camera ray along that line has, and the importance
    /// factor `1 / (A cos^3 theta)` (`A` the film's area on the plane at distance 1, `theta` the
    /// angle to `forward`). A light-path vertex of throughput `beta` then adds
    /// `beta f |cos| importance / distance^2` (visibility aside) to the sum of its pixel, which
    /// the render divides by `spp` like the camera samples' sum. `None` behind the lens plane
    /// or off the film.
    #[must_use]
    pub fn connect(&self, p: DVec3, u: glam::DVec2) -> Option<CameraConnection> {
        let c = self.camera;
        let on_lens = if self.has_lens() {
            let lens = c.aperture_radius * crate::sampling::warp::square_to_concentric_disk(u);
            lens.x * c.right + lens.y * c.up
        } else {
            DVec3::ZERO
        };
        // Relative to the eye, as the camera rays are made.
        let rel = p - c.position - on_lens;
        let along = rel.dot(c.forward);
        let distance = rel.length();
        if !(along > 0.0 && distance > 0.0 && distance.is_finite()) {
            return None;
        }
        let direction = rel / distance;
        let (fx, fy) = self.film_of(on_lens, rel, along);
        let inside =
            (0.0..f64::from(c.width)).contains(&fx) && (0.0..f64::from(c.height)).contains(&fy);
        if !inside {
            return None;
        }
        let cos = direction.dot(c.forward);
        let area = 4.0 * self.half_w * self.half_h;
        Some(CameraConnection {
            film: (fx, fy),
            lens: c.position + on_lens,
            direction,
            distance,
            importance: 1.0 / (area * cos * cos * cos),
        })
    }

    /// The solid-angle density with which the camera's rays leave lens point `lens` along unit
    /// `w` (pbrt-v3 `PerspectiveCamera::Pdf_We`'s `pdfDir`): `1 / (A cos^3 theta)` where the
    /// ray lands on the film, 0 elsewhere. The lens point's own density (`1 / (pi r^2)`, 1 for a
    /// pinhole) cancels in BDPT's ratios, which use only this.
    #[must_use]
    pub fn pdf_dir(&self, lens: DVec3, w: DVec3) -> f64 {
        let c = self.camera;
        match self.connect_from(lens - c.position, w) {
            Some(cos) => 1.0 / (4.0 * self.half_w * self.half_h * cos * cos * cos),
            None => 0.0,
        }
    }

    /// The cosine to `forward` of the ray from lens offset `on_lens` (relative to the eye)
    /// along `rel`, when it lands on the film.
    fn connect_from(&self, on_lens: DVec3, rel: DVec3) -> Option<f64> {
        let c = self.camera;
        let along = rel.dot(c.forward);
        let len = rel.length();
        if !(along > 0.0 && len > 0.0 && len.is_finite()) {
            return None;
        }
        let (fx, fy) = self.film_of(on_lens, rel, along);
        let inside =
            (0.0..f64::from(c.width)).contains(&fx) && (0.0..f64::from(c.height)).contains(&fy);
        inside.then_some(along / len)
    }

    /// The film position of the ray from lens offset `on_lens` along `rel` (`along` its
    /// component on `forward`, > 0): where it meets the plane in focus (distance 1 for a
    /// pinhole), in the pinhole's plane coordinates ([`Film::to_plane`]).
    fn film_of(&self, on_lens: DVec3, rel: DVec3, along: f64) -> (f64, f64) {
        let c = self.camera;
        let depth = if self.has_lens() {
            c.focus_distance
        } else {
            1.0
        };
        let on_plane = on_lens + rel * (depth / along);
        let (pu, pv) = (on_plane.dot(c.right) / depth, on_plane.dot(c.up) / depth);
        let fx = (pu / self.half_w + 1.0) * 0.5 * f64::from(c.width);
        let fy = (1.0 - pv / self.half_h) * 0.5 * f64::from(c.height);
        (fx, fy)
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

/// A point connected to the camera ([`Film::connect`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraConnection {
    /// Film position in pixels where the point is seen.
    pub film: (f64, f64),
    /// The point on the lens (the eye for a pinhole).
    pub lens: DVec3,
    /// Unit direction from `lens` to the point.
    pub direction: DVec3,
    /// Distance from `lens` to the point.
    pub distance: f64,
    /// `1 / (A cos^3 theta)`: the camera's importance per unit of `f |cos| / distance^2`.
    pub importance: f64,
}

impl CameraConnection {
    /// The pixel of [`Self::film`].
    #[must_use]
    pub fn pixel(&self) -> (u32, u32) {
        // In range: `Film::connect` keeps only positions on the film.
        (self.film.0 as u32, self.film.1 as u32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(aperture: f64) -> Camera {
        Camera {
            position: DVec3::new(0.5, 1.0, 4.0),
            forward: DVec3::NEG_Z,
            right: DVec3::X,
            up: DVec3::Y,
            fov_y: 40.0,
            width: 64,
            height: 48,
            aperture_radius: aperture,
            focus_distance: 3.0,
        }
    }

    /// A camera ray's points connect back to its film position, through a pinhole and through
    /// the lens point it left from.
    #[test]
    fn connect_inverts_the_camera_ray() {
        for aperture in [0.0, 0.2] {
            let cam = camera(aperture);
            let film = cam.film();
            for (fx, fy, u) in [(10.25, 7.5, (0.3, 0.8)), (63.9, 0.1, (0.9, 0.1))] {
                let u = glam::DVec2::new(u.0, u.1);
                let ray = if aperture > 0.0 {
                    film.lens_ray(fx, fy, u)
                } else {
                    film.ray(fx, fy)
                };
                let c = film.connect(ray.at(5.0), u).unwrap();
                assert!((c.film.0 - fx).abs() < 1e-9 && (c.film.1 - fy).abs() < 1e-9);
                assert!((c.lens - ray.origin).length() < 1e-12);
                assert!((c.distance - 5.0).abs() < 1e-12);
                assert!((c.direction - ray.direction).length() < 1e-12);
            }
        }
    }

    /// The importance integrates to 1 over the film: `A cos^3` is the solid angle a unit of
    /// film area subtends, so `importance * dA / dω` is 1 at the centre (cos 1) and off-axis.
    #[test]
    fn importance_is_one_over_the_film_area_at_the_centre() {
        let cam = camera(0.0);
        let film = cam.film();
        let c = film
            .connect(cam.position + 2.0 * cam.forward, glam::DVec2::ZERO)
            .unwrap();
        let half_h = 20f64.to_radians().tan();
        let area = 4.0 * half_h * half_h * 64.0 / 48.0;
        assert!((c.importance * area - 1.0).abs() < 1e-12);
        assert_eq!(c.pixel(), (32, 24));
        // Behind the camera and off the film: no connection.
        assert!(
            film.connect(cam.position - cam.forward, glam::DVec2::ZERO)
                .is_none()
        );
        assert!(
            film.connect(cam.position + DVec3::new(5.0, 0.0, -1.0), glam::DVec2::ZERO)
                .is_none()
        );
    }
}
