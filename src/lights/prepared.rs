//! Area lights with what does not depend on the shading point computed once per light, for
//! every light sampler ([`super::AreaShape::Planar`]): a quad's or triangle's unit normal, `edge_u x edge_v` and
//! area (a cross product, a square root and a division per light sample before). The samples
//! and pdfs are those of [`PlanarEmitter::sample`] and [`PlanarEmitter::pdf`] bit for bit (the
//! same code, given the same values).

use super::{LightSample, PlanarEmitter};
use crate::math::Rgb;
use glam::{DVec2, DVec3};

/// A [`PlanarEmitter`] with its normal (`None` when degenerate), `edge_u x edge_v`, its
/// squared length and the area.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PreparedPlanar {
    emitter: PlanarEmitter,
    normal: Option<DVec3>,
    cross: DVec3,
    cross2: f64,
    area: f64,
}

impl PreparedPlanar {
    /// `e` with its constants computed.
    #[must_use]
    pub fn new(e: PlanarEmitter) -> Self {
        let cross = e.edge_u.cross(e.edge_v);
        Self {
            emitter: e,
            normal: e.normal(),
            cross,
            cross2: cross.length_squared(),
            area: e.area(),
        }
    }

    /// The emitter.
    #[must_use]
    pub fn emitter(&self) -> &PlanarEmitter {
        &self.emitter
    }

    /// Area (0 for degenerate edges), as [`PlanarEmitter::area`].
    #[must_use]
    pub fn area(&self) -> f64 {
        self.area
    }

    /// Unit normal on the outer side (`None` when degenerate).
    #[must_use]
    pub fn normal(&self) -> Option<DVec3> {
        self.normal
    }

    /// A point uniform in area ([`PlanarEmitter::sample_point`]).
    #[must_use]
    pub fn sample_point(&self, u: DVec2) -> DVec3 {
        self.emitter.sample_point(u)
    }

    /// [`PlanarEmitter::sample`].
    #[inline(always)]
    #[must_use]
    pub fn sample(&self, p: DVec3, radiance: Rgb, u: DVec2) -> Option<LightSample> {
        let n = self.normal?;
        self.emitter.sample_given(n, || self.area, p, radiance, u)
    }

    /// [`PlanarEmitter::pdf`].
    #[inline]
    #[must_use]
    pub fn pdf(&self, p: DVec3, wi: DVec3) -> f64 {
        let Some(n) = self.normal else {
            return 0.0;
        };
        let c = (self.cross, self.cross2);
        self.emitter.pdf_given(n, c, || self.area, p, wi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::SplitMix64;

    /// The prepared quad and triangle sample and weigh exactly as the plain ones, from points
    /// in front, behind and beside them (a cached normal of the wrong sign, a stale area or a
    /// swapped cross product fails this), and a degenerate emitter gives nothing either way.
    #[test]
    fn prepared_planar_emitters_are_the_plain_ones_bit_for_bit() {
        let quad = PlanarEmitter::quad(
            DVec3::new(-1.0, 2.0, -1.0),
            DVec3::new(2.0, 0.0, 0.1),
            DVec3::new(0.0, -0.2, 3.0),
        );
        let tri = PlanarEmitter::triangle(
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 1.5, 0.0),
            DVec3::new(0.0, 1.2, 1.0),
        );
        let flat = PlanarEmitter::quad(DVec3::ZERO, DVec3::X, 2.0 * DVec3::X);
        let mut rng = SplitMix64::new(3);
        let radiance = Rgb::new(1.0, 2.0, 3.0);
        let mut made = 0;
        for e in [quad, tri, flat] {
            let prepared = PreparedPlanar::new(e);
            for _ in 0..2000 {
                let p = 4.0 * (DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) - 0.5);
                let u = (rng.next_f64(), rng.next_f64());
                let got = prepared.sample(p, radiance, DVec2::new(u.0, u.1));
                assert_eq!(got, e.sample(p, radiance, DVec2::new(u.0, u.1)));
                made += usize::from(got.is_some());
                let wi =
                    (DVec3::new(0.0, 1.5, 0.3) - p).normalize() + 0.3 * (rng.next_2d().x - 0.5);
                let wi = wi.normalize();
                assert_eq!(prepared.pdf(p, wi).to_bits(), e.pdf(p, wi).to_bits());
                if let Some(s) = got {
                    assert_eq!(
                        prepared.pdf(p, s.direction).to_bits(),
                        e.pdf(p, s.direction).to_bits()
                    );
                }
            }
        }
        assert!(made > 1000, "only {made} samples were made");
    }
}
