//! The graph of states of the growth model: which specular object a ray can reach from
//! which side (see the parent module's documentation).

use crate::geometry::Shape;
use crate::math::FresnelModel;
use crate::scene::{Material, Scene};
use glam::DVec3;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Side {
    Outside,
    Inside,
}

/// The closed solid an object bounds, if any (planes: the half-space behind the normal).
pub(super) fn closed(shape: &Shape) -> bool {
    matches!(
        shape,
        Shape::Sphere { .. } | Shape::Box { .. } | Shape::Plane { .. }
    )
}

/// Whether `p` is strictly inside the solid of `shape`.
pub(super) fn point_inside(shape: &Shape, p: DVec3) -> bool {
    match *shape {
        Shape::Sphere { center, radius } => (p - center).length() < radius,
        Shape::Box { min, max } => p.cmpgt(min).all() && p.cmplt(max).all(),
        Shape::Plane { point, normal } => (p - point).dot(normal) < 0.0,
        Shape::Triangle { .. } | Shape::Quad { .. } | Shape::Mesh(_) => false,
    }
}

/// Whether object `b`'s bounds lie strictly inside object `a`'s solid.
pub(super) fn contains(a: &Shape, b: &Shape) -> bool {
    if !closed(a) {
        return false;
    }
    let Some((lo, hi)) = b.bounds() else {
        return false;
    };
    (0..8).all(|i| {
        let c = DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        point_inside(a, c)
    })
}

pub(super) fn volume(shape: &Shape) -> f64 {
    shape.bounds().map_or(f64::INFINITY, |(lo, hi)| {
        let d = hi - lo;
        d.x * d.y * d.z
    })
}

/// Whether a hit on `m` spawns two rays at once: transmissive with a Fresnel model (reflection
/// and refraction except under TIR) or with reflectivity. A rough material (`integrator::whitted::glossy`)
/// draws one ray per rough lobe below a path's first rough hit (which fans out
/// `glossy_samples` rays once, a constant factor), so it branches only with both lobes.
pub(super) fn branches(scene: &Scene, m: &Material) -> bool {
    if m.is_rough() {
        return m.is_transmissive() && m.reflectivity.max_element() > 0.0;
    }
    m.is_transmissive()
        && (scene.settings.whitted.fresnel != FresnelModel::None
            || m.reflectivity.max_element() > 0.0)
}

/// Region a ray is in: the world (`None`) or inside object `k`.
pub(super) type Region = Option<usize>;

pub(super) struct Graph<'a> {
    pub(super) scene: &'a Scene,
    /// Specular objects (indices into `scene.objects`).
    pub(super) specular: Vec<usize>,
    /// Innermost container of each object.
    pub(super) parent: Vec<Region>,
    /// States: (object, side).
    pub(super) states: Vec<(usize, Side)>,
    /// Per state, its children: each a list of successor states. One entry for a hit with one
    /// child (or alternatives), two for a branching hit.
    pub(super) children: Vec<Vec<Vec<usize>>>,
    pub(super) branching: Vec<bool>,
}

impl<'a> Graph<'a> {
    pub(super) fn new(scene: &'a Scene) -> Self {
        let objs = &scene.objects;
        let mat = |j: usize| scene.material_of(j);
        let specular: Vec<usize> = (0..objs.len())
            .filter(|&j| mat(j).is_transmissive() || mat(j).reflectivity.max_element() > 0.0)
            .collect();
        // Only specular objects' regions matter (non-specular ones have no state).
        let parent: Vec<Region> = (0..objs.len())
            .map(|j| {
                if !specular.contains(&j) {
                    return None;
                }
                (0..objs.len())
                    .filter(|&k| k != j && contains(&objs[k].shape, &objs[j].shape))
                    .min_by(|&a, &b| volume(&objs[a].shape).total_cmp(&volume(&objs[b].shape)))
            })
            .collect();
        let mut states = Vec::new();
        for &j in &specular {
            states.push((j, Side::Outside));
            if closed(&objs[j].shape) && mat(j).is_transmissive() {
                states.push((j, Side::Inside));
            }
        }
        let mut g = Self {
            scene,
            specular,
            parent,
            states,
            children: Vec::new(),
            branching: Vec::new(),
        };
        for i in 0..g.states.len() {
            let (j, side) = g.states[i];
            let m = mat(j);
            let other = match side {
                Side::Outside => Side::Inside,
                Side::Inside => Side::Outside,
            };
            let reflected = g.arrivals(j, side);
            let (kids, branch) = if m.is_transmissive() {
                let refracted = g.arrivals(j, other);
                if branches(scene, m) {
                    (vec![reflected, refracted], true)
                } else {
                    // One child per hit: refracted, or reflected under TIR.
                    let mut both = reflected;
                    both.extend(refracted);
                    both.sort_unstable();
                    both.dedup();
                    (vec![both], false)
                }
            } else {
                (vec![reflected], false)
            };
            g.children.push(kids);
            g.branching.push(branch);
        }
        g
    }

    pub(super) fn state(&self, j: usize, side: Side) -> Option<usize> {
        self.states.iter().position(|&s| s == (j, side))
    }

    /// States a ray leaving object `j` into its `side` can arrive at.
    pub(super) fn arrivals(&self, j: usize, side: Side) -> Vec<usize> {
        let objs = &self.scene.objects;
        let region: Region = match side {
            Side::Inside if closed(&objs[j].shape) => Some(j),
            // Open shapes have no inside: both sides are the object's own region.
            _ => self.parent[j],
        };
        let mut out = Vec::new();
        if let Some(k) = region
            && let Some(s) = self.state(k, Side::Inside)
        {
            out.push(s);
        }
        for &m in &self.specular {
            if self.parent[m] != region {
                continue;
            }
            // A convex object is not hit again from outside by a ray that leaves it outward.
            if m == j && !matches!(objs[j].shape, Shape::Mesh(_)) {
                continue;
            }
            if let Some(s) = self.state(m, Side::Outside) {
                out.push(s);
            }
        }
        out
    }

    /// Strongly connected components (Tarjan), as a component id per state.
    pub(super) fn components(&self) -> Vec<usize> {
        struct Tarjan<'g> {
            succ: &'g [Vec<Vec<usize>>],
            index: Vec<usize>,
            low: Vec<usize>,
            on: Vec<bool>,
            stack: Vec<usize>,
            comp: Vec<usize>,
            next: usize,
            ncomp: usize,
        }
        impl Tarjan<'_> {
            fn visit(&mut self, v: usize) {
                self.index[v] = self.next;
                self.low[v] = self.next;
                self.next += 1;
                self.stack.push(v);
                self.on[v] = true;
                let succ = self.succ;
                for &w in succ[v].iter().flatten() {
                    if self.index[w] == usize::MAX {
                        self.visit(w);
                        self.low[v] = self.low[v].min(self.low[w]);
                    } else if self.on[w] {
                        self.low[v] = self.low[v].min(self.index[w]);
                    }
                }
                if self.low[v] == self.index[v] {
                    while let Some(w) = self.stack.pop() {
                        self.on[w] = false;
                        self.comp[w] = self.ncomp;
                        if w == v {
                            break;
                        }
                    }
                    self.ncomp += 1;
                }
            }
        }
        let n = self.states.len();
        let mut t = Tarjan {
            succ: &self.children,
            index: vec![usize::MAX; n],
            low: vec![0; n],
            on: vec![false; n],
            stack: Vec::new(),
            comp: vec![usize::MAX; n],
            next: 0,
            ncomp: 0,
        };
        for v in 0..n {
            if t.index[v] == usize::MAX {
                t.visit(v);
            }
        }
        t.comp
    }

    pub(super) fn describe(&self, state: usize) -> String {
        let (j, side) = self.states[state];
        let name = &self.scene.objects[j].name;
        match side {
            Side::Outside => name.clone(),
            Side::Inside => format!("{name} (inside)"),
        }
    }
}
