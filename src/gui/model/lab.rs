//! The acne lab's parameters (issue 17): the offset strategy and epsilon counted, and the
//! scene's scale and distance from the origin. Plain data the document holds and the lab's
//! worker ([`crate::gui::jobs::acne_lab`]) renders.

use crate::scene::OffsetStrategy;

/// What the lab renders.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LabParams {
    /// Offset strategy of the count.
    pub strategy: OffsetStrategy,
    /// Epsilon of the count (0 allowed).
    pub epsilon: f64,
    /// Scene scale about the origin (positive).
    pub scale: f64,
    /// Distance moved from the origin per unit scale and axis (as `raytree acne --shift`).
    pub shift: f64,
}

impl Default for LabParams {
    fn default() -> Self {
        Self {
            strategy: OffsetStrategy::Normal,
            epsilon: 1e-4,
            scale: 1.0,
            shift: 0.0,
        }
    }
}

impl LabParams {
    /// Why these parameters cannot be rendered, if they cannot.
    pub fn check(&self) -> Result<(), String> {
        if !(self.epsilon.is_finite() && self.epsilon >= 0.0) {
            return Err(format!("epsilon must be >= 0, got {}", self.epsilon));
        }
        if !(self.scale.is_finite() && self.scale > 0.0) {
            return Err(format!("scale must be positive, got {}", self.scale));
        }
        if !(self.shift.is_finite() && self.shift >= 0.0) {
            return Err(format!(
                "distance from the origin must be >= 0, got {}",
                self.shift
            ));
        }
        Ok(())
    }
}
