//! A subpath vertex and the densities BDPT's MIS weights are made of (pbrt-v3 `bdpt.h`,
//! `Vertex`; Veach 1997, section 10.2): forward and reverse densities per unit area, the
//! conversion from solid angle, and the light's emission and origin densities.

use crate::bsdf::Bsdf;
use crate::interaction::SurfaceId;
use crate::lights::Light;
use crate::math::Rgb;
use crate::tree::NodeId;
use glam::DVec3;
use std::f64::consts::PI;

/// What a vertex is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Kind {
    /// The lens point (the eye of a pinhole).
    Camera,
    /// A light subpath's first vertex (or a light sampled for s = 1): light `index` of the
    /// light sampler.
    Light {
        /// Index in the light sampler.
        index: usize,
    },
    /// A surface hit.
    Surface,
}

/// A vertex of a camera or light subpath.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Vertex {
    pub kind: Kind,
    pub p: DVec3,
    /// Geometric normal; zero where the vertex is on no surface (camera, point and directional
    /// lights).
    pub ng: DVec3,
    /// Shading normal (the geometric one without a smooth mesh).
    pub ns: DVec3,
    /// Unit direction back along the subpath (surface vertices).
    pub wo: DVec3,
    /// Throughput arriving at the vertex (a light vertex: `Le / pdf_fwd`).
    pub beta: Rgb,
    /// Scattered by a delta lobe (no connection can use it).
    pub delta: bool,
    /// Density of this vertex per unit area from its subpath's previous vertex.
    pub pdf_fwd: f64,
    /// Density of this vertex per unit area from the next vertex, as the other subpath would
    /// sample it.
    pub pdf_rev: f64,
    pub bsdf: Bsdf,
    /// A smooth shading normal (Veach's adjoint correction applies).
    pub smooth: bool,
    /// Emitted radiance towards `wo` (surface vertices on an emitter's outer side).
    pub le: Rgb,
    /// The area light this surface vertex lies on (index in the light sampler).
    pub emitter: Option<usize>,
    /// A point or directional light (only light sampling finds it).
    pub delta_light: bool,
    /// A directional light: at infinity, densities in solid angle.
    pub infinite: bool,
    /// The surface (for offsets).
    pub from: Option<SurfaceId>,
    /// The recorded ray that arrived here (recording only).
    pub id: Option<NodeId>,
    /// The event by which the subpath left this vertex (its light path expression letter).
    pub event: &'static str,
}

impl Vertex {
    /// A vertex of `kind` at `p` with everything else empty.
    pub fn at(kind: Kind, p: DVec3) -> Self {
        Self {
            kind,
            p,
            ng: DVec3::ZERO,
            ns: DVec3::ZERO,
            wo: DVec3::ZERO,
            beta: Rgb::ONE,
            delta: false,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
            bsdf: Bsdf::EMPTY,
            smooth: false,
            le: Rgb::ZERO,
            emitter: None,
            delta_light: false,
            infinite: false,
            from: None,
            id: None,
            event: "",
        }
    }

    /// On a surface (geometric normal known).
    pub fn on_surface(&self) -> bool {
        self.ng != DVec3::ZERO
    }

    /// Whether a connection can use this vertex: a surface with a non-delta lobe, the camera,
    /// or a light that does not emit along one direction only.
    pub fn connectible(&self) -> bool {
        match self.kind {
            Kind::Surface => !self.bsdf.is_delta() && self.bsdf.lobes().next().is_some(),
            Kind::Camera => true,
            Kind::Light { .. } => !self.infinite,
        }
    }

    /// A solid-angle density `pdf` of the direction from this vertex to `next`, per unit area
    /// at `next` (`|cos| / d^2`; unchanged towards a light at infinity).
    pub fn convert_density(&self, pdf: f64, next: &Vertex) -> f64 {
        if next.infinite {
            return pdf;
        }
        let w = next.p - self.p;
        let d2 = w.length_squared();
        if d2 == 0.0 {
            return 0.0;
        }
        let cos = if next.on_surface() {
            next.ng.dot(w / d2.sqrt()).abs()
        } else {
            1.0
        };
        pdf * cos / d2
    }

    /// The BSDF `f` from this vertex towards `next`, the subpath arriving along `wo`; a light
    /// subpath's (`importance`) with Veach's adjoint shading-normal factor.
    pub fn f(&self, next: &Vertex, importance: bool) -> Rgb {
        let wi = (next.p - self.p).normalize_or_zero();
        let f = self.bsdf.eval(self.wo, wi);
        if importance && self.smooth {
            let num = self.wo.dot(self.ns).abs() * wi.dot(self.ng).abs();
            let den = self.wo.dot(self.ng).abs() * wi.dot(self.ns).abs();
            if den == 0.0 {
                return Rgb::ZERO;
            }
            return f * (num / den);
        }
        f
    }

    /// The density per unit area at `next` with which light `light` emits from this vertex
    /// (on it) towards `next` (pbrt-v3 `Vertex::PdfLight`); for a light at infinity the density
    /// of its disc of radius `radius`.
    pub fn pdf_light(&self, light: &Light<'_>, next: &Vertex, radius: f64) -> f64 {
        let w = next.p - self.p;
        let d2 = w.length_squared();
        if d2 == 0.0 {
            return 0.0;
        }
        let w = w / d2.sqrt();
        let mut pdf = if self.infinite {
            // The disc covers the bounded objects' sphere: a point outside its cylinder (an
            // infinite plane beyond the objects) is not lit by the light's subpaths, only by
            // light sampling (s = 1).
            match *light {
                Light::Directional {
                    direction, center, ..
                } => {
                    let r = next.p - center;
                    let off_axis = r - r.dot(direction) * direction;
                    if off_axis.length_squared() > radius * radius {
                        // Not 0, which the MIS ratios read as a delta density (`remap0`):
                        // the strategy is impossible, so its ratio must vanish.
                        f64::MIN_POSITIVE
                    } else {
                        1.0 / (PI * radius * radius)
                    }
                }
                _ => 1.0 / (PI * radius * radius),
            }
        } else {
            let normal = self.on_surface().then_some(self.ng);
            light.pdf_le(self.p, normal, w).1 / d2
        };
        if next.on_surface() {
            pdf *= next.ng.dot(w).abs();
        }
        pdf
    }

    /// The density per unit area of this light vertex's position (pbrt-v3
    /// `Vertex::PdfLightOrigin`): the light's selection probability times its position
    /// density; 0 for a light at infinity (a delta direction).
    pub fn pdf_light_origin(&self, light: &Light<'_>, p_choose: f64, next: &Vertex) -> f64 {
        let _ = next;
        if self.infinite {
            return 0.0;
        }
        // The position density alone (pbrt's `pdfPos` does not depend on the direction).
        let pos = match light {
            Light::Area { shape, .. } => 1.0 / shape.area(),
            Light::Point { .. } => 1.0,
            Light::Directional { radius, .. } => 1.0 / (PI * radius * radius),
        };
        if pos.is_finite() { pos * p_choose } else { 0.0 }
    }
}
