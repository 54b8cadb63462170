//! The diagram plane: how it is chosen, its 2D frame, and the world-to-canvas mapping.

use crate::scene::Scene;
use crate::tree::{NodeId, RayKind, RayTree};
use glam::{DVec2, DVec3};

/// Which plane to slice the scene with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PlaneSpec {
    /// The plane of incidence at the camera ray's first hit, or the plane through a ray of the
    /// first bounce and the camera ray when that plane holds clearly more of the pixel's light
    /// (a shadow ray through a translucent ball): see `plane_pick`.
    Auto,
    /// The plane of incidence at the camera ray's first hit (camera ray and surface normal).
    Incidence,
    /// The plane through a ray and its parent ray (for a reflected or refracted ray this is the
    /// plane of incidence at the parent's hit; for a camera ray, the plane of incidence at its
    /// hit).
    Ray(NodeId),
    /// The plane through the camera ray and the camera's up vector.
    Camera,
    /// `x = value` (axis 0), `y = value` (1) or `z = value` (2).
    Axis {
        /// 0, 1 or 2.
        axis: usize,
        /// The coordinate.
        value: f64,
    },
    /// Through `point` with normal `normal` (need not be unit length).
    Explicit {
        /// A point on the plane.
        point: DVec3,
        /// Its normal.
        normal: DVec3,
    },
}

impl PlaneSpec {
    /// Parse `auto`, `incidence`, `camera`, `ray=N`, `x=V`, `y=V`, `z=V` or
    /// `PX,PY,PZ,NX,NY,NZ`.
    pub fn parse(s: &str) -> Result<Self, String> {
        let s = s.trim();
        match s {
            "auto" => return Ok(Self::Auto),
            "incidence" => return Ok(Self::Incidence),
            "camera" => return Ok(Self::Camera),
            _ => {}
        }
        if let Some((axis, value)) = s.split_once('=') {
            if axis.trim() == "ray" {
                let id: u32 = value
                    .trim()
                    .parse()
                    .map_err(|_| format!("ray={value}: expected a node id (a whole number)"))?;
                return Ok(Self::Ray(NodeId(id)));
            }
            let axis = match axis.trim() {
                "x" | "X" => 0,
                "y" | "Y" => 1,
                "z" | "Z" => 2,
                a => return Err(format!("unknown axis {a:?} (expected x, y or z)")),
            };
            let value: f64 = value
                .trim()
                .parse()
                .map_err(|_| format!("{value:?} is not a number"))?;
            if !value.is_finite() {
                return Err(format!("{value} is not finite"));
            }
            return Ok(Self::Axis { axis, value });
        }
        let nums: Vec<f64> = s
            .split(',')
            .map(|p| p.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| {
                format!(
                    "expected auto, incidence, camera, ray=N, x=V, y=V, z=V or PX,PY,PZ,NX,NY,NZ; got {s:?}"
                )
            })?;
        if nums.len() != 6 || nums.iter().any(|v| !v.is_finite()) {
            return Err(format!(
                "expected six finite numbers PX,PY,PZ,NX,NY,NZ; got {s:?}"
            ));
        }
        let normal = DVec3::new(nums[3], nums[4], nums[5]);
        if normal.length() < 1e-12 {
            return Err("the plane normal must not be zero".to_string());
        }
        Ok(Self::Explicit {
            point: DVec3::new(nums[0], nums[1], nums[2]),
            normal,
        })
    }
}

/// The diagram plane with an in-plane frame (`u` right, `v` up) and the canvas mapping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneFrame {
    /// A point on the plane (the origin of plane coordinates).
    pub origin: DVec3,
    /// Unit in-plane axis drawn to the right.
    pub u: DVec3,
    /// Unit in-plane axis drawn upwards.
    pub v: DVec3,
    /// Unit normal, `u x v`.
    pub normal: DVec3,
    /// Pixels per world unit.
    pub scale: f64,
    /// Plane coordinates shown at `canvas_center`.
    pub plane_center: DVec2,
    /// Canvas point of `plane_center`.
    pub canvas_center: DVec2,
}

impl PlaneFrame {
    /// A frame through `origin` with unit `normal`; `v` follows `up_hint` projected into the
    /// plane (or any in-plane direction), and `u` is flipped so that `right_hint` points right.
    #[must_use]
    pub fn new(origin: DVec3, normal: DVec3, up_hint: DVec3, right_hint: DVec3) -> Self {
        let mut n = normal.normalize();
        let project = |d: DVec3| (d - d.dot(n) * n).try_normalize();
        let v = project(up_hint)
            .filter(|p| p.dot(up_hint.normalize_or_zero()).abs() > 0.05)
            .or_else(|| project(DVec3::Y))
            .or_else(|| project(DVec3::Z))
            .unwrap_or(DVec3::X);
        let mut u = v.cross(n);
        if u.dot(right_hint) < 0.0 {
            u = -u;
            n = -n;
        }
        Self {
            origin,
            u,
            v,
            normal: n,
            scale: 1.0,
            plane_center: DVec2::ZERO,
            canvas_center: DVec2::ZERO,
        }
    }

    /// Plane coordinates `(x, y)` of the orthogonal projection of `p`.
    #[must_use]
    pub fn plane_coords(&self, p: DVec3) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(d.dot(self.u), d.dot(self.v))
    }

    /// Signed distance of `p` from the plane.
    #[must_use]
    pub fn distance(&self, p: DVec3) -> f64 {
        (p - self.origin).dot(self.normal)
    }

    /// Canvas point of plane coordinates `q`.
    #[must_use]
    pub fn plane_to_canvas(&self, q: DVec2) -> DVec2 {
        let d = (q - self.plane_center) * self.scale;
        self.canvas_center + DVec2::new(d.x, -d.y)
    }

    /// Plane coordinates of canvas point `c`.
    #[must_use]
    pub fn canvas_to_plane(&self, c: DVec2) -> DVec2 {
        let d = (c - self.canvas_center) / self.scale;
        self.plane_center + DVec2::new(d.x, -d.y)
    }

    /// Canvas point of the projection of world point `p`.
    #[must_use]
    pub fn to_canvas(&self, p: DVec3) -> DVec2 {
        self.plane_to_canvas(self.plane_coords(p))
    }

    /// The projection of world direction `d` in canvas axes (y down), not normalized.
    #[must_use]
    pub fn dir_to_canvas(&self, d: DVec3) -> DVec2 {
        DVec2::new(d.dot(self.u), -d.dot(self.v))
    }
}

/// The chosen plane and a sentence saying how it was chosen.
#[must_use]
pub fn choose(
    spec: PlaneSpec,
    scene: &Scene,
    tree: &RayTree,
    sample: usize,
) -> (PlaneFrame, String) {
    let cam = &scene.camera;
    let root = tree
        .samples
        .get(sample)
        .map(|s| tree.node(s.root))
        .filter(|n| n.kind == RayKind::Camera);
    let (eye, dir) = root.map_or((cam.position, cam.forward), |r| (r.origin, r.direction));
    let right = dir.cross(cam.up).try_normalize().unwrap_or(cam.right);
    let camera_plane = || {
        let n = dir.cross(cam.up).try_normalize().unwrap_or(cam.right);
        (
            PlaneFrame::new(eye, n, DVec3::Y, dir),
            "through the camera ray and the camera's up vector".to_string(),
        )
    };
    match spec {
        PlaneSpec::Ray(id) if id.index() < tree.nodes.len() => {
            super::plane_pick::through_ray(scene, tree, id)
        }
        PlaneSpec::Incidence | PlaneSpec::Auto | PlaneSpec::Ray(_) => {
            let Some(hit) = root.and_then(|r| r.hit.as_ref()) else {
                let (f, text) = camera_plane();
                return (
                    f,
                    format!("{text} (the camera ray misses: no plane of incidence)"),
                );
            };
            match dir.cross(hit.normal).try_normalize() {
                Some(n) if dir.cross(hit.normal).length() > 1e-6 => (
                    PlaneFrame::new(hit.point, n, DVec3::Y, dir),
                    format!("plane of incidence at {}", hit.object_name),
                ),
                _ => {
                    let (f, text) = camera_plane();
                    (
                        f,
                        format!(
                            "{text} (normal incidence on {}: any plane contains the normal)",
                            hit.object_name
                        ),
                    )
                }
            }
        }
        PlaneSpec::Camera => camera_plane(),
        PlaneSpec::Axis { axis, value } => {
            let mut normal = DVec3::ZERO;
            normal[axis] = 1.0;
            let mut point = DVec3::ZERO;
            point[axis] = value;
            let up = if axis == 1 { -DVec3::Z } else { DVec3::Y };
            let name = ["x", "y", "z"][axis];
            (
                PlaneFrame::new(point, normal, up, right),
                format!("plane {name} = {value}"),
            )
        }
        PlaneSpec::Explicit { point, normal } => (
            PlaneFrame::new(point, normal, cam.up, right),
            format!(
                "plane through ({:.3}, {:.3}, {:.3}) with normal ({:.3}, {:.3}, {:.3})",
                point.x, point.y, point.z, normal.x, normal.y, normal.z
            ),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_form_and_rejects_junk() {
        assert_eq!(PlaneSpec::parse("incidence"), Ok(PlaneSpec::Incidence));
        assert_eq!(PlaneSpec::parse("camera"), Ok(PlaneSpec::Camera));
        assert_eq!(
            PlaneSpec::parse("y=0.5"),
            Ok(PlaneSpec::Axis {
                axis: 1,
                value: 0.5
            })
        );
        assert_eq!(
            PlaneSpec::parse("0,1,2,0,0,3"),
            Ok(PlaneSpec::Explicit {
                point: DVec3::new(0.0, 1.0, 2.0),
                normal: DVec3::new(0.0, 0.0, 3.0)
            })
        );
        for bad in ["w=1", "x=abc", "1,2,3", "0,0,0,0,0,0", "sideways", "x=inf"] {
            assert!(PlaneSpec::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn frame_is_orthonormal_and_maps_round_trip() {
        let mut f = PlaneFrame::new(DVec3::ONE, DVec3::new(1.0, 2.0, 0.5), DVec3::Y, DVec3::X);
        assert!((f.u.cross(f.v) - f.normal).length() < 1e-12);
        assert!(f.u.dot(f.v).abs() < 1e-12);
        f.scale = 50.0;
        f.canvas_center = DVec2::new(300.0, 200.0);
        let p = DVec3::new(0.3, -2.0, 4.0);
        let c = f.to_canvas(p);
        let back = f.canvas_to_plane(c);
        assert!((back - f.plane_coords(p)).length() < 1e-12);
        let q = f.origin + 2.0 * f.u + 3.0 * f.v + 0.7 * f.normal;
        assert!((f.distance(q) - 0.7).abs() < 1e-12);
        assert!((f.plane_coords(q) - DVec2::new(2.0, 3.0)).length() < 1e-12);
    }
}
