//! Annotations at hits and on segments: normals, angle arcs, n1/n2, R/T, TIR, Beer factors.

use super::DiagramOptions;
use super::layout::{Owner, Pending};
use super::model::{Anchor, AngleArc, HitMark, LabelRole, Point, RayEnd, RaySegment};
use super::plane::PlaneFrame;
use super::segments::Seg3;
use crate::math::Rgb;
use crate::tree::{EndReason, HitInfo, Interface, RayKind, RayNode, RayTree};
use glam::DVec2;

/// A factor as text: one number when the channels agree, else three.
#[must_use]
pub fn factor_text(f: Rgb) -> String {
    if (f.max_element() - f.min_element()).abs() < 5e-3 {
        format!("{:.2}", f.x)
    } else {
        format!("({:.2}, {:.2}, {:.2})", f.x, f.y, f.z)
    }
}

fn anchor_for(dir: Point) -> Anchor {
    if dir.x > 0.3 {
        Anchor::Start
    } else if dir.x < -0.3 {
        Anchor::End
    } else {
        Anchor::Middle
    }
}

/// Baseline position for text centred on `p` (shift down by a third of the size).
fn centred(p: Point, fs: f64) -> Point {
    p + DVec2::new(0.0, 0.35 * fs)
}

fn arc(center: Point, from: Point, to: Point, radius: f64, degrees: f64) -> AngleArc {
    let start = from.y.atan2(from.x);
    let mut sweep = to.y.atan2(to.x) - start;
    while sweep > std::f64::consts::PI {
        sweep -= std::f64::consts::TAU;
    }
    while sweep < -std::f64::consts::PI {
        sweep += std::f64::consts::TAU;
    }
    AngleArc {
        center,
        radius,
        start,
        sweep,
        degrees,
    }
}

/// Hit marks for every drawn non-shadow ray that hit, and their labels.
pub(super) fn hits(
    tree: &RayTree,
    segs: &[Seg3],
    rays: &[RaySegment],
    frame: &PlaneFrame,
    fs: f64,
    opts: &DiagramOptions,
    pending: &mut Vec<Pending>,
) -> Vec<HitMark> {
    let annotator = Annotator {
        tree,
        segs,
        rays,
        frame,
        fs,
    };
    let mut out = Vec::new();
    for (s, r) in segs.iter().zip(rays) {
        let n = s.node;
        let labelled = n.depth <= opts.label_depth;
        if labelled {
            segment_labels(s, r, fs, 1 + n.depth, pending);
        }
        let Some(hit) = &n.hit else { continue };
        if n.kind == RayKind::Shadow {
            continue;
        }
        // A hit outside the view (its ray leaves through the frame) gets no mark.
        if s.end
            .is_none_or(|e| (frame.to_canvas(e) - r.to).length() > 0.5)
        {
            continue;
        }
        out.push(annotator.hit_mark(s, r, hit, labelled, pending));
    }
    out
}

/// What marking the hits of one figure reads: the drawn segments of the chosen sample and
/// their rays on the canvas (in the same order), the plane and the font size.
struct Annotator<'a> {
    tree: &'a RayTree,
    segs: &'a [Seg3<'a>],
    rays: &'a [RaySegment],
    frame: &'a PlaneFrame,
    fs: f64,
}

/// A hit on the canvas, for its labels.
struct Vertex<'a> {
    node: &'a RayNode,
    /// The hit point.
    at: Point,
    /// The unit normal on the side the ray came from (zero if it is perpendicular to the
    /// plane).
    normal: DVec2,
    /// `normal` turned a quarter.
    tangent: DVec2,
    fs: f64,
}

impl Vertex<'_> {
    /// A label of this vertex, tried at `spots` in order.
    fn label(&self, spots: Vec<(Point, Anchor)>, text: &str, role: LabelRole) -> Pending {
        Pending::new(spots, text, self.fs, role, 1 + self.node.depth)
            .for_node(self.node.id, self.node.kind)
            .owned_by(Owner::Vertex(self.at))
    }

    /// An angle's label: beyond the middle of its arc `a`, or at `fallback` without one.
    fn angle_label(&self, a: Option<&AngleArc>, text: &str, fallback: Point) -> Pending {
        let fs = self.fs;
        let spot = a.map_or(fallback, |a| {
            let mid = a.start + a.sweep * 0.5;
            a.center + (a.radius + 0.9 * fs) * DVec2::new(mid.cos(), mid.sin())
        });
        let alt = spot + (spot - self.at).normalize_or_zero() * 1.2 * fs;
        self.label(
            vec![
                (centred(spot, fs), Anchor::Middle),
                (centred(alt, fs), Anchor::Middle),
            ],
            text,
            LabelRole::Angle,
        )
    }
}

impl Annotator<'_> {
    /// The mark of the hit of segment `s` (drawn as `r`), and with `labelled` its angles and
    /// interface labels.
    fn hit_mark(
        &self,
        s: &Seg3,
        r: &RaySegment,
        hit: &HitInfo,
        labelled: bool,
        pending: &mut Vec<Pending>,
    ) -> HitMark {
        let (n, fs, frame) = (s.node, self.fs, self.frame);
        let h = r.to;
        // Marks no longer than a fraction of the shortest ray drawn at this vertex, so a short
        // ray is not hidden under its normal and arcs (issue 32: the caustic's diffuse bounce,
        // 5 px long, lay under 40 px of marks).
        let shortest = shortest_at(n.id, r, self.segs, self.rays);
        let normal_cap = shortest.max(0.6 * fs);
        let ni = if hit.entering {
            hit.normal
        } else {
            -hit.normal
        };
        let proj = frame.dir_to_canvas(ni);
        let nc = proj.try_normalize().unwrap_or(DVec2::ZERO);
        let normal_len = (2.4 * fs * proj.length().min(1.0)).min(normal_cap);
        let tir = n.interface.as_ref().is_some_and(|i| i.tir);
        let w = frame
            .dir_to_canvas(-n.direction)
            .try_normalize()
            .unwrap_or(DVec2::ZERO);
        let mut arcs = Vec::new();
        let v = Vertex {
            node: n,
            at: h,
            normal: nc,
            tangent: DVec2::new(-nc.y, nc.x),
            fs,
        };
        if labelled {
            let in_plane = !r.off_plane && proj.length() > 0.9 && w != DVec2::ZERO;
            let radius = (1.9 * fs).min((0.6 * shortest).max(0.3 * fs));
            self.angles(&v, hit, w, in_plane.then_some(radius), &mut arcs, pending);
            if let Some(i) = &n.interface {
                let side = if w.dot(v.tangent) >= 0.0 { 1.0 } else { -1.0 };
                interface_labels(&v, i, normal_len, side, pending);
            }
        }
        HitMark {
            node: n.id,
            point: h,
            normal: nc,
            normal_len,
            tir,
            truncated: matches!(
                n.end,
                EndReason::MaxDepth | EndReason::MinWeight | EndReason::RayBudget
            ),
            arcs,
            fade: r.fade,
        }
    }

    /// The angle of incidence at `v` and, where the ray refracts, the angle of transmission:
    /// their labels, and their arcs (of `arc_radius`, when the angles lie in the plane) pushed
    /// onto `arcs`. `w` is the unit direction back along the ray on the canvas.
    fn angles(
        &self,
        v: &Vertex,
        hit: &HitInfo,
        w: DVec2,
        arc_radius: Option<f64>,
        arcs: &mut Vec<AngleArc>,
        pending: &mut Vec<Pending>,
    ) {
        let (n, h, nc, fs) = (v.node, v.at, v.normal, self.fs);
        let theta_i = hit.cos_i.clamp(-1.0, 1.0).acos().to_degrees();
        if let Some(radius) = arc_radius {
            arcs.push(arc(h, nc, w, radius, theta_i));
        }
        pending.push(v.angle_label(
            arcs.last(),
            &format!("θi = {theta_i:.1}°"),
            h + DVec2::new(fs, -fs),
        ));
        let refracted = n
            .children
            .iter()
            .map(|c| self.tree.node(*c))
            .find(|c| c.kind == RayKind::Refracted);
        if let (Some(i), Some(t)) = (&n.interface, refracted)
            && i.cos_t.is_none_or(f64::is_finite)
        {
            let theta_t = i.cos_t.unwrap_or(1.0).clamp(-1.0, 1.0).acos().to_degrees();
            let tc = self.frame.dir_to_canvas(t.direction).try_normalize();
            let before = arcs.len();
            if let (Some(radius), Some(tc)) = (arc_radius, tc) {
                arcs.push(arc(h, -nc, tc, radius, theta_t));
            }
            let a = (arcs.len() > before).then(|| arcs.last()).flatten();
            pending.push(v.angle_label(
                a,
                &format!("θt = {theta_t:.1}°"),
                h + DVec2::new(fs, 2.0 * fs),
            ));
        }
    }
}

/// The labels of an interface at `v`: n1 and n2 at the ends of the normal (`normal_len`
/// long), and R and T (or TIR) on the side of the tangent given by `side` (+1 or -1).
fn interface_labels(
    v: &Vertex,
    i: &Interface,
    normal_len: f64,
    side: f64,
    pending: &mut Vec<Pending>,
) {
    let (h, nc, fs) = (v.at, v.normal, v.fs);
    let tip = normal_len + 0.6 * fs;
    let n1 = h + nc * tip;
    let n2 = h - nc * tip;
    for (p, text) in [
        (n1, format!("n1 = {:.2}", i.n1)),
        (n2, format!("n2 = {:.2}", i.n2)),
    ] {
        let off = v.tangent * 0.8 * fs;
        pending.push(v.label(
            vec![
                (centred(p, fs), Anchor::Middle),
                (centred(p + off, fs), Anchor::Start),
                (centred(p - off, fs), Anchor::End),
            ],
            &text,
            LabelRole::Interface,
        ));
    }
    let rt = if i.tir {
        format!("TIR: θi > θc, R = {:.2}", i.fresnel.r)
    } else {
        format!("R = {:.3}  T = {:.3}", i.fresnel.r, i.fresnel.t)
    };
    let d = v.tangent * side;
    let spot = h - nc * 1.3 * fs + d * 0.8 * fs;
    let spot2 = h + nc * 1.3 * fs - d * 2.5 * fs;
    pending.push(v.label(
        vec![
            (centred(spot, fs), anchor_for(d)),
            (centred(spot2, fs), anchor_for(-d)),
            (centred(h - nc * 2.0 * fs, fs), Anchor::Middle),
        ],
        &rt,
        LabelRole::Interface,
    ));
}

/// The length in pixels of the shortest ray drawn at the hit of ray `id` (drawn as `r`): `r`
/// itself and the rays spawned there.
fn shortest_at(id: crate::tree::NodeId, r: &RaySegment, segs: &[Seg3], rays: &[RaySegment]) -> f64 {
    segs.iter()
        .zip(rays)
        .filter(|(s, _)| s.node.parent == Some(id))
        .map(|(_, c)| (c.to - c.from).length())
        .chain([(r.to - r.from).length()])
        .filter(|l| *l > 0.0)
        .fold(f64::INFINITY, f64::min)
}

/// Beer factors on segments and the outcome of shadow rays.
fn segment_labels(s: &Seg3, r: &RaySegment, fs: f64, prio: u32, pending: &mut Vec<Pending>) {
    let n = s.node;
    let d = r.to - r.from;
    if d.length() < 3.0 * fs {
        return; // too short to carry text
    }
    let mid = (r.from + r.to) * 0.5;
    let perp = DVec2::new(-d.y, d.x).normalize_or_zero();
    let spots = |p: Point| {
        vec![
            (centred(p + perp * 0.9 * fs, fs), anchor_for(perp)),
            (centred(p - perp * 0.9 * fs, fs), anchor_for(-perp)),
        ]
    };
    let text = if let Some(a) = &n.attenuation {
        if a.distance.is_finite() {
            format!("Beer ×{} over {:.2}", factor_text(a.factor), a.distance)
        } else {
            "Beer: absorbed".to_string()
        }
    } else if let Some(sh) = &n.shadow {
        match r.end {
            RayEnd::Blocked => {
                let who = sh.blockers.first().map_or("?", |b| b.object_name.as_str());
                format!("blocked by {who}")
            }
            RayEnd::Light if n.end == EndReason::Attenuated => {
                format!("×{} to {}", factor_text(sh.transmittance), sh.light_name)
            }
            _ => return,
        }
    } else {
        return;
    };
    let at = if n.kind == RayKind::Shadow {
        r.from + d * 0.3
    } else {
        mid
    };
    pending.push(
        Pending::new(
            spots(at),
            &text,
            fs * 0.95,
            LabelRole::Attenuation,
            prio + 1,
        )
        .for_node(n.id, n.kind)
        .owned_by(Owner::Segment(r.from, r.to)),
    );
}
