//! The stack of media a ray is inside, so that n1 and n2 come from where the ray really is
//! (a glass ball inside water refracts with 1.5 / 1.333, not 1.5 / 1).

/// Deepest nesting tracked; deeper entries are dropped (outermost first).
const CAPACITY: usize = 6;

/// One medium: the object and its effective index of refraction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Medium {
    /// Object index.
    pub object: u32,
    /// Index of refraction inside it.
    pub ior: f64,
}

/// Media the ray is inside, innermost last. `Copy`, so recursion needs no allocation.
#[derive(Clone, Copy, Debug)]
pub struct MediaStack {
    items: [Medium; CAPACITY],
    len: usize,
}

impl Default for MediaStack {
    fn default() -> Self {
        Self::AIR
    }
}

impl PartialEq for MediaStack {
    fn eq(&self, other: &Self) -> bool {
        self.items[..self.len] == other.items[..other.len]
    }
}

impl MediaStack {
    /// The empty stack: the surrounding air (ior 1). A constant, so camera rays borrow it
    /// instead of building one per ray.
    pub const AIR: Self = Self {
        items: [Medium {
            object: 0,
            ior: 1.0,
        }; CAPACITY],
        len: 0,
    };

    /// The innermost medium, `None` in the surrounding air (ior 1).
    #[must_use]
    pub fn top(&self) -> Option<Medium> {
        self.len.checked_sub(1).map(|i| self.items[i])
    }

    /// Index of refraction where the ray is now.
    #[must_use]
    pub fn ior(&self) -> f64 {
        self.top().map_or(1.0, |m| m.ior)
    }

    /// Whether `object` is on the stack.
    #[must_use]
    pub fn contains(&self, object: usize) -> bool {
        self.items[..self.len]
            .iter()
            .any(|m| m.object as usize == object)
    }

    /// The stack after entering `object`.
    #[must_use]
    pub fn entered(mut self, object: usize, ior: f64) -> Self {
        if self.len == CAPACITY {
            self.items.copy_within(1.., 0);
            self.len -= 1;
        }
        self.items[self.len] = Medium {
            object: object as u32,
            ior,
        };
        self.len += 1;
        self
    }

    /// `self.left(object).ior()` without building the new stack (a 104-byte copy per
    /// dielectric hit from inside): the index of refraction outside `object`.
    #[must_use]
    #[inline]
    pub fn ior_outside(&self, object: usize) -> f64 {
        match self.items[..self.len]
            .iter()
            .rposition(|m| m.object as usize == object)
        {
            // Leaving the innermost medium: the one below it (or air).
            Some(i) if i + 1 == self.len => i.checked_sub(1).map_or(1.0, |j| self.items[j].ior),
            // Leaving one further out, or one the ray is not in: the innermost stays on top.
            _ => self.ior(),
        }
    }

    /// The stack after a ray transmitted through `object`'s surface: entering it (with the
    /// material's `ior`, or the current index when it has none), or leaving it.
    #[must_use]
    #[inline]
    pub fn crossed(self, object: usize, entering: bool, ior: Option<f64>) -> Self {
        if entering {
            let ior = ior.unwrap_or(self.ior());
            self.entered(object, ior)
        } else {
            self.left(object)
        }
    }

    /// The stack after leaving `object` (wherever it is on the stack; unchanged if absent).
    #[must_use]
    pub fn left(mut self, object: usize) -> Self {
        if let Some(i) = self.items[..self.len]
            .iter()
            .rposition(|m| m.object as usize == object)
        {
            self.items.copy_within(i + 1..self.len, i);
            self.len -= 1;
        }
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nested_media() {
        let air = MediaStack::default();
        assert_eq!(air.ior(), 1.0);
        let water = air.entered(0, 1.333);
        let glass = water.entered(1, 1.5);
        assert_eq!(glass.ior(), 1.5);
        assert_eq!(glass.left(1).ior(), 1.333);
        // Leaving the outer object first (overlapping solids) keeps the inner one.
        assert_eq!(glass.left(0).ior(), 1.5);
        assert_eq!(glass.left(0).left(1), air);
    }

    /// `ior_outside` is the ior of the stack `left` builds, for every object on or off it.
    #[test]
    fn ior_outside_equals_the_left_stack_ior() {
        let stacks = [
            MediaStack::AIR,
            MediaStack::AIR.entered(3, 1.5),
            MediaStack::AIR.entered(0, 1.333).entered(1, 1.5),
            MediaStack::AIR
                .entered(0, 1.333)
                .entered(1, 1.5)
                .entered(0, 2.0),
        ];
        for s in stacks {
            for object in 0..5 {
                assert_eq!(
                    s.ior_outside(object),
                    s.left(object).ior(),
                    "{s:?} {object}"
                );
            }
        }
    }

    #[test]
    fn overflow_drops_outermost() {
        let mut s = MediaStack::default();
        for i in 0..CAPACITY + 2 {
            s = s.entered(i, i as f64);
        }
        assert_eq!(s.ior(), (CAPACITY + 1) as f64);
        assert!(!s.contains(0) && s.contains(CAPACITY + 1));
    }
}
