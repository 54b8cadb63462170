//! Triangle meshes: plain vertex/face data (from OBJ text or a generator), a transform into
//! world space, a BVH over the triangles, and the queries the tracer and diagrams need.
//!
//! Sides: a triangle's outward (geometric) normal is `(b - a) x (c - a)` of its world-space
//! vertices. When the file gives vertex normals, a triangle whose winding disagrees with the
//! sum of its corner normals is re-wound (pbrt's rule: the shading normals say which side is
//! out). The geometric normal alone decides entering/leaving and the offset side; the shading
//! normal only shades (see [`shading`]).

mod emitter;
pub mod generate;
pub mod obj;
mod packed;
mod packet;
mod query;
pub mod shading;
pub(crate) mod triangle;

use crate::bvh::wide::WideBvh;
use crate::bvh::{Aabb, Bvh};
use glam::{DAffine3, DMat3, DVec3};
use packed::TriPack;
use serde::{Deserialize, Serialize};

pub use obj::{ObjError, parse_obj, parse_obj_read};

/// One triangle of [`MeshData`]: 0-based position indices and optional normal indices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Face {
    /// Indices into [`MeshData::positions`].
    pub vertices: [u32; 3],
    /// Indices into [`MeshData::normals`], when the file gives them for every corner.
    pub normals: Option<[u32; 3]>,
}

/// A mesh as read: object space, indexed, unvalidated geometry (indices are in range).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Vertex normals (need not be unit).
    pub normals: Vec<DVec3>,
    /// Triangles (polygons already fan-triangulated).
    pub faces: Vec<Face>,
}

/// Where shading normals come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MeshNormals {
    /// The file's vertex normals where every corner of a face has one; flat elsewhere.
    #[default]
    File,
    /// Flat: the geometric normal everywhere.
    Flat,
    /// Area-weighted averages of the faces around each vertex position (ignores the file's).
    Smooth,
}

/// Object-to-world placement: scale, then rotate about X, then Y, then Z (degrees; extrinsic
/// XYZ Euler angles, `R = Rz * Ry * Rx`), then translate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    /// Translation.
    pub translate: DVec3,
    /// Rotation angles in degrees about X, Y and Z.
    pub rotate_deg: DVec3,
    /// Per-axis scale (non-zero; a negative determinant mirrors and re-winds).
    pub scale: DVec3,
}

impl Default for Transform {
    fn default() -> Self {
        Self {
            translate: DVec3::ZERO,
            rotate_deg: DVec3::ZERO,
            scale: DVec3::ONE,
        }
    }
}

impl Transform {
    /// The affine map `world_from_object`.
    #[must_use]
    pub fn world_from_object(&self) -> DAffine3 {
        let r = self.rotate_deg;
        let rotation = DMat3::from_rotation_z(r.z.to_radians())
            * DMat3::from_rotation_y(r.y.to_radians())
            * DMat3::from_rotation_x(r.x.to_radians());
        DAffine3::from_mat3_translation(rotation * DMat3::from_diagonal(self.scale), self.translate)
    }
}

/// A world-space triangle mesh with its BVH. Triangles are stored in BVH leaf order, in `f64`
/// (exact tests, hit points) and as `f32` packs, one per BVH group (the fast filter).
#[derive(Clone, PartialEq)]
pub struct Mesh {
    tris: Vec<[DVec3; 3]>,
    corner_normals: Option<Vec<[DVec3; 3]>>,
    source: Vec<u32>,
    bounds: Aabb,
    bvh: WideBvh,
    packs: Vec<TriPack>,
    /// Running sums of the stored triangles' areas ([`Mesh::sample_emitter`]).
    area_cdf: Vec<f64>,
}

impl std::fmt::Debug for Mesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Mesh")
            .field("triangles", &self.tris.len())
            .field("smooth", &self.corner_normals.is_some())
            .field("bvh_nodes", &self.bvh.node_count())
            .field("groups", &self.packs.len())
            .field("stack", &self.bvh.stack)
            .finish()
    }
}

impl Mesh {
    /// Place `data` in the world and build the BVH. Zero-area triangles are dropped; `None`
    /// when none is left.
    #[must_use]
    pub fn new(
        data: &MeshData,
        world_from_object: &DAffine3,
        normals: MeshNormals,
    ) -> Option<Self> {
        let m = world_from_object.matrix3;
        let normal_matrix = m.inverse().transpose();
        let mirror = m.determinant() < 0.0;
        let p: Vec<DVec3> = data
            .positions
            .iter()
            .map(|&x| world_from_object.transform_point3(x))
            .collect();
        let file_n: Vec<DVec3> = data.normals.iter().map(|&n| normal_matrix * n).collect();
        let mut tris = Vec::with_capacity(data.faces.len());
        let mut corners = Vec::with_capacity(data.faces.len());
        let mut source = Vec::with_capacity(data.faces.len());
        for (i, f) in data.faces.iter().enumerate() {
            let [a, mut b, mut c] = f.vertices.map(|v| p[v as usize]);
            let mut n = f.normals.map(|k| k.map(|j| file_n[j as usize]));
            let mut geo = (b - a).cross(c - a);
            if geo.try_normalize().is_none() {
                continue;
            }
            let rewind = match (normals, n) {
                (MeshNormals::File, Some(ns)) => geo.dot(ns[0] + ns[1] + ns[2]) < 0.0,
                _ => mirror,
            };
            if rewind {
                std::mem::swap(&mut b, &mut c);
                n = n.map(|[x, y, z]| [x, z, y]);
                geo = -geo;
            }
            let unit = geo.normalize();
            let ns = match (normals, n) {
                (MeshNormals::File, Some(ns)) => ns.map(|x| x.try_normalize().unwrap_or(unit)),
                _ => [unit; 3],
            };
            tris.push([a, b, c]);
            corners.push(ns);
            source.push(i as u32);
        }
        if tris.is_empty() {
            return None;
        }
        let any_smooth = match normals {
            MeshNormals::Flat => false,
            MeshNormals::File => data.faces.iter().any(|f| f.normals.is_some()),
            MeshNormals::Smooth => {
                smooth_normals(data, &p, &tris, &source, mirror, &mut corners);
                true
            }
        };
        Some(Self::with_bvh(
            &tris,
            any_smooth.then_some(&corners[..]),
            &source,
        ))
    }

    /// Build the BVH over `tris` and store everything in its leaf order.
    fn with_bvh(tris: &[[DVec3; 3]], corners: Option<&[[DVec3; 3]]>, source: &[u32]) -> Self {
        let boxes: Vec<Aabb> = tris
            .iter()
            .map(|&[a, b, c]| Aabb {
                min: a.min(b).min(c),
                max: a.max(b).max(c),
            })
            .collect();
        let bvh = Bvh::build(&boxes);
        let reorder = |v: &[[DVec3; 3]]| bvh.order.iter().map(|&i| v[i as usize]).collect();
        let tris: Vec<[DVec3; 3]> = reorder(tris);
        let wide = WideBvh::from_binary(&bvh);
        let packs = wide
            .groups
            .iter()
            .map(|g| {
                let group = &tris[g.first as usize..(g.first + g.count) as usize];
                TriPack::new(group, wide.center)
            })
            .collect();
        let area_cdf = emitter::area_cdf(&tris);
        Self {
            tris,
            corner_normals: corners.map(reorder),
            source: bvh.order.iter().map(|&i| source[i as usize]).collect(),
            bounds: bvh.bounds().expect("a mesh has triangles"),
            bvh: wide,
            packs,
            area_cdf,
        }
    }

    /// This mesh under `x -> scale * x + translation` (`scale > 0`, for
    /// [`crate::scene::transformed`]): the same triangles, normals and face numbers, with the
    /// BVH rebuilt.
    #[must_use]
    pub fn scaled(&self, scale: f64, translation: DVec3) -> Self {
        let tris: Vec<[DVec3; 3]> = self
            .tris
            .iter()
            .map(|t| t.map(|v| scale * v + translation))
            .collect();
        Self::with_bvh(&tris, self.corner_normals.as_deref(), &self.source)
    }

    /// Number of triangles kept.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    /// Number of BVH nodes.
    #[must_use]
    pub fn bvh_nodes(&self) -> usize {
        self.bvh.node_count()
    }

    /// Stored triangle `i` (BVH order), world space, outward winding.
    #[must_use]
    pub fn triangle(&self, i: usize) -> [DVec3; 3] {
        self.tris[i]
    }

    /// The face index in the input data of stored triangle `i`.
    #[must_use]
    pub fn source_triangle(&self, i: usize) -> u32 {
        self.source[i]
    }

    /// World-space bounds.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Prefetch what testing group `g` of the wide BVH reads: its `f32` pack and the `f64`
    /// vertices of its triangles (72 bytes each: three addresses at most 40 bytes apart, the
    /// last in the final word). The `f64` test reads the vertices of about one triangle in four
    /// a ray's packs let through; fetching them with the pack, rather than once the filter has
    /// run, takes that cache miss off the ray's critical path (docs/mesh.md).
    #[inline(always)]
    pub(crate) fn prefetch_group(&self, g: usize) {
        self.packs[g].prefetch();
        let group = self.bvh.groups[g];
        for s in group.first as usize..(group.first + group.count) as usize {
            crate::bvh::prefetch(&self.tris[s]);
            crate::bvh::prefetch(&self.tris[s][2]);
        }
    }

    /// Prefetch the corner normals [`Mesh::shading_normal`] reads for triangle `i`, when a
    /// query finds it the closest so far (shading follows the query).
    #[inline(always)]
    pub(crate) fn prefetch_shading(&self, i: usize) {
        if let Some(corners) = &self.corner_normals {
            crate::bvh::prefetch(&corners[i][0]);
            crate::bvh::prefetch(&corners[i][1]);
            crate::bvh::prefetch(&corners[i][2].z);
        }
    }

    /// Unit outward geometric normal of stored triangle `i`.
    #[must_use]
    pub fn geometric_normal(&self, i: usize) -> DVec3 {
        let [a, b, c] = self.tris[i];
        (b - a).cross(c - a).normalize()
    }

    /// Interpolated unit shading normal of stored triangle `i` at `p` (outward side as given
    /// by the data, not yet checked against the ray); `None` for flat meshes.
    #[must_use]
    pub fn shading_normal(&self, i: usize, p: DVec3) -> Option<DVec3> {
        let corner = self.corner_normals.as_ref()?[i];
        let w = barycentric(&self.tris[i], p);
        (w.x * corner[0] + w.y * corner[1] + w.z * corner[2]).try_normalize()
    }

    /// Where the plane through `point` with normal `normal` cuts the mesh: one segment per
    /// triangle that straddles it (vertices exactly on the plane count as on the positive
    /// side, so a shared edge is never cut twice). Pure; for diagram slices.
    #[must_use]
    pub fn slice(&self, point: DVec3, normal: DVec3) -> Vec<[DVec3; 2]> {
        let mut out = Vec::new();
        for tri in &self.tris {
            let d = tri.map(|v| (v - point).dot(normal));
            let mut pts = [DVec3::ZERO; 2];
            let mut k = 0;
            for e in 0..3 {
                let (i, j) = (e, (e + 1) % 3);
                if (d[i] >= 0.0) != (d[j] >= 0.0) {
                    let s = d[i] / (d[i] - d[j]);
                    pts[k.min(1)] = tri[i] + s * (tri[j] - tri[i]);
                    k += 1;
                }
            }
            if k == 2 {
                out.push(pts);
            }
        }
        out
    }
}

/// Barycentric weights of `p` (assumed on the triangle's plane), by signed sub-areas.
fn barycentric(t: &[DVec3; 3], p: DVec3) -> DVec3 {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let inv = 1.0 / n.length_squared();
    let w0 = (t[1] - p).cross(t[2] - p).dot(n) * inv;
    let w1 = (t[2] - p).cross(t[0] - p).dot(n) * inv;
    DVec3::new(w0, w1, 1.0 - w0 - w1)
}

/// Area-weighted vertex normals by position index, written into each kept triangle's corners.
fn smooth_normals(
    data: &MeshData,
    p: &[DVec3],
    tris: &[[DVec3; 3]],
    source: &[u32],
    mirror: bool,
    corners: &mut [[DVec3; 3]],
) {
    let mut acc = vec![DVec3::ZERO; p.len()];
    for (k, &s) in source.iter().enumerate() {
        let [a, b, c] = tris[k];
        let area_normal = (b - a).cross(c - a);
        for v in data.faces[s as usize].vertices {
            acc[v as usize] += area_normal;
        }
    }
    for (k, &s) in source.iter().enumerate() {
        let mut v = data.faces[s as usize].vertices;
        if mirror {
            v.swap(1, 2);
        }
        let unit = (tris[k][1] - tris[k][0])
            .cross(tris[k][2] - tris[k][0])
            .normalize();
        corners[k] = v.map(|i| acc[i as usize].try_normalize().unwrap_or(unit));
    }
}

#[cfg(test)]
mod filter_tests;
#[cfg(test)]
mod packet_tests;
#[cfg(test)]
mod tests;
