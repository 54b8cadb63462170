//! The Monte Carlo statistics of one pixel from its recorded nodes (the inspector's debug
//! views): the same numbers [`super::render_aovs`] gathers through its light recorder (tested),
//! plus the share of each standard class ([`super::CLASSES`]).

use super::{CLASSES, McPixel};
use crate::bsdf::luminance;
use crate::lpe::recorded_events;
use crate::math::Rgb;
use crate::tree::{EndReason, RayKind, RayNode};

/// The standard class ([`CLASSES`] index) of a complete recorded path string, by the same rule
/// as the classes' expressions (the first non-specular vertex), without a regex: `None` for a
/// string that is not a complete path (`C`, scattering events, then `L` or `B`).
#[must_use]
pub fn classify(path: &str) -> Option<usize> {
    let events = recorded_events(path)?;
    let (first, rest) = events.split_first()?;
    let (last, mid) = rest.split_last()?;
    if first.kind != 'C' || last.scatter.is_some() || !matches!(last.kind, 'L' | 'B') {
        return None;
    }
    if mid.iter().any(|e| e.scatter.is_none() || e.kind == 'C') {
        return None;
    }
    let light = last.kind == 'L';
    let specular = |e: &crate::lpe::Event| e.scatter == Some('S');
    Some(match mid.iter().position(|e| !specular(e)) {
        None => usize::from(!light),
        Some(j) if j + 1 == mid.len() => 2 + usize::from(!light),
        Some(j) if mid[j + 1..].iter().all(specular) => 4,
        Some(_) => 5,
    })
}

/// Statistics of one pixel from its nodes in recording order (every sample starts at its
/// camera ray; parents need not be linked), and the share of each class in its radiance (by
/// luminance; 0 for a black pixel). A sample's radiance is the sum of its nodes'
/// contributions (path integrator) or its camera ray's radiance (Whitted); a non-finite
/// path sample counts as dropped (black), as the render drops it.
#[must_use]
pub fn pixel_from_nodes(nodes: &[RayNode]) -> (McPixel, [f64; CLASSES.len()]) {
    let mut px = McPixel::default();
    let mut lums = Vec::new();
    let mut segments = 0u64;
    let mut classes = [Rgb::ZERO; CLASSES.len()];
    let mut total = Rgb::ZERO;
    // The current sample: radiance, per class, whether it is a path sample.
    let mut cur: Option<(Rgb, [Rgb; CLASSES.len()], bool)> = None;
    let mut finish = |cur: Option<(Rgb, [Rgb; CLASSES.len()], bool)>, px: &mut McPixel| {
        let Some((l, by_class, path)) = cur else {
            return;
        };
        px.samples += 1;
        if l.is_finite() {
            lums.push(luminance(l));
            total += l;
            for (c, s) in classes.iter_mut().zip(by_class) {
                *c += s;
            }
        } else {
            px.dropped += u32::from(path);
            lums.push(0.0);
        }
    };
    for n in nodes {
        if n.kind == RayKind::Camera {
            finish(cur.take(), &mut px);
            let whitted = if n.path.is_none() {
                n.radiance
            } else {
                Rgb::ZERO
            };
            cur = Some((whitted, [Rgb::ZERO; CLASSES.len()], n.path.is_some()));
        }
        let (Some(p), Some(c)) = (&n.path, cur.as_mut()) else {
            continue;
        };
        c.0 += p.contribution;
        if let Some(k) = classify(&p.lpe)
            && p.contribution != Rgb::ZERO
        {
            c.1[k] += p.contribution;
        }
        if n.kind != RayKind::Shadow {
            segments += 1;
        }
        px.roulette += u32::from(n.end == EndReason::RussianRoulette);
    }
    finish(cur.take(), &mut px);
    px.path_length = segments as f64 / f64::from(px.samples.max(1));
    px.set_spread(&lums);
    let t = luminance(total);
    let shares = classes.map(|c| if t > 0.0 { luminance(c) / t } else { 0.0 });
    (px, shares)
}
