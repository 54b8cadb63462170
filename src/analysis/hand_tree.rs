//! Hand-built path-integrator trees for the unit tests of [`super::samples`] and
//! [`super::firefly`]: a camera ray to a diffuse floor, its shadow ray, and a chain of sampled
//! continuations, with the factors the path tracer records.

use crate::bsdf::LobeKind;
use crate::math::Rgb;
use crate::scene::Settings;
use crate::tree::{EndReason, NodeId, PathInfo, Pdf, RayKind, RayNode, RayTree, SampleRecord};
use glam::DVec3;

/// A tree under construction.
pub struct HandTree {
    pub tree: RayTree,
}

impl HandTree {
    pub fn new() -> Self {
        Self {
            tree: RayTree {
                schema: crate::tree::TREE_SCHEMA.into(),
                pixel: [0, 0],
                settings: Settings::default(),
                radiance: Rgb::ZERO,
                samples: Vec::new(),
                nodes: Vec::new(),
                edge: None,
                splats: Vec::new(),
                splat_divisor: 0,
            },
        }
    }

    fn push(&mut self, parent: Option<NodeId>, kind: RayKind, path: PathInfo) -> NodeId {
        let id = NodeId(self.tree.nodes.len() as u32);
        let depth = parent.map_or(0, |p| {
            let d = self.tree.node(p).depth;
            if kind == RayKind::Shadow { d } else { d + 1 }
        });
        let mut n = RayNode::new(kind, depth, DVec3::ZERO, DVec3::ZERO, DVec3::Z);
        n.id = id;
        n.parent = parent;
        n.end = EndReason::Continued;
        n.path = Some(path);
        if let Some(p) = parent {
            self.tree.nodes[p.index()].children.push(id);
        }
        self.tree.nodes.push(n);
        id
    }

    /// A new sample: its camera ray (lpe `C`).
    pub fn sample(&mut self) -> NodeId {
        let root = self.push(None, RayKind::Camera, info("C", Rgb::ZERO));
        self.tree.samples.push(SampleRecord {
            index: self.tree.samples.len() as u32,
            film: [0.5, 0.5],
            root,
            radiance: Rgb::ZERO,
        });
        root
    }

    /// A shadow ray from `parent`'s hit: light pdf `pdf`, `f cos`, MIS weight, contribution.
    pub fn shadow(&mut self, parent: NodeId, lpe: &str, pdf: f64, mis: f64, c: Rgb) -> NodeId {
        let mut p = info(lpe, c);
        p.pdf = Some(Pdf::Density(pdf));
        p.bsdf_cos_pdf = Some(Rgb::splat(0.2));
        p.mis_weight = Some(mis);
        self.push(Some(parent), RayKind::Shadow, p)
    }

    /// A continuation from `parent`'s hit drawn from `lobe` (`pdf` `None` = delta) with weight
    /// `bsdf_cos_pdf`; `q` is the roulette survival probability taken at `parent`'s hit.
    // One bounce of a hand-built tree: every number a recorded bounce carries, named at the call.
    #[allow(clippy::too_many_arguments)]
    pub fn bounce(
        &mut self,
        parent: NodeId,
        lobe: LobeKind,
        lpe: &str,
        pdf: Option<f64>,
        w: f64,
        q: Option<f64>,
        c: Rgb,
    ) -> NodeId {
        let kind = match lobe {
            LobeKind::Diffuse => RayKind::Diffuse,
            LobeKind::SpecularTransmission | LobeKind::GlossyTransmission => RayKind::Refracted,
            _ => RayKind::Reflected,
        };
        let mut p = info(lpe, c);
        p.lobe = Some(lobe);
        p.pdf = Some(pdf.map_or(Pdf::Delta(crate::tree::DeltaTag::Delta), Pdf::Density));
        p.bsdf_cos_pdf = Some(Rgb::splat(w));
        p.mis_weight = lpe.ends_with(['L', 'B']).then_some(1.0);
        if let Some(q) = q
            && let Some(pp) = self.tree.nodes[parent.index()].path.as_mut()
        {
            pp.roulette = Some(crate::tree::Roulette {
                probability: q,
                survived: true,
            });
        }
        let id = self.push(Some(parent), kind, p);
        self.tree.nodes[id.index()].weight = Rgb::splat(w / q.unwrap_or(1.0));
        id
    }

    /// Set each sample's radiance to the sum of its contributions and the pixel to the mean.
    pub fn finish(mut self) -> RayTree {
        let t = &mut self.tree;
        let mut total = Rgb::ZERO;
        for k in 0..t.samples.len() {
            let sum = t
                .depth_first(t.samples[k].root)
                .iter()
                .filter_map(|id| t.node(*id).path.as_ref().map(|p| p.contribution))
                .fold(Rgb::ZERO, |a, b| a + b);
            t.samples[k].radiance = sum;
            total += sum;
        }
        t.radiance = total / t.samples.len().max(1) as f64;
        self.tree
    }
}

fn info(lpe: &str, contribution: Rgb) -> PathInfo {
    PathInfo {
        lobe: None,
        pdf: None,
        bsdf_cos_pdf: None,
        mis_weight: None,
        roulette: None,
        strategy: None,
        unweighted: None,
        contribution,
        lpe: lpe.into(),
    }
}

/// Samples of radiance `values` (grey), each a camera ray and a shadow ray `C<RD>L` carrying
/// it, behind a diffuse bounce that escapes (`C<RD>B`, nothing).
pub fn grey_samples(values: &[f64]) -> RayTree {
    let mut h = HandTree::new();
    for v in values {
        let root = h.sample();
        h.shadow(root, "C<RD>L", 1.0, 1.0, Rgb::splat(*v));
        h.bounce(
            root,
            LobeKind::Diffuse,
            "C<RD>B",
            Some(0.3),
            0.7,
            None,
            Rgb::ZERO,
        );
    }
    h.finish()
}
