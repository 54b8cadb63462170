//! Validating a `mesh` object: its transform, and its file through the caller's loader.

use super::SceneError;
use super::check::Check;
use super::desc::{ObjectDesc, ScaleDesc};
use crate::geometry::Shape;
use crate::mesh::{Face, Mesh, MeshData, MeshNormals, Transform};
use glam::DAffine3;
use glam::DVec3;
use std::sync::Arc;

/// The caller's mesh-file reader (see [`super::Scene::from_json_with`]).
pub(super) type MeshLoader<'a> = &'a mut dyn FnMut(&str) -> Result<MeshData, String>;

/// The world-space mesh of object `o` at JSON path `p`.
pub(super) fn shape(
    ck: &Check,
    p: &str,
    o: &ObjectDesc,
    load_mesh: MeshLoader,
) -> Result<Shape, SceneError> {
    let ObjectDesc::Mesh {
        file,
        translate,
        rotate,
        scale,
        normals,
        ..
    } = o
    else {
        unreachable!("called for mesh objects only");
    };
    let scale = match *scale {
        ScaleDesc::Uniform(s) => DVec3::splat(ck.finite(&format!("{p}.scale"), s)?),
        ScaleDesc::Axes(v) => ck.vec(&format!("{p}.scale"), v)?,
    };
    if scale.cmpeq(DVec3::ZERO).any() {
        return ck.fail(format!("{p}.scale"), "must be non-zero on every axis");
    }
    let transform = Transform {
        translate: ck.vec(&format!("{p}.translate"), *translate)?,
        rotate_deg: ck.vec(&format!("{p}.rotate"), *rotate)?,
        scale,
    };
    let data = match load_mesh(file) {
        Ok(d) => d,
        Err(e) => return ck.fail(format!("{p}.file"), e),
    };
    match Mesh::new(&data, &transform.world_from_object(), *normals) {
        Some(m) => Ok(Shape::Mesh(Arc::new(m))),
        None => ck.fail(
            format!("{p}.file"),
            format!("{file}: every triangle has zero area"),
        ),
    }
}

/// The world-space mesh of the inline `trimesh` object `o` at JSON path `p`.
pub(super) fn inline(ck: &Check, p: &str, o: &ObjectDesc) -> Result<Shape, SceneError> {
    let ObjectDesc::Trimesh {
        positions,
        indices,
        normals,
        ..
    } = o
    else {
        unreachable!("called for trimesh objects only");
    };
    let mut data = MeshData::default();
    // Checked in bulk; the path is formatted only for the first bad entry.
    let finite = |v: &[f64; 3]| v.iter().all(|c| c.is_finite());
    if let Some(k) = positions.iter().position(|v| !finite(v)) {
        ck.vec(&format!("{p}.positions[{k}]"), positions[k])?;
    }
    data.positions = positions.iter().map(|&v| DVec3::from(v)).collect();
    let n = positions.len();
    if let Some(ns) = normals {
        if ns.len() != n {
            return ck.fail(
                format!("{p}.normals"),
                format!("has {} normals for {n} positions", ns.len()),
            );
        }
        if let Some(k) = ns.iter().position(|v| !finite(v)) {
            ck.vec(&format!("{p}.normals[{k}]"), ns[k])?;
        }
        data.normals = ns.iter().map(|&v| DVec3::from(v)).collect();
    }
    for (k, t) in indices.iter().enumerate() {
        if let Some(bad) = t.iter().find(|&&i| i as usize >= n) {
            return ck.fail(
                format!("{p}.indices[{k}]"),
                format!("index {bad} out of range ({n} positions)"),
            );
        }
        data.faces.push(Face {
            vertices: *t,
            normals: normals.as_ref().map(|_| *t),
        });
    }
    match Mesh::new(&data, &DAffine3::IDENTITY, MeshNormals::File) {
        Some(m) => Ok(Shape::Mesh(Arc::new(m))),
        None => ck.fail(
            format!("{p}.indices"),
            "every triangle has zero area (or there are none)",
        ),
    }
}
