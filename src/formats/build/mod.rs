//! What both front-ends share: placing shapes under arbitrary 4x4 transforms (spheres stay
//! spheres under similarities, parallelograms stay quads under any affine map, everything else
//! is baked into a world-space triangle mesh with its winding and normals carried over), naming
//! materials, and assembling the camera.
//!
//! Sides: a shape's outward side is defined in its own (object) space. A transform that swaps
//! handedness (negative determinant) would turn the world-space winding inside out, so the
//! winding is swapped back, as pbrt-v4 does (`transformSwapsHandedness` in `Triangle` and
//! `BilinearPatch`); `ReverseOrientation` (pbrt) or `flip_normals` (Mitsuba) swaps it once more.

use super::Note;
use super::xform::{is_axis_scale, similarity_scale};
use crate::scene::desc::{
    CameraDesc, LightDesc, MaterialDesc, ObjectDesc, SceneDesc, Settings, Triple,
};
use glam::{DAffine3, DMat3, DVec3};
use std::collections::BTreeMap;

/// Segments of a tessellated disk (pbrt `disk`, Mitsuba `disk`): the polygon's area is
/// `sin(2 pi / N) N / (2 pi)` = 99.8 % of the disk's.
pub const DISK_SEGMENTS: u32 = 96;
/// Subdivisions of the icosphere a non-uniformly scaled sphere is baked into (1280 triangles).
pub const SPHERE_SUBDIVISIONS: u32 = 3;

/// Material, name and orientation of a shape being placed.
#[derive(Clone, Debug)]
pub struct Surface {
    /// Material name (already in [`Builder::materials`]).
    pub material: String,
    /// Display name.
    pub name: Option<String>,
    /// `ReverseOrientation` / `flip_normals`: the outward side is the other one.
    pub flip: bool,
}

/// The camera as a file describes it, in world space.
#[derive(Clone, Copy, Debug)]
pub struct CameraSpec {
    /// Eye position.
    pub position: DVec3,
    /// Viewing direction.
    pub forward: DVec3,
    /// The direction that is up in the image.
    pub up: DVec3,
    /// The direction that is right in the image.
    pub right: DVec3,
    /// Vertical field of view, degrees.
    pub fov_y: f64,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Thin-lens radius.
    pub aperture: f64,
    /// Focus distance (only meaningful with an aperture).
    pub focus: Option<f64>,
}

/// The scene being assembled.
#[derive(Debug, Default)]
pub struct Builder {
    /// Named materials.
    pub materials: BTreeMap<String, MaterialDesc>,
    /// Objects in file order.
    pub objects: Vec<ObjectDesc>,
    /// Point and directional lights.
    pub lights: Vec<LightDesc>,
    /// Radiance of rays that leave the scene.
    pub background: Triple,
    /// Tracer settings.
    pub settings: Settings,
    /// Approximations so far.
    pub notes: Vec<Note>,
    /// Applied after every placement: the identity, or the mirror that makes a left-handed
    /// camera right-handed ([`Builder::set_camera`]).
    world: Option<DAffine3>,
    camera: Option<CameraDesc>,
    vertices: usize,
    vertex_limit: usize,
}

impl Builder {
    /// An empty scene allowing `vertex_limit` vertices in all; the settings are the path
    /// integrator's with area lights sampled (what an imported physically based scene wants).
    #[must_use]
    pub fn new(vertex_limit: usize) -> Self {
        let settings = Settings {
            integrator: crate::scene::IntegratorKind::Path,
            whitted: crate::scene::WhittedSettings {
                light_samples: Some(1),
                ..crate::scene::WhittedSettings::default()
            },
            ..Settings::default()
        };
        Self {
            settings,
            vertex_limit,
            ..Self::default()
        }
    }

    /// Record an approximation.
    pub fn note(&mut self, file: &str, line: usize, message: impl Into<String>) {
        self.notes.push(Note {
            file: file.to_string(),
            line,
            message: message.into(),
        });
    }

    /// Add material `desc` under `name` (made unique with `#2`, `#3`, ... unless an identical
    /// material already has the name); returns the name used.
    pub fn material(&mut self, name: &str, desc: MaterialDesc) -> String {
        let same = |a: &MaterialDesc, b: &MaterialDesc| {
            serde_json::to_value(a).ok() == serde_json::to_value(b).ok()
        };
        let mut candidate = name.to_string();
        for k in 2.. {
            match self.materials.get(&candidate) {
                None => break,
                Some(m) if same(m, &desc) => return candidate,
                Some(_) => candidate = format!("{name}#{k}"),
            }
        }
        self.materials.insert(candidate.clone(), desc);
        candidate
    }

    /// The camera; a camera whose image-right is on the left of `forward x up` (pbrt's
    /// left-handed `LookAt` without `Scale -1 1 1`) cannot be expressed by raytree's camera, so
    /// the whole world is mirrored about the camera's vertical plane instead: the image is the
    /// one the file's renderer makes. Call before placing shapes.
    pub fn set_camera(&mut self, c: &CameraSpec, file: &str, line: usize) {
        let forward = c.forward.normalize();
        let right = forward.cross(c.up).normalize();
        if c.right.dot(right) < 0.0 {
            let r = right;
            let linear = DMat3::IDENTITY - 2.0 * DMat3::from_cols(r * r.x, r * r.y, r * r.z);
            let translation = 2.0 * c.position.dot(r) * r;
            self.world = Some(DAffine3::from_mat3_translation(linear, translation));
            self.note(
                file,
                line,
                "the camera is left-handed in world space (image right is -(forward x up)): \
                 raytree mirrors the world about the camera's vertical plane, so the image is \
                 the file's and the converted coordinates are mirrored",
            );
        }
        if c.forward.normalize().dot(c.up.normalize()).abs() > 1e-9 {
            self.note(
                file,
                line,
                "the camera transform is sheared (up not orthogonal to forward): raytree uses \
                 forward and the up direction's orthogonal part",
            );
        }
        let look_at = c.position + forward;
        self.camera = Some(CameraDesc {
            position: c.position.to_array(),
            look_at: look_at.to_array(),
            up: c.up.normalize().to_array(),
            fov_y: c.fov_y,
            width: c.width,
            height: c.height,
            aperture_radius: c.aperture,
            focus_distance: if c.aperture > 0.0 { c.focus } else { None },
        });
    }

    /// The world map applied to every placement.
    fn world(&self, m: &DAffine3) -> DAffine3 {
        self.world.map_or(*m, |w| w * *m)
    }

    /// Whether the camera was set.
    #[must_use]
    pub fn has_camera(&self) -> bool {
        self.camera.is_some()
    }

    /// A point light at `p` (world space before the camera mirror).
    pub fn point_light(&mut self, p: DVec3, intensity: Triple) {
        let position = self.world(&DAffine3::IDENTITY).transform_point3(p);
        self.lights.push(LightDesc::Point {
            position: position.to_array(),
            intensity,
            name: None,
        });
    }

    /// A spot light at `p` pointing along `axis` (world space before the camera mirror): its
    /// cone and falloff half-angles in degrees, already checked by the front-end.
    pub fn spot_light(
        &mut self,
        (p, axis): (DVec3, DVec3),
        intensity: Triple,
        (cone, falloff): (f64, f64),
        profile: crate::lights::SpotProfile,
    ) {
        let m = self.world(&DAffine3::IDENTITY);
        self.lights.push(LightDesc::Spot {
            position: m.transform_point3(p).to_array(),
            direction: Some(m.transform_vector3(axis).to_array()),
            look_at: None,
            intensity,
            cone_angle: cone,
            falloff_angle: Some(falloff),
            profile,
            name: None,
        });
    }

    /// A directional light travelling along `d`.
    pub fn directional_light(&mut self, d: DVec3, irradiance: Triple) {
        let d = self.world(&DAffine3::IDENTITY).transform_vector3(d);
        self.lights.push(LightDesc::Directional {
            direction: d.to_array(),
            irradiance,
            name: None,
        });
    }

    /// Count `n` more vertices against the limit.
    fn count(&mut self, n: usize) -> Result<(), String> {
        self.vertices = self.vertices.saturating_add(n);
        if self.vertices > self.vertex_limit {
            return Err(format!(
                "the scene has more than {} vertices (the limit)",
                self.vertex_limit
            ));
        }
        Ok(())
    }

    /// A sphere of `radius` at `center` in object space: exact under a similarity, otherwise an
    /// icosphere mesh (and the returned note says so).
    ///
    /// # Errors
    /// A non-finite or non-positive radius.
    pub fn sphere(
        &mut self,
        center: DVec3,
        radius: f64,
        m: &DAffine3,
        s: &Surface,
    ) -> Result<Option<String>, String> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(format!("radius must be a finite number > 0, got {radius}"));
        }
        let w = self.world(m);
        let note = s.flip.then(|| {
            "a sphere with reversed orientation: raytree's spheres face outward".to_string()
        });
        if let Some(k) = similarity_scale(&w.matrix3) {
            self.objects.push(ObjectDesc::Sphere {
                center: w.transform_point3(center).to_array(),
                radius: radius * k,
                material: s.material.clone(),
                name: s.name.clone(),
            });
            return Ok(note);
        }
        let ico = crate::mesh::generate::icosphere(SPHERE_SUBDIVISIONS);
        let local = DAffine3::from_scale_rotation_translation(
            DVec3::splat(radius),
            glam::DQuat::IDENTITY,
            center,
        );
        let full = *m * local;
        let tris: Vec<[u32; 3]> = ico.faces.iter().map(|f| f.vertices).collect();
        self.push_mesh(&ico.positions, &tris, Some(&ico.positions), &full, s, false)?;
        Ok(Some(format!(
            "a sphere under a non-uniform or sheared transform is baked into {} triangles",
            tris.len()
        )))
    }

    /// The parallelogram `corner + a u + b v` (`a, b` in `[0, 1]`) in object space, outward
    /// along `u x v`: exact under any affine map.
    pub fn quad(&mut self, corner: DVec3, u: DVec3, v: DVec3, m: &DAffine3, s: &Surface) {
        let m = self.world(m);
        let (c, mut u, mut v) = (
            m.transform_point3(corner),
            m.transform_vector3(u),
            m.transform_vector3(v),
        );
        if (m.matrix3.determinant() < 0.0) != s.flip {
            std::mem::swap(&mut u, &mut v);
        }
        self.objects.push(ObjectDesc::Quad {
            corner: c.to_array(),
            edge_u: u.to_array(),
            edge_v: v.to_array(),
            material: s.material.clone(),
            name: s.name.clone(),
        });
    }

    /// An axis-aligned box in object space: a box under a per-axis scale and translation, a
    /// 12-triangle mesh otherwise.
    ///
    /// # Errors
    /// Too many vertices in the scene.
    pub fn cube(
        &mut self,
        min: DVec3,
        max: DVec3,
        m: &DAffine3,
        s: &Surface,
    ) -> Result<(), String> {
        let w = self.world(m);
        if is_axis_scale(&w.matrix3) && !s.flip {
            let (a, b) = (w.transform_point3(min), w.transform_point3(max));
            self.objects.push(ObjectDesc::Box {
                min: a.min(b).to_array(),
                max: a.max(b).to_array(),
                material: s.material.clone(),
                name: s.name.clone(),
            });
            return Ok(());
        }
        let (p, t) = box_triangles(min, max);
        self.push_mesh(&p, &t, None, m, s, true)
    }

    /// A triangle mesh in object space (`normals`, when given, one per position). Two
    /// triangles forming a parallelogram become a quad and twelve tiling an axis-aligned box
    /// become a box (the same surfaces, intersected and sampled as raytree's own shapes).
    ///
    /// # Errors
    /// Indices out of range, a normal count that differs from the position count, or too
    /// many vertices.
    pub fn mesh(
        &mut self,
        positions: &[DVec3],
        tris: &[[u32; 3]],
        normals: Option<&[DVec3]>,
        m: &DAffine3,
        s: &Surface,
    ) -> Result<(), String> {
        self.push_mesh(positions, tris, normals, m, s, true)
    }

    fn push_mesh(
        &mut self,
        positions: &[DVec3],
        tris: &[[u32; 3]],
        normals: Option<&[DVec3]>,
        m: &DAffine3,
        s: &Surface,
        recognise: bool,
    ) -> Result<(), String> {
        let n = positions.len();
        if let Some(bad) = tris.iter().flatten().find(|&&i| i as usize >= n) {
            return Err(format!(
                "vertex index {bad} out of range (the mesh has {n} vertices)"
            ));
        }
        if let Some(ns) = normals
            && ns.len() != n
        {
            return Err(format!("{} normals for {n} vertices", ns.len()));
        }
        if positions.iter().any(|p| !p.is_finite()) {
            return Err("a vertex position is not finite".into());
        }
        self.count(n)?;
        let w = self.world(m);
        let world: Vec<DVec3> = positions.iter().map(|&p| w.transform_point3(p)).collect();
        let swap = (w.matrix3.determinant() < 0.0) != s.flip;
        let tris: Vec<[u32; 3]> = tris
            .iter()
            .map(|&[a, b, c]| if swap { [a, c, b] } else { [a, b, c] })
            .collect();
        let normal_matrix = w.matrix3.inverse().transpose();
        let world_n: Option<Vec<DVec3>> = normals.map(|ns| {
            ns.iter()
                .map(|&x| {
                    let v = normal_matrix * x;
                    if s.flip { -v } else { v }
                })
                .collect()
        });
        if recognise && world_n.is_none() {
            if let Some(q) = as_quad(&world, &tris, s) {
                self.objects.push(q);
                return Ok(());
            }
            if let Some(b) = as_box(&world, &tris, s) {
                self.objects.push(b);
                return Ok(());
            }
        }
        self.objects.push(ObjectDesc::Trimesh {
            positions: world.iter().map(|p| p.to_array()).collect(),
            indices: tris,
            normals: world_n.map(|v| v.iter().map(|p| p.to_array()).collect()),
            material: s.material.clone(),
            name: s.name.clone(),
        });
        Ok(())
    }

    /// The scene; `None` when no camera was given.
    #[must_use]
    pub fn finish(self) -> Option<(SceneDesc, Vec<Note>)> {
        let camera = self.camera?;
        Some((
            SceneDesc {
                camera,
                background: self.background,
                ambient: [0.0; 3],
                materials: self.materials,
                objects: self.objects,
                lights: self.lights,
                settings: self.settings,
            },
            self.notes,
        ))
    }
}

/// The twelve outward-wound triangles of the box `[min, max]`.
#[must_use]
pub fn box_triangles(min: DVec3, max: DVec3) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let p: Vec<DVec3> = (0..8)
        .map(|i| {
            DVec3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            )
        })
        .collect();
    // Faces as quads (counter-clockwise seen from outside), two triangles each.
    let quads = [
        [0, 4, 6, 2], // -x
        [1, 3, 7, 5], // +x
        [0, 1, 5, 4], // -y
        [2, 6, 7, 3], // +y
        [0, 2, 3, 1], // -z
        [4, 5, 7, 6], // +z
    ];
    let t = quads
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .collect();
    (p, t)
}

/// Two triangles sharing a diagonal whose four corners form a parallelogram, wound the same
/// way: the quad with the first triangle's free corner as `corner`.
fn as_quad(p: &[DVec3], tris: &[[u32; 3]], s: &Surface) -> Option<ObjectDesc> {
    let [t1, t2] = tris else { return None };
    // Rotate t1 so its corner not in t2 comes first.
    let k = (0..3).find(|&k| !t2.contains(&t1[k]))?;
    let [e, a, b] = [t1[k], t1[(k + 1) % 3], t1[(k + 2) % 3]];
    let other = *t2.iter().find(|&&i| i != a && i != b)?;
    if !(t2.contains(&a) && t2.contains(&b)) || other == e {
        return None;
    }
    let (pe, pa, pb, po) = (
        p[e as usize],
        p[a as usize],
        p[b as usize],
        p[other as usize],
    );
    let (u, v) = (pa - pe, pb - pe);
    let n = u.cross(v);
    let scale = u.length().max(v.length());
    if n.length() <= 1e-12 * scale * scale || (pa + pb - pe - po).length() > 1e-12 * scale {
        return None;
    }
    let n2 = (p[t2[1] as usize] - p[t2[0] as usize]).cross(p[t2[2] as usize] - p[t2[0] as usize]);
    (n2.dot(n) > 0.0).then(|| ObjectDesc::Quad {
        corner: pe.to_array(),
        edge_u: u.to_array(),
        edge_v: v.to_array(),
        material: s.material.clone(),
        name: s.name.clone(),
    })
}

/// Twelve triangles on the eight corners of an axis-aligned box, each lying on a face of it,
/// wound outward, two to a face and covering it: the box.
fn as_box(p: &[DVec3], tris: &[[u32; 3]], s: &Surface) -> Option<ObjectDesc> {
    if tris.len() != 12 || p.len() != 8 {
        return None;
    }
    let lo = p.iter().fold(DVec3::INFINITY, |a, &b| a.min(b));
    let hi = p.iter().fold(DVec3::NEG_INFINITY, |a, &b| a.max(b));
    if !lo.cmplt(hi).all() {
        return None;
    }
    let corner = |v: DVec3| (0..3).all(|k| v[k] == lo[k] || v[k] == hi[k]);
    if !p.iter().all(|&v| corner(v)) {
        return None;
    }
    let mut area = [0.0f64; 6];
    for t in tris {
        let [a, b, c] = t.map(|i| p[i as usize]);
        let n = (b - a).cross(c - a);
        // The face: the axis all three share, at its min or max.
        let face = (0..3).find_map(|k| {
            if a[k] == b[k] && b[k] == c[k] {
                Some((k, a[k] == hi[k]))
            } else {
                None
            }
        })?;
        let (k, high) = face;
        if (n[k] > 0.0) != high || n[k] == 0.0 {
            return None;
        }
        area[2 * k + usize::from(high)] += 0.5 * n[k].abs();
    }
    let size = hi - lo;
    let want = [size.y * size.z, size.x * size.z, size.x * size.y];
    let covered = (0..6).all(|f| (area[f] - want[f / 2]).abs() <= 1e-12 * want[f / 2]);
    covered.then(|| ObjectDesc::Box {
        min: lo.to_array(),
        max: hi.to_array(),
        material: s.material.clone(),
        name: s.name.clone(),
    })
}

/// A disk of `radius` (hole of `inner`) at height `z`, outward along +z, as `N` segments.
#[must_use]
pub fn disk_triangles(radius: f64, inner: f64, z: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let n = DISK_SEGMENTS;
    let ring = |r: f64| -> Vec<DVec3> {
        (0..n)
            .map(|i| {
                let phi = std::f64::consts::TAU * f64::from(i) / f64::from(n);
                DVec3::new(r * phi.cos(), r * phi.sin(), z)
            })
            .collect()
    };
    let mut p = ring(radius);
    let mut t = Vec::new();
    if inner > 0.0 {
        p.extend(ring(inner));
        for i in 0..n {
            let j = (i + 1) % n;
            t.push([i, j, n + j]);
            t.push([i, n + j, n + i]);
        }
    } else {
        p.push(DVec3::new(0.0, 0.0, z));
        for i in 0..n {
            t.push([n, i, (i + 1) % n]);
        }
    }
    (p, t)
}

/// An OBJ mesh as positions, triangles and per-vertex normals: corners with their own normal
/// index become vertices of their own (`(position, normal)` pairs), so normals are per vertex.
/// Normals are kept only when every face has them.
#[must_use]
pub fn unify_obj(d: &crate::mesh::MeshData) -> (Vec<DVec3>, Vec<[u32; 3]>, Option<Vec<DVec3>>) {
    if d.faces.is_empty() || d.faces.iter().any(|f| f.normals.is_none()) {
        return (
            d.positions.clone(),
            d.faces.iter().map(|f| f.vertices).collect(),
            None,
        );
    }
    let mut index = std::collections::HashMap::new();
    let (mut p, mut n, mut t) = (Vec::new(), Vec::new(), Vec::new());
    for f in &d.faces {
        let ns = f.normals.expect("checked");
        let tri = [0, 1, 2].map(|k| {
            *index.entry((f.vertices[k], ns[k])).or_insert_with(|| {
                p.push(d.positions[f.vertices[k] as usize]);
                n.push(d.normals[ns[k] as usize]);
                (p.len() - 1) as u32
            })
        });
        t.push(tri);
    }
    (p, t, Some(n))
}

/// Angle-weighted vertex normals (Thürmer and Wüthrich 1998), what Mitsuba 3 computes for
/// meshes without normals (`Mesh::recompute_vertex_normals`); a vertex no triangle with area
/// touches gets +z.
#[must_use]
pub fn vertex_normals(p: &[DVec3], tris: &[[u32; 3]]) -> Vec<DVec3> {
    let mut n = vec![DVec3::ZERO; p.len()];
    for t in tris {
        let v = t.map(|i| p[i as usize]);
        let Some(face) = (v[1] - v[0]).cross(v[2] - v[0]).try_normalize() else {
            continue;
        };
        for k in 0..3 {
            let (a, b) = (v[(k + 1) % 3] - v[k], v[(k + 2) % 3] - v[k]);
            if let (Some(a), Some(b)) = (a.try_normalize(), b.try_normalize()) {
                n[t[k] as usize] += face * a.dot(b).clamp(-1.0, 1.0).acos();
            }
        }
    }
    n.into_iter()
        .map(|x| x.try_normalize().unwrap_or(DVec3::Z))
        .collect()
}

#[cfg(test)]
mod tests;
