//! What a diff between stochastic settings needs (issue 32, item 16): the first *decision*
//! that differs (the sampled lobe, a Russian-roulette outcome, the dielectric split, which
//! rays a hit spawned) rather than the first number, since a changed value anywhere below
//! changes every radiance above it up to the camera ray; and the pixel difference with its
//! standard error, since two Monte Carlo estimates differ by noise alone.

use super::matched_children;
use crate::math::Rgb;
use crate::tree::{NodeId, RayKind, RayNode, RayTree};
use serde::Serialize;
use std::collections::VecDeque;

/// A sampling decision that differs between two matched rays.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DecisionChange {
    /// The sample (its index, as `raytree trace` numbers them).
    pub sample: u32,
    /// The ray in tree A.
    pub a: NodeId,
    /// The ray in tree B.
    pub b: NodeId,
    /// Their kind.
    pub kind: RayKind,
    /// Their depth.
    pub depth: u32,
    /// Which decision: `sampled lobe`, `path roulette`, `dielectric roulette`, `rays spawned`.
    pub decision: String,
    /// The decision in A, in words.
    pub in_a: String,
    /// The decision in B, in words.
    pub in_b: String,
}

/// The decisions recorded on ray `n`, each as (name, outcome to compare, outcome in words).
fn decisions(t: &RayTree, n: &RayNode) -> Vec<(&'static str, String, String)> {
    let mut out = Vec::new();
    let path = n.path.as_ref();
    if let Some(l) = path.and_then(|p| p.lobe) {
        out.push(("sampled lobe", l.name().to_string(), l.name().to_string()));
    } else if n.kind != RayKind::Shadow && n.kind != RayKind::Camera && path.is_some() {
        out.push(("sampled lobe", "none".into(), "none".into()));
    }
    let rr = match path.and_then(|p| p.roulette) {
        None => ("none".to_string(), "no roulette at this hit".to_string()),
        Some(r) if r.survived => (
            "survived".into(),
            format!("survived the roulette (probability {:.4})", r.probability),
        ),
        Some(r) => (
            "ended".into(),
            format!(
                "the roulette ended the path (survival probability {:.4})",
                r.probability
            ),
        ),
    };
    out.push(("path roulette", rr.0, rr.1));
    let split = match n.interface.as_ref().and_then(|i| i.roulette) {
        None => (
            "none".to_string(),
            "both rays traced (no split roulette)".to_string(),
        ),
        Some(s) => (
            s.ray().to_string(),
            format!(
                "followed the {} ray (probability {:.4})",
                s.ray(),
                s.probability
            ),
        ),
    };
    out.push(("dielectric roulette", split.0, split.1));
    let kids: Vec<&str> = n.children.iter().map(|c| t.node(*c).kind.name()).collect();
    let spawned = if kids.is_empty() {
        format!("no rays ({})", crate::text::end_text(n.end))
    } else {
        kids.join(", ")
    };
    out.push(("rays spawned", kids.join(","), spawned));
    out
}

/// The first decision of `(na, nb)` that differs, if any.
fn first_changed(
    a: &RayTree,
    na: &RayNode,
    b: &RayTree,
    nb: &RayNode,
) -> Option<(String, String, String)> {
    let (da, db) = (decisions(a, na), decisions(b, nb));
    for (x, y) in da.iter().zip(&db) {
        if x.1 != y.1 {
            return Some((x.0.to_string(), x.2.clone(), y.2.clone()));
        }
    }
    None
}

/// For every sample both trees have (matched by position), the shallowest matched pair of
/// rays (breadth-first, then child order) whose decisions differ; samples in order.
#[must_use]
pub fn decision_changes(a: &RayTree, b: &RayTree) -> Vec<DecisionChange> {
    let mut out = Vec::new();
    for (sa, sb) in a.samples.iter().zip(&b.samples) {
        let mut queue = VecDeque::from([(sa.root, sb.root)]);
        while let Some((ia, ib)) = queue.pop_front() {
            let (na, nb) = (a.node(ia), b.node(ib));
            if let Some((decision, in_a, in_b)) = first_changed(a, na, b, nb) {
                out.push(DecisionChange {
                    sample: sa.index,
                    a: ia,
                    b: ib,
                    kind: na.kind,
                    depth: na.depth,
                    decision,
                    in_a,
                    in_b,
                });
                break;
            }
            queue.extend(
                matched_children(a, na, b, nb)
                    .into_iter()
                    .filter_map(|(x, y)| Some((x?, y?))),
            );
        }
    }
    out
}

/// The pixel difference `b - a` of two trees' sample means, with its standard error.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PixelDifference {
    /// Mean of B's samples minus mean of A's (the pixel values under a box filter).
    pub mean: Rgb,
    /// Standard error of `mean` per channel; `None` with fewer than 2 samples a side.
    pub std_error: Option<Rgb>,
    /// Whether the samples were paired by index (same count: the standard deviation of the
    /// per-sample differences over sqrt(n)); otherwise `sqrt(s_a^2/n_a + s_b^2/n_b)`.
    pub paired: bool,
    /// Samples in A and in B.
    pub samples: [usize; 2],
}

/// Mean and unbiased variance of `x`, each sum scaled as it is added (so finite samples near
/// the largest double keep a finite mean).
fn mean_var(x: &[Rgb]) -> (Rgb, Option<Rgb>) {
    let n = x.len() as f64;
    let mean = x.iter().fold(Rgb::ZERO, |s, v| s + *v / n);
    if x.len() < 2 {
        return (mean, None);
    }
    let k = (n - 1.0).sqrt();
    let var = x.iter().fold(Rgb::ZERO, |s, v| {
        let d = (*v - mean) / k;
        s + d * d
    });
    (mean, Some(var))
}

/// `b - a` over the samples of both trees, with its standard error (see [`PixelDifference`]).
#[must_use]
pub fn pixel_difference(a: &RayTree, b: &RayTree) -> PixelDifference {
    let ra: Vec<Rgb> = a.samples.iter().map(|s| s.radiance).collect();
    let rb: Vec<Rgb> = b.samples.iter().map(|s| s.radiance).collect();
    let samples = [ra.len(), rb.len()];
    if ra.len() == rb.len() && !ra.is_empty() {
        let d: Vec<Rgb> = rb.iter().zip(&ra).map(|(y, x)| *y - *x).collect();
        let (mean, var) = mean_var(&d);
        return PixelDifference {
            mean,
            std_error: var.map(|v| (v / d.len() as f64).map(f64::sqrt)),
            paired: true,
            samples,
        };
    }
    let ((ma, va), (mb, vb)) = (mean_var(&ra), mean_var(&rb));
    let std_error = match (va, vb) {
        (Some(va), Some(vb)) => Some((va / ra.len() as f64 + vb / rb.len() as f64).map(f64::sqrt)),
        _ => None,
    };
    PixelDifference {
        mean: mb - ma,
        std_error,
        paired: false,
        samples,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scene;
    use crate::scene::IntegratorKind;
    use crate::trace_pixel;

    fn path_scene(rr_depth: u32) -> Scene {
        let mut s = Scene::default_scene();
        s.settings.integrator = IntegratorKind::Path;
        s.settings.spp = 16;
        s.settings.rr_depth = rr_depth;
        s
    }

    #[test]
    fn a_roulette_depth_first_differs_at_a_roulette_decision() {
        let a = trace_pixel(&path_scene(1), 300, 300).unwrap();
        let b = trace_pixel(&path_scene(8), 300, 300).unwrap();
        let d = decision_changes(&a, &b);
        assert!(!d.is_empty(), "some sample's decisions differ");
        let first = &d[0];
        assert_eq!(first.decision, "path roulette", "{first:?}");
        // Roulette from the first bounce on: played at the camera ray's hit in a, not in b.
        assert_eq!((first.kind, first.depth), (RayKind::Camera, 0), "{first:?}");
        assert!(first.in_b.contains("no roulette"), "{first:?}");
        // The same settings: no decision differs.
        assert!(decision_changes(&a, &a.clone()).is_empty());
    }

    #[test]
    fn the_pixel_difference_has_a_paired_standard_error() {
        let a = trace_pixel(&path_scene(1), 300, 300).unwrap();
        let b = trace_pixel(&path_scene(8), 300, 300).unwrap();
        let p = pixel_difference(&a, &b);
        assert!(p.paired && p.samples == [16, 16]);
        let se = p.std_error.unwrap();
        assert!(se.is_finite() && se.min_element() >= 0.0);
        // By hand: the per-sample differences' spread over sqrt(16).
        let d: Vec<f64> = a
            .samples
            .iter()
            .zip(&b.samples)
            .map(|(x, y)| y.radiance.x - x.radiance.x)
            .collect();
        let m = d.iter().sum::<f64>() / 16.0;
        let v = d.iter().map(|x| (x - m).powi(2)).sum::<f64>() / 15.0;
        assert!((p.mean.x - m).abs() < 1e-12);
        assert!((se.x - (v / 16.0).sqrt()).abs() < 1e-12);
        // A tree against itself: no difference and no spread.
        let z = pixel_difference(&a, &a);
        assert_eq!((z.mean, z.std_error), (Rgb::ZERO, Some(Rgb::ZERO)));
        // Finite samples near the largest double: a finite mean and error.
        let mut big = a.clone();
        for s in &mut big.samples {
            s.radiance = Rgb::splat(1.19e308);
        }
        big.samples[0].radiance = Rgb::splat(-1.19e308);
        let o = pixel_difference(&a, &big);
        assert!(o.mean.is_finite(), "{:?}", o.mean);
    }
}
