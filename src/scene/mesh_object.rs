//! Validating a `mesh` object: its transform, and its file through the caller's loader.

use super::SceneError;
use super::check::Check;
use super::desc::{ObjectDesc, ScaleDesc};
use crate::geometry::Shape;
use crate::mesh::{Mesh, MeshData, Transform};
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
